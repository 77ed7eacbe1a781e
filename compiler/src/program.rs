//! The checked program: every operand resolved to a device of the runtime's
//! areas, every edge instruction given its previous-scan slot, every jump its
//! target, every STL block its extent. The interpreter executes this list
//! directly; the IR lowering starts from it.

use crate::isa::{CompareOp, DataOp, Sense};
use crate::source::Span;
use ladder_runtime::{BitArea, WordArea};

/// A device number, possibly offset at run time by the value of a D register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Address {
    pub index: u32,
    /// `DEV[Dk]`: the register k whose value is added at run time.
    pub offset: Option<u32>,
}

impl Address {
    pub fn fixed(index: u32) -> Address {
        Address { index, offset: None }
    }
}

/// A bit the program reads or writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BitRef {
    Device(BitArea, Address),
    /// Bit `bit` of a word (`D0.F`).
    WordBit(WordArea, Address, u8),
}

/// Where a word value comes from or goes to. Its width (16 or 32 bits) is
/// the instruction's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WordRef {
    /// K or H constant (sign-extended from the instruction's width).
    Constant(i32),
    /// A word; at 32 bits the pair (n+1, n).
    Word(WordArea, Address),
    /// The current value of a 32-bit counter C200–C255 (device number).
    WideCounter(Address),
    /// `KnM0`: the 4·n bits from the start device.
    Digits(BitArea, Address, u8),
}

/// A contact: what it reads and how.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contact {
    /// Normally open or closed.
    Level { bit: BitRef, closed: bool },
    /// Rising or falling transition since this instance last executed.
    Edge { bit: BitRef, falling: bool, slot: u32 },
    /// ATI (true) / AFI (false).
    Constant(bool),
    /// `LD= S1 S2` and friends; `wide` for the D forms.
    Compare {
        op: CompareOp,
        wide: bool,
        left: WordRef,
        right: WordRef,
    },
}

/// What RST clears.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResetTarget {
    Bit(BitRef),
    /// Timers `first`..`first+count`: value, remainder and contact.
    Timer(u32),
    /// Counters: value and contact.
    Counter(u32),
    /// Words written 0.
    Word(WordArea, Address),
}

/// An operand of an application instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataOperand {
    Word(WordRef),
    /// The first of consecutive bits (CMP/ZCP results).
    Bits(BitRef),
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Op {
    /// LD-type contact: starts a block, or a new rung when `new_rung` (the
    /// logic stack is empty then). The block is under the power rail of the
    /// master-control levels in `mc_levels` (bit k = level Nk).
    Load {
        contact: Contact,
        new_rung: bool,
        mc_levels: u8,
    },
    And(Contact),
    Or(Contact),
    AndBlock,
    OrBlock,
    Push,
    Read,
    Pop,
    Invert,
    /// MEP/MEF: edge of the result so far.
    ResultEdge {
        falling: bool,
        slot: u32,
    },
    Out(BitRef),
    OutTimer {
        timer: u32,
        preset: WordRef,
    },
    OutCounter {
        counter: u32,
        preset: WordRef,
    },
    /// SET `count` devices. `transfer_from`: a SET of a state inside the
    /// block of that state, which then turns OFF at the next scan.
    Set {
        target: BitRef,
        count: u32,
        transfer_from: Option<u32>,
    },
    Reset {
        target: ResetTarget,
        count: u32,
    },
    /// PLS (rising) / PLF (falling).
    Pulse {
        target: BitRef,
        sense: Sense,
        slot: u32,
    },
    /// ST: turn the state ON, leave the current one alone.
    StateJump {
        state: u32,
    },
    MasterControl {
        level: u8,
        relay: BitRef,
    },
    /// Jump to instruction index `target` (possibly the end of the list).
    Jump {
        target: usize,
    },
    /// A jump target; does nothing.
    Label,
    StlBegin {
        block: usize,
    },
    StlEnd,
    Data(DataInstruction),
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DataInstruction {
    pub op: DataOp,
    pub wide: bool,
    pub operands: Vec<DataOperand>,
    /// The P form's previous-scan slot (the condition at its last execution).
    pub pulse_slot: Option<u32>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Instruction {
    pub op: Op,
    /// 1-based source line (what D8069 records on an operation error).
    pub line: u32,
    pub span: Span,
}

/// One `STL Sn` ... `STLE` block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StlBlock {
    pub state: u32,
    /// Index of the StlBegin instruction.
    pub begin: usize,
    /// Index of the StlEnd instruction.
    pub end: usize,
    /// Instructions executed with the power OFF when the block is reset once
    /// (its OUT coils, timers, counters, PLS/PLF).
    pub reset_outputs: Vec<usize>,
    /// Slots cleared at that reset (PLS/PLF and P-form instructions).
    pub reset_slots: Vec<u32>,
}

/// The output of the checker.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckedProgram {
    pub name: String,
    /// Executable instructions up to END.
    pub instructions: Vec<Instruction>,
    pub stl_blocks: Vec<StlBlock>,
    /// Number of previous-scan slots used.
    pub edge_slots: u32,
}
