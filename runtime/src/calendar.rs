//! The calendar clock (docs/language.md, "Machine programs"): D8013-D8019 hold
//! the seconds, minutes, hours, day, month, year and day of the week of a
//! clock that a host sets (`ladder_set_clock`; scenarios: `clock`) and that
//! advances by the elapsed time reported to each scan, so a test repeats.
//! A fresh image's clock reads 1980-01-01 00:00:00, a Tuesday.
//!
//! D8018 shows the year's last two digits (FX3U's default); a program that
//! writes 2000 to D8018 switches it to four digits, as on an FX3U.
//!
//! The clock relays: M8015 ON stops the clock (the program may then write
//! D8013-D8019), and when it turns OFF the clock takes those registers (an
//! impossible time leaves it as it was and turns M8019 ON); M8016 ON
//! freezes D8013-D8019 while the clock runs on; M8017 turning ON rounds to
//! the nearest minute (30 s and more to the next); M8018 (clock present) is
//! always ON.
//!
//! Also here: the scan-time registers D8010-D8012, whose "scan time" is
//! the elapsed time reported to the next scan.

use crate::image::{Image, ImageMut};
use crate::layout::{Array, Scalar};
#[cfg(test)]
use crate::memory::Memory;

/// D8010: the latest scan's time, in 0.1 ms.
pub const D_SCAN_TIME: u32 = 8010;
/// D8011: the shortest scan time, in 0.1 ms.
pub const D_SCAN_TIME_MIN: u32 = 8011;
/// D8012: the longest scan time, in 0.1 ms.
pub const D_SCAN_TIME_MAX: u32 = 8012;
/// D8013: the first of the clock registers (seconds); D8019 the day of the week.
pub const D_CLOCK_FIRST: u32 = 8013;

/// The first year the clock shows.
pub const FIRST_YEAR: u32 = 1980;
/// The last year the clock accepts (its two-digit years cover 1980-2079).
pub const LAST_YEAR: u32 = 2079;
/// `calendar_flags`: D8018 shows four digits.
pub const CALENDAR_FOUR_DIGIT_YEAR: u32 = 1;
/// `calendar_flags`: M8015 was ON at the previous scan.
const CALENDAR_WAS_STOPPED: u32 = 2;
/// `calendar_flags`: M8017 was ON at the previous scan.
const CALENDAR_WAS_ROUNDING: u32 = 4;

/// M8015: clock stopped (and preset when it turns OFF).
pub const M_CLOCK_STOP: u32 = 8015;
/// M8016: D8013-D8019 frozen.
pub const M_CLOCK_HOLD: u32 = 8016;
/// M8017: round to the nearest minute (when it turns ON).
pub const M_CLOCK_ROUND: u32 = 8017;
/// M8018: a clock is present.
pub const M_CLOCK_PRESENT: u32 = 8018;
/// M8019: a clock setting was out of range.
pub const M_CLOCK_ERROR: u32 = 8019;

/// A calendar time: year (four digits), month 1-12, day 1-31, hour,
/// minute, second, and the day of the week (0 Sunday to 6 Saturday) when
/// read from the clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CalendarTime {
    pub year: u32,
    pub month: u32,
    pub day: u32,
    pub hour: u32,
    pub minute: u32,
    pub second: u32,
    pub weekday: u32,
}

impl CalendarTime {
    /// A time to set (the day of the week follows from the date).
    pub const fn at(year: u32, month: u32, day: u32, hour: u32, minute: u32, second: u32) -> CalendarTime {
        CalendarTime {
            year,
            month,
            day,
            hour,
            minute,
            second,
            weekday: 0,
        }
    }
}

const fn is_leap(year: u32) -> bool {
    (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400)
}

const fn days_in_month(year: u32, month: u32) -> u32 {
    match month {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if is_leap(year) => 29,
        2 => 28,
        _ => 0,
    }
}

const fn days_in_year(year: u32) -> u32 {
    if is_leap(year) {
        366
    } else {
        365
    }
}

/// The clock's last second, 2079-12-31 23:59:59, where it stops.
pub const LAST_SECOND: u32 = match CalendarTime::at(LAST_YEAR, 12, 31, 23, 59, 59).to_seconds() {
    Some(seconds) => seconds,
    None => u32::MAX,
};

/// The fields D8013-D8017 and D8019 show, in one word: second (bits 0-5),
/// minute (6-11), hour (12-16), day (17-21), month (22-25), day of the
/// week (26-28).
const fn pack(time: CalendarTime) -> u32 {
    time.second | time.minute << 6 | time.hour << 12 | time.day << 17 | time.month << 22 | time.weekday << 26
}

/// The time `pack` packed, in `year`.
const fn unpack(packed: u32, year: u32) -> CalendarTime {
    CalendarTime {
        year,
        month: packed >> 22 & 0xf,
        day: packed >> 17 & 0x1f,
        hour: packed >> 12 & 0x1f,
        minute: packed >> 6 & 0x3f,
        second: packed & 0x3f,
        weekday: packed >> 26 & 0x7,
    }
}

impl CalendarTime {
    /// Seconds since 1980-01-01 00:00:00; `None` for a time that does not
    /// exist or is outside 1980-2079 (the weekday is not looked at).
    pub const fn to_seconds(self) -> Option<u32> {
        let valid = self.year >= FIRST_YEAR
            && self.year <= LAST_YEAR
            && self.month >= 1
            && self.month <= 12
            && self.day >= 1
            && self.day <= days_in_month(self.year, self.month)
            && self.hour < 24
            && self.minute < 60
            && self.second < 60;
        if !valid {
            return None;
        }
        let mut days = 0u32;
        let mut year = FIRST_YEAR;
        while year < self.year {
            days += days_in_year(year);
            year += 1;
        }
        let mut month = 1;
        while month < self.month {
            days += days_in_month(self.year, month);
            month += 1;
        }
        days += self.day - 1;
        Some(days * 86_400 + self.hour * 3_600 + self.minute * 60 + self.second)
    }

    /// The calendar time `seconds` after 1980-01-01 00:00:00.
    pub fn from_seconds(seconds: u32) -> CalendarTime {
        let mut days = seconds / 86_400;
        let in_day = seconds % 86_400;
        // 1980-01-01 was a Tuesday.
        let weekday = (days + 2) % 7;
        let mut year = FIRST_YEAR;
        while days >= days_in_year(year) {
            days -= days_in_year(year);
            year += 1;
        }
        let mut month = 1;
        while days >= days_in_month(year, month) {
            days -= days_in_month(year, month);
            month += 1;
        }
        CalendarTime {
            year,
            month,
            day: days + 1,
            hour: in_day / 3_600,
            minute: in_day % 3_600 / 60,
            second: in_day % 60,
            weekday,
        }
    }
}

/// The two-digit year 80-99 is 1980-1999, 0-79 is 2000-2079; four-digit
/// years stand for themselves.
pub fn full_year(year: i32) -> Option<u32> {
    match year {
        0..=79 => Some(2000 + year as u32),
        80..=99 => Some(1900 + year as u32),
        _ => u32::try_from(year)
            .ok()
            .filter(|y| (FIRST_YEAR..=LAST_YEAR).contains(y)),
    }
}

impl<B: AsRef<[u8]>> Image<'_, B> {
    /// The clock's time now.
    pub fn calendar(&self) -> CalendarTime {
        CalendarTime::from_seconds(self.scalar(Scalar::CalendarSeconds))
    }

    fn flag(&self, flag: u32) -> bool {
        self.scalar(Scalar::CalendarFlags) & flag != 0
    }
}

impl ImageMut<'_> {
    /// Sets the clock (milliseconds below the second start at 0); false,
    /// and nothing changed, for a time that does not exist or is outside
    /// 1980-2079.
    pub fn set_calendar(&mut self, time: CalendarTime) -> bool {
        match time.to_seconds() {
            Some(seconds) => {
                self.set_scalar(Scalar::CalendarSeconds, seconds);
                self.set_scalar(Scalar::CalendarMs, 0);
                self.write_clock_registers();
                true
            }
            None => false,
        }
    }

    fn set_flag(&mut self, flag: u32, on: bool) {
        let flags = self.scalar(Scalar::CalendarFlags);
        self.set_scalar(Scalar::CalendarFlags, if on { flags | flag } else { flags & !flag });
    }

    /// At the start of a scan: the clock advances by the elapsed time; when
    /// the program or its host uses the calendar (`shown`), D8013-D8019
    /// show it and M8015-M8018 act. Date arithmetic is done once per second
    /// (`write_clock_registers`), not at every scan.
    pub(crate) fn advance_calendar(&mut self, elapsed_ms: u32, shown: bool) {
        if !shown {
            self.tick_calendar(elapsed_ms);
            return;
        }
        self.set_u8(Array::M, M_CLOCK_PRESENT, 1);
        let stopped = self.get_u8(Array::M, M_CLOCK_STOP) != 0;
        let was_stopped = self.flag(CALENDAR_WAS_STOPPED);
        if stopped != was_stopped {
            self.set_flag(CALENDAR_WAS_STOPPED, stopped);
        }
        if stopped {
            return;
        }
        if was_stopped {
            self.preset_from_registers();
            return;
        }
        let rounding = self.get_u8(Array::M, M_CLOCK_ROUND) != 0;
        let was_rounding = self.flag(CALENDAR_WAS_ROUNDING);
        if rounding != was_rounding {
            self.set_flag(CALENDAR_WAS_ROUNDING, rounding);
        }
        self.tick_calendar(elapsed_ms);
        if rounding && !was_rounding {
            let seconds = self.scalar(Scalar::CalendarSeconds);
            let second = seconds % 60;
            let minute_start = seconds - second;
            let rounded = if second >= 30 {
                (minute_start + 60).min(LAST_SECOND)
            } else {
                minute_start
            };
            self.set_scalar(Scalar::CalendarSeconds, rounded);
            self.set_scalar(Scalar::CalendarMs, 0);
        }
        if !self.flag(CALENDAR_FOUR_DIGIT_YEAR) && self.get_i16(Array::D, D_CLOCK_FIRST + 5) == 2000 {
            self.set_flag(CALENDAR_FOUR_DIGIT_YEAR, true);
        }
        if self.get_u8(Array::M, M_CLOCK_HOLD) == 0 {
            self.write_clock_registers();
        }
    }

    /// The clock's own time advances by `elapsed_ms` (it stops at the end
    /// of 2079 rather than wrapping).
    fn tick_calendar(&mut self, elapsed_ms: u32) {
        let ms = u64::from(self.scalar(Scalar::CalendarMs)) + u64::from(elapsed_ms);
        if ms < 1000 {
            self.set_scalar(Scalar::CalendarMs, ms as u32);
            return;
        }
        let seconds = u64::from(self.scalar(Scalar::CalendarSeconds)) + ms / 1000;
        self.set_scalar(Scalar::CalendarSeconds, seconds.min(u64::from(LAST_SECOND)) as u32);
        self.set_scalar(Scalar::CalendarMs, (ms % 1000) as u32);
    }

    /// M8015 turned OFF: the clock takes D8013-D8019.
    fn preset_from_registers(&mut self) {
        let register = |image: &Self, offset: u32| i32::from(image.get_i16(Array::D, D_CLOCK_FIRST + offset));
        let year = full_year(register(self, 5));
        let time = year.map(|year| CalendarTime {
            year,
            month: register(self, 4) as u32,
            day: register(self, 3) as u32,
            hour: register(self, 2) as u32,
            minute: register(self, 1) as u32,
            second: register(self, 0) as u32,
            weekday: 0,
        });
        let valid = (0..=5).all(|offset| register(self, offset) >= 0) && time.is_some_and(|t| self.set_calendar(t));
        self.set_u8(Array::M, M_CLOCK_ERROR, u8::from(!valid));
        if !valid {
            self.write_clock_registers();
        }
    }

    /// D8013-D8019 show the clock's time, worked out from its seconds once
    /// per second and kept in the image (`Scalar::CalendarCache*`).
    fn write_clock_registers(&mut self) {
        let seconds = self.scalar(Scalar::CalendarSeconds);
        let cached = self.scalar(Scalar::CalendarCacheAt) == seconds.wrapping_add(1);
        let time = if cached {
            unpack(
                self.scalar(Scalar::CalendarCacheTime),
                self.scalar(Scalar::CalendarCacheYear),
            )
        } else {
            let time = CalendarTime::from_seconds(seconds);
            self.set_scalar(Scalar::CalendarCacheAt, seconds.wrapping_add(1));
            self.set_scalar(Scalar::CalendarCacheTime, pack(time));
            self.set_scalar(Scalar::CalendarCacheYear, time.year);
            time
        };
        let year = if self.flag(CALENDAR_FOUR_DIGIT_YEAR) {
            time.year
        } else {
            time.year % 100
        };
        let fields = [
            time.second,
            time.minute,
            time.hour,
            time.day,
            time.month,
            year,
            time.weekday,
        ];
        for (offset, value) in (0..).zip(fields) {
            self.set_i16(Array::D, D_CLOCK_FIRST + offset, value as i16);
        }
    }

    /// D8010 = the scan time the host reported to this scan (the time of
    /// the scan before it; for the first scan, the time since the host
    /// started it); D8011/D8012 the shortest and longest so far, the first
    /// scan's included (0.1 ms units, at most 32767).
    pub(crate) fn record_scan_time(&mut self, elapsed_ms: u32) {
        let tenths = elapsed_ms.saturating_mul(10).min(i16::MAX as u32) as i16;
        let first = self.scalar(Scalar::ScanCount) == 0;
        self.set_i16(Array::D, D_SCAN_TIME, tenths);
        if first || tenths < self.get_i16(Array::D, D_SCAN_TIME_MIN) {
            self.set_i16(Array::D, D_SCAN_TIME_MIN, tenths);
        }
        if first || tenths > self.get_i16(Array::D, D_SCAN_TIME_MAX) {
            self.set_i16(Array::D, D_SCAN_TIME_MAX, tenths);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn time(year: u32, month: u32, day: u32, hour: u32, minute: u32, second: u32) -> CalendarTime {
        CalendarTime::at(year, month, day, hour, minute, second)
    }

    #[test]
    fn seconds_round_trip_with_weekdays() {
        let t = time(2026, 1, 2, 3, 4, 5);
        let back = CalendarTime::from_seconds(t.to_seconds().unwrap());
        assert_eq!(back, CalendarTime { weekday: 5, ..t }, "2026-01-02 is a Friday");
        assert_eq!(
            CalendarTime::from_seconds(0),
            CalendarTime {
                weekday: 2,
                ..time(1980, 1, 1, 0, 0, 0)
            }
        );
        let leap = time(2024, 2, 29, 23, 59, 59);
        assert_eq!(CalendarTime::from_seconds(leap.to_seconds().unwrap()).day, 29);
        assert_eq!(time(2023, 2, 29, 0, 0, 0).to_seconds(), None);
        assert_eq!(time(2080, 1, 1, 0, 0, 0).to_seconds(), None);
        assert_eq!(time(2000, 13, 1, 0, 0, 0).to_seconds(), None);
    }

    #[test]
    fn the_clock_advances_by_reported_time() {
        let mut mem = Memory::new_boxed();
        assert!(mem.set_calendar(time(2026, 12, 31, 23, 59, 59)));
        mem.scan_with(600, |_| {});
        assert_eq!(mem.d[8013], 59);
        mem.scan_with(600, |_| {});
        assert_eq!((mem.d[8013], mem.d[8014], mem.d[8015]), (0, 0, 0));
        assert_eq!((mem.d[8016], mem.d[8017], mem.d[8018], mem.d[8019]), (1, 1, 27, 5));
        mem.d[8018] = 2000;
        mem.scan_with(0, |_| {});
        assert_eq!(mem.d[8018], 2027, "four-digit mode");
    }

    #[test]
    fn scan_time_registers() {
        let mut mem = Memory::new_boxed();
        mem.scan_with(7, |_| {});
        assert_eq!(
            (mem.d[8010], mem.d[8011], mem.d[8012]),
            (70, 70, 70),
            "the time reported to the first scan"
        );
        for ms in [12, 5, 9] {
            mem.scan_with(ms, |_| {});
        }
        assert_eq!((mem.d[8010], mem.d[8011], mem.d[8012]), (90, 50, 120));
        mem.scan_with(u32::MAX, |_| {});
        assert_eq!(mem.d[8012], 32767);
    }

    #[test]
    fn two_digit_years() {
        assert_eq!(full_year(26), Some(2026));
        assert_eq!(full_year(85), Some(1985));
        assert_eq!(full_year(2026), Some(2026));
        assert_eq!(full_year(150), None);
    }
}
