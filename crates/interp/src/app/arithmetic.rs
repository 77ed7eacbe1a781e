//! Arithmetic: ADD, SUB, MUL, DIV, INC, DEC, NEG, SQR.

use super::wrap;
use ladder_runtime::{OperationError, Width};

/// The smallest and largest value of `width`.
fn limits(width: Width) -> (i64, i64) {
    match width {
        Width::Single => (i64::from(i16::MIN), i64::from(i16::MAX)),
        Width::Double => (i64::from(i32::MIN), i64::from(i32::MAX)),
    }
}

/// The wrapped result and the flags zero, borrow, carry (M8020-M8022).
fn with_flags(exact: i64, width: Width) -> (i64, [bool; 3]) {
    let (min, max) = limits(width);
    let wrapped = wrap(exact, width);
    (wrapped, [wrapped == 0, exact < min, exact > max])
}

pub fn add([a, b]: [i64; 2], width: Width) -> Result<(i64, [bool; 3]), OperationError> {
    Ok(with_flags(a + b, width))
}

pub fn sub([a, b]: [i64; 2], width: Width) -> Result<(i64, [bool; 3]), OperationError> {
    Ok(with_flags(a - b, width))
}

/// The double-width product: (low unit, high unit).
pub fn mul([a, b]: [i64; 2], width: Width) -> Result<[i64; 2], OperationError> {
    let product = a * b;
    Ok([product, product >> width.bits()])
}

/// (quotient, remainder), truncating toward zero; a zero divisor is 4084H.
/// MIN / -1 wraps like the hardware.
pub fn div([a, b]: [i64; 2], _: Width) -> Result<[i64; 2], OperationError> {
    if b == 0 {
        return Err(OperationError::DataOutOfRange);
    }
    Ok([a / b, a % b])
}

pub fn inc(d: i64, _: Width) -> i64 {
    d + 1
}

pub fn dec(d: i64, _: Width) -> i64 {
    d - 1
}

/// Two's complement; the smallest value wraps to itself.
pub fn neg(d: i64, _: Width) -> i64 {
    -d
}

/// The square root rounded down, and the flags borrow (SM152: a fraction
/// was dropped) and zero (SM153: the root is 0). A negative S is 4084H.
pub fn sqr([s]: [i64; 1], _: Width) -> Result<(i64, [bool; 2]), OperationError> {
    if s < 0 {
        return Err(OperationError::DataOutOfRange);
    }
    // The largest r with r·r <= s, by bisection: the specification needs no
    // floating point.
    let (mut low, mut high) = (0i64, s.min(46341) + 1);
    while high - low > 1 {
        let middle = (low + high) / 2;
        if middle * middle <= s {
            low = middle;
        } else {
            high = middle;
        }
    }
    Ok((low, [low * low != s, low == 0]))
}
