//! Reading and writing operands, with the offset rules of docs/language.md:
//! contacts and coils clamp an out-of-range `DEV[Dk]` to the nearest valid
//! device and record an operation error; application instructions refuse it
//! (4085H reading, 4086H writing) and do not execute.

use ladder_front::program::{Address, BitRef, WordRef};
use ladder_runtime::device::FIRST_WIDE_COUNTER;
use ladder_runtime::{Memory, OperationError, Place, Width};

/// The device number an address names now: base plus the offset register's
/// current (signed) value.
pub fn effective_index(mem: &Memory, address: Address) -> i64 {
    let offset = address.index_register.map_or(0, |register| {
        i64::from(mem.word(register.area, register.number).unwrap_or(0))
    });
    i64::from(address.index) + offset
}

/// Clamps `index` into `0..len`; reports whether it had to.
fn clamp(index: i64, len: u32) -> (u32, bool) {
    let clamped = index.clamp(0, i64::from(len) - 1);
    (clamped as u32, clamped != index)
}

/// Where a bit lives: a bit device, or a bit of a word.
pub fn bit_place(bit: BitRef, index: u32) -> Place {
    match bit {
        BitRef::Device(area, _) => Place::Bit(area, index),
        BitRef::WordBit(area, _, b) => Place::WordBit(area, 16 * index + u32::from(b)),
    }
}

/// Resolves a bit for a contact or coil: an out-of-range index register
/// brings the device into its area and records `error`.
pub fn clamp_bit(mem: &mut Memory, bit: BitRef, error: OperationError, line: u32) -> Place {
    let (address, len) = match bit {
        BitRef::Device(area, address) => (address, area.count()),
        BitRef::WordBit(area, address, _) => (address, area.count()),
    };
    let (index, clamped) = clamp(effective_index(mem, address), len);
    if clamped {
        mem.record_error(error, line);
    }
    bit_place(bit, index)
}

pub fn read_place(mem: &Memory, place: Place) -> bool {
    place.read(mem, Width::Single) != 0
}

pub fn write_place(mem: &mut Memory, place: Place, on: bool) {
    place.write(mem, Width::Single, i64::from(on));
}

/// Reads a contact's bit (clamping, 4085H).
pub fn read_bit(mem: &mut Memory, bit: BitRef, line: u32) -> bool {
    let place = clamp_bit(mem, bit, OperationError::ReadOutOfRange, line);
    read_place(mem, place)
}

/// Writes a coil's bit (clamping, 4086H).
pub fn write_bit(mem: &mut Memory, bit: BitRef, on: bool, line: u32) {
    let place = clamp_bit(mem, bit, OperationError::WriteOutOfRange, line);
    write_place(mem, place, on);
}

/// Resolves a word operand of an application instruction covering `units`
/// values of `width` (a MUL result is 2 units, BMOV n is n units).
/// `None` when any of it is outside its area.
pub fn resolve_word(mem: &Memory, word: WordRef, width: Width, units: u32) -> Option<Place> {
    // In 64 bits: a unit count can be as large as an I32 holds.
    let in_range = |index: i64, needed: u64, len: u32| index >= 0 && index as u64 + needed <= u64::from(len);
    let units = u64::from(units);
    match word {
        WordRef::Constant(value) => Some(Place::Constant(value)),
        WordRef::Word(area, address) => {
            let index = effective_index(mem, address);
            let (first, end) = area.reach(address.index);
            let from_first = index - i64::from(first);
            (from_first >= 0 && in_range(index, u64::from(width.words()) * units, end))
                .then_some(Place::Word(area, index as u32))
        }
        WordRef::WideCounter(address) => {
            let index = effective_index(mem, address);
            let first = i64::from(FIRST_WIDE_COUNTER);
            let slot = index - first;
            (slot >= 0 && in_range(slot, units, ladder_runtime::device::WIDE_COUNTER_COUNT))
                .then_some(Place::WideCounter(index as u32))
        }
        WordRef::Digits(area, address, digits) => {
            let index = effective_index(mem, address);
            in_range(index, 4 * u64::from(digits) * units, area.count()).then_some(Place::Digits(
                area,
                index as u32,
                digits,
            ))
        }
    }
}

/// A comparison contact's word operand clamped into its area (the contact
/// rule), for when `resolve_word` refused it.
pub fn clamp_word(mem: &Memory, word: WordRef, width: Width) -> Place {
    let clamp_start = |address: Address, first: u32, span: u32, len: u32| {
        let last = i64::from(len) - i64::from(span);
        effective_index(mem, address).clamp(i64::from(first), last) as u32
    };
    match word {
        WordRef::Constant(value) => Place::Constant(value),
        WordRef::Word(area, address) => {
            let (first, end) = area.reach(address.index);
            Place::Word(area, clamp_start(address, first, width.words(), end))
        }
        WordRef::WideCounter(address) => Place::WideCounter(clamp_start(
            address,
            FIRST_WIDE_COUNTER,
            1,
            ladder_runtime::device::COUNTER_COUNT,
        )),
        WordRef::Digits(area, address, digits) => Place::Digits(
            area,
            clamp_start(address, 0, 4 * u32::from(digits), area.count()),
            digits,
        ),
    }
}
