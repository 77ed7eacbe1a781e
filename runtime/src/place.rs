//! A word operand that is known to lie inside its area: where an application
//! instruction reads or writes its values. Engines decide whether an operand
//! is in range (with their own offset rules); reading and writing a place is
//! the same for all of them.

use crate::device::{BitArea, Width, WordArea};
use crate::image::{AsImage, AsImageMut, ImageMut};
use crate::layout::Array;
#[cfg(test)]
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
    /// One bit device (a run of bits goes device by device).
    Bit(BitArea, u32),
    /// One bit of a word, numbered through the area: bit b of word n is
    /// 16·n + b (a run of bits continues into the next word).
    WordBit(WordArea, u32),
}

impl Place {
    /// The `unit`-th value from this place (BMOV/FMOV walk their operands).
    pub fn nth(self, unit: u32, width: Width) -> Place {
        match self {
            Place::Constant(_) => self,
            Place::Word(area, index) => Place::Word(area, index + unit * width.words()),
            Place::WideCounter(index) => Place::WideCounter(index + unit),
            Place::Digits(area, start, digits) => Place::Digits(area, start + unit * 4 * u32::from(digits), digits),
            Place::Bit(area, index) => Place::Bit(area, index + unit),
            Place::WordBit(area, bit) => Place::WordBit(area, bit + unit),
        }
    }

    /// The value at the instruction's width: 16-bit words sign-extended,
    /// digit groups narrower than the width zero-extended. A place outside
    /// the image reads 0.
    pub fn read(self, mem: &(impl AsImage + ?Sized), width: Width) -> i32 {
        let mem = mem.as_image();
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
            (Place::Bit(area, index), _) => mem.bit(area, index).map_or(0, i32::from),
            (Place::WordBit(area, bit), _) => mem.word(area, bit / 16).map_or(0, |w| i32::from((w >> (bit % 16)) & 1)),
        }
    }

    /// Writes the low bits of `value` that the place holds. A place outside
    /// the image is not written.
    pub fn write(self, mem: &mut (impl AsImageMut + ?Sized), width: Width, value: i64) {
        let mut mem = mem.as_image_mut();
        if !mem.is_full() && self.lacks(&mem, width) {
            mem.missed();
        }
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
            (Place::Bit(area, index), _) => {
                mem.set_bit(area, index, value & 1 != 0);
            }
            (Place::WordBit(area, bit), _) => {
                if let Some(word) = mem.word(area, bit / 16) {
                    let mask = 1i16 << (bit % 16);
                    let updated = if value & 1 != 0 { word | mask } else { word & !mask };
                    mem.set_word(area, bit / 16, updated);
                }
            }
        }
    }

    /// Is part of the place inside its area but not in the image (a
    /// compact layout that missed it)?
    fn lacks(self, mem: &ImageMut<'_>, width: Width) -> bool {
        let lacks = |array: Array, first: u32, count: u32| {
            (first..first.saturating_add(count)).any(|n| array.segment(n).is_some() && !mem.holds(array, n))
        };
        match (self, width) {
            (Place::Constant(_), _) => false,
            (Place::Word(area, index), _) => lacks(Array::of_words(area), index, width.words()),
            (Place::WideCounter(index), _) => lacks(Array::WideCounterValue, index, 1),
            (Place::Digits(area, start, digits), _) => lacks(Array::of_bits(area), start, 4 * u32::from(digits)),
            (Place::Bit(area, index), _) => lacks(Array::of_bits(area), index, 1),
            (Place::WordBit(area, bit), _) => lacks(Array::of_words(area), bit / 16, 1),
        }
    }

    /// What kind of place it is, without the index; `None` for a constant.
    pub fn kind(self) -> Option<PlaceKind> {
        match self {
            Place::Constant(_) => None,
            Place::Word(area, _) => Some(PlaceKind::Word(area)),
            Place::WideCounter(_) => Some(PlaceKind::WideCounter),
            Place::Digits(area, _, digits) => Some(PlaceKind::Digits(area, digits)),
            Place::Bit(area, _) => Some(PlaceKind::Bit(area)),
            Place::WordBit(area, _) => Some(PlaceKind::WordBit(area)),
        }
    }

    /// The place as one u32 for the runtime helpers (`PlaceKind::tag` plus
    /// the index); `None` for a constant, which helpers take as a value.
    pub fn pack(self) -> Option<u32> {
        let index = match self {
            Place::Constant(_) => return None,
            Place::Word(_, index)
            | Place::WideCounter(index)
            | Place::Digits(_, index, _)
            | Place::Bit(_, index)
            | Place::WordBit(_, index) => index,
        };
        Some(self.kind()?.tag() | (index & PLACE_INDEX_MASK))
    }

    /// The inverse of `pack`; `None` for a value that names no place.
    pub fn unpack(packed: u32) -> Option<Place> {
        let index = packed & PLACE_INDEX_MASK;
        let tag = packed & !PLACE_INDEX_MASK;
        let kind = PlaceKind::ALL_TAGS.iter().find(|kind| kind.tag() == tag)?;
        Some(match *kind {
            PlaceKind::Word(area) => Place::Word(area, index),
            PlaceKind::WideCounter => Place::WideCounter(index),
            PlaceKind::Digits(area, digits) => Place::Digits(area, index, digits),
            PlaceKind::Bit(area) => Place::Bit(area, index),
            PlaceKind::WordBit(area) => Place::WordBit(area, index),
        })
    }
}

/// Bits of a packed place that hold the index (areas have at most 32768
/// elements, word bits at most 16 times that).
pub const PLACE_INDEX_MASK: u32 = 0xF_FFFF;

const WORD_AREAS: usize = WordArea::ALL.len();
const BIT_AREAS: usize = BitArea::ALL.len();
/// Words, the 32-bit counters, digit groups of 1-8 digits, bits, word bits.
const TAG_COUNT: usize = WORD_AREAS + 1 + BIT_AREAS * 8 + BIT_AREAS + WORD_AREAS;

/// A place without its index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaceKind {
    Word(WordArea),
    WideCounter,
    /// A digit group of n digits (1..8).
    Digits(BitArea, u8),
    Bit(BitArea),
    WordBit(WordArea),
}

impl PlaceKind {
    /// Every kind that packs (digit counts 1..8), sized from the areas so
    /// that a new area cannot be left out.
    const ALL_TAGS: [PlaceKind; TAG_COUNT] = {
        let mut all = [PlaceKind::WideCounter; TAG_COUNT];
        let mut i = 0;
        while i < WORD_AREAS {
            all[i] = PlaceKind::Word(WordArea::ALL[i]);
            all[WORD_AREAS + 1 + BIT_AREAS * 8 + BIT_AREAS + i] = PlaceKind::WordBit(WordArea::ALL[i]);
            i += 1;
        }
        let mut area = 0;
        while area < BIT_AREAS {
            all[WORD_AREAS + 1 + BIT_AREAS * 8 + area] = PlaceKind::Bit(BitArea::ALL[area]);
            let mut digits = 1;
            while digits <= 8 {
                all[WORD_AREAS + 1 + area * 8 + (digits - 1)] = PlaceKind::Digits(BitArea::ALL[area], digits as u8);
                digits += 1;
            }
            area += 1;
        }
        all
    };

    /// The packed place with index 0: the kind in bits 24-31, the digit
    /// count in bits 20-23.
    pub const fn tag(self) -> u32 {
        match self {
            PlaceKind::Word(area) => (1 + area as u32) << 24,
            PlaceKind::WideCounter => 16 << 24,
            PlaceKind::Digits(area, digits) => ((32 + area as u32) << 24) | ((digits as u32 & 0xF) << 20),
            PlaceKind::Bit(area) => (48 + area as u32) << 24,
            PlaceKind::WordBit(area) => (64 + area as u32) << 24,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packing_round_trips() {
        for place in [
            Place::Word(WordArea::R, 32767),
            Place::Word(WordArea::D, 0),
            Place::WideCounter(201),
            Place::Digits(BitArea::Y, 8, 2),
            Place::Digits(BitArea::CounterContact, 250, 8),
            Place::Bit(BitArea::Sm, 1023),
            Place::WordBit(WordArea::R, 32767 * 16 + 15),
        ] {
            assert_eq!(Place::unpack(place.pack().unwrap()), Some(place), "{place:?}");
        }
        for area in WordArea::ALL {
            for place in [Place::Word(area, 3), Place::WordBit(area, 17)] {
                assert_eq!(Place::unpack(place.pack().unwrap()), Some(place), "{place:?}");
            }
        }
        for area in BitArea::ALL {
            for place in [
                Place::Bit(area, 5),
                Place::Digits(area, 4, 1),
                Place::Digits(area, 0, 8),
            ] {
                assert_eq!(Place::unpack(place.pack().unwrap()), Some(place), "{place:?}");
            }
        }
        assert_eq!(Place::Constant(-5).pack(), None);
        assert_eq!(Place::unpack(0), None);
        assert_eq!(Place::unpack(99 << 24), None);
        assert_eq!(
            Place::unpack(PlaceKind::Digits(BitArea::M, 1).tag() & !(0xF << 20)),
            None
        );
    }

    #[test]
    fn bit_places_run_through_words() {
        let mut mem = Memory::new_boxed();
        let start = Place::WordBit(WordArea::D, 15);
        start.write(&mut mem, Width::Single, 1);
        start.nth(1, Width::Single).write(&mut mem, Width::Single, 1);
        assert_eq!((mem.d[0], mem.d[1]), (-32768, 1));
        assert_eq!(start.nth(1, Width::Single).read(&mem, Width::Single), 1);
        Place::Bit(BitArea::M, 7)
            .nth(2, Width::Single)
            .write(&mut mem, Width::Single, 3);
        assert_eq!(mem.m[9], 1);
    }
}
