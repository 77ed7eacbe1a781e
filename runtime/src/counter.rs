//! Counters (docs/language.md, "Timers and counters").
//!
//! C0–C199 are 16-bit up counters: each rising edge of the coil adds 1 until
//! the preset. C200–C255 are 32-bit up/down counters: they count down while
//! M8200+(n-200) is ON and wrap around. The contact is ON at or above the preset.
//! C235-C255 are high-speed counters: their coil enables counting of their
//! inputs at the input refresh (`hsc.rs`) instead of counting its own edges.

use crate::device::{is_wide_counter, COUNTER_COUNT, FIRST_WIDE_COUNTER};
use crate::image::ImageMut;
use crate::layout::Array;
use crate::memory::FORCE_NONE;
use crate::special::M_COUNTER_DIRECTION_BASE;

impl ImageMut<'_> {
    /// Executes `OUT Cn preset` with the rung result `coil`.
    pub fn counter_coil(&mut self, counter: u32, coil: bool, preset: i32) {
        if counter >= COUNTER_COUNT {
            return;
        }
        let rising = coil && self.get_u8(Array::CounterCoilWasOn, counter) == 0;
        self.set_u8(Array::CounterCoilWasOn, counter, coil as u8);
        if self.get_u8(Array::ForceCounter, counter) != FORCE_NONE {
            return; // a forced counter does not count
        }
        let value = if is_wide_counter(counter) {
            let mut value = self.get_i32(Array::WideCounterValue, counter);
            // A high-speed counter's coil only enables counting (hsc.rs).
            if rising && counter < crate::hsc::FIRST_HSC {
                let direction = M_COUNTER_DIRECTION_BASE + (counter - FIRST_WIDE_COUNTER);
                let step = if self.get_u8(Array::M, direction) != 0 { -1 } else { 1 };
                value = value.wrapping_add(step);
                self.set_i32(Array::WideCounterValue, counter, value);
            }
            value
        } else {
            let value = i32::from(self.get_i16(Array::CounterValue, counter));
            if rising && value < preset {
                // value < preset <= i16::MAX, so the increment cannot overflow
                self.set_i16(Array::CounterValue, counter, (value + 1) as i16);
            }
            i32::from(self.get_i16(Array::CounterValue, counter))
        };
        self.set_u8(Array::CounterContact, counter, (value >= preset) as u8);
    }

    /// `RST Cn`: value and contact cleared (a forced contact keeps its value).
    pub fn reset_counter(&mut self, counter: u32) {
        if counter >= COUNTER_COUNT {
            return;
        }
        if is_wide_counter(counter) {
            self.set_i32(Array::WideCounterValue, counter, 0);
        } else {
            self.set_i16(Array::CounterValue, counter, 0);
        }
        if self.get_u8(Array::ForceCounter, counter) == FORCE_NONE {
            self.set_u8(Array::CounterContact, counter, 0);
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
