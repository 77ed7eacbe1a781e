//! Rotation and shift: ROR, ROL, SFTR, SFTL.

use super::{Outcome, Step};
use crate::access::{read_place, write_place};
use ladder_front::program::{BitRef, WordRef};
use ladder_runtime::device::MAX_SHIFT_BITS;
use ladder_runtime::special::CARRY_FLAG;
use ladder_runtime::{OperationError, Width};

/// ROR/ROL D n: n is read first (0 to the width's bits, else 4084H); M8022
/// takes the last bit rotated out (OFF for n = 0).
pub fn rotate(step: &mut Step, d: &WordRef, n: &WordRef, right: bool) -> Outcome {
    let n = step.count_value(n)?;
    let bits = step.width.bits();
    if !(0..=i64::from(bits)).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let place = step.resolve(d, step.width, 1, true);
    step.commit()?;
    let Some(place) = place else {
        return Ok(());
    };
    let n = n as u32;
    let mask = u64::MAX >> (64 - bits);
    let value = step.read(place) as u64 & mask;
    // Rotating by n is rotating left by bits - n the other way round.
    let left_by = if right { (bits - n) % bits } else { n % bits };
    let rotated = ((value << left_by) | (value >> ((bits - left_by) % bits))) & mask;
    let carry = match (n, right) {
        (0, _) => false,
        (_, true) => rotated >> (bits - 1) & 1 != 0,
        (_, false) => rotated & 1 != 0,
    };
    step.write(place, rotated as i64);
    step.mem.set_bit(CARRY_FLAG.area, CARRY_FLAG.number, carry);
    Ok(())
}

/// SFTR/SFTL S D n1 n2: the counts first (1 <= n2 <= n1 <= 1024, else
/// 4084H), then the n2 bits from S and the n1 bits from D.
pub fn shift_bits(step: &mut Step, s: &BitRef, d: &BitRef, n1: &WordRef, n2: &WordRef, left: bool) -> Outcome {
    let n1 = step.count_value(n1)?;
    let n2 = step.count_value(n2)?;
    if !(1 <= n2 && n2 <= n1 && n1 <= i64::from(MAX_SHIFT_BITS)) {
        return Err(OperationError::DataOutOfRange);
    }
    let (n1, n2) = (n1 as u32, n2 as u32);
    let source = step.bits(s, n2, true);
    let destination = step.bits(d, n1, true);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let read = |step: &Step, place: ladder_runtime::Place, k: u32| read_place(step.mem, place.nth(k, Width::Single));
    let incoming: Vec<bool> = (0..n2).map(|k| read(step, source, k)).collect();
    let before: Vec<bool> = (0..n1).map(|k| read(step, destination, k)).collect();
    for k in 0..n1 {
        let on = if left {
            if k < n2 {
                incoming[k as usize]
            } else {
                before[(k - n2) as usize]
            }
        } else if k < n1 - n2 {
            before[(k + n2) as usize]
        } else {
            incoming[(k - (n1 - n2)) as usize]
        };
        write_place(step.mem, destination.nth(k, Width::Single), on);
    }
    Ok(())
}
