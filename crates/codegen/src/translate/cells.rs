//! Loads and stores of the IR's cells: where each kind of cell lies in the
//! image and how its value is held there (a byte per bit, a force byte, 16 or
//! 32 bits: `Cell::held`).

use super::Translator;
use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{types, InstBuilder, MemFlagsData, Value};
use ladder_ir::{Cell, Held};

impl Translator<'_, '_> {
    /// The address of a cell's first byte, as (pointer, constant offset).
    fn cell_address(&mut self, cell: &Cell, values: &[Option<Value>]) -> (Value, i32) {
        let array = cell.array();
        self.element(array, array.end() - array.first(), cell.span().start, values)
    }

    /// Loads a cell; `wide_load`: a bit that reads four bytes (`wide.rs`).
    pub(super) fn load_cell(&mut self, cell: &Cell, values: &[Option<Value>], wide_load: bool) -> Value {
        let at = self.cell_address(cell, values);
        match cell.held() {
            Held::Bit if wide_load => {
                // Unaligned, and reading three bytes past the device.
                let flags = MemFlagsData::new().with_notrap();
                self.builder.ins().load(types::I32, flags, at.0, at.1)
            }
            Held::Bit => self.load_bit_byte(at),
            Held::Force => {
                let byte = self.load_at(types::I8, at);
                self.builder.ins().icmp_imm_s(IntCC::NotEqual, byte, 0)
            }
            Held::I16 => self.load_at(types::I16, at),
            Held::I32 => self.load_at(types::I32, at),
        }
    }

    /// Stores `value` into a cell: a bit as a byte 0 or 1, a number as it is.
    pub(super) fn store_cell(&mut self, cell: &Cell, value: Value, values: &[Option<Value>]) {
        let at = self.cell_address(cell, values);
        let stored = match cell.held() {
            Held::Bit | Held::Force => self.bit_byte(value),
            Held::I16 | Held::I32 => value,
        };
        self.store_at(stored, at);
    }
}
