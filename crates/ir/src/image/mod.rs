//! The image a compiled program needs.
//!
//! `--image full` is the runtime's full layout: every device of the machine
//! model (666 KB, most of it the buffer memory of eight modules), which any
//! host can address. `--image compact` holds only what the program and its
//! host use, packed (`ladder_runtime::layout::LayoutBuilder`): a traffic
//! light needs a few hundred bytes. Its footprint comes from
//!
//! - the checked program (as the interpreter reads it): every operand, with
//!   the units its kind covers (a run whose length is only known at run
//!   time, or an operand modified by an index register, takes its whole
//!   area), timers, counters, states, instruction instances and sort jobs,
//!   the special relays instructions declare, and what the machine model
//!   needs around instructions (the high-speed counters' inputs, the pulse
//!   outputs' registers, the clock's registers);
//! - the optimised IR, so that code generation finds every device it
//!   addresses (a run-time index takes its whole area, laid out in one
//!   piece);
//! - the operation error (M8067, D8067, D8069), which hosts read;
//! - the devices the host names (`--host-devices`).
//!
//! A device the image lacks reads 0 and is not written (`image.rs` in the
//! runtime); a write to one through an instruction's operand is counted,
//! and the tests insist that there is none.

mod header;
#[cfg(test)]
mod tests;

pub use header::{c_header, device_name};

use crate as ir;
use ladder_front::host_device::HostDevice;
use ladder_front::isa::app::Keeps;
use ladder_front::isa::reach::ReachUnit;
use ladder_front::isa::{MachinePart, OperandKind};
use ladder_front::program::{
    Address, AppInstruction, AppOperand, BitRef, CheckedProgram, Contact, CounterRef, DigitGroup, Element, LineReads,
    Op, Output, RangeEnd, ResetTarget, WordRef,
};
use ladder_runtime::calendar::D_CLOCK_FIRST;
use ladder_runtime::device::{
    buffer_word, BUFFER_UNITS, BUFFER_WORDS_PER_UNIT, COUNTER_COUNT, FIRST_WIDE_COUNTER, HSC_INPUTS,
};
use ladder_runtime::helpers::Helper;
use ladder_runtime::hsc::{FIRST_HSC, M_HSC_DIRECTION_BASE};
use ladder_runtime::layout::{bit_arrays, word_arrays, Array, Layout, LayoutBuilder, COUNTER_ARRAYS};
use ladder_runtime::special::{FIRST_ALARM_STATE, LAST_ALARM_STATE, M_COUNTER_DIRECTION_BASE};
use ladder_runtime::{BitArea, Device, MachineUse, WordArea};

/// Which layout `ladderc build` gives the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// Every device of the machine model (666,520 bytes).
    Full,
    /// Only the devices the program and its host use, packed.
    Compact,
}

/// The compact layout of `program` (checked as `checked`, optimised as
/// `ir`) with the devices its host names.
pub fn compact_layout(checked: &CheckedProgram, ir: &ir::Program, host: &[HostDevice]) -> Layout {
    let mut footprint = Footprint::default();
    footprint.checked_program(checked);
    for function in std::iter::once(&ir.main).chain(&ir.subroutines) {
        footprint.ir_function(function);
    }
    footprint.operation_error();
    for &device in host {
        footprint.host_device(device);
    }
    footprint.whole_clock_block();
    footprint.builder.build()
}

/// The parts of the machine around the program that `checked` (optimised
/// as `ir`) and a host naming `host` use: what its scan keeps up to date
/// (`ladder_runtime::machine`). Decided from the devices they name, as the
/// compact layout is, for any image.
pub fn machine_use(checked: &CheckedProgram, ir: &ir::Program, host: &[HostDevice]) -> MachineUse {
    let mut footprint = Footprint::default();
    footprint.checked_program(checked);
    for function in std::iter::once(&ir.main).chain(&ir.subroutines) {
        footprint.ir_function(function);
    }
    for &device in host {
        footprint.host_device(device);
    }
    footprint.machine
}

/// What the image must hold, as it is found.
#[derive(Default)]
struct Footprint {
    builder: LayoutBuilder,
    /// The parts of the machine the devices named so far use (not merely
    /// devices inside a run that spans them: M8002 and M8067 hold M8015 in
    /// their run, but only a program naming M8015 uses the calendar).
    machine: MachineUse,
}

/// Special registers of the machine model around instructions.
const D_PULSE_REGISTERS: std::ops::Range<u32> = 8136..8144;
const D_POSITIONING_REGISTERS: std::ops::Range<u32> = 8340..8380;
const M_POSITIONING_RELAYS: std::ops::Range<u32> = 8340..8380;
const M_EXECUTION_COMPLETE: u32 = ladder_runtime::special::M_EXECUTION_COMPLETE;
const D_CLOCK_REGISTERS: std::ops::Range<u32> = D_CLOCK_FIRST..8020;
const M_CLOCK_RELAYS: std::ops::Range<u32> = 8015..8020;

impl Footprint {
    fn bits(&mut self, area: BitArea, first: u32, count: u32) {
        let end = first.saturating_add(count);
        self.machine |= MachineUse::of_bits(area, first, end);
        self.builder.include_bits(area, first, end);
    }

    fn words(&mut self, area: WordArea, first: u32, count: u32) {
        let end = first.saturating_add(count);
        self.machine |= MachineUse::of_words(area, first, end);
        self.builder.include_words(area, first, end);
    }

    /// Every device of a bit area, everything that follows them, in one piece.
    fn whole_bits(&mut self, area: BitArea) {
        self.machine |= MachineUse::of_bits(area, 0, area.count());
        for &array in bit_arrays(area) {
            self.builder.include_whole(array);
        }
    }

    fn whole_words(&mut self, area: WordArea) {
        self.machine |= MachineUse::of_words(area, 0, area.count());
        for &array in word_arrays(area) {
            self.builder.include_whole(array);
        }
    }

    /// `count` counters from `first`, as far as there are counters (a run
    /// from C200 whose count is a large constant ends at C255).
    fn counters(&mut self, first: u32, count: u32) {
        for counter in first..first.saturating_add(count).min(COUNTER_COUNT) {
            self.counter(counter);
        }
    }

    /// A counter, with what the machine model reads for it: the direction
    /// relay of C200-C234; the inputs and direction relay of a high-speed
    /// counter.
    fn counter(&mut self, counter: u32) {
        self.bits(BitArea::CounterContact, counter, 1);
        if (FIRST_WIDE_COUNTER..FIRST_HSC).contains(&counter) {
            self.bits(BitArea::M, M_COUNTER_DIRECTION_BASE + (counter - FIRST_WIDE_COUNTER), 1);
        } else if counter >= FIRST_HSC {
            self.bits(BitArea::M, M_HSC_DIRECTION_BASE + counter, 1);
            self.high_speed_inputs();
        }
    }

    fn all_counters(&mut self) {
        for array in COUNTER_ARRAYS {
            self.builder.include_whole(array);
        }
        self.counters(FIRST_HSC, 1);
    }

    fn timers(&mut self, first: u32, count: u32) {
        self.bits(BitArea::TimerContact, first, count);
    }

    /// X0-X7 and what the input refresh counts of them.
    fn high_speed_inputs(&mut self) {
        self.machine |= MachineUse::HIGH_SPEED;
        self.bits(BitArea::X, 0, HSC_INPUTS);
        self.builder.include_whole(Array::PulsesPending);
        self.builder.include_whole(Array::InputEdges);
    }

    /// The calendar reads its registers and relays as a block (all of
    /// D8013-D8019 when M8015 turns OFF, say): a program or host that uses
    /// one of them, with MOV as on an FX, gets them all.
    fn whole_clock_block(&mut self) {
        if self.machine.contains(MachineUse::CALENDAR) {
            self.words(WordArea::D, D_CLOCK_REGISTERS.start, D_CLOCK_REGISTERS.len() as u32);
            self.bits(BitArea::M, M_CLOCK_RELAYS.start, M_CLOCK_RELAYS.len() as u32);
        }
    }

    /// M8067, D8067 and D8069, which hosts read (`ladder_operation_error`).
    fn operation_error(&mut self) {
        use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
        self.bits(BitArea::M, M_OPERATION_ERROR, 1);
        self.words(WordArea::D, D_ERROR_CODE, 1);
        self.words(WordArea::D, D_ERROR_LINE, 1);
    }

    fn host_device(&mut self, device: HostDevice) {
        match device.device {
            Device::Bit(area, n) => self.bits(area, n, 1),
            Device::Word(area, n) => self.words(area, n, device.width.words()),
            Device::WordBit(area, n, _) => self.words(area, n, 1),
            Device::Digits(area, n, digits) => self.bits(area, n, 4 * u32::from(digits)),
            Device::WideCounter(n) => self.counter(n),
        }
    }

    // ---- the checked program ----

    fn checked_program(&mut self, program: &CheckedProgram) {
        self.builder.include(Array::EdgeSlot, 0, program.edge_slots);
        for block in &program.stl_blocks {
            self.bits(BitArea::S, block.state, 1);
        }
        for instruction in &program.instructions {
            match &instruction.op {
                Op::Load { contact, .. } | Op::And(contact) | Op::Or(contact) => self.contact(contact),
                Op::Output(output) => self.output(output),
                Op::Line(line) => match line.reads() {
                    LineReads::Word(count) => self.word(count, 1),
                    // The states of STL blocks are held above.
                    LineReads::State(_) | LineReads::Nothing => {}
                },
                Op::Logic(_) | Op::Jump { .. } | Op::Call { .. } => {}
            }
        }
    }

    fn contact(&mut self, contact: &Contact) {
        match contact {
            Contact::Level { bit, .. } | Contact::Edge { bit, .. } => self.bit(bit, 1),
            Contact::Constant(_) => {}
            Contact::Compare { width, left, right, .. } => {
                self.word(left, width.words());
                self.word(right, width.words());
            }
        }
    }

    fn output(&mut self, output: &Output) {
        match output {
            Output::Coil(bit) | Output::Pulse { target: bit, .. } | Output::MasterControl { relay: bit, .. } => {
                self.bit(bit, 1)
            }
            Output::Timer { timer, preset } => {
                self.timers(*timer, 1);
                self.word(preset, 1);
            }
            Output::Counter { counter, preset } => {
                self.counter(*counter);
                self.word(preset, ladder_runtime::device::counter_width(*counter).words());
            }
            Output::Set {
                target,
                count,
                transfer_from,
                written_out: _,
            } => {
                self.bit(target, *count);
                if let Some(state) = transfer_from {
                    self.bits(BitArea::S, *state, 1);
                }
            }
            Output::Reset { target, count } => match target {
                ResetTarget::Bit(bit) => self.bit(bit, *count),
                ResetTarget::Timer(first) => self.timers(*first, *count),
                ResetTarget::Counter(first) => self.counters(*first, *count),
                ResetTarget::Word(area, address) => self.address_words(*area, *address, *count),
            },
            Output::StateJump { state } => self.bits(BitArea::S, *state, 1),
            Output::App(app) => self.app(app),
        }
    }

    fn app(&mut self, app: &AppInstruction) {
        let spec = app.args.op().spec();
        let words = app.width.words();
        let operands = app.args.operands();
        // A pair of range ends (ZRST, MAX, ...) covers what lies between.
        let ends: Vec<AppOperand> = operands
            .iter()
            .zip(spec.operands)
            .filter(|(_, decl)| matches!(decl.kind, OperandKind::RangeEnd | OperandKind::TableEnd))
            .map(|(operand, _)| *operand)
            .collect();
        if let [first, last] = ends[..] {
            self.range(first, last);
        }
        for (operand, decl) in operands.into_iter().zip(spec.operands) {
            match decl.reach {
                // A run the declaration bounds: as far as it reaches when
                // its counts are constants, its whole area when not.
                Some(reach) => {
                    let length = reach.length(|name| constant_operand(app, name));
                    self.reach(operand, reach.unit, length, decl.kind, words)
                }
                None => self.app_operand(operand, decl.kind, words),
            }
        }
        for special in spec.reads.iter().chain(spec.writes) {
            self.bits(special.area, special.number, 1);
        }
        match (spec.keeps, app.job) {
            (Keeps::SortJob, Some(job)) => {
                self.builder.include(Array::SortState, job, job + 1);
                self.builder.include(Array::SortScans, job, job + 1);
            }
            (Keeps::State, Some(job)) => {
                self.builder.include(Array::Instance, job, job + 1);
            }
            (Keeps::Nothing | Keeps::SortJob | Keeps::State, _) => {}
        }
        // What the instruction declares of the machine model.
        for part in spec.machine {
            match part {
                MachinePart::Clock => {
                    self.words(WordArea::D, D_CLOCK_REGISTERS.start, D_CLOCK_REGISTERS.len() as u32);
                    self.bits(BitArea::M, M_CLOCK_RELAYS.start, M_CLOCK_RELAYS.len() as u32);
                }
                MachinePart::InputCounting => self.high_speed_inputs(),
                MachinePart::PulseOutputs => {
                    self.builder.include_whole(Array::PulseOwner);
                    self.builder.include_whole(Array::PulseRemainder);
                    self.words(WordArea::D, D_PULSE_REGISTERS.start, D_PULSE_REGISTERS.len() as u32);
                    self.words(
                        WordArea::D,
                        D_POSITIONING_REGISTERS.start,
                        D_POSITIONING_REGISTERS.len() as u32,
                    );
                    self.bits(
                        BitArea::M,
                        M_POSITIONING_RELAYS.start,
                        M_POSITIONING_RELAYS.len() as u32,
                    );
                    self.bits(BitArea::M, M_EXECUTION_COMPLETE, 1);
                }
                MachinePart::AlarmStates => {
                    self.bits(BitArea::S, FIRST_ALARM_STATE, LAST_ALARM_STATE - FIRST_ALARM_STATE + 1)
                }
                MachinePart::BufferMemory => self.buffer_transfer(app),
            }
        }
    }

    /// FROM/TO m1 m2 .. n: the buffer words they move, from their unit and
    /// word numbers (values, not operands): n units from word m2 of unit
    /// m1 when all three are constants, the unit's whole buffer when m1 is,
    /// every unit's otherwise.
    fn buffer_transfer(&mut self, app: &AppInstruction) {
        let constant = |name: &str| constant_operand(app, name).and_then(|value| u32::try_from(value).ok());
        let Some(unit) = constant("m1").filter(|&unit| unit < BUFFER_UNITS) else {
            self.builder.include_whole(Array::Buffer);
            return;
        };
        let start = buffer_word(unit, 0);
        let (first, count) = match (constant("m2"), constant("n")) {
            (Some(first), Some(n)) if first < BUFFER_WORDS_PER_UNIT => (
                first,
                n.saturating_mul(app.width.words()).min(BUFFER_WORDS_PER_UNIT - first),
            ),
            _ => (0, BUFFER_WORDS_PER_UNIT),
        };
        self.words(WordArea::Buffer, start + first, count);
    }

    /// An operand whose declared reach holds `length` units (`unit`) from
    /// its device, `None` when a count is only known at run time (then its
    /// whole area); `words` is the instruction's width in words.
    fn reach(&mut self, operand: AppOperand, unit: ReachUnit, length: Option<u32>, kind: OperandKind, words: u32) {
        // A count that makes the instruction fail touches nothing; the
        // device itself is held all the same.
        let length = length.map(|length| length.max(1));
        match (operand, unit, length) {
            // A word in a bit-or-word position (ENCO, DECO) is one word.
            (AppOperand::Word(word) | AppOperand::Element(Element::Word(word)), ReachUnit::Bits, _) => {
                self.word(&word, 1)
            }
            (AppOperand::Word(word) | AppOperand::Element(Element::Word(word)), ReachUnit::Units, Some(length)) => {
                self.word_run(&word, length, words)
            }
            (AppOperand::Word(word) | AppOperand::Element(Element::Word(word)), ReachUnit::Words, Some(length)) => {
                self.word_run(&word, length, 1)
            }
            (
                AppOperand::Word(word) | AppOperand::Element(Element::Word(word)),
                ReachUnit::Units | ReachUnit::Words,
                None,
            ) => self.whole_of_word(&word),
            (
                AppOperand::Bit(bit) | AppOperand::Element(Element::Bits(bit)),
                ReachUnit::Units | ReachUnit::Words | ReachUnit::Bits,
                Some(length),
            ) => self.bit(&bit, length),
            (
                AppOperand::Bit(bit) | AppOperand::Element(Element::Bits(bit)),
                ReachUnit::Units | ReachUnit::Words | ReachUnit::Bits,
                None,
            ) => self.whole_of_bit(&bit),
            // Kinds no reach is declared on: as their kind says.
            (AppOperand::RangeEnd(_) | AppOperand::Digits(_) | AppOperand::Timer(_) | AppOperand::Counter(_), _, _) => {
                self.app_operand(operand, kind, words)
            }
        }
    }

    /// `count` units of `words` words each from a word operand (a digit
    /// group's unit is its bits; a 32-bit counter's, the counter).
    fn word_run(&mut self, word: &WordRef, count: u32, words: u32) {
        match *word {
            WordRef::Constant(_) => {}
            WordRef::Word(area, address) => self.address_words(area, address, count.saturating_mul(words)),
            WordRef::WideCounter(address) => match address.index_register {
                None => self.counters(address.index, count),
                Some(register) => {
                    self.index_register(register);
                    self.all_counters();
                }
            },
            WordRef::Digits(area, address, digits) => self.bit(
                &BitRef::Device(area, address),
                (4 * u32::from(digits)).saturating_mul(count),
            ),
        }
    }

    /// An operand of an application instruction, with the units its kind
    /// covers at the instruction's width (`words`: 1 or 2).
    fn app_operand(&mut self, operand: AppOperand, kind: OperandKind, words: u32) {
        let units = match kind {
            OperandKind::Source | OperandKind::Modified | OperandKind::Destination => Some(words),
            OperandKind::Count => Some(1),
            OperandKind::DoubleDestination => Some(2 * words),
            OperandKind::RealSource | OperandKind::RealDestination | OperandKind::RealModified => Some(2),
            OperandKind::BitDestination => Some(1),
            OperandKind::BitTriple => Some(3),
            OperandKind::DigitSource | OperandKind::DigitDestination => Some(1),
            OperandKind::Timer | OperandKind::HighSpeedCounter => Some(1),
            OperandKind::CounterPair => Some(2),
            // A run whose length the instruction decides (at run time):
            // the whole area, so that it can reach as far as the run goes.
            OperandKind::BlockSource
            | OperandKind::BlockDestination
            | OperandKind::ByteSource
            | OperandKind::BitSource
            | OperandKind::BitModified
            | OperandKind::ElementSource
            | OperandKind::ElementDestination
            | OperandKind::RangeEnd
            | OperandKind::TableEnd => None,
        };
        match (operand, units) {
            (AppOperand::Word(word), Some(units)) => self.word(&word, units),
            (AppOperand::Bit(bit), Some(units)) => self.bit(&bit, units),
            (AppOperand::Digits(group), _) => self.digits(group),
            (AppOperand::Timer(address), Some(units)) => match address.index_register {
                None => self.timers(address.index, units),
                Some(register) => {
                    self.index_register(register);
                    self.whole_bits(BitArea::TimerContact);
                }
            },
            (AppOperand::Counter(CounterRef(address)), Some(units)) => match address.index_register {
                None => self.counters(address.index, units),
                Some(register) => {
                    self.index_register(register);
                    self.all_counters();
                }
            },
            // Range ends were taken as a range; a single one is a device.
            (AppOperand::RangeEnd(end), _) => self.range_end_area(end),
            (AppOperand::Element(Element::Word(word)), _) => self.whole_of_word(&word),
            (AppOperand::Element(Element::Bits(bit)), _) | (AppOperand::Bit(bit), None) => self.whole_of_bit(&bit),
            (AppOperand::Word(word), None) => self.whole_of_word(&word),
            (AppOperand::Timer(_), None) => self.whole_bits(BitArea::TimerContact),
            (AppOperand::Counter(_), None) => self.all_counters(),
        }
    }

    /// ZRST/ZSET ends and MAX/MIN table ends: everything between them
    /// (the whole area when an end is indexed or the ends differ in kind).
    fn range(&mut self, first: AppOperand, last: AppOperand) {
        let fixed = |address: Address| address.index_register.is_none().then_some(address.index);
        let span = |a: u32, b: u32| (a.min(b), a.max(b) - a.min(b) + 1);
        match (first, last) {
            (
                AppOperand::RangeEnd(RangeEnd::Bit(BitRef::Device(area, a))),
                AppOperand::RangeEnd(RangeEnd::Bit(BitRef::Device(other, b))),
            ) if area == other => match (fixed(a), fixed(b)) {
                (Some(a), Some(b)) => {
                    let (start, count) = span(a, b);
                    self.bits(area, start, count);
                }
                _ => self.whole_bits(area),
            },
            (AppOperand::RangeEnd(RangeEnd::Word(area, a)), AppOperand::RangeEnd(RangeEnd::Word(other, b)))
            | (AppOperand::Word(WordRef::Word(area, a)), AppOperand::Word(WordRef::Word(other, b)))
                if area == other =>
            {
                match (fixed(a), fixed(b)) {
                    (Some(a), Some(b)) => {
                        let (start, count) = span(a, b);
                        self.words(area, start, count);
                    }
                    _ => self.whole_words(area),
                }
            }
            (AppOperand::RangeEnd(RangeEnd::Timer(a)), AppOperand::RangeEnd(RangeEnd::Timer(b))) => {
                match (fixed(a), fixed(b)) {
                    (Some(a), Some(b)) => {
                        let (start, count) = span(a, b);
                        self.timers(start, count);
                    }
                    _ => self.whole_bits(BitArea::TimerContact),
                }
            }
            (AppOperand::RangeEnd(RangeEnd::Counter(a)), AppOperand::RangeEnd(RangeEnd::Counter(b))) => {
                match (fixed(a), fixed(b)) {
                    (Some(a), Some(b)) => {
                        let (start, count) = span(a, b);
                        self.counters(start, count);
                    }
                    _ => self.all_counters(),
                }
            }
            // Word bits (D0.0 to D1.F): the words from one end's to the
            // other's (a segment holds one run, but the run may cross
            // segments: D7998.0 to D8001.F).
            (
                AppOperand::RangeEnd(RangeEnd::Bit(BitRef::WordBit(area, a, _))),
                AppOperand::RangeEnd(RangeEnd::Bit(BitRef::WordBit(other, b, _))),
            ) if area == other => match (fixed(a), fixed(b)) {
                (Some(a), Some(b)) => {
                    let (start, count) = span(a, b);
                    self.words(area, start, count);
                }
                _ => {
                    for register in [a.index_register, b.index_register].into_iter().flatten() {
                        self.index_register(register);
                    }
                    self.whole_words(area)
                }
            },
            // Ends of different kinds (the instruction refuses them at run
            // time, touching nothing): each end's device.
            (first, last) => {
                for end in [first, last] {
                    match end {
                        AppOperand::RangeEnd(end) => self.range_end_area(end),
                        AppOperand::Word(word) => self.whole_of_word(&word),
                        AppOperand::Bit(_)
                        | AppOperand::Element(_)
                        | AppOperand::Digits(_)
                        | AppOperand::Timer(_)
                        | AppOperand::Counter(_) => {}
                    }
                }
            }
        }
    }

    /// One range end on its own: the device, plus its whole area when the
    /// range's other end is not a device of the same kind (see `range`).
    fn range_end_area(&mut self, end: RangeEnd) {
        match end {
            RangeEnd::Bit(bit) => self.bit(&bit, 1),
            RangeEnd::Word(area, address) => self.address_words(area, address, 1),
            RangeEnd::Timer(address) | RangeEnd::Counter(address) if address.index_register.is_some() => {
                self.whole_bits(BitArea::TimerContact);
                self.all_counters();
            }
            RangeEnd::Timer(address) => self.timers(address.index, 1),
            RangeEnd::Counter(address) => self.counter(address.index),
        }
    }

    fn index_register(&mut self, register: ladder_front::program::IndexRegister) {
        self.words(register.area, register.number, 1);
    }

    /// `count` bits from `bit` (bits of a word: the words they are in).
    fn bit(&mut self, bit: &BitRef, count: u32) {
        match *bit {
            BitRef::Device(area, address) => match address.index_register {
                None => self.bits(area, address.index, count),
                Some(register) => {
                    self.index_register(register);
                    self.whole_bits(area);
                }
            },
            BitRef::WordBit(area, address, bit) => {
                let words = u32::from(bit).saturating_add(count).div_ceil(16).max(1);
                self.address_words(area, address, words)
            }
        }
    }

    fn address_words(&mut self, area: WordArea, address: Address, count: u32) {
        match address.index_register {
            None => self.words(area, address.index, count),
            Some(register) => {
                self.index_register(register);
                self.whole_words(area);
            }
        }
    }

    /// `units` 16-bit words of a word operand (a digit group: its bits; a
    /// 32-bit counter: itself).
    fn word(&mut self, word: &WordRef, units: u32) {
        match *word {
            WordRef::Constant(_) => {}
            WordRef::Word(area, address) => self.address_words(area, address, units),
            WordRef::WideCounter(address) => match address.index_register {
                None => self.counter(address.index),
                Some(register) => {
                    self.index_register(register);
                    self.all_counters();
                }
            },
            WordRef::Digits(area, address, digits) => self.digits(DigitGroup { area, address, digits }),
        }
    }

    fn digits(&mut self, group: DigitGroup) {
        self.bit(&BitRef::Device(group.area, group.address), 4 * u32::from(group.digits));
    }

    /// The whole area a word operand starts in (a run from it).
    fn whole_of_word(&mut self, word: &WordRef) {
        match *word {
            WordRef::Constant(_) => {}
            WordRef::Word(area, address) => {
                if let Some(register) = address.index_register {
                    self.index_register(register);
                }
                self.whole_words(area);
            }
            WordRef::WideCounter(_) => self.all_counters(),
            WordRef::Digits(area, address, _) => self.whole_of_bit(&BitRef::Device(area, address)),
        }
    }

    /// The whole area a bit operand starts in (a run from it).
    fn whole_of_bit(&mut self, bit: &BitRef) {
        match *bit {
            BitRef::Device(area, address) => {
                if let Some(register) = address.index_register {
                    self.index_register(register);
                }
                self.whole_bits(area);
            }
            BitRef::WordBit(area, address, _) => {
                if let Some(register) = address.index_register {
                    self.index_register(register);
                }
                self.whole_words(area);
            }
        }
    }

    // ---- the optimised IR ----

    fn ir_function(&mut self, function: &ir::Function) {
        for block in &function.blocks {
            for (_, inst) in &block.insts {
                self.ir_inst(inst);
            }
        }
    }

    fn ir_inst(&mut self, inst: &ir::Inst) {
        use ir::{Effect, Index, Space};
        match inst.effect() {
            Effect::Load(span) | Effect::Store(span, _) | Effect::Fill(span) => match (span.space, span.start) {
                (Space::Bits(area), Index::Fixed(n)) => self.bits(area, n, span.count),
                (Space::Bits(area), Index::Dynamic(_)) => self.whole_bits(area),
                (Space::Words(area), Index::Fixed(n)) => self.words(area, n, span.count),
                (Space::Words(area), Index::Dynamic(_)) => self.whole_words(area),
                (Space::WideCounters, Index::Fixed(n)) => self.counter(n),
                (Space::WideCounters, Index::Dynamic(_)) => self.all_counters(),
                (Space::EdgeSlots, Index::Fixed(slot)) => {
                    self.builder.include(Array::EdgeSlot, slot, slot + 1);
                }
                (Space::EdgeSlots, Index::Dynamic(_)) => {
                    self.builder
                        .include(Array::EdgeSlot, Array::EdgeSlot.first(), Array::EdgeSlot.end());
                }
                // A block's "last ran active" flag lives with its state.
                (Space::BlockActive, Index::Fixed(state)) => self.bits(BitArea::S, state, 1),
                (Space::BlockActive, Index::Dynamic(_)) => self.whole_bits(BitArea::S),
                (Space::Bookkeeping(field), index) => self.bookkeeping(field, index),
            },
            Effect::Helper(helper, _) => self.helper(helper),
            Effect::OperationError => self.operation_error(),
            // A subroutine's accesses are its own function's.
            Effect::Subroutine | Effect::Pure | Effect::ReadsLocal | Effect::WritesLocal => {}
        }
    }

    /// A timer's or counter's state, which the layout holds with its
    /// contact.
    fn bookkeeping(&mut self, field: ir::Bookkeeping, index: ir::Index) {
        let timer = match field {
            ir::Bookkeeping::TimerCoil | ir::Bookkeeping::TimerRemainder | ir::Bookkeeping::TimerForced => true,
            ir::Bookkeeping::CounterCoil | ir::Bookkeeping::CounterForced => false,
        };
        match index {
            ir::Index::Fixed(n) if timer => self.timers(n, 1),
            ir::Index::Fixed(n) => self.counter(n),
            ir::Index::Dynamic(_) if timer => self.whole_bits(BitArea::TimerContact),
            ir::Index::Dynamic(_) => self.all_counters(),
        }
    }

    /// What a helper's own bookkeeping needs beyond its operands (which the
    /// checked program gave).
    fn helper(&mut self, helper: Helper) {
        match helper {
            Helper::LoopRepeat | Helper::RecordError | Helper::SortScan | Helper::Pid => self.operation_error(),
            Helper::TimerCoil
            | Helper::CounterCoil
            | Helper::ResetTimer
            | Helper::ResetCounter
            | Helper::ScheduleStateOff
            | Helper::BlockMove
            | Helper::Fill
            | Helper::ShiftBits
            | Helper::Bytes
            | Helper::HighestOn
            | Helper::Zone
            | Helper::Table
            | Helper::SortStop
            | Helper::BlockCheck
            | Helper::Crc
            | Helper::AlarmReset
            | Helper::RealFunction
            | Helper::RealToDecimal
            | Helper::DecimalToReal
            | Helper::SetClock
            | Helper::TimeCompare
            | Helper::TimeZone
            | Helper::TimeAdd
            | Helper::TimeToSeconds
            | Helper::SecondsToTime
            | Helper::Hour
            | Helper::Search
            | Helper::AbsoluteDrum
            | Helper::IncrementalDrum
            | Helper::InstanceOff
            | Helper::Ramp
            | Helper::TeachingTimer
            | Helper::SpecialTimer
            | Helper::Segments
            | Helper::SegmentLatch
            | Helper::Characters
            | Helper::HighSpeedCompare
            | Helper::Speed
            | Helper::PulseOutput
            | Helper::PulseStop
            | Helper::PulseWidth => {}
        }
    }
}

/// The value of `app`'s operand `name` when it is a constant (K, H).
fn constant_operand(app: &AppInstruction, name: &str) -> Option<i64> {
    app.args
        .operands()
        .into_iter()
        .zip(app.args.op().spec().operands)
        .find(|(_, decl)| decl.name == name)
        .and_then(|(operand, _)| match operand {
            AppOperand::Word(WordRef::Constant(value)) => Some(i64::from(value)),
            AppOperand::Word(_)
            | AppOperand::Bit(_)
            | AppOperand::Element(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Digits(_)
            | AppOperand::Timer(_)
            | AppOperand::Counter(_) => None,
        })
}
