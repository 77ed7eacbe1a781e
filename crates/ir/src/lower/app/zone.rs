//! Zones: ZRST, ZSET, through the runtime's zone helper.

use super::Step;
use crate::{BinOp, Type, Value};
use ladder_front::program::{BitRef, RangeEnd};
use ladder_runtime::compiled::Zone;
use ladder_runtime::device::{COUNTER_COUNT, TIMER_COUNT};
use ladder_runtime::helpers::Helper;
use ladder_runtime::OperationError;

/// One end: its zone and its number as an I32, noting an in-range test
/// (both ends are addresses the instruction reads).
fn end(step: &mut Step, end: &RangeEnd) -> (Zone, Value) {
    let (zone, address, len, scale, bit) = match *end {
        RangeEnd::Bit(BitRef::Device(area, address)) => (Zone::Bits(area), address, area.count(), 1, 0),
        RangeEnd::Bit(BitRef::WordBit(area, address, bit)) => {
            (Zone::WordBits(area), address, area.count(), 16, u32::from(bit))
        }
        RangeEnd::Word(area, address) => (Zone::Words(area), address, area.count(), 1, 0),
        RangeEnd::Timer(address) => (Zone::Timers, address, TIMER_COUNT, 1, 0),
        RangeEnd::Counter(address) => (Zone::Counters, address, COUNTER_COUNT, 1, 0),
    };
    let index = step.address_number(address, 0, len);
    let b = step.b();
    let scale = b.constant(Type::I32, i64::from(scale));
    let scaled = b.binary(BinOp::Mul, index, scale);
    let bit = b.constant(Type::I32, i64::from(bit));
    (zone, b.binary(BinOp::Add, scaled, bit))
}

fn zone(step: &mut Step, d1: &RangeEnd, d2: &RangeEnd, on: bool) {
    let (zone, first) = end(step, d1);
    let (other, last) = end(step, d2);
    step.commit();
    // The kinds of both ends are known here: different ones always record
    // 4084H, and so does a ZSET of something other than bits (the checker
    // refuses those, so that is 4087H never reached).
    let bits = matches!(zone, Zone::Bits(_) | Zone::WordBits(_));
    let error = if zone != other {
        Some(OperationError::DataOutOfRange)
    } else if on && !bits {
        Some(OperationError::UnsupportedDevice)
    } else {
        None
    };
    if let Some(error) = error {
        let fail = step.b().bit(false);
        step.require(fail, error);
        return;
    }
    let b = step.b();
    let zone = b.number(zone.code());
    let on = b.number(u32::from(on));
    b.call(Helper::Zone, vec![zone, first, last, on]);
}

pub fn reset(step: &mut Step, d1: &RangeEnd, d2: &RangeEnd) {
    zone(step, d1, d2, false);
}

pub fn set(step: &mut Step, d1: &RangeEnd, d2: &RangeEnd) {
    zone(step, d1, d2, true);
}
