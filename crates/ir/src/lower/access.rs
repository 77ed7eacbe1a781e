//! Device access in the lowering, with the offset rules of docs/language.md for
//! contacts and coils: an out-of-range `DEV[Dk]` uses the nearest valid
//! device and records an operation error.

use super::operand::Operand;
use super::Lowering;
use crate::CompareOp;
use crate::{BinOp, Cell, Index, Inst, Type, Value};
use ladder_front::program::{Address, BitRef, IndexRegister, WordRef};
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER};
use ladder_runtime::{OperationError, Width};

impl Lowering<'_> {
    /// `base` plus the index register's signed value, as an I32.
    pub(super) fn indexed(&mut self, base: u32, register: IndexRegister) -> Value {
        let offset = self.b.load(Cell::Word {
            area: register.area,
            index: Index::Fixed(register.number),
        });
        let offset = self.b.extend(offset, Type::I32, true);
        let base = self.b.constant(Type::I32, i64::from(base));
        self.b.binary(BinOp::Add, base, offset)
    }

    /// The address brought into `first..=last`; leaving that range records
    /// `error`.
    pub(super) fn clamped_index(
        &mut self,
        address: Address,
        first: u32,
        last: u32,
        error: OperationError,
        line: u32,
    ) -> Index {
        let Some(register) = address.index_register else {
            return Index::Fixed(address.index);
        };
        let index = self.indexed(address.index, register);
        let low = self.b.constant(Type::I32, i64::from(first));
        let high = self.b.constant(Type::I32, i64::from(last));
        let below = self.b.compare(CompareOp::Lt, index, low);
        let above = self.b.compare(CompareOp::Gt, index, high);
        let outside = self.b.or(below, above);
        self.b.if_then(outside, |b| b.effect(Inst::RecordError { error, line }));
        let upper = self.b.select(above, high, index);
        Index::Dynamic(self.b.select(below, low, upper))
    }

    pub(super) fn read_bit(&mut self, bit: BitRef, line: u32) -> Value {
        match bit {
            BitRef::Device(area, address) => {
                let index = self.clamped_index(address, 0, area.count() - 1, OperationError::ReadOutOfRange, line);
                self.b.load_bit(area, index)
            }
            BitRef::WordBit(area, address, bit) => {
                let index = self.clamped_index(address, 0, area.count() - 1, OperationError::ReadOutOfRange, line);
                let mask = self.b.constant(Type::I32, 1 << bit);
                self.load_word_bit(area, index, mask)
            }
        }
    }

    pub(super) fn write_bit(&mut self, bit: BitRef, value: Value, line: u32) {
        match bit {
            BitRef::Device(area, address) => {
                let index = self.clamped_index(address, 0, area.count() - 1, OperationError::WriteOutOfRange, line);
                self.b.store_bit(area, index, value);
            }
            BitRef::WordBit(area, address, bit) => {
                let index = self.clamped_index(address, 0, area.count() - 1, OperationError::WriteOutOfRange, line);
                let mask = self.b.constant(Type::I32, 1 << bit);
                self.store_word_bit(area, index, mask, value);
            }
        }
    }

    /// SET/RST of `count` bits; an offset start is clamped so the run fits.
    pub(super) fn write_bits(&mut self, bit: BitRef, count: u32, on: bool, line: u32) {
        match bit {
            BitRef::Device(area, address) => {
                let start = self.clamped_index(address, 0, area.count() - count, OperationError::WriteOutOfRange, line);
                self.b.effect(Inst::FillBits { area, start, count, on });
            }
            BitRef::WordBit(..) => {
                let value = self.b.bit(on);
                self.write_bit(bit, value, line);
            }
        }
    }

    /// A comparison contact's operand as an I64: out of range, it reads the
    /// nearest valid device and records 4085H, like any contact.
    pub(super) fn compare_operand(&mut self, word: WordRef, width: Width, line: u32) -> Value {
        let error = OperationError::ReadOutOfRange;
        let operand = match word {
            WordRef::Constant(value) => Operand::Constant(i64::from(value)),
            WordRef::Word(area, address) => {
                let span = width.words();
                let (first, end) = area.reach(address.index);
                Operand::Word(area, self.clamped_index(address, first, end - span, error, line))
            }
            WordRef::WideCounter(address) => {
                Operand::WideCounter(self.clamped_index(address, FIRST_WIDE_COUNTER, COUNTER_COUNT - 1, error, line))
            }
            WordRef::Digits(area, address, digits) => {
                let span = 4 * u32::from(digits);
                Operand::Digits(
                    area,
                    self.clamped_index(address, 0, area.count() - span, error, line),
                    digits,
                )
            }
        };
        self.read(&operand, width)
    }
}
