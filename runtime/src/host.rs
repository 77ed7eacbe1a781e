//! Host-side access to single devices, as a monitor, a scenario or a C host
//! names them: a bit, a word, a bit of a word, a digit group or a 32-bit value.
//!
//! Composite devices are built from three basic ones (a bit, a word, a 32-bit
//! counter value), the operations the C API offers. `read_composite` and
//! `write_composite` work over any `BasicAccess`: the image in this process,
//! or a compiled program's image in another process.

use crate::device::{BitArea, Width, WordArea, FIRST_WIDE_COUNTER};
use crate::image::{AsImage, Image, ImageMut, ImageRef};
use crate::layout::Array;
use crate::memory::{join_words, split_words, Memory};

/// One device a host can read or write.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Device {
    Bit(BitArea, u32),
    Word(WordArea, u32),
    /// Bit `bit` (0–15) of a word (`D0.F`).
    WordBit(WordArea, u32, u8),
    /// 4·n bits from a start device (`K4M0`), n = 1..8.
    Digits(BitArea, u32, u8),
    /// Current value of a 32-bit counter C200–C255 (device number).
    WideCounter(u32),
}

impl Device {
    /// Is this a bit (read as 0/1)?
    pub fn is_bit(self) -> bool {
        matches!(self, Device::Bit(..) | Device::WordBit(..))
    }
}

/// The devices the basic operations address.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basic {
    Bit(BitArea, u32),
    Word(WordArea, u32),
    WideCounter(u32),
}

/// Why an access failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AccessError {
    /// The device, or part of it, is outside its area; or the width does not
    /// fit the device.
    OutOfRange,
    /// A write through a read-only view of the image.
    ReadOnly,
    /// The device is in range, but the image (a compact layout) does not
    /// hold it.
    NotInImage,
    /// The image could not be reached (a host process that went away).
    #[cfg(feature = "std")]
    Unreachable(String),
}

/// Reading and writing basic devices: bits as 0/1, words sign-extended,
/// 32-bit counter values whole. Writing X sets the input image, which the
/// next scan copies to X.
pub trait BasicAccess {
    fn read_basic(&mut self, device: Basic) -> Result<i32, AccessError>;
    fn write_basic(&mut self, device: Basic, value: i32) -> Result<(), AccessError>;
}

/// Reads a device of any shape through basic reads.
pub fn read_composite(access: &mut impl BasicAccess, device: Device, width: Width) -> Result<i32, AccessError> {
    match (device, width) {
        (Device::Bit(area, n), Width::Single) => access.read_basic(Basic::Bit(area, n)),
        (Device::WordBit(area, n, bit), Width::Single) if bit < 16 => {
            Ok((access.read_basic(Basic::Word(area, n))? >> bit) & 1)
        }
        (Device::Word(area, n), Width::Single) => access.read_basic(Basic::Word(area, n)),
        (Device::Word(area, n), Width::Double) => {
            let high_index = n.checked_add(1).ok_or(AccessError::OutOfRange)?;
            let low = access.read_basic(Basic::Word(area, n))?;
            let high = access.read_basic(Basic::Word(area, high_index))?;
            Ok(join_words(low as i16, high as i16))
        }
        (Device::Digits(area, start, digits), width) if digits <= digit_limit(width) => {
            let mut bits = 0u32;
            for i in 0..4 * u32::from(digits) {
                let index = start.checked_add(i).ok_or(AccessError::OutOfRange)?;
                bits |= (access.read_basic(Basic::Bit(area, index))? as u32 & 1) << i;
            }
            Ok(match width {
                Width::Single => i32::from(bits as i16),
                Width::Double => bits as i32,
            })
        }
        (Device::WideCounter(n), Width::Single | Width::Double) => access.read_basic(Basic::WideCounter(n)),
        // A bit read as a pair, a bit of a word beyond bit 15, more digits
        // than the width holds.
        (Device::Bit(..) | Device::WordBit(..), Width::Double)
        | (Device::WordBit(..), Width::Single)
        | (Device::Digits(..), Width::Single | Width::Double) => Err(AccessError::OutOfRange),
    }
}

/// Writes a device of any shape through basic reads and writes.
pub fn write_composite(
    access: &mut impl BasicAccess,
    device: Device,
    width: Width,
    value: i32,
) -> Result<(), AccessError> {
    match (device, width) {
        (Device::Bit(area, n), Width::Single) => access.write_basic(Basic::Bit(area, n), (value != 0) as i32),
        (Device::WordBit(area, n, bit), Width::Single) if bit < 16 => {
            // In 16 bits: the word reads sign-extended, and clearing bit 15
            // of a negative word must give a word again (-1 → 32767), not
            // the 32-bit -32769 a word cannot hold.
            let word = access.read_basic(Basic::Word(area, n))? as i16;
            let mask = 1i16 << bit;
            let updated = if value != 0 { word | mask } else { word & !mask };
            access.write_basic(Basic::Word(area, n), i32::from(updated))
        }
        (Device::Word(area, n), Width::Single) => access.write_basic(Basic::Word(area, n), i32::from(value as i16)),
        (Device::Word(area, n), Width::Double) => {
            let high_index = n
                .checked_add(1)
                .filter(|&h| h < area.count())
                .ok_or(AccessError::OutOfRange)?;
            let (low, high) = split_words(value);
            access.write_basic(Basic::Word(area, n), i32::from(low))?;
            access.write_basic(Basic::Word(area, high_index), i32::from(high))
        }
        (Device::Digits(area, start, digits), width) if digits <= digit_limit(width) => {
            let count = 4 * u32::from(digits);
            if u64::from(start) + u64::from(count) > u64::from(area.count()) {
                return Err(AccessError::OutOfRange);
            }
            for i in 0..count {
                access.write_basic(Basic::Bit(area, start + i), (value >> i) & 1)?;
            }
            Ok(())
        }
        (Device::WideCounter(n), Width::Single | Width::Double) if n >= FIRST_WIDE_COUNTER => {
            access.write_basic(Basic::WideCounter(n), value)
        }
        // A bit written as a pair, a bit of a word beyond bit 15, more
        // digits than the width holds or beyond the area, a 16-bit counter
        // written as a 32-bit one.
        (Device::Bit(..) | Device::WordBit(..), Width::Double)
        | (Device::WordBit(..), Width::Single)
        | (Device::Digits(..) | Device::WideCounter(_), Width::Single | Width::Double) => Err(AccessError::OutOfRange),
    }
}

fn digit_limit(width: Width) -> u8 {
    match width {
        Width::Single => 4,
        Width::Double => 8,
    }
}

impl<B: AsRef<[u8]>> Image<'_, B> {
    /// Reads a basic device: bits as 0/1, words sign-extended, 32-bit counter
    /// values whole; `None` out of range.
    pub fn basic(&self, device: Basic) -> Option<i32> {
        match device {
            Basic::Bit(area, n) => self.bit(area, n).map(i32::from),
            Basic::Word(area, n) => self.word(area, n).map(i32::from),
            Basic::WideCounter(n) => self.wide_counter(n),
        }
    }

    /// Does the image hold the device (always, with the full layout; a
    /// compact one holds what its program and host use)? An input also
    /// needs its input image, which a compact layout holds with it.
    pub fn holds_basic(&self, device: Basic) -> bool {
        match device {
            Basic::Bit(area, n) => self.holds(Array::of_bits(area), n),
            Basic::Word(area, n) => self.holds(Array::of_words(area), n),
            Basic::WideCounter(n) => self.holds(Array::WideCounterValue, n),
        }
    }

    /// Reads a device; words are sign-extended. `None` when out of range or
    /// when the width does not fit the device.
    pub fn read_device(&self, device: Device, width: Width) -> Option<i32> {
        read_composite(&mut ReadOnly(self.as_image()), device, width).ok()
    }
}

impl ImageMut<'_> {
    /// Writes a device as a host or programming tool would (not forced).
    /// Writing X sets the input image (and X itself unless X is forced).
    /// Returns false when out of range or the width does not fit.
    pub fn write_device(&mut self, device: Device, width: Width, value: i32) -> bool {
        write_composite(self, device, width, value).is_ok()
    }
}

/// Out of range, or in range but not in the image.
fn basic_error<B: AsRef<[u8]>>(image: &Image<'_, B>, device: Basic) -> AccessError {
    let in_area = match device {
        Basic::Bit(area, n) => n < area.count(),
        Basic::Word(area, n) => n < area.count(),
        Basic::WideCounter(n) => (FIRST_WIDE_COUNTER..Array::WideCounterValue.end()).contains(&n),
    };
    if in_area && !image.holds_basic(device) {
        AccessError::NotInImage
    } else {
        AccessError::OutOfRange
    }
}

pub(crate) fn read_held<B: AsRef<[u8]>>(image: &Image<'_, B>, device: Basic) -> Result<i32, AccessError> {
    match image.basic(device) {
        Some(value) if image.holds_basic(device) => Ok(value),
        _ => Err(basic_error(image, device)),
    }
}

impl BasicAccess for ImageMut<'_> {
    fn read_basic(&mut self, device: Basic) -> Result<i32, AccessError> {
        read_held(self, device)
    }

    fn write_basic(&mut self, device: Basic, value: i32) -> Result<(), AccessError> {
        if !self.holds_basic(device) {
            return Err(basic_error(self, device));
        }
        let written = match device {
            // Inputs go to the input image; X takes them at the next scan's
            // input refresh, never in the middle of a scan.
            Basic::Bit(BitArea::X, n) => self.set_u8(Array::InputImage, n, (value != 0) as u8),
            Basic::Bit(area, n) => self.set_bit(area, n, value != 0),
            Basic::Word(area, n) => self.set_word(area, n, value as i16),
            Basic::WideCounter(n) => self.set_wide_counter(n, value),
        };
        written.then_some(()).ok_or(AccessError::OutOfRange)
    }
}

impl BasicAccess for Memory {
    fn read_basic(&mut self, device: Basic) -> Result<i32, AccessError> {
        self.image().read_basic(device)
    }

    fn write_basic(&mut self, device: Basic, value: i32) -> Result<(), AccessError> {
        self.image().write_basic(device, value)
    }
}

/// Reads of a shared image through `BasicAccess`.
struct ReadOnly<'a>(ImageRef<'a>);

impl BasicAccess for ReadOnly<'_> {
    fn read_basic(&mut self, device: Basic) -> Result<i32, AccessError> {
        read_held(&self.0, device)
    }

    fn write_basic(&mut self, _: Basic, _: i32) -> Result<(), AccessError> {
        Err(AccessError::ReadOnly)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn word_bits_and_digit_groups() {
        let mut mem = Memory::new_boxed();
        assert!(mem.write_device(Device::WordBit(WordArea::D, 0, 15), Width::Single, 1));
        assert_eq!(
            mem.read_device(Device::Word(WordArea::D, 0), Width::Single),
            Some(-32768)
        );
        assert!(mem.write_device(Device::Digits(BitArea::M, 0, 4), Width::Single, 0x8001));
        assert_eq!(
            mem.read_device(Device::Digits(BitArea::M, 0, 4), Width::Single),
            Some(-32767)
        );
        assert_eq!(mem.read_device(Device::Digits(BitArea::M, 0, 5), Width::Single), None);
        assert!(mem.write_device(Device::Digits(BitArea::M, 100, 8), Width::Double, -1));
        assert_eq!(
            mem.read_device(Device::Digits(BitArea::M, 100, 8), Width::Double),
            Some(-1)
        );
        assert!(!mem.write_device(Device::Digits(BitArea::X, 250, 2), Width::Single, 1));
    }

    /// A host that, like the C API, refuses a word value outside 16 bits.
    struct StrictWords<'m>(&'m mut Memory);

    impl BasicAccess for StrictWords<'_> {
        fn read_basic(&mut self, device: Basic) -> Result<i32, AccessError> {
            self.0.read_basic(device)
        }

        fn write_basic(&mut self, device: Basic, value: i32) -> Result<(), AccessError> {
            if matches!(device, Basic::Word(..)) && i16::try_from(value).is_err() {
                return Err(AccessError::OutOfRange);
            }
            self.0.write_basic(device, value)
        }
    }

    #[test]
    fn word_bits_of_negative_words_stay_words() {
        let mut mem = Memory::new_boxed();
        mem.d[0] = -1;
        let bit15 = Device::WordBit(WordArea::D, 0, 15);
        assert_eq!(
            write_composite(&mut StrictWords(&mut mem), bit15, Width::Single, 0),
            Ok(())
        );
        assert_eq!(mem.d[0], 32767);
        assert_eq!(
            write_composite(&mut StrictWords(&mut mem), bit15, Width::Single, 1),
            Ok(())
        );
        assert_eq!(mem.d[0], -1);
        mem.d[1] = i16::MIN;
        let bit0 = Device::WordBit(WordArea::D, 1, 0);
        assert_eq!(
            write_composite(&mut StrictWords(&mut mem), bit0, Width::Single, 1),
            Ok(())
        );
        assert_eq!(mem.d[1], -32767);
    }

    #[test]
    fn pairs_and_wide_counters() {
        let mut mem = Memory::new_boxed();
        assert!(mem.write_device(Device::Word(WordArea::D, 10), Width::Double, 0x0001_8000));
        assert_eq!(mem.d[10], -32768);
        assert_eq!(
            mem.read_device(Device::Word(WordArea::D, 10), Width::Double),
            Some(0x0001_8000)
        );
        assert!(!mem.write_device(Device::Word(WordArea::D, 8511), Width::Double, 1));
        assert!(mem.write_device(Device::WideCounter(255), Width::Double, -7));
        assert_eq!(mem.read_device(Device::WideCounter(255), Width::Single), Some(-7));
    }

    #[test]
    fn writing_x_sets_the_input_image() {
        let mut mem = Memory::new_boxed();
        assert!(mem.write_device(Device::Bit(BitArea::X, 7), Width::Single, 1));
        mem.begin_scan(10);
        assert_eq!(mem.x[7], 1);
    }
}
