//! Logic and bits: WAND, WOR, WXOR, CML, BON, SUM, ALT.

use super::Step;
use crate::lower::operand::Units;
use crate::CompareOp;
use crate::{BinOp, Inst, Type, UnaryOp, Value};
use ladder_front::program::BitRef;
use ladder_runtime::Width;

pub fn wand(step: &mut Step, [a, b]: [Value; 2]) -> Value {
    step.b().binary(BinOp::And, a, b)
}

pub fn wor(step: &mut Step, [a, b]: [Value; 2]) -> Value {
    step.b().binary(BinOp::Or, a, b)
}

pub fn wxor(step: &mut Step, [a, b]: [Value; 2]) -> Value {
    step.b().binary(BinOp::Xor, a, b)
}

pub fn cml(step: &mut Step, [s]: [Value; 1]) -> Value {
    let all = step.b().constant(Type::I64, -1);
    step.b().binary(BinOp::Xor, s, all)
}

/// Bit N of S (sign-extended, so an arithmetic shift finds every bit of the
/// width); N outside 0..bits records 4084H.
pub fn bon(step: &mut Step, [s, n]: [Value; 2]) -> Value {
    let bits = i64::from(step.width.bits());
    step.require_within(n, 0, bits - 1);
    let b = step.b();
    let shifted = b.binary(BinOp::Shr, s, n);
    let one = b.constant(Type::I64, 1);
    let bit = b.binary(BinOp::And, shifted, one);
    let zero = b.constant(Type::I64, 0);
    b.compare(CompareOp::Ne, bit, zero)
}

/// The ON bits of S within the width, and SM153 when there are none.
pub fn sum(step: &mut Step, [s]: [Value; 1]) -> (Value, [Value; 1]) {
    let mask = (1i64 << step.width.bits()) - 1;
    let b = step.b();
    let mask = b.constant(Type::I64, mask);
    let bits = b.binary(BinOp::And, s, mask);
    let count = b.push(Inst::Unary {
        op: UnaryOp::PopCount,
        value: bits,
    });
    let zero = b.constant(Type::I64, 0);
    let none = b.compare(CompareOp::Eq, bits, zero);
    (count, [none])
}

/// ALT D: the bit is written back inverted.
pub fn alternate(step: &mut Step, d: &BitRef) {
    let d = step.bits(d, Units::Checked(1), true);
    step.commit();
    let now = step.read_at(&d, Width::Single);
    let zero = step.b().constant(Type::I64, 0);
    let off = step.b().compare(CompareOp::Eq, now, zero);
    step.write_bit(&d, off);
}
