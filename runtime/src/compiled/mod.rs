//! Operations on runs of devices that compiled code delegates to the
//! runtime (through `helpers`): block moves, byte packing, bit searches and
//! zone resets. The compiled code has checked every place and count
//! against its area before the call; these functions clamp again anyway, so
//! a wrong call cannot reach outside the image. Nothing here allocates.
//!
//! The reference interpreter implements the same instructions on its own
//! (a test makes sure it does not call this module), so that the
//! differential test compares two implementations.

pub mod clock;
pub mod handy;
pub mod highspeed;
pub mod pid;
mod real;

pub use real::{decimal_to_real, real_function, real_to_decimal};

use crate::device::{BitArea, Width, WordArea, MAX_BLOCK_UNITS, MAX_SHIFT_BITS, MAX_TRANSFER_UNITS, SORT_INSTANCES};
use crate::image::ImageMut;
use crate::layout::Array;
use crate::place::Place;

/// BMOV (`fill` false) or FMOV (`fill` true) of `n` units. Overlapping
/// blocks move as a whole: units of the same kind and size are copied in
/// the direction that reads each before it is overwritten; units of
/// different kinds or sizes over the same array (digit groups of different
/// sizes, a word and the bits of words, digit groups and single bits) go
/// through a buffer of at most 2 KiB (BMOV moves at most 512 units).
pub fn block_move(mem: &mut ImageMut<'_>, source: Place, destination: Place, n: u32, width: Width, fill: bool) {
    // BMOV/FMOV move at most 512 units, FROM/TO a whole buffer memory.
    let n = n.min(MAX_TRANSFER_UNITS);
    if fill {
        let value = i64::from(source.read(mem, width));
        for unit in 0..n {
            destination.nth(unit, width).write(mem, width, value);
        }
        return;
    }
    let backwards = match (storage(source), storage(destination)) {
        (Some(a), Some(b)) if a == b => match (units(source), units(destination)) {
            (Some((kind, size, s)), Some((other, other_size, d))) if kind == other && size == other_size => d > s,
            // Units of different kinds over the same array: read them all
            // first. Only BMOV moves within one array, at most 512 units.
            (Some(_) | None, Some(_) | None) => {
                let n = n.min(MAX_BLOCK_UNITS);
                let mut values = [0i32; MAX_BLOCK_UNITS as usize];
                for (unit, value) in (0..n).zip(values.iter_mut()) {
                    *value = source.nth(unit, width).read(mem, width);
                }
                for (unit, value) in (0..n).zip(values) {
                    destination.nth(unit, width).write(mem, width, i64::from(value));
                }
                return;
            }
        },
        // Different arrays of the image (or a constant) never overlap.
        (Some(_) | None, Some(_) | None) => false,
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

/// The array of the image a place's units lie in (`None`: a constant).
fn storage(place: Place) -> Option<Array> {
    match place {
        Place::Constant(_) => None,
        Place::Word(area, _) | Place::WordBit(area, _) => Some(Array::of_words(area)),
        Place::WideCounter(_) => Some(Array::WideCounterValue),
        Place::Digits(area, ..) | Place::Bit(area, _) => Some(Array::of_bits(area)),
    }
}

/// A place's units as (kind, size, first): two runs of the same kind and
/// size in one array overlap as their firsts say.
fn units(place: Place) -> Option<(u8, u32, u32)> {
    match place {
        Place::Constant(_) => None,
        Place::Word(_, first) => Some((0, 1, first)),
        Place::WideCounter(first) => Some((1, 1, first)),
        Place::Digits(_, first, digits) => Some((2, u32::from(digits), first)),
        Place::Bit(_, first) => Some((3, 1, first)),
        Place::WordBit(_, first) => Some((4, 1, first)),
    }
}

/// SFTR (`left` false) / SFTL: the `n1` bits from `destination` move by
/// `n2` toward it (right) or away from it (left), and the `n2` bits from
/// `source`, read before anything moves, fill the vacated end. The places
/// and 1 <= n2 <= n1 <= 1024 are checked by the caller.
pub fn shift_bits(mem: &mut ImageMut<'_>, source: Place, destination: Place, n1: u32, n2: u32, left: bool) {
    let n1 = n1.min(MAX_SHIFT_BITS);
    let n2 = n2.min(n1);
    let bit = |mem: &ImageMut<'_>, place: Place, k: u32| place.nth(k, Width::Single).read(mem, Width::Single) != 0;
    // The incoming bits first: the source may lie inside the shifted run.
    let mut incoming = [0u64; (MAX_SHIFT_BITS / 64) as usize];
    for k in 0..n2 {
        incoming[(k / 64) as usize] |= u64::from(bit(mem, source, k)) << (k % 64);
    }
    let set = |mem: &mut ImageMut<'_>, k: u32, on: bool| {
        destination
            .nth(k, Width::Single)
            .write(mem, Width::Single, i64::from(on));
    };
    if left {
        for k in (n2..n1).rev() {
            let moved = bit(mem, destination, k - n2);
            set(mem, k, moved);
        }
    } else {
        for k in 0..n1 - n2 {
            let moved = bit(mem, destination, k + n2);
            set(mem, k, moved);
        }
    }
    let vacated = if left { 0 } else { n1 - n2 };
    for k in 0..n2 {
        let on = incoming[(k / 64) as usize] >> (k % 64) & 1 != 0;
        set(mem, vacated + k, on);
    }
}

/// BTOW (`split` false): the low bytes of `n` words from `source` packed two
/// to a word from `destination` (low byte first; an odd last byte gets a
/// high byte of 0). WTOB (`split` true): `n` bytes of the words from `source`
/// (low byte first) into `n` words from `destination`, high bytes 0.
/// Overlapping ranges give what reading everything first would give.
pub fn bytes(mem: &mut ImageMut<'_>, source: Place, destination: Place, n: u32, split: bool) {
    let word = |mem: &ImageMut<'_>, place: Place, unit: u32| place.nth(unit, Width::Single).read(mem, Width::Single);
    let put = |mem: &mut ImageMut<'_>, unit: u32, value: i32| {
        destination
            .nth(unit, Width::Single)
            .write(mem, Width::Single, i64::from(value))
    };
    let (s, d) = (offset(source), offset(destination));
    if split {
        // Output j comes from input j/2. Outputs whose writes land on inputs
        // not yet read must go first: those from the top down where the
        // destination starts at or after the source, the rest upwards.
        let out = |mem: &mut ImageMut<'_>, j: u32| {
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
        let out = |mem: &mut ImageMut<'_>, i: u32| {
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
pub fn highest_on(mem: &ImageMut<'_>, source: Place, count: u32) -> i32 {
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
pub fn zone(mem: &mut ImageMut<'_>, zone: Zone, first: u32, last: u32, on: bool) {
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

/// The `count` values of `width` from `source`, unit by unit.
fn values<'m>(mem: &'m ImageMut<'_>, source: Place, count: u32, width: Width) -> impl Iterator<Item = i64> + 'm {
    (0..count).map(move |unit| i64::from(source.nth(unit, width).read(mem, width)))
}

/// What `table` computes over a run of values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableOp {
    Max,
    Min,
    /// The mean, truncated toward zero.
    Mean,
    /// The sum, written at twice the width.
    Sum,
}

impl TableOp {
    pub const ALL: [TableOp; 4] = [TableOp::Max, TableOp::Min, TableOp::Mean, TableOp::Sum];

    /// The operation as a helper argument.
    pub const fn code(self) -> u32 {
        self as u32
    }

    pub fn from_code(code: u32) -> Option<TableOp> {
        TableOp::ALL.into_iter().find(|op| op.code() == code)
    }
}

/// MAX, MIN, MEAN, WSUM over `count` values of `width` from `source`,
/// written to `destination` (WSUM at twice the width: a pair, or for DWSUM
/// two pairs; a digit group keeps its own bits).
pub fn table(mem: &mut ImageMut<'_>, op: TableOp, source: Place, count: u32, width: Width, destination: Place) {
    if count == 0 && op != TableOp::Sum {
        return;
    }
    let values = values(mem, source, count, width);
    let result = match op {
        TableOp::Max => values.max().unwrap_or(0),
        TableOp::Min => values.min().unwrap_or(0),
        TableOp::Mean => values.sum::<i64>() / i64::from(count),
        TableOp::Sum => values.sum::<i64>(),
    };
    match (op, width) {
        (TableOp::Max | TableOp::Min | TableOp::Mean, _) => destination.write(mem, width, result),
        (TableOp::Sum, Width::Single) => destination.write(mem, Width::Double, result),
        (TableOp::Sum, Width::Double) => {
            destination.write(mem, Width::Double, result);
            if !matches!(destination, Place::Digits(..)) {
                destination
                    .nth(1, Width::Double)
                    .write(mem, Width::Double, result >> 32);
            }
        }
    }
}

/// A SORT, SORT2 or DSORT2 table and how to sort it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SortJob {
    pub source: Place,
    pub destination: Place,
    /// N1: rows (1..32), N2: columns (1..6), N3: the key column (1..N2).
    pub rows: u32,
    pub columns: u32,
    pub key: u32,
    /// SORT2/DSORT2 lay the table out row by row; SORT column by column.
    pub row_major: bool,
    pub width: Width,
    /// SM165: descending (SORT2/DSORT2).
    pub descending: bool,
    /// The P form sorts at once in the scan its input rises.
    pub at_once: bool,
}

/// Most rows and columns of a sort table.
pub const SORT_MAX_ROWS: u32 = 32;
pub const SORT_MAX_COLUMNS: u32 = 6;
/// SORTs and SORT2/DSORT2s that may be in progress at once.
pub const SORT_LIMIT: u32 = 1;
pub const SORT2_LIMIT: u32 = 2;

impl SortJob {
    /// The unit of row `row`, column `column` (0-based).
    fn unit(&self, row: u32, column: u32) -> u32 {
        if self.row_major {
            row * self.columns + column
        } else {
            column * self.rows + row
        }
    }
}

/// One execution, with its input ON, of the sort instruction `instance`
/// whose operands the compiled code checked: start it (unless too many of
/// its kind are in progress: 4089H against `line`), count its scans, and in
/// its N1-th scan (at once for the P form) sort S into D and set SM229.
/// SM229 shows afterwards whether this instance has finished.
pub fn sort_scan(mem: &mut ImageMut<'_>, instance: u32, job: &SortJob, line: u32) {
    use crate::memory::{SORT2_RUNNING, SORT_DONE, SORT_IDLE, SORT_RUNNING};
    use crate::special::{OperationError, SM_SORT_DONE};
    if !mem.holds(Array::SortState, instance) {
        return;
    }
    let running = if job.row_major { SORT2_RUNNING } else { SORT_RUNNING };
    if mem.get_u8(Array::SortState, instance) == SORT_IDLE {
        let limit = if job.row_major { SORT2_LIMIT } else { SORT_LIMIT };
        let busy = (0..SORT_INSTANCES)
            .filter(|&other| mem.get_u8(Array::SortState, other) == running)
            .count() as u32;
        if busy >= limit {
            mem.record_error(OperationError::TooManyInstructions, line);
            mem.set_u8(Array::Sm, SM_SORT_DONE.number, 0);
            return;
        }
        mem.set_u8(Array::SortState, instance, running);
        mem.set_u8(Array::SortScans, instance, 0);
    }
    if mem.get_u8(Array::SortState, instance) == running {
        let scans = mem.get_u8(Array::SortScans, instance).saturating_add(1);
        mem.set_u8(Array::SortScans, instance, scans);
        if job.at_once || u32::from(scans) >= job.rows {
            sort_table(mem, job);
            mem.set_u8(Array::SortState, instance, SORT_DONE);
        }
    }
    let done = mem.get_u8(Array::SortState, instance) == SORT_DONE;
    mem.set_u8(Array::Sm, SM_SORT_DONE.number, u8::from(done));
}

/// The sort instruction `instance` executed with its input OFF: whatever it
/// was doing ends, and it may start again.
pub fn sort_stop(mem: &mut ImageMut<'_>, instance: u32) {
    mem.set_u8(Array::SortState, instance, crate::memory::SORT_IDLE);
    mem.set_u8(Array::SortScans, instance, 0);
}

/// Sorts the rows of the table by the key column, stably, from S into D
/// (every value read before any is written, so S may be D).
fn sort_table(mem: &mut ImageMut<'_>, job: &SortJob) {
    const CELLS: usize = (SORT_MAX_ROWS * SORT_MAX_COLUMNS) as usize;
    let rows = job.rows.min(SORT_MAX_ROWS);
    let columns = job.columns.min(SORT_MAX_COLUMNS);
    let key = job.key.clamp(1, columns.max(1)) - 1;
    let mut cells = [0i32; CELLS];
    for row in 0..rows {
        for column in 0..columns {
            let place = job.source.nth(job.unit(row, column), job.width);
            cells[(row * columns + column) as usize] = place.read(mem, job.width);
        }
    }
    // Insertion sort of row numbers: stable, and no allocation.
    let mut order = [0u8; SORT_MAX_ROWS as usize];
    for (row, slot) in order.iter_mut().enumerate() {
        *slot = row as u8;
    }
    let key_of = |row: u8| cells[(u32::from(row) * columns + key) as usize];
    for i in 1..rows as usize {
        let mut j = i;
        while j > 0 {
            let (before, here) = (key_of(order[j - 1]), key_of(order[j]));
            let out_of_order = if job.descending { before < here } else { before > here };
            if !out_of_order {
                break;
            }
            order.swap(j - 1, j);
            j -= 1;
        }
    }
    for (row, &from) in order.iter().take(rows as usize).enumerate() {
        for column in 0..columns {
            let value = cells[(u32::from(from) * columns + column) as usize];
            let place = job.destination.nth(job.unit(row as u32, column), job.width);
            place.write(mem, job.width, i64::from(value));
        }
    }
}

/// Calls `each` with the bytes BCC and CRC work on: in 16-bit mode the low
/// then the high byte of each word from `source`; in 8-bit mode (SM161) the
/// low byte of each.
fn for_each_check_byte(mem: &ImageMut<'_>, source: Place, count: u32, eight_bit: bool, mut each: impl FnMut(u8)) {
    let words = if eight_bit { count } else { count.div_ceil(2) };
    let mut left = count;
    let mut take = |word: i64| {
        for byte in [word as u8, (word >> 8) as u8]
            .into_iter()
            .take(if eight_bit { 1 } else { 2 })
        {
            if left > 0 {
                each(byte);
                left -= 1;
            }
        }
    };
    for unit in 0..words {
        take(i64::from(source.nth(unit, Width::Single).read(mem, Width::Single)));
    }
}

fn eight_bit_mode(mem: &ImageMut<'_>) -> bool {
    mem.get_u8(Array::Sm, crate::special::SM_EIGHT_BIT_MODE.number) != 0
}

/// BCC: the block check of `count` bytes from `source` by `method` (0 add,
/// 1 subtract from 0, 2 exclusive OR) into the low byte of `destination`,
/// whose high byte stays.
pub fn block_check(mem: &mut ImageMut<'_>, method: u32, source: Place, count: u32, destination: Place) {
    let eight_bit = eight_bit_mode(mem);
    let (mut sum, mut xor) = (0u8, 0u8);
    for_each_check_byte(mem, source, count, eight_bit, |byte| {
        sum = sum.wrapping_add(byte);
        xor ^= byte;
    });
    let code = match method {
        0 => sum,
        1 => 0u8.wrapping_sub(sum),
        2 => xor,
        _ => return,
    };
    let high = destination.read(mem, Width::Single) & !0xFF;
    destination.write(mem, Width::Single, i64::from(high | i32::from(code)));
}

/// CRC-16/MODBUS of `count` bytes from `source`: in 16-bit mode the CRC
/// word to `destination`; in 8-bit mode its low byte to `destination` and
/// its high byte to the next word.
pub fn crc(mem: &mut ImageMut<'_>, source: Place, count: u32, destination: Place) {
    // Slice-by-16 tables: the fastest of the crate on 256 bytes.
    const MODBUS: crc::Crc<u16, crc::Table<16>> = crc::Crc::<u16, crc::Table<16>>::new(&crc::CRC_16_MODBUS);
    let eight_bit = eight_bit_mode(mem);
    // The bytes, at most 256, go to the crc crate as one slice.
    let mut bytes = [0u8; 256];
    let mut filled = 0;
    for_each_check_byte(mem, source, count.min(256), eight_bit, |byte| {
        bytes[filled] = byte;
        filled += 1;
    });
    let code = MODBUS.checksum(&bytes[..filled]);
    if eight_bit {
        destination.write(mem, Width::Single, i64::from(code & 0xFF));
        destination
            .nth(1, Width::Single)
            .write(mem, Width::Single, i64::from(code >> 8));
    } else {
        destination.write(mem, Width::Single, i64::from(code));
    }
}

/// ANR: the lowest alarm state S900-S999 that is ON turns OFF.
pub fn alarm_reset(mem: &mut ImageMut<'_>) {
    use crate::special::{FIRST_ALARM_STATE, LAST_ALARM_STATE};
    if let Some(state) = (FIRST_ALARM_STATE..=LAST_ALARM_STATE).find(|&s| mem.get_u8(Array::S, s) != 0) {
        mem.set_u8(Array::S, state, 0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::memory::Memory;

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
                            &mut mem.image(),
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
            &mut mem.image(),
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
            &mut mem.image(),
            Place::Word(WordArea::D, 0),
            Place::Word(WordArea::D, 1),
            3,
            Width::Single,
            false,
        );
        assert_eq!(&mem.d[..4], &[1, 1, 2, 3]);
        block_move(
            &mut mem.image(),
            Place::Word(WordArea::D, 1),
            Place::Word(WordArea::D, 0),
            3,
            Width::Single,
            false,
        );
        assert_eq!(&mem.d[..4], &[1, 2, 3, 3]);
        block_move(
            &mut mem.image(),
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
            &mut mem.image(),
            Place::Digits(BitArea::M, 100, 1),
            Place::Digits(BitArea::M, 104, 2),
            2,
            Width::Single,
            false,
        );
        assert_eq!(mem.digits(BitArea::M, 104, 4), Some(0x0A05));
    }

    /// Each unit of the source as it was before the move, written in order:
    /// what a block move means, however the runs overlap.
    fn moved_as_a_whole(mem: &mut Memory, source: Place, destination: Place, n: u32) -> Box<Memory> {
        let mut expected = Memory::new_boxed();
        bytemuck::bytes_of_mut(&mut *expected).copy_from_slice(bytemuck::bytes_of(&*mem));
        let values: Vec<i32> = (0..n)
            .map(|unit| source.nth(unit, Width::Single).read(&expected.image(), Width::Single))
            .collect();
        for (unit, value) in (0..n).zip(values) {
            destination
                .nth(unit, Width::Single)
                .write(&mut expected.image(), Width::Single, i64::from(value));
        }
        block_move(&mut mem.image(), source, destination, n, Width::Single, false);
        expected
    }

    #[test]
    fn block_moves_over_one_array_in_different_units_overlap_as_a_whole() {
        let cases = [
            // A word and the bits of words of the same area, both ways.
            (Place::Word(WordArea::D, 0), Place::WordBit(WordArea::D, 8), 12),
            (Place::WordBit(WordArea::D, 4), Place::Word(WordArea::D, 0), 20),
            // Digit groups and single relays of the same area, both ways.
            (Place::Digits(BitArea::M, 0, 2), Place::Bit(BitArea::M, 3), 10),
            (Place::Bit(BitArea::M, 2), Place::Digits(BitArea::M, 0, 1), 6),
            // The same kind and size, overlapping forwards and backwards.
            (Place::WordBit(WordArea::D, 0), Place::WordBit(WordArea::D, 5), 30),
            (Place::Bit(BitArea::M, 9), Place::Bit(BitArea::M, 2), 30),
        ];
        for (source, destination, n) in cases {
            let mut mem = Memory::new_boxed();
            for (k, word) in mem.d[..4].iter_mut().enumerate() {
                *word = [0x1234, -0x5A5B, 0x0F0F, 0x7001][k];
            }
            for (k, relay) in mem.m[..40].iter_mut().enumerate() {
                *relay = u8::from((k * 7 + 3) % 5 < 2);
            }
            let expected = moved_as_a_whole(&mut mem, source, destination, n);
            assert!(
                bytemuck::bytes_of(&*mem) == bytemuck::bytes_of(&*expected),
                "{source:?} -> {destination:?} x{n}"
            );
        }
    }

    #[test]
    fn crc_of_the_seed_example() {
        let mut mem = Memory::new_boxed();
        mem.d[100..103].copy_from_slice(&[0x0301, 0x0203, 0x1400]);
        crc(
            &mut mem.image(),
            Place::Word(WordArea::D, 100),
            6,
            Place::Word(WordArea::D, 0),
        );
        assert_eq!(mem.d[0] as u16, 0x41E4);
        mem.sm[161] = 1;
        mem.d[100..106].copy_from_slice(&[0x01, 0x03, 0x03, 0x02, 0x00, 0x14]);
        crc(
            &mut mem.image(),
            Place::Word(WordArea::D, 100),
            6,
            Place::Word(WordArea::D, 0),
        );
        assert_eq!((mem.d[0], mem.d[1]), (0xE4, 0x41));
    }

    #[test]
    fn block_checks_of_the_seed_example() {
        let mut mem = Memory::new_boxed();
        // "%01#RC": D0 = H3025, D1 = H2331, D2 = H4352.
        mem.d[..3].copy_from_slice(&[0x3025, 0x2331, 0x4352]);
        mem.d[6] = 0x7700;
        for (method, code) in [(2, 0x16), (0, 0x3E), (1, 0xC2)] {
            block_check(
                &mut mem.image(),
                method,
                Place::Word(WordArea::D, 0),
                6,
                Place::Word(WordArea::D, 6),
            );
            assert_eq!(mem.d[6], 0x7700 | code, "method {method}");
        }
    }

    #[test]
    fn sorts_are_stable_and_follow_the_layout() {
        let mut mem = Memory::new_boxed();
        // The seed's SORT2 table: 5 rows x 4 columns, sorted by column 2.
        let table = [
            [1, 150, 45, 20],
            [2, 180, 50, 40],
            [3, 160, 70, 30],
            [4, 100, 20, 8],
            [5, 150, 50, 45],
        ];
        for (r, row) in table.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                mem.d[r * 4 + c] = v;
            }
        }
        let job = SortJob {
            source: Place::Word(WordArea::D, 0),
            destination: Place::Word(WordArea::D, 100),
            rows: 5,
            columns: 4,
            key: 2,
            row_major: true,
            width: Width::Single,
            descending: false,
            at_once: true,
        };
        sort_scan(&mut mem.image(), 0, &job, 1);
        let firsts: Vec<i16> = (0..5).map(|r| mem.d[100 + 4 * r]).collect();
        assert_eq!(firsts, [4, 1, 5, 3, 2], "equal keys 150 keep their order");
        assert_eq!(mem.sm[229], 1);
    }

    #[test]
    fn zones_and_searches() {
        let mut mem = Memory::new_boxed();
        zone(&mut mem.image(), Zone::Bits(BitArea::M), 3, 1, true);
        assert_eq!(&mem.m[..5], &[0, 0, 0, 1, 0], "last below first: first alone");
        zone(&mut mem.image(), Zone::WordBits(WordArea::D), 14, 17, true);
        assert_eq!((mem.d[0], mem.d[1]), (-16384, 3));
        assert_eq!(highest_on(&mem.image(), Place::Bit(BitArea::M, 0), 8), 3);
        assert_eq!(highest_on(&mem.image(), Place::Bit(BitArea::M, 4), 8), -1);
        for code in 0..64 {
            if let Some(zone) = Zone::from_code(code) {
                assert_eq!(zone.code(), code);
            }
        }
    }
}
