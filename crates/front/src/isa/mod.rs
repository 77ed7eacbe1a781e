//! The instruction set, declared once.
//!
//! - `bits`: the bit instructions (contacts, coils, rung structure, program
//!   control), one row each;
//! - `app`: the application instructions, one declaration each (names, D and
//!   P forms, operands with their kinds and device tables, flags);
//! - `operand`: operand kinds and device tables;
//! - `reach`: how far an operand's run reaches, where its kind does not say;
//! - `table`: the mnemonic lookup built from both.
//!
//! Adding an application instruction: its declaration in `app.rs`, its
//! kernel in `interp/app/` and in `lower/app/`, its section in
//! docs/language.md and a scenario. See docs/architecture.md.

// Before `app`, whose declarations use its macro.
#[macro_use]
pub mod reach;
pub mod app;
pub mod bits;
mod dispatch;
pub mod fx;
pub mod operand;
pub mod reference;
mod table;

pub use app::{AppArgs, AppOp, AppSpec, Family, MachinePart, OperandDecl};
pub use bits::BitSpec;
pub use operand::{DeviceClass, Devices, OperandKind};
pub use table::{lookup, mnemonics, AppForm, Mnemonic};

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
    pub const ALL: [CompareOp; 6] = [
        CompareOp::Eq,
        CompareOp::Ne,
        CompareOp::Gt,
        CompareOp::Lt,
        CompareOp::Ge,
        CompareOp::Le,
    ];

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

/// What a bit instruction does, as far as the checker and engines care.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BitClass {
    Contact(Role, Sense),
    /// NOI/NCI/PTI/NTI: a contact whose role depends on its position.
    AliasContact(Sense),
    /// ATI/AFI: always true/false, role by position, device optional.
    AliasConstant(bool),
    /// `LD=`, `ANDD>`, ...
    Compare(Role, CompareOp),
    /// ANB.
    BlockAnd,
    /// ORB.
    BlockOr,
    /// MPS: stores the power flow at a branch point.
    BranchPush,
    /// MRD: reads the branch point back.
    BranchRead,
    /// MPP: reads the branch point back and drops it.
    BranchPop,
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
    /// STLE, or RET (`fx_return`: the FX spelling, which also returns to
    /// the main bus).
    StlEnd {
        fx_return: bool,
    },
    /// FEND: the main program ends; subroutines follow.
    MainEnd,
    /// CALL/CALLP Pn.
    Call {
        pulse: bool,
    },
    /// SRET: the end of a subroutine.
    SubroutineReturn,
    /// FOR n.
    LoopStart,
    /// NEXT.
    LoopEnd,
    /// NOP: does nothing.
    Nop,
    Network,
    /// POP: ends the current rung (not MPP, which pops a branch point).
    RungEnd,
    End,
}
