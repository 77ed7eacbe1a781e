//! Transfers: MOV, BMOV, FMOV, PRUN, XCH.

use super::Step;
use crate::lower::operand::Units;
use crate::CompareOp;
use crate::{Type, Value};
use ladder_front::program::{BitRef, DigitGroup, WordRef};
use ladder_runtime::device::MAX_BLOCK_UNITS;
use ladder_runtime::helpers::{self, Helper};
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

/// Where bit `k` of a digit group lies from its start: X and Y count in
/// octal already; on M the octal digits of k read as decimal (8 is M10).
fn octal_position(group: &DigitGroup, k: u32) -> u32 {
    if group.area.is_octal() {
        k
    } else {
        (k / 64) * 100 + ((k / 8) % 8) * 10 + k % 8
    }
}

/// PRUN S D, unrolled: bit k of S to bit k of D with octal numbering on M;
/// D's group decides the bits, those beyond S's own are 0.
pub fn octal_move(step: &mut Step, s: &DigitGroup, d: &DigitGroup) {
    let (s_bits, d_bits) = (4 * u32::from(s.digits), 4 * u32::from(d.digits));
    let s_extent = octal_position(s, s_bits - 1) + 1;
    let d_extent = octal_position(d, d_bits - 1) + 1;
    let source = step.bits(&BitRef::Device(s.area, s.address), Units::Checked(s_extent), true);
    let destination = step.bits(&BitRef::Device(d.area, d.address), Units::Checked(d_extent), false);
    step.commit();
    // Every source bit is read before any destination bit is written (as
    // BMOV, SFTR and BTOW do), so overlapping groups move as a whole.
    let values: Vec<Value> = (0..d_bits)
        .map(|k| {
            if k < s_bits {
                let unit = step.l.nth(&source, octal_position(s, k), Width::Single);
                step.read_at(&unit, Width::Single)
            } else {
                step.b().constant(Type::I64, 0)
            }
        })
        .collect();
    for (k, value) in (0..d_bits).zip(values) {
        let unit = step.l.nth(&destination, octal_position(d, k), Width::Single);
        step.l.write(&unit, Width::Single, value);
    }
}

/// XCH D1 D2: both read, then D1 = old D2 and D2 = old D1.
pub fn exchange(step: &mut Step, d1: &WordRef, d2: &WordRef) {
    let width = step.width;
    let first = step.resolve(d1, width, Units::Checked(1), true);
    let second = step.resolve(d2, width, Units::Checked(1), true);
    step.commit();
    let (a, b) = (step.read(&first), step.read(&second));
    step.write(&first, b);
    step.write(&second, a);
}
