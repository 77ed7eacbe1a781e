//! Timers (docs/language.md, "Timers and counters").
//!
//! The timer is updated when its `OUT Tn` executes. While the coil is ON the
//! timer adds the scan's elapsed time, from the scan after the coil turned ON,
//! carrying the remainder below its resolution. The current value stops at the
//! preset; the contact is ON once the value reaches the preset.

use crate::device::{TimerClass, TIMER_COUNT};
use crate::image::ImageMut;
use crate::layout::{Array, Scalar};
use crate::memory::FORCE_NONE;

impl ImageMut<'_> {
    /// Executes `OUT Tn preset` with the rung result `coil`.
    pub fn timer_coil(&mut self, timer: u32, coil: bool, preset: i32) {
        if timer >= TIMER_COUNT {
            return;
        }
        let was_on = self.get_u8(Array::TimerCoilWasOn, timer) != 0;
        self.set_u8(Array::TimerCoilWasOn, timer, coil as u8);
        if self.get_u8(Array::ForceTimer, timer) != FORCE_NONE {
            return; // a forced timer neither times nor changes its contact
        }
        let class = TimerClass::of(timer);
        if !coil {
            if !class.retentive {
                self.clear_timer(timer);
            }
            return;
        }
        if was_on {
            let total = u64::from(self.get_i16(Array::TimerRemainder, timer) as u16)
                + u64::from(self.scalar(Scalar::ElapsedMs));
            let resolution = u64::from(class.resolution_ms);
            self.set_i16(Array::TimerRemainder, timer, (total % resolution) as u16 as i16);
            let value = i64::from(self.get_i16(Array::TimerValue, timer));
            let limit = i64::from(preset).min(i64::from(i16::MAX));
            if value < limit {
                let counts = (total / resolution) as i64;
                self.set_i16(Array::TimerValue, timer, (value + counts).min(limit) as i16);
            }
        }
        let reached = i32::from(self.get_i16(Array::TimerValue, timer)) >= preset;
        self.set_u8(Array::TimerContact, timer, reached as u8);
    }

    /// `RST Tn`: value, remainder and contact cleared (a forced contact keeps
    /// its forced value). A coil that stays ON times again from the next scan.
    pub fn reset_timer(&mut self, timer: u32) {
        if timer < TIMER_COUNT {
            self.clear_timer(timer);
        }
    }

    fn clear_timer(&mut self, timer: u32) {
        self.set_i16(Array::TimerValue, timer, 0);
        self.set_i16(Array::TimerRemainder, timer, 0);
        if self.get_u8(Array::ForceTimer, timer) == FORCE_NONE {
            self.set_u8(Array::TimerContact, timer, 0);
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::device::BitArea;
    use crate::memory::Memory;

    /// Runs `scans` scans of `OUT Tn preset` with the coil ON; returns the
    /// 1-based scan at which the contact closed.
    fn scans_until_contact(timer: u32, preset: i32, scan_ms: u32, scans: u32) -> Option<u32> {
        let mut mem = Memory::new_boxed();
        (1..=scans).find(|_| {
            mem.scan_with(scan_ms, |m| m.timer_coil(timer, true, preset));
            mem.timer_contact[timer as usize] != 0
        })
    }

    #[test]
    fn dialect_example_closes_at_the_101st_scan() {
        assert_eq!(scans_until_contact(0, 10, 10, 200), Some(101));
    }

    #[test]
    fn preset_zero_closes_at_once() {
        assert_eq!(scans_until_contact(0, 0, 10, 5), Some(1));
    }

    #[test]
    fn remainder_below_resolution_carries_over() {
        // 30 ms scans on a 100 ms timer: after the first scan, 10 scans are 300 ms.
        let mut mem = Memory::new_boxed();
        for _ in 0..11 {
            mem.scan_with(30, |m| m.timer_coil(0, true, 100));
        }
        assert_eq!(mem.timer_value[0], 3);
        assert_eq!(mem.timer_remainder_ms[0], 0);
        mem.scan_with(30, |m| m.timer_coil(0, true, 100));
        assert_eq!((mem.timer_value[0], mem.timer_remainder_ms[0]), (3, 30));
    }

    #[test]
    fn value_stops_at_preset() {
        let mut mem = Memory::new_boxed();
        for _ in 0..50 {
            mem.scan_with(100, |m| m.timer_coil(0, true, 5));
        }
        assert_eq!(mem.timer_value[0], 5);
    }

    #[test]
    fn non_retentive_clears_retentive_keeps() {
        let mut mem = Memory::new_boxed();
        for _ in 0..5 {
            mem.scan_with(100, |m| {
                m.timer_coil(0, true, 100);
                m.timer_coil(250, true, 100);
            });
        }
        mem.scan_with(100, |m| {
            m.timer_coil(0, false, 100);
            m.timer_coil(250, false, 100);
        });
        assert_eq!(mem.timer_value[0], 0);
        assert_eq!(mem.timer_value[250], 4);
        mem.reset_timer(250);
        assert_eq!(mem.timer_value[250], 0);
    }

    #[test]
    fn forced_timer_does_not_time() {
        let mut mem = Memory::new_boxed();
        mem.force(BitArea::TimerContact, 3, true).unwrap();
        for _ in 0..5 {
            mem.scan_with(100, |m| m.timer_coil(3, true, 100));
        }
        assert_eq!((mem.timer_value[3], mem.timer_contact[3]), (0, 1));
    }
}
