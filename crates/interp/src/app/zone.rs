//! Zones: ZRST, ZSET.

use super::{Outcome, Step};
use crate::access::effective_index;
use ladder_front::program::{Address, BitRef, RangeEnd};
use ladder_runtime::device::{COUNTER_COUNT, TIMER_COUNT};
use ladder_runtime::{BitArea, OperationError, Place, Width, WordArea};

/// What a range covers: both ends must name the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Bits(BitArea),
    /// Bits of words, numbered through the area (16·word + bit).
    WordBits(WordArea),
    Words(WordArea),
    Timers,
    Counters,
}

/// One end: its kind and number, or None when it is outside its area.
fn end(step: &Step, end: &RangeEnd) -> Option<(Kind, u32)> {
    let number = |address: Address, len: u32| {
        let index = effective_index(step.mem, address);
        (0..i64::from(len)).contains(&index).then_some(index as u32)
    };
    match *end {
        RangeEnd::Bit(BitRef::Device(area, address)) => Some((Kind::Bits(area), number(address, area.count())?)),
        RangeEnd::Bit(BitRef::WordBit(area, address, bit)) => Some((
            Kind::WordBits(area),
            16 * number(address, area.count())? + u32::from(bit),
        )),
        RangeEnd::Word(area, address) => Some((Kind::Words(area), number(address, area.count())?)),
        RangeEnd::Timer(address) => Some((Kind::Timers, number(address, TIMER_COUNT)?)),
        RangeEnd::Counter(address) => Some((Kind::Counters, number(address, COUNTER_COUNT)?)),
    }
}

/// The kind and the numbers from D1 to D2 (D1 alone when D2 is below it).
/// Both ends are addresses the instruction reads: outside their area is
/// 4085H; ends of different kinds are 4084H.
fn range(step: &Step, d1: &RangeEnd, d2: &RangeEnd) -> Result<(Kind, u32, u32), OperationError> {
    let (Some((kind, first)), Some((other, last))) = (end(step, d1), end(step, d2)) else {
        return Err(OperationError::ReadOutOfRange);
    };
    if kind != other {
        return Err(OperationError::DataOutOfRange);
    }
    Ok((kind, first, last.max(first)))
}

/// ZRST D1 D2: bits OFF, words 0, timers and counters reset.
pub fn reset(step: &mut Step, d1: &RangeEnd, d2: &RangeEnd) -> Outcome {
    let (kind, first, last) = range(step, d1, d2)?;
    for number in first..=last {
        match kind {
            Kind::Bits(area) => Place::Bit(area, number).write(step.mem, Width::Single, 0),
            Kind::WordBits(area) => Place::WordBit(area, number).write(step.mem, Width::Single, 0),
            Kind::Words(area) => Place::Word(area, number).write(step.mem, Width::Single, 0),
            Kind::Timers => step.mem.reset_timer(number),
            Kind::Counters => step.mem.reset_counter(number),
        }
    }
    Ok(())
}

/// ZSET D1 D2: every bit ON. Its ends are bits (the checker refuses other
/// devices); anything else would be 4087H.
pub fn set(step: &mut Step, d1: &RangeEnd, d2: &RangeEnd) -> Outcome {
    let (kind, first, last) = range(step, d1, d2)?;
    for number in first..=last {
        let place = match kind {
            Kind::Bits(area) => Place::Bit(area, number),
            Kind::WordBits(area) => Place::WordBit(area, number),
            Kind::Words(_) | Kind::Timers | Kind::Counters => return Err(OperationError::UnsupportedDevice),
        };
        place.write(step.mem, Width::Single, 1);
    }
    Ok(())
}
