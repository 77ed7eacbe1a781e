//! Forced devices (DIALECT.md, small-PLC model of seeds/forced-io.txt):
//! forced X is what the program reads; forced Y and M are written over the
//! program's results before the output refresh; a forced T or C contact reads
//! the forced value and its timer or counter stops timing or counting.

use crate::device::BitArea;
use crate::memory::{Memory, FORCE_NONE, FORCE_OFF, FORCE_ON};

/// Why a force request was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForceError {
    /// Only X, Y, M, T and C can be forced.
    NotForceable,
    /// The device number is outside its area.
    OutOfRange,
}

impl core::fmt::Display for ForceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            ForceError::NotForceable => "only X, Y, M, T and C devices can be forced",
            ForceError::OutOfRange => "device number out of range",
        })
    }
}

impl core::error::Error for ForceError {}

impl Memory {
    fn force_table_mut(&mut self, area: BitArea) -> Option<&mut [u8]> {
        match area {
            BitArea::X => Some(&mut self.force_x),
            BitArea::Y => Some(&mut self.force_y),
            BitArea::M => Some(&mut self.force_m),
            BitArea::TimerContact => Some(&mut self.force_timer),
            BitArea::CounterContact => Some(&mut self.force_counter),
            BitArea::S | BitArea::Sm => None,
        }
    }

    fn force_table(&self, area: BitArea) -> Option<&[u8]> {
        match area {
            BitArea::X => Some(&self.force_x),
            BitArea::Y => Some(&self.force_y),
            BitArea::M => Some(&self.force_m),
            BitArea::TimerContact => Some(&self.force_timer),
            BitArea::CounterContact => Some(&self.force_counter),
            BitArea::S | BitArea::Sm => None,
        }
    }

    /// Forces a device ON or OFF until `unforce`. The device shows the forced
    /// value at once, so a monitor sees it before the next scan.
    pub fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), ForceError> {
        let table = self.force_table_mut(area).ok_or(ForceError::NotForceable)?;
        let entry = table.get_mut(index as usize).ok_or(ForceError::OutOfRange)?;
        let was_forced = *entry != FORCE_NONE;
        *entry = if on { FORCE_ON } else { FORCE_OFF };
        if !was_forced {
            self.forced_count += 1;
        }
        self.bits_mut(area)[index as usize] = on as u8;
        Ok(())
    }

    /// Ends a force. An unforced X shows the input image again at once; other
    /// devices keep their value until the program changes it.
    pub fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), ForceError> {
        let table = self.force_table_mut(area).ok_or(ForceError::NotForceable)?;
        let entry = table.get_mut(index as usize).ok_or(ForceError::OutOfRange)?;
        if *entry == FORCE_NONE {
            return Ok(());
        }
        *entry = FORCE_NONE;
        self.forced_count -= 1;
        if area == BitArea::X {
            self.x[index as usize] = self.input_image[index as usize];
        }
        Ok(())
    }

    /// The forced value of a device, or `None` when it is not forced.
    pub fn forced(&self, area: BitArea, index: u32) -> Option<bool> {
        match self.force_table(area)?.get(index as usize).copied()? {
            FORCE_ON => Some(true),
            FORCE_OFF => Some(false),
            _ => None,
        }
    }

    /// Step 1: forced X, and forced T/C contacts, before the program runs.
    pub(crate) fn apply_forced_inputs(&mut self) {
        apply(&self.force_x, &mut self.x);
        apply(&self.force_timer, &mut self.timer_contact);
        apply(&self.force_counter, &mut self.counter_contact);
    }

    /// Step 4: forced Y and M over the program's results.
    pub(crate) fn apply_forced_outputs(&mut self) {
        apply(&self.force_y, &mut self.y);
        apply(&self.force_m, &mut self.m);
    }
}

fn apply(table: &[u8], devices: &mut [u8]) {
    for (device, &entry) in devices.iter_mut().zip(table) {
        match entry {
            FORCE_ON => *device = 1,
            FORCE_OFF => *device = 0,
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forced_input_wins_over_input_image() {
        let mut mem = Memory::new_boxed();
        mem.input_image[0] = 1;
        mem.force(BitArea::X, 0, false).unwrap();
        mem.begin_scan(10);
        assert_eq!(mem.x[0], 0);
        mem.end_scan();
        mem.unforce(BitArea::X, 0).unwrap();
        assert_eq!(mem.x[0], 1, "unforced X shows the input image again");
        assert_eq!(mem.forced_count, 0);
    }

    #[test]
    fn forced_output_is_written_over_program_result() {
        let mut mem = Memory::new_boxed();
        mem.force(BitArea::Y, 1, true).unwrap();
        mem.scan_with(10, |m| {
            m.y[1] = 0;
            assert_eq!(m.y[1], 0, "the program reads its own value during the scan");
        });
        assert_eq!((mem.y[1], mem.output_image[1]), (1, 1));
    }

    #[test]
    fn refuses_unforceable_devices() {
        let mut mem = Memory::new_boxed();
        assert_eq!(mem.force(BitArea::S, 0, true), Err(ForceError::NotForceable));
        assert_eq!(mem.force(BitArea::X, 256, true), Err(ForceError::OutOfRange));
        mem.force(BitArea::M, 5, true).unwrap();
        mem.force(BitArea::M, 5, false).unwrap();
        assert_eq!(mem.forced_count, 1, "re-forcing counts once");
        assert_eq!(mem.forced(BitArea::M, 5), Some(false));
    }
}
