//! Transfers: MOV, BMOV, FMOV.

use super::Step;
use crate::ir::{Type, Value};
use crate::isa::CompareOp;
use crate::lower::operand::Units;
use crate::program::WordRef;
use ladder_runtime::helpers::{self, Helper};
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

/// BMOV S D n calls the runtime's block move, which reads every value
/// before it writes any.
pub fn block_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = block_count(step, n);
    let width = step.width;
    let source = step.resolve(s, width, Units::Dynamic(n), true);
    let destination = step.resolve(d, width, Units::Dynamic(n), false);
    step.commit();
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    let width = step.b().number(helpers::width_arg(width));
    step.b().call(Helper::BlockMove, vec![source, destination, n, width]);
}

/// FMOV S D n: S read here, written into n units by the runtime.
pub fn fill_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = block_count(step, n);
    let width = step.width;
    let source = step.source(s);
    let destination = step.resolve(d, width, Units::Dynamic(n), false);
    step.commit();
    let value = step.read(&source);
    let value = step.b().truncate(value, Type::I32);
    let destination = step.l.place(&destination);
    let width = step.b().number(helpers::width_arg(width));
    step.b().call(Helper::Fill, vec![destination, n, width, value]);
}
