//! The instruction set: one table from mnemonic to what the instruction is,
//! which operands it takes, its width and whether it is a pulse (P) form.
//! Adding an instruction is one entry here plus its semantics in the
//! interpreter and the lowering.

mod table;

pub use table::{lookup, mnemonics};

/// How a contact looks at its device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sense {
    /// Normally open: passes when the device is ON.
    Open,
    /// Normally closed: passes when the device is OFF.
    Closed,
    /// Passes for one execution when the device turned ON since the last one.
    Rising,
    /// Passes for one execution when the device turned OFF since the last one.
    Falling,
}

/// Where a contact connects to the rung.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// LD-type: starts a block (or the rung).
    Load,
    /// AND-type: in series with the current block.
    And,
    /// OR-type: in parallel with the current block.
    Or,
}

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

/// Application (data) instructions. The 16/32-bit width and the pulse form
/// are properties of the table entry, not of the operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DataOp {
    /// MOV S D
    Mov,
    /// BMOV S D n: n words from S to D.
    BlockMov,
    /// FMOV S D n: S into n words from D.
    FillMov,
    /// ADD S1 S2 D
    Add,
    /// SUB S1 S2 D
    Sub,
    /// MUL S1 S2 D: product to a double-width D.
    Mul,
    /// DIV S1 S2 D: quotient to D, remainder to the next unit.
    Div,
    /// INC D
    Inc,
    /// DEC D
    Dec,
    /// CMP S1 S2 D: D, D+1, D+2 = S1>S2, S1=S2, S1<S2.
    Cmp,
    /// ZCP S1 S2 S D: D, D+1, D+2 = S<S1, S1<=S<=S2, S>S2.
    ZoneCmp,
}

/// What an instruction does, as far as the checker and engines care.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Class {
    Contact(Role, Sense),
    /// NOI/NCI/PTI/NTI: a contact whose role depends on its position.
    AliasContact(Sense),
    /// ATI/AFI: always true/false, role by position, device optional.
    AliasConstant(bool),
    /// `LD=`, `ANDD>`, ...
    Compare(Role, CompareOp),
    BlockAnd,
    BlockOr,
    Push,
    Read,
    Pop,
    Invert,
    /// MEP/MEF: rising/falling edge of the result so far.
    ResultEdge(Sense),
    Out,
    Set,
    Reset,
    /// PLS (Rising) / PLF (Falling).
    Pulse(Sense),
    /// ST Sn: turn a state ON without leaving the current one.
    StateJump,
    MasterControl,
    MasterControlReset,
    Jump,
    Stl,
    StlEnd,
    Network,
    /// POP: ends the current rung.
    RungEnd,
    End,
    Data(DataOp),
}

/// What an operand position accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OperandKind {
    /// A bit read by a contact: X Y M S SM T C, Dn.b.
    BitSource,
    /// A coil of OUT: Y M S SM Dn.b, or a timer/counter (then a preset follows).
    Coil,
    /// The preset of a timer or counter coil: K or D.
    Preset,
    /// A bit written by SET/PLS/PLF: Y M S SM Dn.b.
    BitTarget,
    /// What RST clears: a bit target, T, C, or a word (D R SD).
    ResetTarget,
    /// Number of consecutive devices for SET/RST: K1..
    DeviceCount,
    /// A state Sn.
    State,
    /// A master-control level N0..N7.
    NestLevel,
    /// A jump label Pn.
    Label,
    /// A word value read by the instruction (constants allowed).
    Source,
    /// A word written by the instruction.
    Destination,
    /// A destination twice the instruction's width (MUL/DIV results).
    WideDestination,
    /// The first of three bits written (CMP/ZCP results): Y M S.
    BitTriple,
    /// A word count: K or a word source (BMOV/FMOV n).
    WordCount,
}

/// One row of the instruction table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InstrSpec {
    pub name: &'static str,
    pub class: Class,
    pub operands: &'static [OperandKind],
    /// `operands[..required]` must be present; the rest are optional.
    pub required: usize,
    /// The 32-bit (D-prefixed) form.
    pub wide: bool,
    /// The pulse (P-suffixed) form: runs once per rising edge of its condition.
    pub pulse: bool,
}
