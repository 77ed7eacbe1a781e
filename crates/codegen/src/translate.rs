//! IR to Cranelift IR, one function. Shared by the JIT and object back ends.
//!
//! Every device access is a load or store at a fixed offset from the image
//! pointer, where the image's layout (full or compact) puts the device. A
//! run-time index is clamped into its area here once more, so no generated
//! access can leave the device image whatever the lowering did.
//!
//! Bit values are `i8` (0 or 1), except on x86-64, where they are "wide
//! bits" (`wide.rs`): `i32` values whose byte 0 is the bit, so that a
//! contact's load becomes the memory operand of its AND or OR. Wherever a
//! bit leaves bit logic (stored, tested, widened to a number, compared,
//! passed on) it is taken from byte 0.

use crate::divide;
use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{types, FuncRef, InstBuilder, MemFlagsData, Value};
use cranelift_frontend::{FunctionBuilder, Variable};
use ladder_ir::CompareOp;
use ladder_ir::{self as ir, BinOp, Conversion, FloatOp, FloatUnaryOp, Index, Inst, Terminator, Type, UnaryOp};
use ladder_runtime::helpers::Helper;
use ladder_runtime::layout::{Array, Layout, Scalar};
use rustc_hash::FxHashMap;

mod cells;

/// The Cranelift type of an IR type; a bit is an `i8` (see
/// `Translator::bit_type` for wide bits).
fn cl_type(ty: Type) -> types::Type {
    match ty {
        Type::Bit => types::I8,
        Type::I16 => types::I16,
        Type::I32 => types::I32,
        Type::I64 => types::I64,
        Type::F32 => types::F32,
        Type::F64 => types::F64,
    }
}

fn float_condition(op: CompareOp) -> FloatCC {
    match op {
        CompareOp::Eq => FloatCC::Equal,
        CompareOp::Ne => FloatCC::NotEqual,
        CompareOp::Lt => FloatCC::LessThan,
        CompareOp::Le => FloatCC::LessThanOrEqual,
        CompareOp::Gt => FloatCC::GreaterThan,
        CompareOp::Ge => FloatCC::GreaterThanOrEqual,
    }
}

fn condition(op: CompareOp) -> IntCC {
    match op {
        CompareOp::Eq => IntCC::Equal,
        CompareOp::Ne => IntCC::NotEqual,
        CompareOp::Gt => IntCC::SignedGreaterThan,
        CompareOp::Lt => IntCC::SignedLessThan,
        CompareOp::Ge => IntCC::SignedGreaterThanOrEqual,
        CompareOp::Le => IntCC::SignedLessThanOrEqual,
    }
}

/// Loads and stores of the image: aligned, never trapping (in bounds).
fn flags() -> MemFlagsData {
    MemFlagsData::trusted()
}

/// Where the master-control powers and loop counts (IR locals) live while
/// `translate` runs.
pub enum Locals {
    /// In Cranelift variables: the function is the whole program part.
    Variables,
    /// In `locals_size` bytes behind the function's second parameter,
    /// loaded at entry and stored at exit: the function is one chunk of a
    /// program part compiled as several functions.
    Memory,
}

/// Offset of loop count `level` in the locals memory: after one byte per
/// master-control power, 4-byte aligned.
fn loop_count_offset(func: &ir::Function, level: u8) -> i32 {
    (i32::from(func.locals) + 3) / 4 * 4 + 4 * i32::from(level)
}

/// Bytes of locals memory a chunked function needs.
pub fn locals_size(func: &ir::Function) -> u32 {
    loop_count_offset(func, func.loop_levels) as u32
}

/// Translates blocks `range` of `func` into the builder, whose function
/// takes the image pointer (and, with `Locals::Memory`, the locals pointer).
/// A jump to `range.end` and a return both return. `values` maps IR values
/// to Cranelift values; entries this call defines are cleared again, so one
/// vector serves every chunk.
/// `helpers` holds the imported runtime helpers in `Helper::ALL` order,
/// `subroutines` the program's subroutine functions by number; `layout` is
/// the image's.
/// With `wide_bits`, bit values are wide (x86-64, `wide.rs`).
#[allow(clippy::too_many_arguments)]
pub fn translate(
    layout: &Layout,
    func: &ir::Function,
    range: std::ops::Range<usize>,
    locals_at: Locals,
    builder: &mut FunctionBuilder,
    helpers: &[FuncRef],
    subroutines: &[FuncRef],
    pointer: types::Type,
    values: &mut [Option<Value>],
    wide_bits: bool,
) {
    let wide_loads = wide_bits.then(|| super::wide::wide_bit_loads(layout, func, range.clone()));
    let uses = func.use_counts();
    let bit_type = if wide_bits { types::I32 } else { types::I8 };
    let entry = builder.create_block();
    let blocks: Vec<_> = range.clone().map(|_| builder.create_block()).collect();
    let exit = builder.create_block();
    builder.append_block_params_for_function_params(entry);
    builder.switch_to_block(entry);
    let mem = builder.block_params(entry)[0];
    let locals_pointer = match locals_at {
        Locals::Variables => None,
        Locals::Memory => Some(builder.block_params(entry)[1]),
    };
    let locals: Vec<Variable> = (0..func.locals).map(|_| builder.declare_var(bit_type)).collect();
    let loop_counts: Vec<Variable> = (0..func.loop_levels).map(|_| builder.declare_var(types::I32)).collect();
    if let Some(at) = locals_pointer {
        for (offset, &local) in locals.iter().enumerate() {
            let value = if wide_bits {
                builder.ins().uload8(types::I32, flags(), at, offset as i32)
            } else {
                builder.ins().load(types::I8, flags(), at, offset as i32)
            };
            builder.def_var(local, value);
        }
        for (level, &count) in (0u8..).zip(&loop_counts) {
            let value = builder
                .ins()
                .load(types::I32, flags(), at, loop_count_offset(func, level));
            builder.def_var(count, value);
        }
    }
    // A subtraction, not an addition: Cranelift folds a constant added to
    // the image pointer into each address made from the sum, which would
    // make every displacement four bytes again. This holds at `opt_level`
    // none (`lib.rs`); its optimiser would turn the subtraction back into
    // that addition (`tests/commands/code_size.rs` would see it).
    let bases = if wide_bits {
        super::near::window_centres(layout, func, range.clone())
    } else {
        Vec::new()
    }
    .into_iter()
    .map(|centre| {
        let minus_centre = builder.ins().iconst(pointer, -i64::from(centre));
        (centre, builder.ins().isub(mem, minus_centre))
    })
    .collect();
    builder.ins().jump(blocks[0], &[]);
    let target = |block: ir::BlockId| {
        let index = block.0 as usize;
        if range.contains(&index) {
            blocks[index - range.start]
        } else {
            exit
        }
    };
    let mut t = Translator {
        builder,
        layout,
        mem,
        pointer,
        helpers,
        subroutines,
        locals,
        loop_counts,
        value_types: &func.value_types,
        wide_bits,
        negations: FxHashMap::default(),
        extending_load: None,
        bases,
    };
    let mut defined = Vec::new();
    for number in range.clone() {
        let block = &func.blocks[number];
        t.builder.switch_to_block(blocks[number - range.start]);
        if block.cold {
            // Laid out after the rest of the function.
            t.builder.set_cold_block(blocks[number - range.start]);
        }
        // The value a load made already extended, for the next instruction.
        let mut extended: Option<Value> = None;
        for (position, (result, inst)) in block.insts.iter().enumerate() {
            if let (Some(result), Some(value)) = (result, extended.take()) {
                values[result.0 as usize] = Some(value);
                defined.push(*result);
                continue;
            }
            let fuse = result
                .and_then(|result| cells::extending_load(func, inst, result, block.insts.get(position + 1), &uses));
            t.extending_load = fuse;
            let wide_load = wide_loads
                .as_ref()
                .is_some_and(|wide| wide[number - range.start][position]);
            let value = t.inst(inst, values, wide_load);
            // `load_at` took the extension: the next instruction (the
            // extension, the load's one use) is this value.
            if fuse.is_some() && t.extending_load.take().is_none() {
                extended = value;
                continue;
            }
            if let (Some(result), Some(value)) = (result, value) {
                values[result.0 as usize] = Some(value);
                defined.push(*result);
            }
        }
        let get = |v: ir::Value| values[v.0 as usize].expect("defined before use");
        match &block.terminator {
            Terminator::Jump(to) => {
                t.builder.ins().jump(target(*to), &[]);
            }
            Terminator::Branch {
                condition,
                then,
                otherwise,
            } => {
                // On a bit `not` made, branch on what it inverts, the
                // other way round.
                let (value, then, otherwise) = match t.negations.get(&get(*condition)) {
                    Some(&original) => (original, otherwise, then),
                    None => (get(*condition), then, otherwise),
                };
                let value = t.clean(*condition, value);
                t.builder.ins().brif(value, target(*then), &[], target(*otherwise), &[]);
            }
            Terminator::Return => {
                t.builder.ins().jump(exit, &[]);
            }
        }
    }
    t.builder.switch_to_block(exit);
    if let Some(at) = locals_pointer {
        for (offset, local) in t.locals.clone().into_iter().enumerate() {
            let value = t.builder.use_var(local);
            let value = t.bit_byte(value);
            t.builder.ins().store(flags(), value, at, offset as i32);
        }
        for (level, &count) in (0u8..).zip(&t.loop_counts) {
            let value = t.builder.use_var(count);
            t.builder
                .ins()
                .store(flags(), value, at, loop_count_offset(func, level));
        }
    }
    t.builder.ins().return_(&[]);
    t.builder.seal_all_blocks();
    remove_unused_negations(t.builder.func, t.negations.keys().copied());
    for value in defined {
        values[value.0 as usize] = None;
    }
}

/// Removes the XORs `not` made that nothing uses (an AND, an OR or a
/// branch took what they invert instead). Cranelift would not emit them,
/// but it counts their use of their operand, and it never takes a value
/// used twice, nor the loads that value was computed from, as a memory
/// operand.
fn remove_unused_negations(func: &mut cranelift_codegen::ir::Function, negations: impl Iterator<Item = Value>) {
    let mut used = cranelift_codegen::entity::EntitySet::with_capacity(func.dfg.num_values());
    for block in func.layout.blocks() {
        for inst in func.layout.block_insts(block) {
            for value in func.dfg.inst_values(inst) {
                used.insert(func.dfg.resolve_aliases(value));
            }
        }
    }
    for negation in negations {
        if let (false, cranelift_codegen::ir::ValueDef::Result(inst, _)) =
            (used.contains(negation), func.dfg.value_def(negation))
        {
            func.layout.remove_inst(inst);
        }
    }
}

/// Splits the blocks of `func` into ranges of about `size` IR instructions
/// that can be compiled as separate functions called one after another:
/// a cut before block k needs no control flow across it other than falling
/// into k, no value defined before it used after it, and no return before
/// it. Cranelift's memory and time grow with the function, so a large
/// program compiled in chunks builds in memory proportional to a chunk.
pub fn chunks(func: &ir::Function, size: usize) -> Vec<std::ops::Range<usize>> {
    let n = func.blocks.len();
    let mut defined_in = vec![usize::MAX; func.value_types.len()];
    for (number, block) in func.blocks.iter().enumerate() {
        for (result, _) in &block.insts {
            if let Some(result) = result {
                defined_in[result.0 as usize] = number;
            }
        }
    }
    // blocked[k] counts the reasons against a cut before block k, as a
    // difference array: +1 where a reason starts, -1 after it ends.
    let mut blocked = vec![0i64; n + 2];
    let mut forbid = |first: usize, last: usize| {
        if first <= last {
            blocked[first] += 1;
            blocked[last + 1] -= 1;
        }
    };
    for (number, block) in func.blocks.iter().enumerate() {
        let mut uses: Vec<ir::Value> = block.insts.iter().flat_map(|(_, inst)| inst.operands()).collect();
        if let Terminator::Branch { condition, .. } = block.terminator {
            uses.push(condition);
        }
        for value in uses {
            let definition = defined_in[value.0 as usize];
            if definition < number {
                forbid(definition + 1, number);
            }
        }
        for successor in block.terminator.successors() {
            let successor = successor.0 as usize;
            if successor > number {
                forbid(number + 1, successor - 1);
            } else {
                forbid(successor + 1, number);
            }
        }
        if block.terminator == Terminator::Return {
            forbid(number + 1, n.saturating_sub(1));
        }
    }
    let mut ranges = Vec::new();
    let (mut start, mut since_cut, mut reasons) = (0, 0, 0i64);
    for (k, against) in blocked.iter().enumerate().take(n).skip(1) {
        reasons += against;
        since_cut += func.blocks[k - 1].insts.len();
        if reasons == 0 && since_cut >= size {
            ranges.push(start..k);
            start = k;
            since_cut = 0;
        }
    }
    ranges.push(start..n);
    ranges
}

struct Translator<'a, 'b> {
    builder: &'a mut FunctionBuilder<'b>,
    layout: &'a Layout,
    mem: Value,
    pointer: types::Type,
    helpers: &'a [FuncRef],
    subroutines: &'a [FuncRef],
    locals: Vec<Variable>,
    loop_counts: Vec<Variable>,
    /// The IR type of every value of the function.
    value_types: &'a [Type],
    /// Bits are wide `i32` values (see the module).
    wide_bits: bool,
    /// Bits made as `x ^ 1`, with their `x`: a later AND or OR of one
    /// takes `x` instead (`polarity`), and the XOR goes if nothing else
    /// uses it.
    negations: FxHashMap<Value, Value>,
    /// The type and signedness the number being loaded is extended to
    /// next (`extending_load`); `load_at` takes it.
    extending_load: Option<(types::Type, bool)>,
    /// Pointers into the image, with the offset each points at, that
    /// accesses near them address from (`near.rs`; x86-64 only).
    bases: Vec<(u32, Value)>,
}

/// An operand of a bit operation: a bit, or the inverse of one.
#[derive(Clone, Copy)]
enum Bit {
    Plain(Value),
    Inverse(Value),
}

impl Translator<'_, '_> {
    /// The Cranelift type of an IR type here: `cl_type`, with wide bits.
    fn ty(&self, ty: Type) -> types::Type {
        match ty {
            Type::Bit if self.wide_bits => types::I32,
            Type::Bit | Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64 => cl_type(ty),
        }
    }

    /// A bit as an `i8` 0 or 1: byte 0 of a wide bit (free: its low byte;
    /// a constant stays one, so that a store of it takes it as immediate).
    fn bit_byte(&mut self, bit: Value) -> Value {
        if self.builder.func.dfg.value_type(bit) == types::I8 {
            return bit;
        }
        match self.constant(bit) {
            Some(value) => self.iconst(types::I8, value & 1),
            None => self.builder.ins().ireduce(types::I8, bit),
        }
    }

    /// The bits of `value` when it is an `iconst` (a narrow type's are
    /// zero-extended).
    fn constant(&self, value: Value) -> Option<i64> {
        let inst = self.builder.func.dfg.value_def(value).inst()?;
        if let cranelift_codegen::ir::InstructionData::UnaryImm { imm, .. } = self.builder.func.dfg.insts[inst] {
            Some(imm.bits())
        } else {
            None
        }
    }

    /// `value` (IR value `ir`) as its type's clean value: a bit as an `i8`
    /// 0 or 1, anything else as it is.
    fn clean(&mut self, ir: ir::Value, value: Value) -> Value {
        match self.value_types[ir.0 as usize] {
            Type::Bit => self.bit_byte(value),
            Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64 => value,
        }
    }

    /// A bit as this function's bits for logic with wide bits: a bit made
    /// by a comparison stays an `i8` until then (a store takes it as it is).
    fn wide(&mut self, bit: Value) -> Value {
        if self.wide_bits && self.builder.func.dfg.value_type(bit) == types::I8 {
            self.builder.ins().uextend(types::I32, bit)
        } else {
            bit
        }
    }

    /// Two bits of the same type, for one instruction.
    fn alike(&mut self, a: Value, b: Value) -> (Value, Value) {
        let dfg = &self.builder.func.dfg;
        if dfg.value_type(a) == dfg.value_type(b) {
            (a, b)
        } else {
            (self.wide(a), self.wide(b))
        }
    }

    /// NOT `bit`: `bit ^ 1` (the low byte stays 0 or 1), or what `bit`
    /// was made from by a NOT.
    fn not(&mut self, bit: Value) -> Value {
        if let Some(&original) = self.negations.get(&bit) {
            return original;
        }
        let inverse = self.builder.ins().bxor_imm_u(bit, 1);
        self.negations.insert(inverse, bit);
        inverse
    }

    /// An operand of an AND or an OR: a bit `not` made stands for what it
    /// inverts (and its XOR goes when nothing else uses it).
    fn polarity(&self, operand: Value) -> Bit {
        match self.negations.get(&operand) {
            Some(&original) => Bit::Inverse(original),
            None => Bit::Plain(operand),
        }
    }

    /// a AND b. An inverted operand is taken by `andn` (x86 with BMI1;
    /// `bic` on AArch64), two by De Morgan: NOT a AND NOT b = NOT (a OR
    /// b), whose NOT the next AND or OR takes the same way, so an XOR is
    /// made only for an inverted value that leaves the logic (a store, a
    /// comparison, a helper's argument).
    fn and(&mut self, a: Bit, b: Bit) -> Value {
        match (a, b) {
            (Bit::Plain(a), Bit::Plain(b)) => {
                let (a, b) = self.alike(a, b);
                self.builder.ins().band(a, b)
            }
            (Bit::Plain(a), Bit::Inverse(c)) | (Bit::Inverse(c), Bit::Plain(a)) => self.and_not(a, c),
            (Bit::Inverse(a), Bit::Inverse(b)) => {
                let (a, b) = self.alike(a, b);
                let either = self.builder.ins().bor(a, b);
                self.not(either)
            }
        }
    }

    /// a OR b by De Morgan when an operand is inverted: a OR NOT c = NOT
    /// (c AND NOT a), NOT a OR NOT b = NOT (a AND b).
    fn or(&mut self, a: Bit, b: Bit) -> Value {
        let inverse = match (a, b) {
            (Bit::Plain(a), Bit::Plain(b)) => {
                let (a, b) = self.alike(a, b);
                return self.builder.ins().bor(a, b);
            }
            (Bit::Plain(a), Bit::Inverse(c)) | (Bit::Inverse(c), Bit::Plain(a)) => self.and_not(c, a),
            (Bit::Inverse(a), Bit::Inverse(b)) => {
                let (a, b) = self.alike(a, b);
                self.builder.ins().band(a, b)
            }
        };
        self.not(inverse)
    }

    /// `a AND NOT c` (`andn` on x86 with BMI1): the low byte stays 0 or 1
    /// (c's bits 1-7 inverted meet a's zeros).
    fn and_not(&mut self, a: Value, c: Value) -> Value {
        let (a, c) = self.alike(a, c);
        self.builder.ins().band_not(a, c)
    }

    /// A bit of bookkeeping (edge slot, block flag) loaded as this
    /// function's bits.
    fn load_bit_byte(&mut self, at: (Value, i32)) -> Value {
        if self.wide_bits {
            self.builder.ins().uload8(types::I32, flags(), at.0, at.1)
        } else {
            self.load_at(types::I8, at)
        }
    }

    fn iconst(&mut self, ty: types::Type, value: i64) -> Value {
        self.builder.ins().iconst(ty, value)
    }

    /// The address of image offset `offset`: from the base register whose
    /// window holds it, else from the image pointer.
    fn near(&self, offset: u32) -> (Value, i32) {
        let reach = super::near::REACH;
        for &(centre, base) in &self.bases {
            if offset + reach >= centre && offset < centre + reach {
                return (base, offset as i32 - centre as i32);
            }
        }
        (self.mem, offset as i32)
    }

    /// Where an access goes that the image's layout lacks. The layout of a
    /// compact image was made from this program's IR, so this does not
    /// happen; if it did, the access stays inside the image: at the scalar
    /// that counts layout misses, where the tests would see it.
    fn missing(&self) -> (Value, i32) {
        (self.mem, Scalar::LayoutMisses.offset() as i32)
    }

    /// The address of element `index` of `array` (numbered from its first
    /// element), clamped into the `len` elements from there, as (pointer,
    /// constant offset).
    fn element(&mut self, array: Array, len: u32, index: Index, values: &[Option<Value>]) -> (Value, i32) {
        let (first, size) = (array.first(), array.size());
        let len = len.max(1);
        match index {
            Index::Fixed(n) => {
                let n = n.clamp(first, first + len - 1);
                match self.layout.offset(array, n) {
                    Some(offset) => self.near(offset as u32),
                    None => self.missing(),
                }
            }
            Index::Dynamic(v) => {
                // A run-time index: the layout holds the whole array in one piece.
                let Some(base) = self.layout.whole(array) else {
                    return self.missing();
                };
                let mut index = values[v.0 as usize].expect("defined before use");
                if first != 0 {
                    index = self.builder.ins().iadd_imm_s(index, -i64::from(first));
                }
                // Unsigned minimum: a negative index is huge and clamps too.
                let last = self.iconst(types::I32, i64::from(len - 1));
                let clamped = self.builder.ins().umin(index, last);
                let wide = self.builder.ins().uextend(self.pointer, clamped);
                let scaled = self.builder.ins().imul_imm_u(wide, size as i64);
                (self.builder.ins().iadd(self.mem, scaled), base as i32)
            }
        }
    }

    /// `count` elements of `array` from `start` set to `value`: one fill
    /// where the image holds them in one piece, else element by element.
    fn fill_run(
        &mut self,
        array: Array,
        area_count: u32,
        start: Index,
        count: u32,
        value: Value,
        values: &[Option<Value>],
    ) {
        // The start clamped so that the whole run stays in the area.
        let count = count.clamp(1, area_count);
        let at = self.element(array, area_count - count + 1, start, values);
        let contiguous = match start {
            Index::Dynamic(_) => at != self.missing(),
            Index::Fixed(n) => {
                let n = n.clamp(array.first(), array.first() + area_count - count);
                match (self.layout.offset(array, n), self.layout.offset(array, n + count - 1)) {
                    (Some(a), Some(b)) => b - a == (count as usize - 1) * array.size(),
                    _ => false,
                }
            }
        };
        if contiguous {
            self.fill(at, array.size(), count, value);
            return;
        }
        if let Index::Fixed(n) = start {
            let n = n.clamp(array.first(), array.first() + area_count - count);
            for k in 0..count {
                let at = self.element(array, area_count, Index::Fixed(n + k), values);
                self.store_at(value, at);
            }
        } else {
            let at = self.missing();
            self.store_at(value, at);
        }
    }

    fn store_at(&mut self, value: Value, (address, offset): (Value, i32)) {
        self.builder.ins().store(flags(), value, address, offset);
    }

    /// `count` elements of `size` bytes from an address set to `value`.
    fn fill(&mut self, (address, offset): (Value, i32), size: usize, count: u32, value: Value) {
        const UNROLL: u32 = 16;
        if count <= UNROLL {
            for i in 0..count {
                self.builder
                    .ins()
                    .store(flags(), value, address, offset + (i as usize * size) as i32);
            }
            return;
        }
        let start = self.builder.ins().iadd_imm_s(address, i64::from(offset));
        let end = self.builder.ins().iadd_imm_s(start, (count as usize * size) as i64);
        let header = self.builder.create_block();
        let body = self.builder.create_block();
        let done = self.builder.create_block();
        self.builder.append_block_param(header, self.pointer);
        self.builder.ins().jump(header, &[start.into()]);
        self.builder.switch_to_block(header);
        let cursor = self.builder.block_params(header)[0];
        let more = self.builder.ins().icmp(IntCC::UnsignedLessThan, cursor, end);
        self.builder.ins().brif(more, body, &[], done, &[]);
        self.builder.switch_to_block(body);
        self.builder.ins().store(flags(), value, cursor, 0);
        let next = self.builder.ins().iadd_imm_s(cursor, size as i64);
        self.builder.ins().jump(header, &[next.into()]);
        self.builder.switch_to_block(done);
    }

    /// The image pointer as a call's argument: a copy for each call, so
    /// that the pointer itself never has to be in the first argument
    /// register, and the register allocator keeps it in one callee-saved
    /// register for the whole function instead of moving it back at every
    /// block (measured on the mixed plant: a `mov` per block and jumps that
    /// could not be threaded).
    fn image_argument(&mut self) -> Value {
        self.builder.ins().iadd_imm_s(self.mem, 0)
    }

    /// Calls a runtime helper with the image and `args`; its result, if any.
    fn call(&mut self, helper: Helper, args: &[Value]) -> Option<Value> {
        let image = self.image_argument();
        let mut all = vec![image];
        all.extend_from_slice(args);
        let call = self.builder.ins().call(self.helpers[helper as usize], &all);
        self.builder.inst_results(call).first().copied()
    }

    /// Translates one instruction; `wide_load`: a load of a bit that reads four
    /// bytes (`wide.rs`).
    fn inst(&mut self, inst: &Inst, values: &[Option<Value>], wide_load: bool) -> Option<Value> {
        let get = |v: &ir::Value| values[v.0 as usize].expect("defined before use");
        let ins_value = match inst {
            Inst::Const { ty: Type::F32, value } => self.builder.ins().f32const(f32::from_bits(*value as u32)),
            Inst::Const { ty: Type::F64, value } => self.builder.ins().f64const(f64::from_bits(*value as u64)),
            Inst::Const { ty, value } => {
                let ty = self.ty(*ty);
                self.iconst(ty, *value)
            }
            Inst::Load { cell } => self.load_cell(cell, values, wide_load),
            Inst::Store { cell, value } => {
                self.store_cell(cell, get(value), values);
                return None;
            }
            Inst::FillBits { area, start, count, on } => {
                let value = self.iconst(types::I8, i64::from(*on));
                self.fill_run(Array::of_bits(*area), area.count(), *start, *count, value, values);
                return None;
            }
            Inst::ClearWords { area, start, count } => {
                let zero = self.iconst(types::I16, 0);
                self.fill_run(Array::of_words(*area), area.count(), *start, *count, zero, values);
                return None;
            }
            Inst::LoadElapsed => self.load_at(types::I32, (self.mem, Scalar::ElapsedMs.offset() as i32)),
            Inst::GetLocal { local } => self.builder.use_var(self.locals[local.0 as usize]),
            Inst::SetLocal { local, value } => {
                let value = self.wide(get(value));
                self.builder.def_var(self.locals[local.0 as usize], value);
                return None;
            }
            Inst::LoadLoopCount { level } => self.builder.use_var(self.loop_counts[*level as usize]),
            Inst::StoreLoopCount { level, value } => {
                self.builder.def_var(self.loop_counts[*level as usize], get(value));
                return None;
            }
            Inst::CallSubroutine { subroutine } => {
                let image = self.image_argument();
                self.builder
                    .ins()
                    .call(self.subroutines[*subroutine as usize], &[image]);
                return None;
            }
            Inst::Not { value } => self.not(get(value)),
            Inst::And { a, b } => {
                let (a, b) = (self.polarity(get(a)), self.polarity(get(b)));
                self.and(a, b)
            }
            Inst::Or { a, b } => {
                let (a, b) = (self.polarity(get(a)), self.polarity(get(b)));
                self.or(a, b)
            }
            Inst::Binary { op, a, b } => {
                // Arithmetic on bits (not made by the lowering today) on
                // their clean bytes; a bit result stays an `i8` (`wide`).
                let (a, b) = (self.clean(*a, get(a)), self.clean(*b, get(b)));
                let by_constant = match op {
                    BinOp::Div => self.constant(b).and_then(|d| divide::quotient(self.builder, a, d)),
                    BinOp::Rem => self.constant(b).and_then(|d| divide::remainder(self.builder, a, d)),
                    BinOp::Add
                    | BinOp::Sub
                    | BinOp::Mul
                    | BinOp::And
                    | BinOp::Or
                    | BinOp::Xor
                    | BinOp::Shl
                    | BinOp::Shr
                    | BinOp::UShr => None,
                };
                if let Some(result) = by_constant {
                    return Some(result);
                }
                let ins = self.builder.ins();
                match op {
                    BinOp::Add => ins.iadd(a, b),
                    BinOp::Sub => ins.isub(a, b),
                    BinOp::Mul => ins.imul(a, b),
                    BinOp::Div => ins.sdiv(a, b),
                    BinOp::Rem => ins.srem(a, b),
                    BinOp::And => ins.band(a, b),
                    BinOp::Or => ins.bor(a, b),
                    BinOp::Xor => ins.bxor(a, b),
                    BinOp::Shl => ins.ishl(a, b),
                    BinOp::Shr => ins.sshr(a, b),
                    BinOp::UShr => ins.ushr(a, b),
                }
            }
            Inst::Unary { op, value } => {
                let value = self.clean(*value, get(value));
                match op {
                    UnaryOp::PopCount => self.builder.ins().popcnt(value),
                    UnaryOp::LeadingZeros => self.builder.ins().clz(value),
                    UnaryOp::SquareRoot => {
                        // Exact through f64 for the 32-bit values it is used on.
                        let ty = self.builder.func.dfg.value_type(value);
                        let float = self.builder.ins().fcvt_from_sint(types::F64, value);
                        let root = self.builder.ins().sqrt(float);
                        self.builder.ins().fcvt_to_sint_sat(ty, root)
                    }
                }
            }
            Inst::Compare { op, a, b } => {
                let (a, b) = (self.clean(*a, get(a)), self.clean(*b, get(b)));
                self.builder.ins().icmp(condition(*op), a, b)
            }
            Inst::Extend { value, to, signed } => {
                let (value, to) = (self.clean(*value, get(value)), cl_type(*to));
                if *signed {
                    self.builder.ins().sextend(to, value)
                } else {
                    self.builder.ins().uextend(to, value)
                }
            }
            Inst::Truncate { value, to } => self.builder.ins().ireduce(cl_type(*to), get(value)),
            Inst::Select {
                condition,
                if_true,
                if_false,
            } => {
                let condition = self.clean(*condition, get(condition));
                let (if_true, if_false) = match self.value_types[if_true.0 as usize] {
                    Type::Bit => self.alike(get(if_true), get(if_false)),
                    Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64 => (get(if_true), get(if_false)),
                };
                self.builder.ins().select(condition, if_true, if_false)
            }
            Inst::Float { op, a, b } => {
                let (a, b) = (get(a), get(b));
                let ins = self.builder.ins();
                match op {
                    FloatOp::Add => ins.fadd(a, b),
                    FloatOp::Sub => ins.fsub(a, b),
                    FloatOp::Mul => ins.fmul(a, b),
                    FloatOp::Div => ins.fdiv(a, b),
                }
            }
            Inst::FloatUnary { op, value } => {
                let value = get(value);
                let ins = self.builder.ins();
                match op {
                    FloatUnaryOp::SquareRoot => ins.sqrt(value),
                    FloatUnaryOp::Neg => ins.fneg(value),
                    FloatUnaryOp::Abs => ins.fabs(value),
                }
            }
            Inst::FloatCompare { op, a, b } => self.builder.ins().fcmp(float_condition(*op), get(a), get(b)),
            Inst::Bitcast { value, to } => self
                .builder
                .ins()
                .bitcast(cl_type(*to), MemFlagsData::new(), get(value)),
            Inst::Convert { value, to, conversion } => {
                let (value, to) = (get(value), cl_type(*to));
                let ins = self.builder.ins();
                match conversion {
                    Conversion::IntToFloat => ins.fcvt_from_sint(to, value),
                    // Saturating: never a trap, whatever the value.
                    Conversion::FloatToInt => ins.fcvt_to_sint_sat(to, value),
                    Conversion::FloatToFloat if to == types::F64 => ins.fpromote(to, value),
                    Conversion::FloatToFloat => ins.fdemote(to, value),
                }
            }
            Inst::RecordError { error, line } => {
                let code = self.iconst(types::I32, i64::from(error.code()));
                let line = self.iconst(types::I32, i64::from(*line as i32));
                self.call(Helper::RecordError, &[code, line]);
                return None;
            }
            Inst::Call { helper, args } => {
                let args: Vec<Value> = args.iter().map(|arg| self.clean(*arg, get(arg))).collect();
                return self.call(*helper, &args);
            }
        };
        Some(ins_value)
    }
}
