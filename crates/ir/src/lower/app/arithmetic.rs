//! Arithmetic: ADD, SUB, MUL, DIV, INC, DEC, NEG, SQR.

use super::Step;
use crate::CompareOp;
use crate::{BinOp, Type, UnaryOp, Value};
use ladder_runtime::{OperationError, Width};

/// The wrapped result of an exact I64 and the flags zero, borrow, carry.
fn with_flags(step: &mut Step, exact: Value) -> (Value, [Value; 3]) {
    let width = step.width;
    let wrapped = step.l.wrap(exact, width);
    let (min, max) = match width {
        Width::Single => (i64::from(i16::MIN), i64::from(i16::MAX)),
        Width::Double => (i64::from(i32::MIN), i64::from(i32::MAX)),
    };
    let b = step.b();
    let zero = b.constant(Type::I64, 0);
    let min = b.constant(Type::I64, min);
    let max = b.constant(Type::I64, max);
    let flags = [
        b.compare(CompareOp::Eq, wrapped, zero),
        b.compare(CompareOp::Lt, exact, min),
        b.compare(CompareOp::Gt, exact, max),
    ];
    (wrapped, flags)
}

pub fn add(step: &mut Step, [a, b]: [Value; 2]) -> (Value, [Value; 3]) {
    let exact = step.b().binary(BinOp::Add, a, b);
    with_flags(step, exact)
}

pub fn sub(step: &mut Step, [a, b]: [Value; 2]) -> (Value, [Value; 3]) {
    let exact = step.b().binary(BinOp::Sub, a, b);
    with_flags(step, exact)
}

/// (low unit, high unit) of the product.
pub fn mul(step: &mut Step, [a, b]: [Value; 2]) -> [Value; 2] {
    let bits = i64::from(step.width.bits());
    let b_ = step.b();
    let product = b_.binary(BinOp::Mul, a, b);
    let half = b_.constant(Type::I64, bits);
    let high = b_.binary(BinOp::Shr, product, half);
    [product, high]
}

/// (quotient, remainder); a zero divisor records 4084H.
pub fn div(step: &mut Step, [a, b]: [Value; 2]) -> [Value; 2] {
    let zero = step.b().constant(Type::I64, 0);
    let divisor_ok = step.b().compare(CompareOp::Ne, b, zero);
    step.require(divisor_ok, OperationError::DataOutOfRange);
    let quotient = step.b().binary(BinOp::Div, a, b);
    let remainder = step.b().binary(BinOp::Rem, a, b);
    [quotient, remainder]
}

fn add_constant(step: &mut Step, d: Value, delta: i64) -> Value {
    let delta = step.b().constant(Type::I64, delta);
    step.b().binary(BinOp::Add, d, delta)
}

pub fn inc(step: &mut Step, d: Value) -> Value {
    add_constant(step, d, 1)
}

pub fn dec(step: &mut Step, d: Value) -> Value {
    add_constant(step, d, -1)
}

pub fn neg(step: &mut Step, d: Value) -> Value {
    let zero = step.b().constant(Type::I64, 0);
    step.b().binary(BinOp::Sub, zero, d)
}

/// The root rounded down, with SM152 (a fraction was dropped) and SM153
/// (the root is 0); a negative S records 4084H.
pub fn sqr(step: &mut Step, [s]: [Value; 1]) -> (Value, [Value; 2]) {
    let zero = step.b().constant(Type::I64, 0);
    let valid = step.b().compare(CompareOp::Ge, s, zero);
    step.require(valid, OperationError::DataOutOfRange);
    let b = step.b();
    let root = b.push(crate::Inst::Unary {
        op: UnaryOp::SquareRoot,
        value: s,
    });
    let square = b.binary(BinOp::Mul, root, root);
    let dropped = b.compare(CompareOp::Ne, square, s);
    let is_zero = b.compare(CompareOp::Eq, root, zero);
    (root, [dropped, is_zero])
}
