//! Transfers: MOV, BMOV, FMOV.

use super::{Outcome, Step};
use crate::program::WordRef;
use ladder_runtime::place::MAX_BLOCK_UNITS;
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
