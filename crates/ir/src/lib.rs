//! The SSA intermediate representation between the checked program and
//! machine code. It makes the PLC's hidden state explicit:
//!
//! - device reads and writes are loads and stores of the image's cells
//!   (`Cell`: a bit, a word, an edge slot, a timer's bookkeeping, ...), each
//!   cell saying where it lies and how the image holds it;
//! - every edge instruction's previous-scan slot is a named load and store;
//! - an STL block is a gated region: run while its state is ON, reset once
//!   (OUT coils off, timers cleared, slots cleared) when found OFF after running,
//!   skipped otherwise, with the block's "last ran active" flag loaded and stored;
//! - timer and counter updates are explicit operations;
//! - the logic stack (ANB/ORB/MPS, `ladder_front::logic`) lives in SSA
//!   values, never in memory.
//!
//! A function is a list of blocks; each block holds instructions and ends in a
//! terminator. A value is defined once and used in blocks its definition
//! dominates. The master-control power of each level is a local variable.

mod builder;
mod cfg;
mod effect;
pub mod image;
pub mod lower;
mod memory;
pub mod passes;
mod print;
mod ranges;
mod replacements;
mod verify;

pub use builder::Builder;
pub use effect::{Effect, Space, Span};
pub use verify::{verify, verify_function, Problem, VerifyError};

/// The optimised IR of a checked program: lowered once, then the passes;
/// what every back end compiles. Timers and 16-bit counters inline.
pub fn lower_and_optimize(program: &ladder_front::program::CheckedProgram) -> Program {
    lower_and_optimize_with(program, Coils::Inline)
}

/// `lower_and_optimize` with the timer and counter coils as `coils` says.
pub fn lower_and_optimize_with(program: &ladder_front::program::CheckedProgram, coils: Coils) -> Program {
    let mut ir = lower::lower(program, coils);
    if cfg!(debug_assertions) {
        if let Err(error) = verify(&ir) {
            panic!("the IR is not well formed after `lower`:\n{error}");
        }
    }
    passes::optimize(&mut ir);
    ir
}

/// How `OUT Tn` and `OUT Cn` of a 16-bit counter are compiled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coils {
    /// As code of their own (`lower/coil.rs`): no call on the scan's path,
    /// some 100-180 bytes of code each. For native code and the C of a
    /// host.
    Inline,
    /// As calls of the runtime's coils (some 12-15 bytes each): for
    /// microcontrollers, where flash is short and a call is cheap.
    Calls,
}

use ladder_runtime::helpers::Helper;
use ladder_runtime::{BitArea, OperationError, WordArea};

/// An SSA value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Value(pub u32);

/// A basic block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BlockId(pub u32);

/// A local variable (the power of a master-control level).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Local(pub u8);

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Type {
    /// 0 or 1.
    Bit,
    I16,
    I32,
    I64,
    /// IEEE-754 binary32 (the floats of the image's word pairs); a
    /// constant's value holds its bits.
    F32,
    /// IEEE-754 binary64, for exact intermediate results of float
    /// instructions; a constant's value holds its bits.
    F64,
}

impl Type {
    /// The bits of a value of this type.
    pub fn bits(self) -> u32 {
        match self {
            Type::Bit => 1,
            Type::I16 => 16,
            Type::I32 | Type::F32 => 32,
            Type::I64 | Type::F64 => 64,
        }
    }

    /// `value` as a constant of this type holds it: integers wrapped to
    /// their bits and sign-extended, a bit 0 or 1, a float's bits as an
    /// unsigned number of its width. Constant folding writes every
    /// constant so, and the verifier holds the lowering to it.
    pub fn wrap(self, value: i64) -> i64 {
        match self {
            Type::Bit => value & 1,
            Type::I16 => i64::from(value as i16),
            Type::I32 => i64::from(value as i32),
            Type::I64 => value,
            // Float constants hold their bits.
            Type::F32 => i64::from(value as u32),
            Type::F64 => value,
        }
    }
}

/// A device number: fixed, or computed at run time and already brought into
/// the area by the lowering (code generation clamps it once more, so a
/// lowering mistake cannot reach outside the image).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Index {
    Fixed(u32),
    /// An I32 value.
    Dynamic(Value),
}

/// State the runtime keeps for a timer or counter besides its value and
/// contact, which the inline `OUT T` and `OUT C` of the lowering read and
/// write as the runtime's coils do (`runtime/src/timer.rs`, `counter.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bookkeeping {
    /// Whether the timer's coil was ON at its last `OUT` (Bit).
    TimerCoil,
    /// The milliseconds below the timer's resolution carried to its next
    /// scan (I16, unsigned, below the resolution).
    TimerRemainder,
    /// Whether the timer is forced (Bit: its force byte is not
    /// `FORCE_NONE`). The lowering only reads it.
    TimerForced,
    /// Whether the counter's coil was ON at its last `OUT` (Bit).
    CounterCoil,
    /// Whether the counter is forced (Bit), read only.
    CounterForced,
}

impl Bookkeeping {
    /// The layout's array that holds it.
    pub fn array(self) -> ladder_runtime::layout::Array {
        use ladder_runtime::layout::Array;
        match self {
            Bookkeeping::TimerCoil => Array::TimerCoilWasOn,
            Bookkeeping::TimerRemainder => Array::TimerRemainder,
            Bookkeeping::TimerForced => Array::ForceTimer,
            Bookkeeping::CounterCoil => Array::CounterCoilWasOn,
            Bookkeeping::CounterForced => Array::ForceCounter,
        }
    }

    /// How the image holds an element.
    pub fn held(self) -> Held {
        match self {
            Bookkeeping::TimerRemainder => Held::I16,
            Bookkeeping::TimerCoil | Bookkeeping::CounterCoil => Held::Bit,
            Bookkeeping::TimerForced | Bookkeeping::CounterForced => Held::Force,
        }
    }

    /// The name `print` shows.
    pub fn name(self) -> &'static str {
        match self {
            Bookkeeping::TimerCoil => "timer_coil",
            Bookkeeping::TimerRemainder => "timer_remainder",
            Bookkeeping::TimerForced => "timer_forced",
            Bookkeeping::CounterCoil => "counter_coil",
            Bookkeeping::CounterForced => "counter_forced",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    /// Signed, truncating toward zero. The divisor is never zero.
    Div,
    /// Signed remainder (sign of the dividend). The divisor is never zero.
    Rem,
    And,
    Or,
    Xor,
    Shl,
    /// Arithmetic shift right.
    Shr,
    /// Logical shift right.
    UShr,
}

/// A comparison, as the IR's `Compare` (signed) and `FloatCompare`
/// (ordered) make it. The IR owns it so that the back ends need nothing of
/// the front end; the lowering converts the instruction set's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CompareOp {
    Eq,
    Ne,
    Gt,
    Lt,
    Ge,
    Le,
}

impl CompareOp {
    pub fn holds<T: Ord>(self, left: T, right: T) -> bool {
        match self {
            CompareOp::Eq => left == right,
            CompareOp::Ne => left != right,
            CompareOp::Gt => left > right,
            CompareOp::Lt => left < right,
            CompareOp::Ge => left >= right,
            CompareOp::Le => left <= right,
        }
    }

    /// As the text form prints it (the instruction list's own symbols).
    pub fn symbol(self) -> &'static str {
        match self {
            CompareOp::Eq => "=",
            CompareOp::Ne => "<>",
            CompareOp::Gt => ">",
            CompareOp::Lt => "<",
            CompareOp::Ge => ">=",
            CompareOp::Le => "<=",
        }
    }
}

impl From<ladder_front::isa::CompareOp> for CompareOp {
    fn from(op: ladder_front::isa::CompareOp) -> CompareOp {
        use ladder_front::isa::CompareOp as Isa;
        match op {
            Isa::Eq => CompareOp::Eq,
            Isa::Ne => CompareOp::Ne,
            Isa::Gt => CompareOp::Gt,
            Isa::Lt => CompareOp::Lt,
            Isa::Ge => CompareOp::Ge,
            Isa::Le => CompareOp::Le,
        }
    }
}

/// Float operations of two operands (both F32 or both F64), IEEE-754
/// round to nearest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FloatOp {
    Add,
    Sub,
    Mul,
    /// The divisor is never zero.
    Div,
}

/// Float operations of one operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FloatUnaryOp {
    /// Of a value that is not negative.
    SquareRoot,
    Neg,
    Abs,
}

/// Numeric conversions (not bit casts).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Conversion {
    /// A signed integer to the nearest float.
    IntToFloat,
    /// A float to a signed integer, toward zero, saturating (NaN is 0):
    /// callers check the range first.
    FloatToInt,
    /// F32 to F64 (exact) or F64 to F32 (to nearest).
    FloatToFloat,
}

/// Integer operations of one operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// The number of one bits.
    PopCount,
    /// The number of leading zero bits.
    LeadingZeros,
    /// The integer square root (rounded down) of a value that is not
    /// negative.
    SquareRoot,
}

/// One element of the image, or of the runtime's state in it, that
/// `Inst::Load` reads and `Inst::Store` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    Bit {
        area: BitArea,
        index: Index,
    },
    Word {
        area: WordArea,
        index: Index,
    },
    /// The current value of a 32-bit counter (index = device number).
    WideCounter {
        index: Index,
    },
    /// The previous-scan value of edge instruction `slot`.
    Slot {
        slot: u32,
    },
    /// Whether the block of `state` last ran with its state ON.
    BlockActive {
        state: u32,
    },
    /// The runtime's own state of timer or counter `index` (`Bookkeeping`).
    Bookkeeping {
        field: Bookkeeping,
        index: u32,
    },
}

/// How the image holds a cell's value; both back ends load and store a
/// cell by this.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Held {
    /// A byte 0 or 1.
    Bit,
    /// A force byte: FORCE_NONE (0), FORCE_OFF or FORCE_ON. It loads as a
    /// bit (forced either way) and is stored as 0 or 1.
    Force,
    /// A 16-bit number.
    I16,
    /// A 32-bit number.
    I32,
}

impl Cell {
    /// How the image holds the cell's value.
    pub fn held(self) -> Held {
        match self {
            Cell::Bit { .. } | Cell::Slot { .. } | Cell::BlockActive { .. } => Held::Bit,
            Cell::Word { .. } => Held::I16,
            Cell::WideCounter { .. } => Held::I32,
            Cell::Bookkeeping { field, .. } => field.held(),
        }
    }

    /// The type of the value a load of the cell defines.
    pub fn value_type(self) -> Type {
        match self.held() {
            Held::Bit | Held::Force => Type::Bit,
            Held::I16 => Type::I16,
            Held::I32 => Type::I32,
        }
    }

    /// The device number of a cell addressed by one (fixed, or a value);
    /// the others are fixed by the program.
    pub fn index_mut(&mut self) -> Option<&mut Index> {
        match self {
            Cell::Bit { index, .. } | Cell::Word { index, .. } | Cell::WideCounter { index } => Some(index),
            Cell::Slot { .. } | Cell::BlockActive { .. } | Cell::Bookkeeping { .. } => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Inst {
    Const {
        ty: Type,
        value: i64,
    },
    /// Reads one element of the image.
    Load {
        cell: Cell,
    },
    /// Writes `value` into one element.
    Store {
        cell: Cell,
        value: Value,
    },
    /// `count` consecutive bits from `start` set to `on` (SET/RST Kn).
    FillBits {
        area: BitArea,
        start: Index,
        count: u32,
        on: bool,
    },
    /// `count` consecutive words from `start` set to 0 (RST Dn Kn).
    ClearWords {
        area: WordArea,
        start: Index,
        count: u32,
    },
    /// The milliseconds since the previous scan (I32 holding the image's
    /// unsigned count). Nothing changes it while the program runs, so it
    /// is pure.
    LoadElapsed,
    GetLocal {
        local: Local,
    },
    SetLocal {
        local: Local,
        value: Value,
    },
    /// The repetitions left in the FOR/NEXT loop at nesting `level` (an
    /// I32 local of the function).
    LoadLoopCount {
        level: u8,
    },
    StoreLoopCount {
        level: u8,
        value: Value,
    },
    /// Runs subroutine `subroutine` (its function in `Program`): may read
    /// and write anything in the image.
    CallSubroutine {
        subroutine: u32,
    },
    Not {
        value: Value,
    },
    And {
        a: Value,
        b: Value,
    },
    Or {
        a: Value,
        b: Value,
    },
    Binary {
        op: BinOp,
        a: Value,
        b: Value,
    },
    Unary {
        op: UnaryOp,
        value: Value,
    },
    /// Signed comparison giving a Bit.
    Compare {
        op: CompareOp,
        a: Value,
        b: Value,
    },
    Extend {
        value: Value,
        to: Type,
        signed: bool,
    },
    Truncate {
        value: Value,
        to: Type,
    },
    Select {
        condition: Value,
        if_true: Value,
        if_false: Value,
    },
    Float {
        op: FloatOp,
        a: Value,
        b: Value,
    },
    FloatUnary {
        op: FloatUnaryOp,
        value: Value,
    },
    /// Ordered float comparison giving a Bit (-0 equals +0).
    FloatCompare {
        op: CompareOp,
        a: Value,
        b: Value,
    },
    /// The same bits as another type of the same size (I32 <-> F32).
    Bitcast {
        value: Value,
        to: Type,
    },
    Convert {
        value: Value,
        to: Type,
        conversion: Conversion,
    },
    /// M8067 ON, D8067 = code, D8069 = line (a call of the runtime's
    /// `RecordError` helper in machine code).
    RecordError {
        error: OperationError,
        line: u32,
    },
    /// A call of a runtime helper; the arguments follow the helper's
    /// declaration (I32 values; places packed by `Place::pack`). Defines a
    /// value when the helper returns one.
    Call {
        helper: Helper,
        args: Vec<Value>,
    },
}

impl Inst {
    /// The type of the value the instruction defines, if it defines one;
    /// `value_type` gives the types of its operands.
    pub fn result_type(&self, value_type: impl Fn(Value) -> Type) -> Option<Type> {
        Some(match self {
            Inst::Const { ty, .. } => *ty,
            Inst::Load { cell } => cell.value_type(),
            Inst::GetLocal { .. }
            | Inst::Not { .. }
            | Inst::And { .. }
            | Inst::Or { .. }
            | Inst::Compare { .. }
            | Inst::FloatCompare { .. } => Type::Bit,
            Inst::LoadLoopCount { .. } | Inst::LoadElapsed => Type::I32,
            Inst::Binary { a, .. } => value_type(*a),
            Inst::Unary { value, .. } => value_type(*value),
            Inst::Extend { to, .. } | Inst::Truncate { to, .. } => *to,
            Inst::Select { if_true, .. } => value_type(*if_true),
            Inst::Float { a, .. } => value_type(*a),
            Inst::FloatUnary { value, .. } => value_type(*value),
            Inst::Bitcast { to, .. } | Inst::Convert { to, .. } => *to,
            Inst::Call { helper, .. } => return helper.decl().returns.map(|_| Type::I32),
            Inst::Store { .. }
            | Inst::FillBits { .. }
            | Inst::ClearWords { .. }
            | Inst::SetLocal { .. }
            | Inst::StoreLoopCount { .. }
            | Inst::CallSubroutine { .. }
            | Inst::RecordError { .. } => return None,
        })
    }

    /// Has no effect besides its result, so it may be removed when unused
    /// (loads of the image included; see `Effect::is_removable`).
    pub fn is_pure(&self) -> bool {
        self.effect().is_removable()
    }

    /// Values the instruction reads: inline for up to four (every
    /// instruction but a call with more arguments), since the passes ask
    /// for every instruction of the program.
    pub fn operands(&self) -> smallvec::SmallVec<[Value; 4]> {
        let mut operands = smallvec::SmallVec::new();
        self.clone().for_each_operand_mut(|v| operands.push(*v));
        operands
    }

    /// Visits every value the instruction reads, mutably (for rewriting).
    pub fn for_each_operand_mut(&mut self, mut visit: impl FnMut(&mut Value)) {
        self.visit_operands_mut(|operand| match operand {
            OperandMut::Index(Index::Dynamic(value)) | OperandMut::Value(value) => visit(value),
            OperandMut::Index(Index::Fixed(_)) => {}
        });
    }

    /// Visits every operand mutably: the index of an image access (a
    /// device number or a value) and every value.
    pub fn visit_operands_mut(&mut self, mut visit: impl FnMut(OperandMut<'_>)) {
        match self {
            Inst::Const { .. }
            | Inst::LoadElapsed
            | Inst::GetLocal { .. }
            | Inst::LoadLoopCount { .. }
            | Inst::CallSubroutine { .. }
            | Inst::RecordError { .. } => {}
            Inst::Load { cell } => {
                if let Some(index) = cell.index_mut() {
                    visit(OperandMut::Index(index));
                }
            }
            Inst::FillBits { start: index, .. } | Inst::ClearWords { start: index, .. } => {
                visit(OperandMut::Index(index))
            }
            Inst::Store { cell, value } => {
                if let Some(index) = cell.index_mut() {
                    visit(OperandMut::Index(index));
                }
                visit(OperandMut::Value(value));
            }
            Inst::SetLocal { value, .. }
            | Inst::StoreLoopCount { value, .. }
            | Inst::Not { value }
            | Inst::Unary { value, .. }
            | Inst::Extend { value, .. }
            | Inst::Truncate { value, .. }
            | Inst::FloatUnary { value, .. }
            | Inst::Bitcast { value, .. }
            | Inst::Convert { value, .. } => visit(OperandMut::Value(value)),
            Inst::And { a, b }
            | Inst::Or { a, b }
            | Inst::Binary { a, b, .. }
            | Inst::Compare { a, b, .. }
            | Inst::Float { a, b, .. }
            | Inst::FloatCompare { a, b, .. } => {
                visit(OperandMut::Value(a));
                visit(OperandMut::Value(b));
            }
            Inst::Select {
                condition,
                if_true,
                if_false,
            } => {
                visit(OperandMut::Value(condition));
                visit(OperandMut::Value(if_true));
                visit(OperandMut::Value(if_false));
            }
            Inst::Call { args, .. } => args.iter_mut().for_each(|arg| visit(OperandMut::Value(arg))),
        }
    }
}

/// An operand as `Inst::visit_operands_mut` hands it over.
pub enum OperandMut<'a> {
    /// Where an image access starts: a device number, or a value.
    Index(&'a mut Index),
    Value(&'a mut Value),
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Terminator {
    Jump(BlockId),
    Branch {
        condition: Value,
        then: BlockId,
        otherwise: BlockId,
    },
    Return,
}

impl Terminator {
    /// The same terminator with every target passed through `map`.
    pub fn map_targets(&self, map: impl Fn(BlockId) -> BlockId) -> Terminator {
        match *self {
            Terminator::Jump(target) => Terminator::Jump(map(target)),
            Terminator::Branch {
                condition,
                then,
                otherwise,
            } => Terminator::Branch {
                condition,
                then: map(then),
                otherwise: map(otherwise),
            },
            Terminator::Return => Terminator::Return,
        }
    }

    pub fn successors(&self) -> Vec<BlockId> {
        match self {
            Terminator::Jump(b) => vec![*b],
            Terminator::Branch { then, otherwise, .. } => vec![*then, *otherwise],
            Terminator::Return => vec![],
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    /// Instructions with the value each defines (None for effects).
    pub insts: Vec<(Option<Value>, Inst)>,
    pub terminator: Terminator,
    /// Runs only when something changes: an STL state turns OFF (its
    /// outputs are reset) or hands over to the next. Code generation
    /// places it out of the way of the code every scan runs.
    pub cold: bool,
}

/// One function: the main program (the body of the scan, step 3) or a
/// subroutine.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Function {
    pub blocks: Vec<Block>,
    /// The type of every value, by number.
    pub value_types: Vec<Type>,
    /// Number of bit locals (master-control levels).
    pub locals: u8,
    /// Number of loop-count locals (FOR/NEXT nesting levels).
    pub loop_levels: u8,
}

/// A whole program: the main program and its subroutines, each compiled
/// once (a CALL is a call, not a copy).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    pub main: Function,
    /// By subroutine number (`Inst::CallSubroutine`).
    pub subroutines: Vec<Function>,
}

impl Function {
    pub fn value_type(&self, value: Value) -> Type {
        self.value_types[value.0 as usize]
    }

    pub fn block(&self, block: BlockId) -> &Block {
        &self.blocks[block.0 as usize]
    }

    /// How many times each value is used, by number (as an operand or a
    /// branch condition).
    pub fn use_counts(&self) -> Vec<u32> {
        let mut uses = vec![0u32; self.value_types.len()];
        for block in &self.blocks {
            for (_, inst) in &block.insts {
                for operand in inst.operands() {
                    uses[operand.0 as usize] += 1;
                }
            }
            if let Terminator::Branch { condition, .. } = block.terminator {
                uses[condition.0 as usize] += 1;
            }
        }
        uses
    }

    /// The value of every constant.
    pub fn constants(&self) -> rustc_hash::FxHashMap<Value, i64> {
        self.blocks
            .iter()
            .flat_map(|b| b.insts.iter())
            .filter_map(|(result, inst)| {
                let (Some(r), Inst::Const { value, .. }) = (result, inst) else {
                    return None;
                };
                Some((*r, *value))
            })
            .collect()
    }
}
