//! Rotation and shift: ROR, ROL, SFTR, SFTL.

use super::Step;
use crate::lower::operand::Units;
use crate::CompareOp;
use crate::{BinOp, Index, Type};
use ladder_front::program::{BitRef, WordRef};
use ladder_runtime::device::MAX_SHIFT_BITS;
use ladder_runtime::helpers::Helper;
use ladder_runtime::special::CARRY_FLAG;
use ladder_runtime::OperationError;

/// ROR/ROL D n: n first (0 to the width's bits, else 4084H); the rotation
/// as two shifts of the value masked to the width; M8022 the bit that
/// arrived at the end the rotation moved toward (OFF for n = 0).
pub fn rotate(step: &mut Step, d: &WordRef, n: &WordRef, right: bool) {
    let n = step.count_value(n);
    let bits = i64::from(step.width.bits());
    step.require_within(n, 0, bits);
    let width = step.width;
    let d = step.resolve(d, width, Units::Checked(1), true);
    step.commit();
    let value = step.read(&d);
    let b = step.b();
    let mask = b.constant(Type::I64, (1i64 << bits) - 1);
    let unsigned = b.binary(BinOp::And, value, mask);
    let width_bits = b.constant(Type::I64, bits);
    let toward_left = if right { b.binary(BinOp::Sub, width_bits, n) } else { n };
    let left_by = b.binary(BinOp::Rem, toward_left, width_bits);
    let complement = b.binary(BinOp::Sub, width_bits, left_by);
    let right_by = b.binary(BinOp::Rem, complement, width_bits);
    let high = b.binary(BinOp::Shl, unsigned, left_by);
    let low = b.binary(BinOp::UShr, unsigned, right_by);
    let joined = b.binary(BinOp::Or, high, low);
    let rotated = b.binary(BinOp::And, joined, mask);
    let carry_position = b.constant(Type::I64, if right { bits - 1 } else { 0 });
    let shifted = b.binary(BinOp::UShr, rotated, carry_position);
    let one = b.constant(Type::I64, 1);
    let carry_bit = b.binary(BinOp::And, shifted, one);
    let zero = b.constant(Type::I64, 0);
    let carry_set = b.compare(CompareOp::Ne, carry_bit, zero);
    let moved = b.compare(CompareOp::Ne, n, zero);
    let carry = b.and(carry_set, moved);
    step.write(&d, rotated);
    step.b()
        .store_bit(CARRY_FLAG.area, Index::Fixed(CARRY_FLAG.number), carry);
}

/// SFTR/SFTL S D n1 n2: the counts first (1 <= n2 <= n1 <= 1024, else
/// 4084H), then both runs of bits; the runtime's `shift_bits` moves them.
pub fn shift_bits(step: &mut Step, s: &BitRef, d: &BitRef, n1: &WordRef, n2: &WordRef, left: bool) {
    let n1 = step.count_value(n1);
    let n2 = step.count_value(n2);
    let b = step.b();
    let one = b.constant(Type::I64, 1);
    let most = b.constant(Type::I64, i64::from(MAX_SHIFT_BITS));
    let some = b.compare(CompareOp::Ge, n2, one);
    let within = b.compare(CompareOp::Le, n2, n1);
    let bounded = b.compare(CompareOp::Le, n1, most);
    let first = b.and(some, within);
    let valid = b.and(first, bounded);
    step.require(valid, OperationError::DataOutOfRange);
    let n1 = step.b().truncate(n1, Type::I32);
    let n2 = step.b().truncate(n2, Type::I32);
    let source = step.bits(s, Units::Dynamic(n2), true);
    let destination = step.bits(d, Units::Dynamic(n1), true);
    step.commit();
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    let left = step.b().number(u32::from(left));
    step.b()
        .call(Helper::ShiftBits, vec![source, destination, n1, n2, left]);
}
