//! Building a function block by block.

use super::{BinOp, Block, BlockId, Cell, Function, Index, Inst, Local, Terminator, Type, Value};
use crate::CompareOp;
use ladder_runtime::helpers::Helper;

/// Appends instructions to the current block of a function being built.
pub struct Builder {
    func: Function,
    current: BlockId,
    terminated: Vec<bool>,
}

impl Default for Builder {
    fn default() -> Self {
        Builder::new()
    }
}

impl Builder {
    /// A function with an empty entry block, which is current.
    pub fn new() -> Builder {
        let mut builder = Builder {
            func: Function {
                blocks: Vec::new(),
                value_types: Vec::new(),
                locals: 0,
                loop_levels: 0,
            },
            current: BlockId(0),
            terminated: Vec::new(),
        };
        builder.create_block();
        builder
    }

    /// A new block; made while the current block is cold, it is cold too
    /// (the rest of a cold region: an inline timer in an STL reset).
    pub fn create_block(&mut self) -> BlockId {
        let cold = self
            .func
            .blocks
            .get(self.current.0 as usize)
            .is_some_and(|block| block.cold);
        self.func.blocks.push(Block {
            insts: Vec::new(),
            terminator: Terminator::Return,
            cold,
        });
        self.terminated.push(false);
        BlockId(self.func.blocks.len() as u32 - 1)
    }

    /// Marks the current block as one that runs only when something
    /// changes (`Block::cold`).
    pub fn mark_cold(&mut self) {
        self.block_mut().cold = true;
    }

    pub fn switch_to(&mut self, block: BlockId) {
        self.current = block;
    }

    pub fn value_type(&self, value: Value) -> Type {
        self.func.value_type(value)
    }

    /// Appends an instruction that defines a value.
    pub fn push(&mut self, inst: Inst) -> Value {
        let ty = self.result_type(&inst).expect("instruction defines a value");
        let value = Value(self.func.value_types.len() as u32);
        self.func.value_types.push(ty);
        self.block_mut().insts.push((Some(value), inst));
        value
    }

    /// Appends an instruction kept for its effect.
    pub fn effect(&mut self, inst: Inst) {
        debug_assert!(self.result_type(&inst).is_none(), "{inst:?} defines a value");
        self.block_mut().insts.push((None, inst));
    }

    /// Ends the current block.
    pub fn terminate(&mut self, terminator: Terminator) {
        let index = self.current.0 as usize;
        debug_assert!(!self.terminated[index], "block{index} terminated twice");
        self.terminated[index] = true;
        self.func.blocks[index].terminator = terminator;
    }

    /// Jumps from the current block to `target` and continues there.
    pub fn jump_to(&mut self, target: BlockId) {
        self.terminate(Terminator::Jump(target));
        self.switch_to(target);
    }

    /// Runs `then` in a new block only when `condition` holds; continues after.
    pub fn if_then(&mut self, condition: Value, then: impl FnOnce(&mut Builder)) {
        let after = self.begin_if(condition);
        then(self);
        self.jump_to(after);
    }

    /// Switches to a new block that runs only when `condition` holds and
    /// returns the block after it, which the caller jumps to at its end
    /// (`if_then` for a body that needs only the builder).
    pub fn begin_if(&mut self, condition: Value) -> BlockId {
        let (then_block, after) = self.branch_to_new(condition);
        self.switch_to(then_block);
        after
    }

    /// Ends the current block with a branch on `condition` to two new
    /// blocks, returned as (taken when it holds, taken when not).
    pub fn branch_to_new(&mut self, condition: Value) -> (BlockId, BlockId) {
        let then_block = self.create_block();
        let otherwise = self.create_block();
        self.terminate(Terminator::Branch {
            condition,
            then: then_block,
            otherwise,
        });
        (then_block, otherwise)
    }

    pub fn finish(self, locals: u8, loop_levels: u8) -> Function {
        debug_assert!(self.terminated.iter().all(|&t| t), "every block ends in a terminator");
        Function {
            locals,
            loop_levels,
            ..self.func
        }
    }

    fn block_mut(&mut self) -> &mut Block {
        &mut self.func.blocks[self.current.0 as usize]
    }

    fn result_type(&self, inst: &Inst) -> Option<Type> {
        inst.result_type(|v| self.value_type(v))
    }

    // ---- shorthands ----

    pub fn constant(&mut self, ty: Type, value: i64) -> Value {
        self.push(Inst::Const { ty, value })
    }

    /// A u32 argument of a helper call (a device number, a code).
    pub fn number(&mut self, value: u32) -> Value {
        self.constant(Type::I32, i64::from(value as i32))
    }

    /// Calls a runtime helper; its value, when it returns one.
    pub fn call(&mut self, helper: Helper, args: Vec<Value>) -> Option<Value> {
        debug_assert_eq!(args.len(), helper.decl().params.len(), "{helper:?} arguments");
        let inst = Inst::Call { helper, args };
        if self.result_type(&inst).is_some() {
            Some(self.push(inst))
        } else {
            self.effect(inst);
            None
        }
    }

    pub fn bit(&mut self, on: bool) -> Value {
        self.constant(Type::Bit, on as i64)
    }

    pub fn and(&mut self, a: Value, b: Value) -> Value {
        self.push(Inst::And { a, b })
    }

    pub fn or(&mut self, a: Value, b: Value) -> Value {
        self.push(Inst::Or { a, b })
    }

    pub fn not(&mut self, value: Value) -> Value {
        self.push(Inst::Not { value })
    }

    pub fn binary(&mut self, op: BinOp, a: Value, b: Value) -> Value {
        debug_assert_eq!(self.value_type(a), self.value_type(b), "{op:?} of two types");
        self.push(Inst::Binary { op, a, b })
    }

    pub fn compare(&mut self, op: CompareOp, a: Value, b: Value) -> Value {
        self.push(Inst::Compare { op, a, b })
    }

    pub fn extend(&mut self, value: Value, to: Type, signed: bool) -> Value {
        if self.value_type(value) == to {
            return value;
        }
        self.push(Inst::Extend { value, to, signed })
    }

    pub fn truncate(&mut self, value: Value, to: Type) -> Value {
        if self.value_type(value) == to {
            return value;
        }
        self.push(Inst::Truncate { value, to })
    }

    pub fn select(&mut self, condition: Value, if_true: Value, if_false: Value) -> Value {
        self.push(Inst::Select {
            condition,
            if_true,
            if_false,
        })
    }

    /// An F32 constant.
    pub fn real(&mut self, value: f32) -> Value {
        self.constant(Type::F32, i64::from(value.to_bits()))
    }

    /// An F64 constant.
    pub fn real64(&mut self, value: f64) -> Value {
        self.constant(Type::F64, value.to_bits() as i64)
    }

    pub fn float(&mut self, op: crate::FloatOp, a: Value, b: Value) -> Value {
        debug_assert_eq!(self.value_type(a), self.value_type(b), "{op:?} of two types");
        self.push(Inst::Float { op, a, b })
    }

    pub fn float_unary(&mut self, op: crate::FloatUnaryOp, value: Value) -> Value {
        self.push(Inst::FloatUnary { op, value })
    }

    pub fn float_compare(&mut self, op: CompareOp, a: Value, b: Value) -> Value {
        self.push(Inst::FloatCompare { op, a, b })
    }

    pub fn bitcast(&mut self, value: Value, to: Type) -> Value {
        self.push(Inst::Bitcast { value, to })
    }

    pub fn convert(&mut self, value: Value, to: Type, conversion: crate::Conversion) -> Value {
        self.push(Inst::Convert { value, to, conversion })
    }

    pub fn load(&mut self, cell: Cell) -> Value {
        self.push(Inst::Load { cell })
    }

    pub fn store(&mut self, cell: Cell, value: Value) {
        self.effect(Inst::Store { cell, value });
    }

    pub fn load_bit(&mut self, area: ladder_runtime::BitArea, index: Index) -> Value {
        self.load(Cell::Bit { area, index })
    }

    pub fn store_bit(&mut self, area: ladder_runtime::BitArea, index: Index, value: Value) {
        self.store(Cell::Bit { area, index }, value);
    }

    pub fn get_local(&mut self, local: Local) -> Value {
        self.push(Inst::GetLocal { local })
    }
}
