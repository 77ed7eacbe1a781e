//! The checked program: every operand resolved to a device of the runtime's
//! areas, every edge instruction given its previous-scan slot, every jump its
//! target, every STL block its extent. The interpreter executes this list
//! directly; the IR lowering starts from it.

use crate::isa::{AppArgs, CompareOp, Sense};
use crate::source::Span;
use ladder_runtime::pulse::PulseKind;
use ladder_runtime::{BitArea, Width, WordArea};

/// The register whose value modifies a device number at run time: `Dk` in
/// `DEV[Dk]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct IndexRegister {
    pub area: WordArea,
    pub number: u32,
}

/// A device number, possibly modified at run time by an index register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Address {
    /// The number as written (octal already converted for X/Y).
    pub index: u32,
    /// `DEV[Dk]`: the register whose current (signed) value is added.
    pub index_register: Option<IndexRegister>,
}

impl Address {
    pub fn fixed(index: u32) -> Address {
        Address {
            index,
            index_register: None,
        }
    }

    /// The number is known at compile time.
    pub fn is_fixed(self) -> bool {
        self.index_register.is_none()
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
    /// `LD= S1 S2` and friends; `Width::Double` for the D forms.
    Compare {
        op: CompareOp,
        width: Width,
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

/// The start of a run of bits, or a word: where an operand may be either
/// (ENCO S, DECO D). A word is 16 bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Element {
    /// Bit devices (or bits of a word), one bit per unit.
    Bits(BitRef),
    /// A word value (a device, a digit group or a constant).
    Word(WordRef),
}

/// A digit group: 4·digits bits from a start device (`K4M0`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DigitGroup {
    pub area: BitArea,
    pub address: Address,
    pub digits: u8,
}

/// One end of a device range that ZRST/ZSET write.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RangeEnd {
    /// A bit device or a bit of a word.
    Bit(BitRef),
    /// A data register (D, R, SD).
    Word(WordArea, Address),
    /// A timer: value, contact and bookkeeping.
    Timer(Address),
    /// A counter: value, contact and bookkeeping.
    Counter(Address),
}

/// A checked operand of an application instruction, before it takes the
/// type of its kind in `AppArgs`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AppOperand {
    Word(WordRef),
    Bit(BitRef),
    Element(Element),
    RangeEnd(RangeEnd),
    Digits(DigitGroup),
    /// A timer by number (ANS S).
    Timer(Address),
    /// A counter by number (DHSCS S2, INCD S2).
    Counter(CounterRef),
}

/// A counter named as a device (not its value): the high-speed counter a
/// DHSCS compares, the counters INCD drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CounterRef(pub Address);

impl From<CounterRef> for AppOperand {
    fn from(counter: CounterRef) -> Self {
        AppOperand::Counter(counter)
    }
}

impl From<Address> for AppOperand {
    fn from(timer: Address) -> Self {
        AppOperand::Timer(timer)
    }
}

impl From<DigitGroup> for AppOperand {
    fn from(group: DigitGroup) -> Self {
        AppOperand::Digits(group)
    }
}

impl From<RangeEnd> for AppOperand {
    fn from(end: RangeEnd) -> Self {
        AppOperand::RangeEnd(end)
    }
}

impl From<WordRef> for AppOperand {
    fn from(word: WordRef) -> Self {
        AppOperand::Word(word)
    }
}

impl From<BitRef> for AppOperand {
    fn from(bit: BitRef) -> Self {
        AppOperand::Bit(bit)
    }
}

impl From<Element> for AppOperand {
    fn from(element: Element) -> Self {
        AppOperand::Element(element)
    }
}

/// One instruction of the checked program. The kinds a walker other than
/// the interpreter and the lowering seldom tells apart are grouped: `Logic`
/// (works on the rung's result, names no device) and `Line` (a line of its
/// own, outside every rung), so that a walker names the groups it passes
/// over instead of listing every kind.
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
    /// ANB, ORB, MPS, MRD, MPP, INV, MEP/MEF.
    Logic(Logic),
    /// An instruction that takes the rung result: a coil, SET/RST, an
    /// application instruction, ...
    Output(Output),
    /// CJ `Plabel`: jump to instruction index `target` (possibly the end of
    /// the list).
    Jump {
        target: usize,
        label: u32,
    },
    /// CALL/CALLP: runs subroutine `subroutine` (an index into
    /// `CheckedProgram::subroutines`) while the rung is ON, or with `slot`
    /// (CALLP) at its rising edge, and continues after the CALL.
    Call {
        subroutine: usize,
        slot: Option<u32>,
    },
    /// P labels, MCR, STL, RET, FEND, SRET, FOR, NEXT.
    Line(Line),
}

/// An instruction that works on the rung's result (and the logic stack)
/// and names no device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Logic {
    /// ANB.
    AndBlock,
    /// ORB.
    OrBlock,
    /// MPS.
    BranchPush,
    /// MRD.
    BranchRead,
    /// MPP.
    BranchPop,
    Invert,
    /// MEP/MEF: edge of the result so far.
    ResultEdge {
        falling: bool,
        slot: u32,
    },
}

/// An instruction on a line of its own: no rung leads to it and it takes
/// no result.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Line {
    /// A jump target `Pn` (also a subroutine's entry); does nothing.
    Label {
        number: u32,
    },
    /// MCR `Nlevel`: closes the level (and deeper ones). It does nothing
    /// when it runs: the loads after it name the levels they are under.
    MasterControlReset {
        level: u8,
    },
    StlBegin {
        block: usize,
    },
    StlEnd,
    /// FEND: the main program ends here; subroutines follow.
    MainEnd,
    /// SRET: the end of a subroutine.
    SubroutineReturn,
    /// FOR: the instructions up to the NEXT at index `end` run `count`
    /// times (below 1 counts as 1; the runtime's watchdog may stop it).
    LoopStart {
        count: WordRef,
        end: usize,
    },
    /// NEXT of the FOR at index `start`.
    LoopEnd {
        start: usize,
    },
}

/// What a line of its own reads when it runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineReads<'a> {
    /// FOR: its count.
    Word(&'a WordRef),
    /// STL: the state of block `n` (`CheckedProgram::stl_blocks`).
    State(usize),
    /// P labels, MCR, RET, FEND, SRET, NEXT.
    Nothing,
}

impl Line {
    pub fn reads(&self) -> LineReads<'_> {
        match self {
            Line::LoopStart { count, .. } => LineReads::Word(count),
            Line::StlBegin { block } => LineReads::State(*block),
            Line::Label { .. }
            | Line::MasterControlReset { .. }
            | Line::StlEnd
            | Line::MainEnd
            | Line::SubroutineReturn
            | Line::LoopEnd { .. } => LineReads::Nothing,
        }
    }
}

/// What an output instruction does with the rung result (its power).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Output {
    /// OUT on a bit.
    Coil(BitRef),
    /// OUT Tn preset.
    Timer {
        timer: u32,
        preset: WordRef,
    },
    /// OUT Cn preset.
    Counter {
        counter: u32,
        preset: WordRef,
    },
    /// SET `count` devices. `transfer_from`: a SET of a state inside the
    /// block of that state, which then turns OFF at the next scan.
    /// `written_out`: the source wrote `OUT Sn` inside a block, which is this
    /// transfer (the ladder draws it as the coil it was written as).
    Set {
        target: BitRef,
        count: u32,
        transfer_from: Option<u32>,
        written_out: bool,
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
    App(AppInstruction),
}

impl Output {
    /// The bits the output may write at fixed or indexed addresses (the
    /// first of a run for SET/RST with a count and for bit ranges).
    pub fn written_bits(&self) -> Vec<BitRef> {
        match self {
            Output::Coil(bit) | Output::Set { target: bit, .. } | Output::Pulse { target: bit, .. } => vec![*bit],
            Output::Reset { target, .. } => match target {
                ResetTarget::Bit(bit) => vec![*bit],
                ResetTarget::Timer(_) | ResetTarget::Counter(_) | ResetTarget::Word(..) => Vec::new(),
            },
            Output::MasterControl { relay, .. } => vec![*relay],
            Output::StateJump { state } => vec![BitRef::Device(BitArea::S, Address::fixed(*state))],
            Output::App(app) => app
                .args
                .operands()
                .into_iter()
                .zip(app.args.op().spec().operands)
                .filter(|(_, decl)| decl.kind.writes_bits())
                .filter_map(|(operand, _)| match operand {
                    AppOperand::Bit(bit)
                    | AppOperand::Element(Element::Bits(bit))
                    | AppOperand::RangeEnd(RangeEnd::Bit(bit)) => Some(bit),
                    AppOperand::Digits(group) => Some(BitRef::Device(group.area, group.address)),
                    AppOperand::Word(_)
                    | AppOperand::Timer(_)
                    | AppOperand::Counter(_)
                    | AppOperand::Element(Element::Word(_))
                    | AppOperand::RangeEnd(RangeEnd::Word(..) | RangeEnd::Timer(_) | RangeEnd::Counter(_)) => None,
                })
                .collect(),
            Output::Timer { .. } | Output::Counter { .. } => Vec::new(),
        }
    }
}

/// An application instruction with its checked operands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AppInstruction {
    /// 16-bit (`MOV`) or 32-bit (`DMOV`) form.
    pub width: Width,
    pub args: AppArgs,
    /// The P form's previous-scan slot (the condition at its last execution).
    pub pulse_slot: Option<u32>,
    /// The instruction's job (SORT, SORT2, DSORT2: `Memory::sort_state`) or instance
    /// state (`Memory::instance`) in the image, as its declaration `keeps`.
    pub job: Option<u32>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Instruction {
    pub op: Op,
    /// 1-based source line (what D8069 records on an operation error,
    /// unless `step` is known).
    pub line: u32,
    pub span: Span,
    /// The step a GX Developer project gives the instruction (its listing
    /// starts the line with it): D8069 records it, as on the PLC.
    pub step: Option<u32>,
}

impl Instruction {
    /// What D8069 records when the instruction fails: its step in a GX
    /// Developer project, else its source line.
    pub fn error_line(&self) -> u32 {
        self.step.unwrap_or(self.line)
    }
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

/// A subroutine: label `Pn` after FEND, its instructions, SRET.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Subroutine {
    pub label: u32,
    /// Index of its label (the first instruction it runs).
    pub entry: usize,
    /// Index of its SRET.
    pub end: usize,
}

/// The output of the checker.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckedProgram {
    pub name: String,
    /// Executable instructions up to END.
    pub instructions: Vec<Instruction>,
    pub stl_blocks: Vec<StlBlock>,
    /// The subroutines after FEND, in source order.
    pub subroutines: Vec<Subroutine>,
    /// Index of FEND, where the main program ends (the end of the list when
    /// there is none).
    pub main_end: usize,
    /// Number of previous-scan slots used.
    pub edge_slots: u32,
}

/// The operands of a pulse instruction (PLSY, PLSR, PLSV, DRVI, DRVA, ZRN,
/// DSZR) by their role, built once in the dispatch both engines share.
pub struct PulseOperands<'a> {
    pub kind: PulseKind,
    pub frequency: Option<&'a WordRef>,
    pub amount: Option<&'a WordRef>,
    pub ramp: Option<&'a WordRef>,
    pub creep: Option<&'a WordRef>,
    pub near_point: Option<&'a BitRef>,
    /// DSZR's zero signal: read (its range checked), not used by the model.
    pub zero_signal: Option<&'a BitRef>,
    pub output: &'a BitRef,
    pub direction: Option<&'a BitRef>,
}

impl<'a> PulseOperands<'a> {
    pub fn new(kind: PulseKind, output: &'a BitRef) -> PulseOperands<'a> {
        PulseOperands {
            kind,
            frequency: None,
            amount: None,
            ramp: None,
            creep: None,
            near_point: None,
            zero_signal: None,
            output,
            direction: None,
        }
    }

    pub fn frequency(self, word: &'a WordRef) -> Self {
        PulseOperands {
            frequency: Some(word),
            ..self
        }
    }

    pub fn amount(self, word: &'a WordRef) -> Self {
        PulseOperands {
            amount: Some(word),
            ..self
        }
    }

    pub fn ramp(self, word: &'a WordRef) -> Self {
        PulseOperands {
            ramp: Some(word),
            ..self
        }
    }

    pub fn creep(self, word: &'a WordRef) -> Self {
        PulseOperands {
            creep: Some(word),
            ..self
        }
    }

    pub fn near_point(self, bit: &'a BitRef) -> Self {
        PulseOperands {
            near_point: Some(bit),
            ..self
        }
    }

    pub fn zero_signal(self, bit: &'a BitRef) -> Self {
        PulseOperands {
            zero_signal: Some(bit),
            ..self
        }
    }

    pub fn direction(self, bit: &'a BitRef) -> Self {
        PulseOperands {
            direction: Some(bit),
            ..self
        }
    }
}
