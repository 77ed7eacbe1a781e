//! Logic and bits: WAND, WOR, WXOR, CML, BON, SUM, ALT.

use super::{Outcome, Step};
use crate::access::{read_place, write_place};
use ladder_front::program::BitRef;
use ladder_runtime::{OperationError, Width};

pub fn wand([a, b]: [i64; 2], _: Width) -> Result<i64, OperationError> {
    Ok(a & b)
}

pub fn wor([a, b]: [i64; 2], _: Width) -> Result<i64, OperationError> {
    Ok(a | b)
}

pub fn wxor([a, b]: [i64; 2], _: Width) -> Result<i64, OperationError> {
    Ok(a ^ b)
}

pub fn cml([s]: [i64; 1], _: Width) -> Result<i64, OperationError> {
    Ok(!s)
}

/// Bit N of S; N outside the width's bits (0-15, 0-31) is 4084H.
pub fn bon([s, n]: [i64; 2], width: Width) -> Result<bool, OperationError> {
    if !(0..i64::from(width.bits())).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    Ok((s >> n) & 1 != 0)
}

/// The number of ON bits of S at the width, and the zero flag (SM153: S
/// has no ON bit).
pub fn sum([s]: [i64; 1], width: Width) -> Result<(i64, [bool; 1]), OperationError> {
    let bits = s as u64 & (u64::MAX >> (64 - width.bits()));
    Ok((i64::from(bits.count_ones()), [bits == 0]))
}

/// ALT D: bit D turns to its opposite.
pub fn alternate(step: &mut Step, d: &BitRef) -> Outcome {
    let place = step.bits(d, 1, true);
    step.commit()?;
    if let Some(place) = place {
        let on = read_place(step.mem, place);
        write_place(step.mem, place, !on);
    }
    Ok(())
}
