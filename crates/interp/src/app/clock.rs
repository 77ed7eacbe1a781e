//! The clock: TRD, TWR, TCMP, TZCP, TADD, TSUB, HTOS, STOH, HOUR.
//!
//! A time of day is three words: hour 0-23, minute 0-59, second 0-59;
//! anything else is 4084H. The clock itself (D8013-D8019, advancing with
//! the reported time) is the runtime's, shared by every engine, as timers
//! are; these kernels read and set it.

use super::{Outcome, Step};
use ladder_front::program::{BitRef, WordRef};
use ladder_runtime::calendar::{full_year, CalendarTime, D_CLOCK_FIRST};
use ladder_runtime::special::SpecialBit;
use ladder_runtime::{OperationError, Place, Width};

const DAY: i64 = 86_400;

/// The second of the day of hour, minute, second; `None` out of range.
fn day_second([hour, minute, second]: [i64; 3]) -> Option<i64> {
    ((0..24).contains(&hour) && (0..60).contains(&minute) && (0..60).contains(&second))
        .then_some(hour * 3_600 + minute * 60 + second)
}

fn hms(seconds: i64) -> [i64; 3] {
    [seconds / 3_600, seconds % 3_600 / 60, seconds % 60]
}

impl Step<'_> {
    /// The first of `units` words from `word`.
    fn words(&mut self, word: &WordRef, units: u32, read: bool) -> Option<Place> {
        self.resolve(word, Width::Single, units, read)
    }

    fn three(&self, place: Option<Place>) -> [i64; 3] {
        let Some(place) = place else { return [0; 3] };
        [0, 1, 2].map(|unit| self.read_at(place.nth(unit, Width::Single), Width::Single))
    }

    fn write_words(&mut self, place: Option<Place>, values: &[i64]) {
        if let Some(place) = place {
            for (unit, &value) in (0..).zip(values) {
                self.write_at(place.nth(unit, Width::Single), Width::Single, value);
            }
        }
    }

    fn write_bits(&mut self, place: Option<Place>, values: [bool; 3]) {
        self.write_words(place, &values.map(i64::from));
    }
}

/// TRD D: D..D+6 = year, month, day, hour, minute, second, day of week.
pub fn read(step: &mut Step, d: &WordRef) -> Outcome {
    let d = step.words(d, 7, false);
    step.commit()?;
    let register = |offset: u32| i64::from(step.mem.d[(D_CLOCK_FIRST + offset) as usize]);
    let values = [5, 4, 3, 2, 1, 0, 6].map(register);
    step.write_words(d, &values);
    Ok(())
}

/// TWR S: the clock takes S..S+6 (year 0-99 or 1980-2079, month, day,
/// hour, minute, second, day of week 0-6); out of range is 4084H.
pub fn write(step: &mut Step, s: &WordRef) -> Outcome {
    let s = step.words(s, 7, true);
    step.commit()?;
    let Some(s) = s else { return Ok(()) };
    let value = |unit: u32| step.read_at(s.nth(unit, Width::Single), Width::Single);
    let field = |unit: u32| u32::try_from(value(unit)).ok();
    let time = match (
        full_year(value(0) as i32),
        field(1),
        field(2),
        field(3),
        field(4),
        field(5),
    ) {
        (Some(year), Some(month), Some(day), Some(hour), Some(minute), Some(second)) => {
            CalendarTime::at(year, month, day, hour, minute, second)
        }
        _ => return Err(OperationError::DataOutOfRange),
    };
    if !(0..=6).contains(&value(6)) || !step.mem.set_calendar(time) {
        return Err(OperationError::DataOutOfRange);
    }
    Ok(())
}

/// TCMP S1 S2 S3 S D: D, D+1, D+2 = the time S1:S2:S3 is later than, the
/// same as, earlier than the time S..S+2.
pub fn compare(step: &mut Step, [s1, s2, s3]: [&WordRef; 3], s: &WordRef, d: &BitRef) -> Outcome {
    let limits = [s1, s2, s3].map(|w| step.count(w));
    let s = step.words(s, 3, true);
    let d = step.bits(d, 3, false);
    step.commit()?;
    let limit = limits.map(|p| p.map_or(0, |p| step.read_at(p, Width::Single)));
    let (Some(limit), Some(time)) = (day_second(limit), day_second(step.three(s))) else {
        return Err(OperationError::DataOutOfRange);
    };
    step.write_bits(d, [limit > time, limit == time, limit < time]);
    Ok(())
}

/// TZCP S1 S2 S D: D, D+1, D+2 = the time S is before S1, from S1 to S2,
/// after S2.
pub fn zone(step: &mut Step, s1: &WordRef, s2: &WordRef, s: &WordRef, d: &BitRef) -> Outcome {
    let places = [s1, s2, s].map(|w| step.words(w, 3, true));
    let d = step.bits(d, 3, false);
    step.commit()?;
    let [Some(low), Some(high), Some(time)] = places.map(|p| day_second(step.three(p))) else {
        return Err(OperationError::DataOutOfRange);
    };
    // A reversed zone counts as the single time S1, as in ZCP.
    let high = high.max(low);
    step.write_bits(d, [time < low, low <= time && time <= high, time > high]);
    Ok(())
}

/// TADD (`subtract` false) / TSUB S1 S2 D: the time of day S1 ± S2 wrapped
/// to 24 hours; M8020 when it is 00:00:00, M8022 (TADD) when the sum passed
/// 24 hours, M8021 (TSUB) when the difference went below 0.
pub fn add(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &WordRef, subtract: bool, flags: &[SpecialBit]) -> Outcome {
    let sources = [s1, s2].map(|w| step.words(w, 3, true));
    let d = step.words(d, 3, false);
    step.commit()?;
    let [Some(a), Some(b)] = sources.map(|p| day_second(step.three(p))) else {
        return Err(OperationError::DataOutOfRange);
    };
    let exact = if subtract { a - b } else { a + b };
    let wrapped = exact.rem_euclid(DAY);
    step.write_words(d, &hms(wrapped));
    let beyond = if subtract { exact < 0 } else { exact >= DAY };
    step.write_flags(flags, &[wrapped == 0, beyond]);
    Ok(())
}

/// HTOS/DHTOS S D: hours S, minutes S+1 (0-59), seconds S+2 (0-59) as
/// seconds; hours 0-32767, and the result must fit the width.
pub fn to_seconds(step: &mut Step, s: &WordRef, d: &WordRef) -> Outcome {
    let s = step.words(s, 3, true);
    let d = step.destination(d);
    step.commit()?;
    let [hour, minute, second] = step.three(s);
    let limit = match step.width {
        Width::Single => i64::from(i16::MAX),
        Width::Double => i64::from(i32::MAX),
    };
    let seconds = hour * 3_600 + minute * 60 + second;
    if hour < 0 || !(0..60).contains(&minute) || !(0..60).contains(&second) || seconds > limit {
        return Err(OperationError::DataOutOfRange);
    }
    if let Some(d) = d {
        step.write(d, seconds);
    }
    Ok(())
}

/// STOH/DSTOH S D: seconds S (0 up to 32767:59:59) as hours, minutes,
/// seconds in D..D+2.
pub fn to_time(step: &mut Step, s: &WordRef, d: &WordRef) -> Outcome {
    let s = step.source(s);
    let d = step.words(d, 3, false);
    step.commit()?;
    let seconds = s.map_or(0, |p| step.read(p));
    if !(0..=32_767 * 3_600 + 3_599).contains(&seconds) {
        return Err(OperationError::DataOutOfRange);
    }
    step.write_words(d, &hms(seconds));
    Ok(())
}

/// HOUR/DHOUR S D1 D2: while the rung is ON, the reported time adds up in
/// hours D1 (DHOUR: the pair D1, D1+1) and seconds below an hour in the
/// next word (the milliseconds below a second kept in the instance state);
/// D2 turns ON once the hours reach S. It stops at the largest hour with
/// 3599 seconds.
pub fn hour(step: &mut Step, instance: u32, s: &WordRef, d1: &WordRef, d2: &BitRef) -> Outcome {
    let wide = step.width == Width::Double;
    let s = step.source(s);
    let hours_words = if wide { 2 } else { 1 };
    let d1 = step.words(d1, hours_words + 1, false);
    let d2 = step.bits(d2, 1, false);
    step.commit()?;
    let (Some(d1), Some(d2)) = (d1, d2) else { return Ok(()) };
    let limit = s.map_or(0, |p| step.read(p));
    let seconds_place = d1.nth(hours_words, Width::Single);
    let hours = step.read_at(d1, step.width);
    let seconds = step.read_at(seconds_place, Width::Single);
    let max_hours = if wide { i64::from(i32::MAX) } else { i64::from(i16::MAX) };
    let elapsed = i64::from(step.mem.elapsed_ms);
    let Some(state) = step.mem.instance.get_mut(instance as usize) else {
        return Ok(());
    };
    let ms = i64::from(state.a) + elapsed;
    state.a = (ms % 1_000) as i32;
    let total = (hours.max(0) * 3_600 + seconds.clamp(0, 3_599) + ms / 1_000).min(max_hours * 3_600 + 3_599);
    step.write_at(d1, step.width, total / 3_600);
    step.write_at(seconds_place, Width::Single, total % 3_600);
    step.write_at(d2, Width::Single, i64::from(total / 3_600 >= limit));
    Ok(())
}
