//! Transfers: MOV, BMOV, FMOV.

use super::Step;
use crate::ir::{Inst, Type, Value};
use crate::isa::CompareOp;
use crate::lower::operand::Units;
use crate::program::WordRef;
use ladder_runtime::place::MAX_BLOCK_UNITS;
use ladder_runtime::{OperationError, Width};

pub fn mov(_: &mut Step, [s]: [Value; 1]) -> Value {
    s
}

/// The unit count of BMOV/FMOV as an I32: 1..512, else 4084H.
fn block_count(step: &mut Step, n: &WordRef) -> Value {
    let n = step.count(n);
    step.commit();
    let n = step.read_at(&n, Width::Single);
    let n = step.b().truncate(n, Type::I32);
    let one = step.b().constant(Type::I32, 1);
    let most = step.b().constant(Type::I32, i64::from(MAX_BLOCK_UNITS));
    let at_least_one = step.b().compare(CompareOp::Ge, n, one);
    let at_most = step.b().compare(CompareOp::Le, n, most);
    let valid = step.b().and(at_least_one, at_most);
    step.require(valid, OperationError::DataOutOfRange);
    n
}

/// BMOV/FMOV call the runtime's block move, which reads every value before
/// it writes any.
fn emit_block_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef, fill: bool) {
    let n = block_count(step, n);
    let width = step.width;
    let source_units = if fill { Units::Checked(1) } else { Units::Dynamic(n) };
    let source = step.resolve(s, width, source_units, true);
    let destination = step.resolve(d, width, Units::Dynamic(n), false);
    step.commit();
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    step.b().effect(Inst::BlockMove {
        source,
        destination,
        count: n,
        width,
        fill,
    });
}

pub fn block_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    emit_block_move(step, s, d, n, false);
}

pub fn fill_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    emit_block_move(step, s, d, n, true);
}
