//! Operations on runs of devices that compiled code delegates to the
//! runtime (through `helpers`): block moves, byte packing, bit searches and
//! zone resets. The compiled code has checked every place and count
//! against its area before the call; these functions clamp again anyway, so
//! a wrong call cannot reach outside the image. Nothing here allocates.
//!
//! The reference interpreter implements the same instructions on its own
//! (a test makes sure it does not call this module), so that the
//! differential test compares two implementations.

use crate::device::{BitArea, WordArea, MAX_BLOCK_UNITS};
use crate::host::Width;
use crate::memory::Memory;
use crate::place::Place;

/// BMOV (`fill` false) or FMOV (`fill` true) of `n` units. Overlapping
/// blocks move as a whole: units of the same size are copied in the
/// direction that reads each before it is overwritten; digit groups of
/// different sizes in one area go through a buffer of at most 1 KiB.
pub fn block_move(mem: &mut Memory, source: Place, destination: Place, n: u32, width: Width, fill: bool) {
    let n = n.min(MAX_BLOCK_UNITS);
    if fill {
        let value = i64::from(source.read(mem, width));
        for unit in 0..n {
            destination.nth(unit, width).write(mem, width, value);
        }
        return;
    }
    let backwards = match (source, destination) {
        (Place::Word(a, s), Place::Word(b, d)) if a == b => d > s,
        (Place::WideCounter(s), Place::WideCounter(d)) => d > s,
        (Place::Digits(a, s, k), Place::Digits(b, d, l)) if a == b && k == l => d > s,
        (Place::Digits(a, ..), Place::Digits(b, ..)) if a == b => {
            // Units of different sizes over the same bits: read them all
            // first (BMOV is 16-bit, so they fit in i16).
            let mut values = [0i16; MAX_BLOCK_UNITS as usize];
            for (unit, value) in (0..n).zip(values.iter_mut()) {
                *value = source.nth(unit, width).read(mem, width) as i16;
            }
            for (unit, value) in (0..n).zip(values) {
                destination.nth(unit, width).write(mem, width, i64::from(value));
            }
            return;
        }
        // Different areas never overlap.
        _ => false,
    };
    let mut copy = |unit: u32| {
        let value = i64::from(source.nth(unit, width).read(mem, width));
        destination.nth(unit, width).write(mem, width, value);
    };
    if backwards {
        (0..n).rev().for_each(&mut copy);
    } else {
        (0..n).for_each(&mut copy);
    }
}

/// BTOW (`split` false): the low bytes of `n` words from `source` packed two
/// to a word from `destination` (low byte first; an odd last byte gets a
/// high byte of 0). WTOB (`split` true): `n` bytes of the words from `source`
/// (low byte first) into `n` words from `destination`, high bytes 0.
/// Overlapping ranges give what reading everything first would give.
pub fn bytes(mem: &mut Memory, source: Place, destination: Place, n: u32, split: bool) {
    let word = |mem: &Memory, place: Place, unit: u32| place.nth(unit, Width::Single).read(mem, Width::Single);
    let put = |mem: &mut Memory, unit: u32, value: i32| {
        destination
            .nth(unit, Width::Single)
            .write(mem, Width::Single, i64::from(value))
    };
    let (s, d) = (offset(source), offset(destination));
    if split {
        // Output j comes from input j/2. Outputs whose writes land on inputs
        // not yet read must go first: those from the top down where the
        // destination starts at or after the source, the rest upwards.
        let out = |mem: &mut Memory, j: u32| {
            let value = word(mem, source, j / 2);
            put(
                mem,
                j,
                if j.is_multiple_of(2) {
                    value & 0xFF
                } else {
                    (value >> 8) & 0xFF
                },
            );
        };
        let split_at = if d >= s {
            0
        } else {
            (2 * (s - d)).min(i64::from(n)) as u32
        };
        // Inputs i >= s - d are overwritten only by outputs of inputs >= i.
        for j in (split_at..n).rev() {
            out(mem, j);
        }
        for j in 0..split_at {
            out(mem, j);
        }
    } else {
        // Output i comes from inputs 2i and 2i+1.
        let words = n.div_ceil(2);
        let out = |mem: &mut Memory, i: u32| {
            let low = word(mem, source, 2 * i) & 0xFF;
            let high = if 2 * i + 1 < n {
                word(mem, source, 2 * i + 1) & 0xFF
            } else {
                0
            };
            put(mem, i, low | (high << 8));
        };
        // Outputs up to d - s are safe from the top down, the rest upwards.
        let split_at = if d <= s {
            0
        } else {
            ((d - s) + 1).min(i64::from(words)) as u32
        };
        for i in (0..split_at).rev() {
            out(mem, i);
        }
        for i in split_at..words {
            out(mem, i);
        }
    }
}

/// Where a place starts, for comparing ranges: word areas are spread
/// apart so that ranges of different areas never seem to overlap. BTOW and
/// WTOB take word registers only, so other places do not occur.
fn offset(place: Place) -> i64 {
    match place {
        Place::Word(area, index) => ((area as i64 + 1) << 24) + i64::from(index),
        Place::Constant(_) | Place::WideCounter(_) | Place::Digits(..) | Place::Bit(..) | Place::WordBit(..) => 0,
    }
}

/// The number (0-based) of the highest ON bit among `count` bits from
/// `source`, or -1 when all are OFF (ENCO on bit devices).
pub fn highest_on(mem: &Memory, source: Place, count: u32) -> i32 {
    (0..count)
        .rev()
        .find(|&unit| source.nth(unit, Width::Single).read(mem, Width::Single) != 0)
        .map_or(-1, |unit| unit as i32)
}

/// What a zone (ZRST, ZSET) covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Zone {
    Bits(BitArea),
    /// Bits of words, numbered through the area (16·word + bit).
    WordBits(WordArea),
    Words(WordArea),
    Timers,
    Counters,
}

impl Zone {
    /// The zone as a helper argument.
    pub const fn code(self) -> u32 {
        match self {
            Zone::Bits(area) => area as u32,
            Zone::WordBits(area) => 16 + area as u32,
            Zone::Words(area) => 32 + area as u32,
            Zone::Timers => 48,
            Zone::Counters => 49,
        }
    }

    pub fn from_code(code: u32) -> Option<Zone> {
        let bits = BitArea::ALL.into_iter().map(Zone::Bits);
        let word_bits = WordArea::ALL.into_iter().map(Zone::WordBits);
        let words = WordArea::ALL.into_iter().map(Zone::Words);
        bits.chain(word_bits)
            .chain(words)
            .chain([Zone::Timers, Zone::Counters])
            .find(|zone| zone.code() == code)
    }
}

/// ZRST (`on` false) or ZSET (`on` true) from `first` to `last` of a zone;
/// when `last` is below `first`, `first` alone. Words are cleared, timers
/// and counters reset.
pub fn zone(mem: &mut Memory, zone: Zone, first: u32, last: u32, on: bool) {
    let last = last.max(first);
    for index in first..=last {
        match zone {
            Zone::Bits(area) => {
                mem.set_bit(area, index, on);
            }
            Zone::WordBits(area) => Place::WordBit(area, index).write(mem, Width::Single, i64::from(on)),
            Zone::Words(area) => {
                mem.set_word(area, index, 0);
            }
            Zone::Timers => mem.reset_timer(index),
            Zone::Counters => mem.reset_counter(index),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What BTOW/WTOB give when everything is read first.
    fn reference(words: &[i16], s: usize, d: usize, n: usize, split: bool) -> Vec<i16> {
        let mut out = words.to_vec();
        let input: Vec<i16> = words.to_vec();
        if split {
            for j in 0..n {
                let w = input[s + j / 2];
                out[d + j] = if j % 2 == 0 { w & 0xFF } else { (w >> 8) & 0xFF };
            }
        } else {
            for i in 0..n.div_ceil(2) {
                let low = input[s + 2 * i] & 0xFF;
                let high = if 2 * i + 1 < n { input[s + 2 * i + 1] & 0xFF } else { 0 };
                out[d + i] = low | (high << 8);
            }
        }
        out
    }

    #[test]
    fn byte_packing_overlaps_like_reading_first() {
        let pattern: Vec<i16> = (0..64)
            .map(|i| (0x1111u16.wrapping_mul(i + 1) ^ 0x5A3C) as i16)
            .collect();
        for split in [false, true] {
            for s in 0..12 {
                for d in 0..12 {
                    for n in 0..20 {
                        let mut mem = Memory::new_boxed();
                        mem.d[..64].copy_from_slice(&pattern);
                        bytes(
                            &mut mem,
                            Place::Word(WordArea::D, s),
                            Place::Word(WordArea::D, d),
                            n,
                            split,
                        );
                        let expected = reference(&pattern, s as usize, d as usize, n as usize, split);
                        assert_eq!(&mem.d[..64], &expected[..], "split {split} s {s} d {d} n {n}");
                    }
                }
            }
        }
    }

    #[test]
    fn byte_packing_across_areas() {
        let mut mem = Memory::new_boxed();
        mem.r[..3].copy_from_slice(&[0x1234, 0x0056, 0x0078]);
        bytes(
            &mut mem,
            Place::Word(WordArea::R, 0),
            Place::Word(WordArea::D, 0),
            3,
            false,
        );
        assert_eq!(&mem.d[..2], &[0x5634, 0x0078]);
    }

    #[test]
    fn block_moves_overlap_as_a_whole() {
        let mut mem = Memory::new_boxed();
        mem.d[..4].copy_from_slice(&[1, 2, 3, 4]);
        block_move(
            &mut mem,
            Place::Word(WordArea::D, 0),
            Place::Word(WordArea::D, 1),
            3,
            Width::Single,
            false,
        );
        assert_eq!(&mem.d[..4], &[1, 1, 2, 3]);
        block_move(
            &mut mem,
            Place::Word(WordArea::D, 1),
            Place::Word(WordArea::D, 0),
            3,
            Width::Single,
            false,
        );
        assert_eq!(&mem.d[..4], &[1, 2, 3, 3]);
        block_move(
            &mut mem,
            Place::Constant(7),
            Place::Digits(BitArea::M, 0, 1),
            2,
            Width::Single,
            true,
        );
        assert_eq!(mem.digits(BitArea::M, 0, 2), Some(0x77));
        // Digit groups of different sizes over the same relays.
        mem.set_digits(BitArea::M, 100, 2, 0xA5);
        block_move(
            &mut mem,
            Place::Digits(BitArea::M, 100, 1),
            Place::Digits(BitArea::M, 104, 2),
            2,
            Width::Single,
            false,
        );
        assert_eq!(mem.digits(BitArea::M, 104, 4), Some(0x0A05));
    }

    #[test]
    fn zones_and_searches() {
        let mut mem = Memory::new_boxed();
        zone(&mut mem, Zone::Bits(BitArea::M), 3, 1, true);
        assert_eq!(&mem.m[..5], &[0, 0, 0, 1, 0], "last below first: first alone");
        zone(&mut mem, Zone::WordBits(WordArea::D), 14, 17, true);
        assert_eq!((mem.d[0], mem.d[1]), (-16384, 3));
        assert_eq!(highest_on(&mem, Place::Bit(BitArea::M, 0), 8), 3);
        assert_eq!(highest_on(&mem, Place::Bit(BitArea::M, 4), 8), -1);
        for code in 0..64 {
            if let Some(zone) = Zone::from_code(code) {
                assert_eq!(zone.code(), code);
            }
        }
    }
}
