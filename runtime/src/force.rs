//! Forced devices (docs/language.md, small-PLC model of seeds/forced-io.txt):
//! forced X is what the program reads; forced Y and M are written over the
//! program's results before the output refresh; a forced T or C contact reads
//! the forced value and its timer or counter stops timing or counting.

use crate::device::BitArea;
use crate::image::{Image, ImageMut};
use crate::layout::{Array, Scalar};
#[cfg(test)]
use crate::memory::Memory;
use crate::memory::{FORCE_NONE, FORCE_OFF, FORCE_ON};

/// Why a force request was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForceError {
    /// Only X, Y, M, T and C can be forced.
    NotForceable,
    /// The device number is outside its area.
    OutOfRange,
    /// The image's compact layout does not hold the device.
    NotInImage,
}

impl core::fmt::Display for ForceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            ForceError::NotForceable => "only X, Y, M, T and C devices can be forced",
            ForceError::OutOfRange => "device number out of range",
            ForceError::NotInImage => "the image (a compact layout) does not hold the device",
        })
    }
}

impl core::error::Error for ForceError {}

/// The force table of a bit area; `None` for S and SM, which cannot be forced.
fn force_table(area: BitArea) -> Option<Array> {
    match area {
        BitArea::X => Some(Array::ForceX),
        BitArea::Y => Some(Array::ForceY),
        BitArea::M => Some(Array::ForceM),
        BitArea::TimerContact => Some(Array::ForceTimer),
        BitArea::CounterContact => Some(Array::ForceCounter),
        BitArea::S | BitArea::Sm => None,
    }
}

impl<B: AsRef<[u8]>> Image<'_, B> {
    /// The forced value of a device, or `None` when it is not forced.
    pub fn forced(&self, area: BitArea, index: u32) -> Option<bool> {
        match self.get_u8(force_table(area)?, index) {
            FORCE_ON => Some(true),
            FORCE_OFF => Some(false),
            _ => None,
        }
    }
}

impl ImageMut<'_> {
    /// The force table entry of a device: refused for devices that cannot
    /// be forced, outside the area, or not in the image.
    fn force_entry(&self, area: BitArea, index: u32) -> Result<Array, ForceError> {
        let table = force_table(area).ok_or(ForceError::NotForceable)?;
        if index >= area.count() {
            return Err(ForceError::OutOfRange);
        }
        if !self.holds(table, index) {
            return Err(ForceError::NotInImage);
        }
        Ok(table)
    }

    /// Forces a device ON or OFF until `unforce`. The device shows the forced
    /// value at once, so a monitor sees it before the next scan.
    pub fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), ForceError> {
        let table = self.force_entry(area, index)?;
        let was_forced = self.get_u8(table, index) != FORCE_NONE;
        self.set_u8(table, index, if on { FORCE_ON } else { FORCE_OFF });
        if !was_forced {
            let count = self.scalar(Scalar::ForcedCount);
            self.set_scalar(Scalar::ForcedCount, count + 1);
        }
        self.set_bit(area, index, on);
        Ok(())
    }

    /// Ends a force. An unforced X shows the input image again at once; other
    /// devices keep their value until the program changes it.
    pub fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), ForceError> {
        let table = self.force_entry(area, index)?;
        if self.get_u8(table, index) == FORCE_NONE {
            return Ok(());
        }
        self.set_u8(table, index, FORCE_NONE);
        let count = self.scalar(Scalar::ForcedCount);
        self.set_scalar(Scalar::ForcedCount, count.saturating_sub(1));
        if area == BitArea::X {
            let input = self.get_u8(Array::InputImage, index);
            self.set_u8(Array::X, index, input);
        }
        Ok(())
    }

    /// Step 1: forced X, and forced T/C contacts, before the program runs.
    pub(crate) fn apply_forced_inputs(&mut self) {
        self.zip_bytes(Array::ForceX, Array::X, apply);
        self.zip_bytes(Array::ForceTimer, Array::TimerContact, apply);
        self.zip_bytes(Array::ForceCounter, Array::CounterContact, apply);
    }

    /// Step 4: forced Y and M over the program's results.
    pub(crate) fn apply_forced_outputs(&mut self) {
        self.zip_bytes(Array::ForceY, Array::Y, apply);
        self.zip_bytes(Array::ForceM, Array::M, apply);
    }
}

fn apply(entry: &mut u8, device: &mut u8) {
    match *entry {
        FORCE_ON => *device = 1,
        FORCE_OFF => *device = 0,
        _ => {}
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
