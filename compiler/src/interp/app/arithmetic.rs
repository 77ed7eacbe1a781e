//! Arithmetic: ADD, SUB, MUL, DIV, INC, DEC.

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
