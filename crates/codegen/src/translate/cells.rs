//! Loads and stores of the IR's cells: where each kind of cell lies in the
//! image and how its value is held there (a byte per bit, a force byte, 16 or
//! 32 bits: `Cell::held`); and a load that makes the extension after it
//! itself (`extending_load`).

use super::{cl_type, flags, Translator};
use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{types, InstBuilder, MemFlagsData, Value};
use ladder_ir::{self as ir, Cell, Held, Inst, Type};

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

    /// A load; of a number whose extension comes next (`extending_load`),
    /// the extending load, which takes `extending_load` for done.
    pub(super) fn load_at(&mut self, ty: types::Type, (address, offset): (Value, i32)) -> Value {
        let ins = self.builder.ins();
        let extended = match (self.extending_load, ty) {
            (Some((to, true)), types::I16) => ins.sload16(to, flags(), address, offset),
            (Some((to, false)), types::I16) => ins.uload16(to, flags(), address, offset),
            (Some((types::I64, true)), types::I32) => ins.sload32(flags(), address, offset),
            (Some((types::I64, false)), types::I32) => ins.uload32(flags(), address, offset),
            _ => return ins.load(ty, flags(), address, offset),
        };
        self.extending_load = None;
        extended
    }
}

/// The extension a load of a number makes itself (`sload16` and the
/// like, one instruction instead of two: Cranelift does not fold a load
/// into an extension to 64 bits): when the load's one use is the
/// extension right after it. The type and signedness to extend to.
pub(super) fn extending_load(
    func: &ir::Function,
    inst: &Inst,
    result: ir::Value,
    next: Option<&(Option<ir::Value>, Inst)>,
    uses: &[u32],
) -> Option<(types::Type, bool)> {
    let number = matches!(func.value_type(result), Type::I16 | Type::I32);
    let load = matches!(inst.effect(), ir::Effect::Load(_)) || matches!(inst, Inst::LoadElapsed);
    let Some((_, Inst::Extend { value, to, signed })) = next else {
        return None;
    };
    (number && load && *value == result && uses[result.0 as usize] == 1).then_some((cl_type(*to), *signed))
}
