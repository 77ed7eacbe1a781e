//! Transfers: MOV, BMOV, FMOV, PRUN, XCH.

use super::{Outcome, Step};
use ladder_front::program::{BitRef, DigitGroup, WordRef};
use ladder_runtime::device::MAX_BLOCK_UNITS;
use ladder_runtime::{OperationError, Width};

pub fn mov([s]: [i64; 1], _: Width) -> Result<i64, OperationError> {
    Ok(s)
}

/// The unit count of BMOV/FMOV: 1..512, else 4084H.
fn block_count(step: &mut Step, n: &WordRef) -> Result<u32, OperationError> {
    let place = step.count(n);
    step.commit()?;
    let n = place.map_or(0, |p| step.read_at(p, Width::Single));
    if !(1..=i64::from(MAX_BLOCK_UNITS)).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    Ok(n as u32)
}

/// BMOV S D n: every value is read before any is written, so overlapping
/// blocks move as a whole.
pub fn block_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = block_count(step, n)?;
    let width = step.width;
    let source = step.resolve(s, width, n, true);
    let destination = step.resolve(d, width, n, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let values: Vec<i64> = (0..n).map(|i| step.read(source.nth(i, width))).collect();
    for (i, value) in (0..n).zip(values) {
        step.write(destination.nth(i, width), value);
    }
    Ok(())
}

/// FMOV S D n: S into each of n units from D.
pub fn fill_move(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = block_count(step, n)?;
    let width = step.width;
    let source = step.source(s);
    let destination = step.resolve(d, width, n, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let value = step.read(source);
    for i in 0..n {
        step.write(destination.nth(i, width), value);
    }
    Ok(())
}

/// The device number of bit `k` of a digit group: X and Y count in octal
/// already; on M the octal digits of k are read as decimal (k = 8 is M10).
fn octal_position(group: &DigitGroup, k: u32) -> u32 {
    if group.area.is_octal() {
        k
    } else {
        (k / 64) * 100 + ((k / 8) % 8) * 10 + k % 8
    }
}

/// PRUN S D: bit k of the group S to bit k of the group D, numbering the M
/// side in octal steps (K4X0 to K4M0 fills M0-M7 and M10-M17, not M8, M9).
/// D's group decides how many bits; beyond S's own bits they are 0.
pub fn octal_move(step: &mut Step, s: &DigitGroup, d: &DigitGroup) -> Outcome {
    let (s_bits, d_bits) = (4 * u32::from(s.digits), 4 * u32::from(d.digits));
    let s_extent = octal_position(s, s_bits - 1) + 1;
    let d_extent = octal_position(d, d_bits - 1) + 1;
    let source = step.bits(&BitRef::Device(s.area, s.address), s_extent, true);
    let destination = step.bits(&BitRef::Device(d.area, d.address), d_extent, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let values: Vec<i64> = (0..d_bits)
        .map(|k| {
            if k < s_bits {
                step.read_at(source.nth(octal_position(s, k), Width::Single), Width::Single)
            } else {
                0
            }
        })
        .collect();
    for (k, value) in (0..).zip(values) {
        step.write(destination.nth(octal_position(d, k), Width::Single), value);
    }
    Ok(())
}

/// XCH D1 D2: both read, then D1 = old D2 and D2 = old D1 (in that order,
/// so of overlapping pairs the shared word ends as D2's new value).
pub fn exchange(step: &mut Step, d1: &WordRef, d2: &WordRef) -> Outcome {
    let first = step.resolve(d1, step.width, 1, true);
    let second = step.resolve(d2, step.width, 1, true);
    step.commit()?;
    if let (Some(first), Some(second)) = (first, second) {
        let (a, b) = (step.read(first), step.read(second));
        step.write(first, b);
        step.write(second, a);
    }
    Ok(())
}
