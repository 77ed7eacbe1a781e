//! Host-side access to single devices, as a monitor, a scenario or a C host
//! names them: a bit, a word, a bit of a word, a digit group or a 32-bit value.

use crate::device::{BitArea, WordArea, FIRST_WIDE_COUNTER};
use crate::memory::Memory;

/// One device a host can read or write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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

/// How many bits a host access covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Width {
    /// One bit, or one 16-bit word.
    Single,
    /// A 32-bit pair (n+1, n) of words, or a 32-bit device.
    Double,
}

impl Device {
    /// Is this a bit (read as 0/1)?
    pub fn is_bit(self) -> bool {
        matches!(self, Device::Bit(..) | Device::WordBit(..))
    }
}

impl Memory {
    /// Reads a device; words are sign-extended. `None` when out of range or
    /// when the width does not fit the device.
    pub fn read_device(&self, device: Device, width: Width) -> Option<i32> {
        match (device, width) {
            (Device::Bit(area, n), Width::Single) => self.bit(area, n).map(i32::from),
            (Device::WordBit(area, n, bit), Width::Single) if bit < 16 => {
                self.word(area, n).map(|w| i32::from((w >> bit) & 1))
            }
            (Device::Word(area, n), Width::Single) => self.word(area, n).map(i32::from),
            (Device::Word(area, n), Width::Double) => self.word_pair(area, n),
            (Device::Digits(area, start, digits), Width::Single) if digits <= 4 => self
                .digits(area, start, u32::from(digits))
                .map(|v| i32::from(v as i16)),
            (Device::Digits(area, start, digits), Width::Double) if digits <= 8 => {
                self.digits(area, start, u32::from(digits))
            }
            (Device::WideCounter(n), _) => self.wide_counter(n),
            _ => None,
        }
    }

    /// Writes a device as a host or programming tool would (not forced).
    /// Writing X sets the input image (and X itself unless X is forced).
    /// Returns false when out of range or the width does not fit.
    pub fn write_device(&mut self, device: Device, width: Width, value: i32) -> bool {
        match (device, width) {
            (Device::Bit(BitArea::X, n), Width::Single) => {
                let Some(image) = self.input_image.get_mut(n as usize) else {
                    return false;
                };
                *image = (value != 0) as u8;
                if self.forced(BitArea::X, n).is_none() {
                    self.x[n as usize] = (value != 0) as u8;
                }
                true
            }
            (Device::Bit(area, n), Width::Single) => self.set_bit(area, n, value != 0),
            (Device::WordBit(area, n, bit), Width::Single) if bit < 16 => {
                let Some(word) = self.word(area, n) else {
                    return false;
                };
                let mask = 1i16 << bit;
                let updated = if value != 0 {
                    word | mask
                } else {
                    word & !mask
                };
                self.set_word(area, n, updated)
            }
            (Device::Word(area, n), Width::Single) => self.set_word(area, n, value as i16),
            (Device::Word(area, n), Width::Double) => self.set_word_pair(area, n, value),
            (Device::Digits(area, start, digits), Width::Single) if digits <= 4 => {
                self.set_digits(area, start, u32::from(digits), value)
            }
            (Device::Digits(area, start, digits), Width::Double) if digits <= 8 => {
                self.set_digits(area, start, u32::from(digits), value)
            }
            (Device::WideCounter(n), _) if n >= FIRST_WIDE_COUNTER => {
                self.set_wide_counter(n, value)
            }
            _ => false,
        }
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
        assert_eq!(
            mem.read_device(Device::Digits(BitArea::M, 0, 5), Width::Single),
            None
        );
    }

    #[test]
    fn writing_x_sets_the_input_image() {
        let mut mem = Memory::new_boxed();
        assert!(mem.write_device(Device::Bit(BitArea::X, 7), Width::Single, 1));
        mem.begin_scan(10);
        assert_eq!(mem.x[7], 1);
    }
}
