//! The clock in the lowering: TRD reads D8013-D8019 as plain loads; the
//! others resolve and check their operands here and call the runtime's
//! helpers, which return whether the times were in range (4084H if not).

use super::Step;
use crate::lower::operand::Units;
use crate::CompareOp;
use crate::{BinOp, Cell, Index, Type, Value};
use ladder_front::program::{BitRef, WordRef};
use ladder_runtime::calendar::D_CLOCK_FIRST;
use ladder_runtime::compiled::clock::{TIME_OK, TIME_WRAPPED, TIME_ZERO};
use ladder_runtime::helpers::Helper;
use ladder_runtime::special::SpecialBit;
use ladder_runtime::{OperationError, Width, WordArea};

impl Step<'_, '_> {
    fn words(&mut self, word: &WordRef, units: u32, read: bool) -> crate::lower::operand::Operand {
        let units = self.run_of(units);
        self.resolve(word, Width::Single, units, read)
    }
}

/// TRD D: year, month, day, hour, minute, second, day of week. The seven
/// clock words are read before any is written: D may overlap D8013-D8019
/// (`TRD D8011` writes D8013 before it would read D8016), and the clock is
/// read as one reading, as the interpreter does.
pub fn read(step: &mut Step, d: &WordRef) {
    let d = step.words(d, 7, false);
    step.commit();
    let values: Vec<Value> = [5, 4, 3, 2, 1, 0, 6]
        .into_iter()
        .map(|offset| {
            let value = step.b().load(Cell::Word {
                area: WordArea::D,
                index: Index::Fixed(D_CLOCK_FIRST + offset),
            });
            step.b().extend(value, Type::I64, true)
        })
        .collect();
    for (unit, value) in (0..).zip(values) {
        let target = step.l.nth(&d, unit, Width::Single);
        step.l.write(&target, Width::Single, value);
    }
}

/// TWR S.
pub fn write(step: &mut Step, s: &WordRef) {
    let s = step.words(s, 7, true);
    step.commit();
    let source = step.l.place(&s);
    let answer = step.helper(Helper::SetClock, vec![source]);
    step.require_ok(answer);
}

/// TCMP S1 S2 S3 S D.
pub fn compare(step: &mut Step, [s1, s2, s3]: [&WordRef; 3], s: &WordRef, d: &BitRef) {
    let limits = [s1, s2, s3].map(|w| step.count(w));
    let s = step.words(s, 3, true);
    let d = step.bits(d, Units::Checked(3), false);
    step.commit();
    let mut args: Vec<Value> = limits
        .iter()
        .map(|limit| {
            let value = step.read_at(limit, Width::Single);
            step.b().truncate(value, Type::I32)
        })
        .collect();
    args.push(step.l.place(&s));
    args.push(step.l.place(&d));
    let answer = step.helper(Helper::TimeCompare, args);
    step.require_ok(answer);
}

/// TZCP S1 S2 S D.
pub fn zone(step: &mut Step, s1: &WordRef, s2: &WordRef, s: &WordRef, d: &BitRef) {
    let places = [s1, s2, s].map(|w| step.words(w, 3, true));
    let d = step.bits(d, Units::Checked(3), false);
    step.commit();
    let mut args: Vec<Value> = places.iter().map(|p| step.l.place(p)).collect();
    args.push(step.l.place(&d));
    let answer = step.helper(Helper::TimeZone, args);
    step.require_ok(answer);
}

/// TADD / TSUB S1 S2 D, with the zero flag and carry (TADD) or borrow.
pub fn add(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &WordRef, subtract: bool, flags: &[SpecialBit]) {
    let sources = [s1, s2].map(|w| step.words(w, 3, true));
    let d = step.words(d, 3, false);
    step.commit();
    let mut args: Vec<Value> = sources.iter().map(|p| step.l.place(p)).collect();
    args.push(step.l.place(&d));
    args.push(step.b().number(u32::from(subtract)));
    let answer = step.helper(Helper::TimeAdd, args);
    let b = step.b();
    let mask = |b: &mut crate::Builder, bit: i32| {
        let bit = b.constant(Type::I32, i64::from(bit));
        let set = b.binary(BinOp::And, answer, bit);
        let zero = b.constant(Type::I32, 0);
        b.compare(CompareOp::Ne, set, zero)
    };
    let ok = mask(b, TIME_OK);
    step.require(ok, OperationError::DataOutOfRange);
    let b = step.b();
    let on = [mask(b, TIME_ZERO), mask(b, TIME_WRAPPED)];
    for (flag, on) in flags.iter().zip(on) {
        step.b().store_bit(flag.area, Index::Fixed(flag.number), on);
    }
}

/// HTOS / DHTOS S D.
pub fn to_seconds(step: &mut Step, s: &WordRef, d: &WordRef) {
    let s = step.words(s, 3, true);
    let d = step.destination(d);
    step.commit();
    let limit = match step.width {
        Width::Single => i64::from(i16::MAX),
        Width::Double => i64::from(i32::MAX),
    };
    let source = step.l.place(&s);
    let limit = step.b().constant(Type::I32, limit);
    let seconds = step.helper(Helper::TimeToSeconds, vec![source, limit]);
    let zero = step.b().constant(Type::I32, 0);
    let valid = step.b().compare(CompareOp::Ge, seconds, zero);
    step.require(valid, OperationError::DataOutOfRange);
    let wide = step.b().extend(seconds, Type::I64, true);
    step.write(&d, wide);
}

/// STOH / DSTOH S D.
pub fn to_time(step: &mut Step, s: &WordRef, d: &WordRef) {
    let s = step.source(s);
    let d = step.words(d, 3, false);
    step.commit();
    let seconds = step.read(&s);
    step.require_within(seconds, 0, 32_767 * 3_600 + 3_599);
    let seconds = step.b().truncate(seconds, Type::I32);
    let destination = step.l.place(&d);
    let answer = step.helper(Helper::SecondsToTime, vec![seconds, destination]);
    step.require_ok(answer);
}

/// HOUR / DHOUR S D1 D2 (instance `instance`), run while its rung is ON.
pub fn hour(step: &mut Step, instance: u32, s: &WordRef, d1: &WordRef, d2: &BitRef) {
    let wide = step.width == Width::Double;
    let s = step.source(s);
    let d1 = step.words(d1, if wide { 3 } else { 2 }, false);
    let d2 = step.bits(d2, Units::Checked(1), false);
    step.commit();
    let limit = step.read(&s);
    let limit = step.b().truncate(limit, Type::I32);
    let instance = step.b().number(instance);
    let (hours, alarm) = (step.l.place(&d1), step.l.place(&d2));
    let wide = step.b().number(u32::from(wide));
    step.b().call(Helper::Hour, vec![instance, limit, hours, alarm, wide]);
}
