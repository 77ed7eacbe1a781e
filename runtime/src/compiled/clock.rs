//! The clock instructions of compiled code (TWR, TCMP, TZCP, TADD, TSUB,
//! HTOS, STOH, HOUR): the same rules as the interpreter's clock kernels,
//! written apart from them. Places are checked by the caller.

use crate::calendar::{full_year, CalendarTime};
use crate::device::Width;
use crate::image::ImageMut;
use crate::layout::Scalar;
use crate::place::Place;

const DAY: i64 = 86_400;

fn words<const N: usize>(mem: &ImageMut<'_>, place: Place) -> [i64; N] {
    let mut values = [0i64; N];
    for (unit, value) in (0..).zip(values.iter_mut()) {
        *value = i64::from(place.nth(unit, Width::Single).read(mem, Width::Single));
    }
    values
}

fn write_words(mem: &mut ImageMut<'_>, place: Place, values: &[i64]) {
    for (unit, &value) in (0..).zip(values) {
        place.nth(unit, Width::Single).write(mem, Width::Single, value);
    }
}

/// Seconds of the day, when hour 0-23, minute and second 0-59.
fn day_second([hour, minute, second]: [i64; 3]) -> Option<i64> {
    if (0..=23).contains(&hour) && (0..=59).contains(&minute) && (0..=59).contains(&second) {
        Some(hour * 3_600 + minute * 60 + second)
    } else {
        None
    }
}

fn time_of_day(seconds: i64) -> [i64; 3] {
    [seconds / 3_600, (seconds / 60) % 60, seconds % 60]
}

/// TWR: sets the clock from the 7 words at `source`; false when they are
/// out of range (nothing changed).
pub fn set_clock(mem: &mut ImageMut<'_>, source: Place) -> bool {
    let [year, month, day, hour, minute, second, weekday] = words::<7>(mem, source);
    let field = |v: i64| u32::try_from(v).ok();
    let Some(year) = full_year(year as i32) else {
        return false;
    };
    let (Some(month), Some(day), Some(hour), Some(minute), Some(second)) =
        (field(month), field(day), field(hour), field(minute), field(second))
    else {
        return false;
    };
    (0..=6).contains(&weekday) && mem.set_calendar(CalendarTime::at(year, month, day, hour, minute, second))
}

/// TCMP: the time `limit` against the 3 words at `data`; three bits to
/// `destination`. False when a time is out of range.
pub fn time_compare(mem: &mut ImageMut<'_>, limit: [i64; 3], data: Place, destination: Place) -> bool {
    let (Some(limit), Some(time)) = (day_second(limit), day_second(words(mem, data))) else {
        return false;
    };
    let bits = [limit > time, limit == time, limit < time].map(i64::from);
    write_words(mem, destination, &bits);
    true
}

/// TZCP: the time at `data` against the zone `low`..`high`.
pub fn time_zone(mem: &mut ImageMut<'_>, low: Place, high: Place, data: Place, destination: Place) -> bool {
    let (Some(low), Some(high), Some(time)) = (
        day_second(words(mem, low)),
        day_second(words(mem, high)),
        day_second(words(mem, data)),
    ) else {
        return false;
    };
    let high = high.max(low); // a reversed zone is the single time `low`
    let bits = [time < low, (low..=high).contains(&time), time > high].map(i64::from);
    write_words(mem, destination, &bits);
    true
}

/// `time_add` result: the times were in range.
pub const TIME_OK: i32 = 1;
/// `time_add` result: the result is 00:00:00.
pub const TIME_ZERO: i32 = 2;
/// `time_add` result: the sum passed 24 hours (TADD) or the difference
/// went below 0 (TSUB).
pub const TIME_WRAPPED: i32 = 4;

/// TADD (`subtract` false) or TSUB.
pub fn time_add(mem: &mut ImageMut<'_>, a: Place, b: Place, destination: Place, subtract: bool) -> i32 {
    let (Some(a), Some(b)) = (day_second(words(mem, a)), day_second(words(mem, b))) else {
        return 0;
    };
    let exact = if subtract { a - b } else { a + b };
    let wrapped = exact.rem_euclid(DAY);
    write_words(mem, destination, &time_of_day(wrapped));
    let beyond = if subtract { exact < 0 } else { exact >= DAY };
    TIME_OK | if wrapped == 0 { TIME_ZERO } else { 0 } | if beyond { TIME_WRAPPED } else { 0 }
}

/// HTOS: the seconds of hours, minutes, seconds at `source`, or -1 when out
/// of range or above `limit`.
pub fn time_to_seconds(mem: &ImageMut<'_>, source: Place, limit: i64) -> i64 {
    let [hour, minute, second] = words::<3>(mem, source);
    if hour < 0 || !(0..=59).contains(&minute) || !(0..=59).contains(&second) {
        return -1;
    }
    let seconds = hour * 3_600 + minute * 60 + second;
    if seconds > limit {
        -1
    } else {
        seconds
    }
}

/// STOH: `seconds` as hours, minutes, seconds; false out of range.
pub fn seconds_to_time(mem: &mut ImageMut<'_>, seconds: i64, destination: Place) -> bool {
    if !(0..=32_767 * 3_600 + 3_599).contains(&seconds) {
        return false;
    }
    write_words(mem, destination, &time_of_day(seconds));
    true
}

/// HOUR/DHOUR instance `instance`, executed with its rung ON: adds the
/// scan's reported time to the hours at `hours` (a pair when `wide`) and
/// the seconds in the word after them; the alarm bit at `alarm` turns ON
/// once the hours reach `limit`.
pub fn hour(mem: &mut ImageMut<'_>, instance: u32, limit: i64, hours: Place, alarm: Place, wide: bool) {
    let width = if wide { Width::Double } else { Width::Single };
    let seconds_place = hours.nth(width.words(), Width::Single);
    let max_hours = if wide { i64::from(i32::MAX) } else { i64::from(i16::MAX) };
    let elapsed = i64::from(mem.scalar(Scalar::ElapsedMs));
    let Some(mut state) = mem.instance(instance) else {
        return;
    };
    let ms = i64::from(state.a) + elapsed;
    state.a = (ms % 1_000) as i32;
    mem.set_instance(instance, state);
    let counted_hours = i64::from(hours.read(mem, width)).max(0);
    let counted_seconds = i64::from(seconds_place.read(mem, Width::Single)).clamp(0, 3_599);
    let total = (counted_hours * 3_600 + counted_seconds + ms / 1_000).min(max_hours * 3_600 + 3_599);
    hours.write(mem, width, total / 3_600);
    seconds_place.write(mem, Width::Single, total % 3_600);
    alarm.write(mem, Width::Single, i64::from(total / 3_600 >= limit));
}
