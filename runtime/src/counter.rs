//! Counters (DIALECT.md, "Timers and counters").
//!
//! C0–C199 are 16-bit up counters: each rising edge of the coil adds 1 until
//! the preset. C200–C255 are 32-bit up/down counters: they count down while
//! M8200+(n-200) is ON and wrap around. The contact is ON at or above the preset.
//! C235-C255 are high-speed counters: their coil enables counting of their
//! inputs at the input refresh (`hsc.rs`) instead of counting its own edges.

use crate::device::{is_wide_counter, COUNTER_COUNT, FIRST_WIDE_COUNTER};
use crate::memory::{Memory, FORCE_NONE};
use crate::special::M_COUNTER_DIRECTION_BASE;

impl Memory {
    /// Executes `OUT Cn preset` with the rung result `coil`.
    pub fn counter_coil(&mut self, counter: u32, coil: bool, preset: i32) {
        if counter >= COUNTER_COUNT {
            return;
        }
        let n = counter as usize;
        let rising = coil && self.counter_coil_was_on[n] == 0;
        self.counter_coil_was_on[n] = coil as u8;
        if self.force_counter[n] != FORCE_NONE {
            return; // a forced counter does not count
        }
        let value = if is_wide_counter(counter) {
            let slot = n - FIRST_WIDE_COUNTER as usize;
            // A high-speed counter's coil only enables counting (hsc.rs).
            if rising && counter < crate::hsc::FIRST_HSC {
                let direction = M_COUNTER_DIRECTION_BASE as usize + slot;
                let step = if self.m[direction] != 0 { -1 } else { 1 };
                self.wide_counter_value[slot] = self.wide_counter_value[slot].wrapping_add(step);
            }
            self.wide_counter_value[slot]
        } else {
            let value = i32::from(self.counter_value[n]);
            if rising && value < preset {
                // value < preset <= i16::MAX, so the increment cannot overflow
                self.counter_value[n] = (value + 1) as i16;
            }
            i32::from(self.counter_value[n])
        };
        self.counter_contact[n] = (value >= preset) as u8;
    }

    /// `RST Cn`: value and contact cleared (a forced contact keeps its value).
    pub fn reset_counter(&mut self, counter: u32) {
        if counter >= COUNTER_COUNT {
            return;
        }
        let n = counter as usize;
        if is_wide_counter(counter) {
            self.wide_counter_value[n - FIRST_WIDE_COUNTER as usize] = 0;
        } else {
            self.counter_value[n] = 0;
        }
        if self.force_counter[n] == FORCE_NONE {
            self.counter_contact[n] = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::memory::Memory;

    fn pulse(mem: &mut Memory, counter: u32, preset: i32) {
        mem.counter_coil(counter, true, preset);
        mem.counter_coil(counter, false, preset);
    }

    #[test]
    fn up_counter_counts_rising_edges_until_preset() {
        let mut mem = Memory::new_boxed();
        mem.counter_coil(0, true, 3);
        mem.counter_coil(0, true, 3); // held ON: no new edge
        assert_eq!(mem.counter_value[0], 1);
        mem.counter_coil(0, false, 3);
        pulse(&mut mem, 0, 3);
        assert_eq!(mem.counter_contact[0], 0);
        pulse(&mut mem, 0, 3);
        pulse(&mut mem, 0, 3);
        assert_eq!((mem.counter_value[0], mem.counter_contact[0]), (3, 1));
        mem.reset_counter(0);
        assert_eq!((mem.counter_value[0], mem.counter_contact[0]), (0, 0));
    }

    #[test]
    fn wide_counter_counts_down_and_wraps() {
        let mut mem = Memory::new_boxed();
        pulse(&mut mem, 200, 1);
        assert_eq!((mem.wide_counter(200), mem.counter_contact[200]), (Some(1), 1));
        mem.m[8200] = 1;
        pulse(&mut mem, 200, 1);
        pulse(&mut mem, 200, 1);
        assert_eq!((mem.wide_counter(200), mem.counter_contact[200]), (Some(-1), 0));
        mem.set_wide_counter(201, i32::MAX);
        pulse(&mut mem, 201, 0);
        assert_eq!(mem.wide_counter(201), Some(i32::MIN));
    }
}
