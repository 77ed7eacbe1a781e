//! A word operand that is known to lie inside its area: where an application
//! instruction reads or writes its values. Engines decide whether an operand
//! is in range (with their own offset rules); reading and writing a place is
//! the same for all of them.

use crate::device::{BitArea, WordArea};
use crate::host::Width;
use crate::memory::Memory;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    Constant(i32),
    /// A word; at 32 bits the pair (n+1, n).
    Word(WordArea, u32),
    /// A 32-bit counter value, by device number (C200..C255).
    WideCounter(u32),
    /// 4·n bits from a start device.
    Digits(BitArea, u32, u8),
}

impl Place {
    /// The `unit`-th value from this place (BMOV/FMOV walk their operands).
    pub fn nth(self, unit: u32, width: Width) -> Place {
        match self {
            Place::Constant(_) => self,
            Place::Word(area, index) => Place::Word(area, index + unit * width.words()),
            Place::WideCounter(index) => Place::WideCounter(index + unit),
            Place::Digits(area, start, digits) => Place::Digits(area, start + unit * 4 * u32::from(digits), digits),
        }
    }

    /// The value at the instruction's width: 16-bit words sign-extended,
    /// digit groups narrower than the width zero-extended. A place outside
    /// the image reads 0.
    pub fn read(self, mem: &Memory, width: Width) -> i32 {
        match (self, width) {
            (Place::Constant(value), _) => value,
            (Place::Word(area, index), Width::Double) => mem.word_pair(area, index).unwrap_or(0),
            (Place::Word(area, index), Width::Single) => mem.word(area, index).map_or(0, i32::from),
            (Place::WideCounter(index), _) => mem.wide_counter(index).unwrap_or(0),
            (Place::Digits(area, start, digits), _) => {
                let bits = mem.digits(area, start, u32::from(digits)).unwrap_or(0);
                match width {
                    Width::Double => bits,
                    Width::Single => i32::from(bits as i16),
                }
            }
        }
    }

    /// Writes the low bits of `value` that the place holds. A place outside
    /// the image is not written.
    pub fn write(self, mem: &mut Memory, width: Width, value: i64) {
        match (self, width) {
            (Place::Constant(_), _) => {}
            (Place::Word(area, index), Width::Double) => {
                mem.set_word_pair(area, index, value as i32);
            }
            (Place::Word(area, index), Width::Single) => {
                mem.set_word(area, index, value as i16);
            }
            (Place::WideCounter(index), _) => {
                mem.set_wide_counter(index, value as i32);
            }
            (Place::Digits(area, start, digits), _) => {
                mem.set_digits(area, start, u32::from(digits), value as i32);
            }
        }
    }

    /// Encodes the place for the C ABI of the runtime helpers:
    /// (kind, index, digits).
    pub fn encode(self) -> (u32, u32, u32) {
        match self {
            Place::Constant(value) => (PLACE_CONSTANT, value as u32, 0),
            Place::Word(area, index) => (area as u32, index, 0),
            Place::WideCounter(index) => (PLACE_WIDE_COUNTER, index, 0),
            Place::Digits(area, start, digits) => (PLACE_DIGITS + area as u32, start, u32::from(digits)),
        }
    }

    /// The inverse of `encode`; `None` for a kind that does not exist.
    pub fn decode(kind: u32, index: u32, digits: u32) -> Option<Place> {
        let word = WordArea::ALL.iter().find(|&&a| a as u32 == kind);
        let bits = BitArea::ALL.iter().find(|&&a| PLACE_DIGITS + a as u32 == kind);
        match (kind, word, bits) {
            (PLACE_CONSTANT, _, _) => Some(Place::Constant(index as i32)),
            (PLACE_WIDE_COUNTER, _, _) => Some(Place::WideCounter(index)),
            (_, Some(&area), _) => Some(Place::Word(area, index)),
            (_, _, Some(&area)) if (1..=8).contains(&digits) => Some(Place::Digits(area, index, digits as u8)),
            _ => None,
        }
    }
}

/// Place kind of a constant (its value is the index).
pub const PLACE_CONSTANT: u32 = 255;
/// Place kind of a 32-bit counter value.
pub const PLACE_WIDE_COUNTER: u32 = 8;
/// Place kinds of digit groups: this plus the bit area.
pub const PLACE_DIGITS: u32 = 16;

/// Largest word count of BMOV/FMOV.
pub const MAX_BLOCK_UNITS: u32 = 512;

impl Memory {
    /// BMOV (`fill` false) or FMOV (`fill` true) of `n` units, after the
    /// caller checked that both places hold `n` units. Overlapping blocks move
    /// as a whole; nothing is allocated.
    pub fn block_move(&mut self, source: Place, destination: Place, n: u32, width: Width, fill: bool) {
        let n = n.min(MAX_BLOCK_UNITS);
        let mut values = [0i32; MAX_BLOCK_UNITS as usize];
        for (unit, value) in values.iter_mut().enumerate().take(n as usize) {
            *value = source.nth(if fill { 0 } else { unit as u32 }, width).read(self, width);
        }
        for (unit, value) in values.iter().enumerate().take(n as usize) {
            destination
                .nth(unit as u32, width)
                .write(self, width, i64::from(*value));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_round_trips() {
        for place in [
            Place::Constant(-5),
            Place::Word(WordArea::R, 9),
            Place::WideCounter(201),
            Place::Digits(BitArea::Y, 8, 2),
        ] {
            let (kind, index, digits) = place.encode();
            assert_eq!(Place::decode(kind, index, digits), Some(place));
        }
        assert_eq!(Place::decode(99, 0, 0), None);
        assert_eq!(Place::decode(PLACE_DIGITS, 0, 9), None);
    }

    #[test]
    fn overlapping_block_moves_move_as_a_whole() {
        let mut mem = Memory::new_boxed();
        mem.d[..3].copy_from_slice(&[1, 2, 3]);
        mem.block_move(
            Place::Word(WordArea::D, 0),
            Place::Word(WordArea::D, 1),
            3,
            Width::Single,
            false,
        );
        assert_eq!(&mem.d[..4], &[1, 1, 2, 3]);
        mem.block_move(
            Place::Constant(7),
            Place::Digits(BitArea::M, 0, 1),
            2,
            Width::Single,
            true,
        );
        assert_eq!(mem.digits(BitArea::M, 0, 2), Some(0x77));
    }
}
