//! Word operands in the lowering: resolving a `WordRef` to an IR operand
//! (with an in-range test when the range is not known at compile time), and
//! reading and writing operands at a width.

use super::Lowering;
use crate::CompareOp;
use crate::{BinOp, Cell, Index, Type, Value};
use ladder_front::program::WordRef;
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER};
use ladder_runtime::place::PlaceKind;
use ladder_runtime::{BitArea, Width, WordArea};

/// A resolved operand: where a value lives, with its index in the IR (the
/// lowering's counterpart of the runtime's `Place`).
#[derive(Clone, Copy, Debug)]
pub(super) enum Operand {
    Constant(i64),
    Word(WordArea, Index),
    WideCounter(Index),
    Digits(BitArea, Index, u8),
    /// One bit device (value 0 or 1).
    Bit(BitArea, Index),
    /// One bit of a word, numbered through the area (16·word + bit).
    WordBit(WordArea, Index),
}

/// How many values an operand covers.
#[derive(Clone, Copy, Debug)]
pub(super) enum Units {
    /// A count the checker already proved to fit at a fixed address.
    Checked(u32),
    /// A count known only at run time (BMOV/FMOV n), an I32.
    Dynamic(Value),
}

impl Lowering<'_> {
    /// Resolves a word operand: the operand, and an in-range test (a Bit)
    /// when the range is not known to hold at compile time.
    pub(super) fn resolve(&mut self, word: WordRef, width: Width, units: Units) -> (Operand, Option<Value>) {
        let (address, first, len, per_unit) = match word {
            WordRef::Constant(value) => return (Operand::Constant(i64::from(value)), None),
            WordRef::Word(area, address) => {
                let (first, end) = area.reach(address.index);
                (address, first, end, width.words())
            }
            WordRef::WideCounter(address) => (address, FIRST_WIDE_COUNTER, COUNTER_COUNT, 1),
            WordRef::Digits(area, address, digits) => (address, 0, area.count(), 4 * u32::from(digits)),
        };
        let statically_fine = address.is_fixed() && matches!(units, Units::Checked(_));
        let (index, check) = if statically_fine {
            (Index::Fixed(address.index), None)
        } else {
            let index = match address.index_register {
                Some(register) => self.indexed(address.index, register),
                None => self.b.constant(Type::I32, i64::from(address.index)),
            };
            // The end in 64 bits: a count known only at run time may be
            // as large as an I32 holds, and must not wrap.
            let units = match units {
                Units::Checked(n) => self.b.constant(Type::I64, i64::from(n)),
                Units::Dynamic(n) => self.b.extend(n, Type::I64, true),
            };
            let per_unit = self.b.constant(Type::I64, i64::from(per_unit));
            let span = self.b.binary(BinOp::Mul, units, per_unit);
            let start = self.b.extend(index, Type::I64, true);
            let end = self.b.binary(BinOp::Add, start, span);
            let low = self.b.constant(Type::I32, i64::from(first));
            let high = self.b.constant(Type::I64, i64::from(len));
            let above_first = self.b.compare(CompareOp::Ge, index, low);
            let fits = self.b.compare(CompareOp::Le, end, high);
            (Index::Dynamic(index), Some(self.b.and(above_first, fits)))
        };
        let operand = match word {
            WordRef::Constant(value) => Operand::Constant(i64::from(value)),
            WordRef::Word(area, _) => Operand::Word(area, index),
            WordRef::WideCounter(_) => Operand::WideCounter(index),
            WordRef::Digits(area, _, digits) => Operand::Digits(area, index, digits),
        };
        (operand, check)
    }

    /// `value` wrapped to `width`, sign-extended again to I64.
    pub(super) fn wrap(&mut self, value: Value, width: Width) -> Value {
        let narrow = self.b.truncate(value, width_type(width));
        self.b.extend(narrow, Type::I64, true)
    }

    pub(super) fn index_plus(&mut self, index: Index, delta: u32) -> Index {
        match index {
            Index::Fixed(n) => Index::Fixed(n + delta),
            Index::Dynamic(_) if delta == 0 => index,
            Index::Dynamic(value) => {
                let delta = self.b.constant(Type::I32, i64::from(delta));
                Index::Dynamic(self.b.binary(BinOp::Add, value, delta))
            }
        }
    }

    /// `index` plus an I32 computed at run time.
    pub(super) fn index_plus_value(&mut self, index: Index, delta: Value) -> Index {
        let base = match index {
            Index::Fixed(n) => self.b.constant(Type::I32, i64::from(n)),
            Index::Dynamic(value) => value,
        };
        Index::Dynamic(self.b.binary(BinOp::Add, base, delta))
    }

    /// The `unit`-th value from an operand.
    pub(super) fn nth(&mut self, operand: &Operand, unit: u32, width: Width) -> Operand {
        match *operand {
            Operand::Constant(_) => *operand,
            Operand::Word(area, index) => Operand::Word(area, self.index_plus(index, unit * width.words())),
            Operand::WideCounter(index) => Operand::WideCounter(self.index_plus(index, unit)),
            Operand::Digits(area, start, digits) => {
                Operand::Digits(area, self.index_plus(start, unit * 4 * u32::from(digits)), digits)
            }
            Operand::Bit(area, index) => Operand::Bit(area, self.index_plus(index, unit)),
            Operand::WordBit(area, index) => Operand::WordBit(area, self.index_plus(index, unit)),
        }
    }

    /// The word and the bit mask of a word bit numbered through its area.
    fn word_bit(&mut self, index: Index) -> (Index, Value) {
        match index {
            Index::Fixed(n) => {
                let mask = self.b.constant(Type::I32, 1 << (n % 16));
                (Index::Fixed(n / 16), mask)
            }
            Index::Dynamic(n) => {
                let four = self.b.constant(Type::I32, 4);
                let word = self.b.binary(BinOp::Shr, n, four);
                let fifteen = self.b.constant(Type::I32, 15);
                let bit = self.b.binary(BinOp::And, n, fifteen);
                let one = self.b.constant(Type::I32, 1);
                let mask = self.b.binary(BinOp::Shl, one, bit);
                (Index::Dynamic(word), mask)
            }
        }
    }

    /// Reads an operand at the instruction's width as an I64: 16-bit words
    /// sign-extended, digit groups narrower than the width zero-extended.
    pub(super) fn read(&mut self, operand: &Operand, width: Width) -> Value {
        let wide = width == Width::Double;
        match *operand {
            Operand::Constant(value) => self.b.constant(Type::I64, value),
            Operand::Word(area, index) if wide => {
                let low = self.b.load(Cell::Word { area, index });
                let high_index = self.index_plus(index, 1);
                let high = self.b.load(Cell::Word {
                    area,
                    index: high_index,
                });
                let low = self.b.extend(low, Type::I32, false);
                let high = self.b.extend(high, Type::I32, true);
                let sixteen = self.b.constant(Type::I32, 16);
                let high = self.b.binary(BinOp::Shl, high, sixteen);
                let joined = self.b.binary(BinOp::Or, high, low);
                self.b.extend(joined, Type::I64, true)
            }
            Operand::Word(area, index) => {
                let word = self.b.load(Cell::Word { area, index });
                self.b.extend(word, Type::I64, true)
            }
            Operand::WideCounter(index) => {
                let value = self.b.load(Cell::WideCounter { index });
                self.b.extend(value, Type::I64, true)
            }
            Operand::Digits(area, start, digits) => {
                let mut bits = self.b.constant(Type::I32, 0);
                for bit in 0..4 * u32::from(digits) {
                    let index = self.index_plus(start, bit);
                    let on = self.b.load_bit(area, index);
                    let on = self.b.extend(on, Type::I32, false);
                    let shift = self.b.constant(Type::I32, i64::from(bit));
                    let placed = self.b.binary(BinOp::Shl, on, shift);
                    bits = self.b.binary(BinOp::Or, bits, placed);
                }
                if wide {
                    self.b.extend(bits, Type::I64, true)
                } else {
                    let word = self.b.truncate(bits, Type::I16);
                    self.b.extend(word, Type::I64, true)
                }
            }
            Operand::Bit(area, index) => {
                let on = self.b.load_bit(area, index);
                self.b.extend(on, Type::I64, false)
            }
            Operand::WordBit(area, index) => {
                let (index, mask) = self.word_bit(index);
                let on = self.load_word_bit(area, index, mask);
                self.b.extend(on, Type::I64, false)
            }
        }
    }

    /// Writes the low bits of an I64 that the operand holds.
    pub(super) fn write(&mut self, operand: &Operand, width: Width, value: Value) {
        let wide = width == Width::Double;
        match *operand {
            Operand::Constant(_) => {}
            Operand::Word(area, index) => {
                let low = self.b.truncate(value, Type::I16);
                self.b.store(Cell::Word { area, index }, low);
                if wide {
                    let sixteen = self.b.constant(Type::I64, 16);
                    let high = self.b.binary(BinOp::Shr, value, sixteen);
                    let high = self.b.truncate(high, Type::I16);
                    let high_index = self.index_plus(index, 1);
                    self.b.store(
                        Cell::Word {
                            area,
                            index: high_index,
                        },
                        high,
                    );
                }
            }
            Operand::WideCounter(index) => {
                let value = self.b.truncate(value, Type::I32);
                self.b.store(Cell::WideCounter { index }, value);
            }
            Operand::Digits(area, start, digits) => {
                let one = self.b.constant(Type::I64, 1);
                let zero = self.b.constant(Type::I64, 0);
                for bit in 0..4 * u32::from(digits) {
                    let shift = self.b.constant(Type::I64, i64::from(bit));
                    let shifted = self.b.binary(BinOp::Shr, value, shift);
                    let masked = self.b.binary(BinOp::And, shifted, one);
                    let on = self.b.compare(CompareOp::Ne, masked, zero);
                    let index = self.index_plus(start, bit);
                    self.b.store_bit(area, index, on);
                }
            }
            Operand::Bit(area, index) => {
                let on = self.low_bit(value);
                self.b.store_bit(area, index, on);
            }
            Operand::WordBit(area, index) => {
                let on = self.low_bit(value);
                let (index, mask) = self.word_bit(index);
                self.store_word_bit(area, index, mask, on);
            }
        }
    }

    /// The bit of word `index` that `mask` (an I32 with one bit set) picks.
    pub(super) fn load_word_bit(&mut self, area: WordArea, index: Index, mask: Value) -> Value {
        let word = self.b.load(Cell::Word { area, index });
        let word = self.b.extend(word, Type::I32, true);
        let masked = self.b.binary(BinOp::And, word, mask);
        let zero = self.b.constant(Type::I32, 0);
        self.b.compare(CompareOp::Ne, masked, zero)
    }

    /// Sets the bit of word `index` that `mask` picks to the Bit `on`,
    /// keeping the other bits.
    pub(super) fn store_word_bit(&mut self, area: WordArea, index: Index, mask: Value, on: Value) {
        let word = self.b.load(Cell::Word { area, index });
        let word = self.b.extend(word, Type::I32, true);
        let all = self.b.constant(Type::I32, -1);
        let keep = self.b.binary(BinOp::Xor, mask, all);
        let cleared = self.b.binary(BinOp::And, word, keep);
        let zero = self.b.constant(Type::I32, 0);
        let set = self.b.select(on, mask, zero);
        let updated = self.b.binary(BinOp::Or, cleared, set);
        let updated = self.b.truncate(updated, Type::I16);
        self.b.store(Cell::Word { area, index }, updated);
    }

    /// Bit 0 of an I64 as a Bit.
    fn low_bit(&mut self, value: Value) -> Value {
        let one = self.b.constant(Type::I64, 1);
        let masked = self.b.binary(BinOp::And, value, one);
        let zero = self.b.constant(Type::I64, 0);
        self.b.compare(CompareOp::Ne, masked, zero)
    }

    /// A block operand as a packed runtime place (an I32), for helpers.
    /// Constants are not places: helpers take them as values.
    pub(super) fn place(&mut self, operand: &Operand) -> Value {
        let (kind, index) = match *operand {
            Operand::Constant(value) => return self.b.constant(Type::I32, value),
            Operand::Word(area, index) => (PlaceKind::Word(area), index),
            Operand::WideCounter(index) => (PlaceKind::WideCounter, index),
            Operand::Digits(area, index, digits) => (PlaceKind::Digits(area, digits), index),
            Operand::Bit(area, index) => (PlaceKind::Bit(area), index),
            Operand::WordBit(area, index) => (PlaceKind::WordBit(area), index),
        };
        match index {
            Index::Fixed(n) => self.b.constant(Type::I32, i64::from(kind.tag() | n)),
            Index::Dynamic(index) => {
                let tag = self.b.constant(Type::I32, i64::from(kind.tag() as i32));
                self.b.binary(BinOp::Or, tag, index)
            }
        }
    }
}

/// The IR type of a value of `width`.
pub(super) fn width_type(width: Width) -> Type {
    match width {
        Width::Single => Type::I16,
        Width::Double => Type::I32,
    }
}
