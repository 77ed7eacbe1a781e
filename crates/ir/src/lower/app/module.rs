//! FROM and TO in the lowering: the buffer words are a run of the buffer
//! area, moved with the runtime's block helpers.

use super::Step;
use crate::lower::operand::{Operand, Units};
use crate::CompareOp;
use crate::{BinOp, Index, Type};
use ladder_front::program::WordRef;
use ladder_runtime::device::{BUFFER_UNITS, BUFFER_WORDS_PER_UNIT};
use ladder_runtime::helpers::{width_arg, Helper};
use ladder_runtime::{OperationError, WordArea};

/// FROM m1 m2 D n (`from`) or TO m1 m2 S n.
pub fn transfer(step: &mut Step, m1: &WordRef, m2: &WordRef, other: &WordRef, n: &WordRef, from: bool) {
    let width = step.width;
    // DFROM/DTO read m1, m2 and n as pairs, as every operand of a D form.
    let unit = step.source_value(m1);
    let first = step.source_value(m2);
    let n = step.source_value(n);
    let b = step.b();
    let (zero, one) = (b.constant(Type::I64, 0), b.constant(Type::I64, 1));
    let units = b.constant(Type::I64, i64::from(BUFFER_UNITS));
    let words_per = b.constant(Type::I64, i64::from(width.words()));
    let end = b.constant(Type::I64, i64::from(BUFFER_WORDS_PER_UNIT));
    let unit_low = b.compare(CompareOp::Ge, unit, zero);
    let unit_high = b.compare(CompareOp::Lt, unit, units);
    let first_ok = b.compare(CompareOp::Ge, first, zero);
    let some = b.compare(CompareOp::Ge, n, one);
    let words = b.binary(BinOp::Mul, n, words_per);
    let last = b.binary(BinOp::Add, first, words);
    let inside = b.compare(CompareOp::Le, last, end);
    let checks = [unit_high, first_ok, some, inside];
    let valid = checks.into_iter().fold(unit_low, |all, check| b.and(all, check));
    step.require(valid, OperationError::DataOutOfRange);
    let count = step.b().truncate(n, Type::I32);
    let device = step.resolve(other, width, Units::Dynamic(count), !from);
    step.commit();
    let b = step.b();
    let per_unit = b.constant(Type::I64, i64::from(BUFFER_WORDS_PER_UNIT));
    let base = b.binary(BinOp::Mul, unit, per_unit);
    let index = b.binary(BinOp::Add, base, first);
    let index = b.truncate(index, Type::I32);
    let buffer = step.l.place(&Operand::Word(WordArea::Buffer, Index::Dynamic(index)));
    let width = step.b().number(width_arg(width));
    match (from, other) {
        (false, WordRef::Constant(value)) => {
            let value = step.b().constant(Type::I32, i64::from(*value));
            step.b().call(Helper::Fill, vec![buffer, count, width, value]);
        }
        (true, _) | (false, WordRef::Word(..) | WordRef::WideCounter(_) | WordRef::Digits(..)) => {
            let device = step.l.place(&device);
            let (source, destination) = if from { (buffer, device) } else { (device, buffer) };
            step.b()
                .call(Helper::BlockMove, vec![source, destination, count, width]);
        }
    }
}
