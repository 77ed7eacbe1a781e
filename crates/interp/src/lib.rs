//! The reference interpreter: the executable specification of docs/language.md.
//!
//! It runs the checked instruction list directly, one instruction at a time,
//! with an explicit logic stack (`ladder_front::logic`, shared with the IR
//! lowering, which holds IR values where this holds bits). It is written for
//! clarity, not speed; the native engines are tested against it.

/// Operand access with the offset rules: public because the live ladder
/// monitor shows the device an indexed operand names now by the same rule.
pub mod access;
mod app;

use access::{read_bit, resolve_word, write_bit};
use ladder_front::isa::Sense;
use ladder_front::logic::{LogicStack, RungLogic};
use ladder_front::program::{
    BitRef, CheckedProgram, Contact, Instruction, Line, Op, Output, ResetTarget, StlBlock, WordRef,
};
use ladder_runtime::special::LOOP_REPETITION_LIMIT;
use ladder_runtime::{Memory, OperationError, Width};

/// Runs a checked program against device memory.
pub struct Interpreter<'p> {
    program: &'p CheckedProgram,
}

impl<'p> Interpreter<'p> {
    pub fn new(program: &'p CheckedProgram) -> Interpreter<'p> {
        Interpreter { program }
    }

    /// One whole scan: the runtime's steps 1-2, the program, steps 4.
    pub fn scan(&self, mem: &mut Memory, elapsed_ms: u32) {
        mem.scan_with(elapsed_ms, |mem| self.run_program(mem));
    }

    /// A whole scan keeping only the parts `machine` of the machine up to
    /// date, as a program compiled with that set does.
    pub fn scan_using(&self, mem: &mut Memory, elapsed_ms: u32, machine: ladder_runtime::MachineUse) {
        mem.scan_using(elapsed_ms, machine, |mem| self.run_program(mem));
    }

    /// Step 3 of the scan: the program from top to END.
    pub fn run_program(&self, mem: &mut Memory) {
        let mut run = Run {
            mem,
            program: self.program,
            logic: LogicStack::new(false),
            mc_power: [true; 8],
            loops: Vec::new(),
        };
        run.run_part(0);
    }
}

/// The state of one pass through the program.
struct Run<'a> {
    mem: &'a mut Memory,
    program: &'a CheckedProgram,
    /// The rung's power flow so far, and what ANB/ORB and MRD/MPP read.
    logic: LogicStack<bool>,
    /// The condition each master-control level was last opened with.
    mc_power: [bool; 8],
    /// Repetitions left in each open FOR/NEXT loop, innermost last.
    loops: Vec<i64>,
}

/// The interpreter's rung values are bits.
impl RungLogic for Run<'_> {
    type Value = bool;

    fn logic_stack(&mut self) -> &mut LogicStack<bool> {
        &mut self.logic
    }
    fn and(&mut self, a: bool, b: bool) -> bool {
        a && b
    }
    fn or(&mut self, a: bool, b: bool) -> bool {
        a || b
    }
    fn not(&mut self, value: bool) -> bool {
        !value
    }
    fn transition(&mut self, slot: u32, value: bool, falling: bool) -> bool {
        self.edge(slot, value, falling)
    }
    fn off(&mut self) -> bool {
        false
    }
    fn evaluate_contact(&mut self, contact: &Contact, line: u32) -> bool {
        self.contact(contact, line)
    }
    fn under_rails(&mut self, mc_levels: u8, passes: bool) -> bool {
        let rail = (0..8)
            .filter(|level| mc_levels & (1 << level) != 0)
            .all(|level| self.mc_power[level]);
        rail && passes
    }
}

impl Run<'_> {
    /// Runs the main program (from 0) or a subroutine (from its entry) up
    /// to FEND, SRET or the end of the list.
    fn run_part(&mut self, start: usize) {
        let instructions = &self.program.instructions;
        let mut pc = start;
        while let Some(instruction) = instructions.get(pc) {
            if matches!(instruction.op, Op::Line(Line::MainEnd | Line::SubroutineReturn)) {
                return;
            }
            pc = self.step(pc, instruction);
        }
    }

    /// CALL: the subroutine runs with a logic stack of its own, empty and
    /// OFF as the lowering starts a function (a checked subroutine starts
    /// every rung with a load, so nothing reads that OFF); the rung around
    /// the CALL continues afterwards with its own.
    fn call(&mut self, subroutine: usize) {
        let entry = self.program.subroutines[subroutine].entry;
        let around = std::mem::replace(&mut self.logic, LogicStack::new(false));
        self.run_part(entry);
        self.logic = around;
    }

    /// NEXT: back to the instruction after FOR while repetitions are left
    /// and the scan's watchdog allows one more.
    fn next(&mut self, start: usize, pc: usize, line: u32) -> usize {
        let Some(remaining) = self.loops.last_mut() else {
            return pc + 1;
        };
        *remaining -= 1;
        if *remaining > 0 {
            if self.mem.loop_repetitions < LOOP_REPETITION_LIMIT {
                self.mem.loop_repetitions += 1;
                return start + 1;
            }
            self.mem.record_error(OperationError::LoopWatchdog, line);
        }
        self.loops.pop();
        pc + 1
    }
    /// Executes one instruction; returns the index of the next one.
    fn step(&mut self, pc: usize, instruction: &Instruction) -> usize {
        let line = instruction.error_line();
        match &instruction.op {
            Op::Load { .. } | Op::And(_) | Op::Or(_) | Op::Logic(_) => self.evaluate(&instruction.op, line),
            Op::Jump { target, .. } => {
                if self.logic.result {
                    return *target;
                }
            }
            Op::Line(Line::StlBegin { block }) => return self.enter_block(&self.program.stl_blocks[*block], pc),
            Op::Line(Line::Label { .. } | Line::MasterControlReset { .. } | Line::StlEnd) => {}
            Op::Output(output) => self.output(output, self.logic.result, line),
            Op::Call { subroutine, slot } => {
                let power = self.pulsed(*slot, self.logic.result);
                if power {
                    self.call(*subroutine);
                }
            }
            Op::Line(Line::LoopStart { count, .. }) => {
                let count = self.compare_operand(*count, Width::Single, line);
                self.loops.push(i64::from(count.max(1)));
            }
            Op::Line(Line::LoopEnd { start }) => return self.next(*start, pc, line),
            // The end of a part: `run_part` stops before these.
            Op::Line(Line::MainEnd | Line::SubroutineReturn) => {}
        }
        pc + 1
    }

    /// An output instruction with the rung result `power`. The STL one-time
    /// reset runs the same code with the power OFF.
    fn output(&mut self, output: &Output, power: bool, line: u32) {
        match output {
            Output::Coil(bit) => write_bit(self.mem, *bit, power, line),
            Output::Timer { timer, preset } => {
                let preset = self.preset(*preset, Width::Single);
                self.mem.timer_coil(*timer, power, preset);
            }
            Output::Counter { counter, preset } => {
                let width = ladder_runtime::device::counter_width(*counter);
                let preset = self.preset(*preset, width);
                self.mem.counter_coil(*counter, power, preset);
            }
            Output::Set {
                target,
                count,
                transfer_from,
                written_out: _,
            } => {
                if power {
                    self.write_bits(*target, *count, true, line);
                    if let Some(source) = transfer_from {
                        self.mem.schedule_state_off(*source);
                    }
                }
            }
            Output::Reset { target, count } => {
                if power {
                    self.reset(*target, *count, line);
                }
            }
            Output::Pulse { target, sense, slot } => {
                let pulse = self.edge(*slot, power, *sense == Sense::Falling);
                write_bit(self.mem, *target, pulse, line);
            }
            Output::StateJump { state } => {
                if power {
                    self.mem.s[*state as usize] = 1;
                }
            }
            Output::MasterControl { level, relay } => {
                self.mc_power[*level as usize] = power;
                write_bit(self.mem, *relay, power, line);
            }
            Output::App(app) => {
                let power = self.pulsed(app.pulse_slot, power);
                app::execute(self.mem, app, power, line);
            }
        }
    }

    /// `STL Sn`: run the block while Sn is ON; reset it once when Sn is found
    /// OFF after the block last ran ON; skip it otherwise.
    fn enter_block(&mut self, block: &StlBlock, pc: usize) -> usize {
        let state = block.state as usize;
        if self.mem.s[state] != 0 {
            self.mem.stl_block_active[state] = 1;
            return pc + 1;
        }
        if self.mem.stl_block_active[state] != 0 {
            self.mem.stl_block_active[state] = 0;
            for &index in &block.reset_outputs {
                let instruction = &self.program.instructions[index];
                if let Op::Output(output) = &instruction.op {
                    self.output(output, false, instruction.error_line());
                }
            }
            for &slot in &block.reset_slots {
                self.mem.edge_slot[slot as usize] = 0;
            }
        }
        block.end + 1
    }

    fn contact(&mut self, contact: &Contact, line: u32) -> bool {
        match *contact {
            Contact::Level { bit, closed } => read_bit(self.mem, bit, line) != closed,
            Contact::Edge { bit, falling, slot } => {
                let now = read_bit(self.mem, bit, line);
                self.edge(slot, now, falling)
            }
            Contact::Constant(value) => value,
            Contact::Compare { op, width, left, right } => {
                let left = self.compare_operand(left, width, line);
                let right = self.compare_operand(right, width, line);
                op.holds(left, right)
            }
        }
    }

    /// Compares `now` with what this edge instance saw last time, and
    /// remembers `now`.
    fn edge(&mut self, slot: u32, now: bool, falling: bool) -> bool {
        let cell = &mut self.mem.edge_slot[slot as usize];
        let before = *cell != 0;
        *cell = now as u8;
        if falling {
            before && !now
        } else {
            now && !before
        }
    }

    /// A comparison contact's operand: out of range, it reads the nearest
    /// valid device and records 4085H, like any contact.
    fn compare_operand(&mut self, word: WordRef, width: Width, line: u32) -> i32 {
        match resolve_word(self.mem, word, width, 1) {
            Some(place) => place.read(self.mem, width),
            None => {
                self.mem.record_error(OperationError::ReadOutOfRange, line);
                let clamped = access::clamp_word(self.mem, word, width);
                clamped.read(self.mem, width)
            }
        }
    }

    fn preset(&self, preset: WordRef, width: Width) -> i32 {
        resolve_word(self.mem, preset, width, 1).map_or(0, |place| place.read(self.mem, width))
    }

    /// SET/RST of `count` bits from `target`; an offset start is clamped so
    /// the whole run fits.
    fn write_bits(&mut self, target: BitRef, count: u32, on: bool, line: u32) {
        match target {
            BitRef::Device(area, address) => {
                let start = access::effective_index(self.mem, address);
                let last_start = i64::from(area.count() - count);
                let clamped = start.clamp(0, last_start);
                if clamped != start {
                    self.mem.record_error(OperationError::WriteOutOfRange, line);
                }
                let start = clamped as usize;
                self.mem.bits_mut(area)[start..start + count as usize].fill(on as u8);
            }
            BitRef::WordBit(..) => write_bit(self.mem, target, on, line),
        }
    }

    fn reset(&mut self, target: ResetTarget, count: u32, line: u32) {
        match target {
            ResetTarget::Bit(bit) => self.write_bits(bit, count, false, line),
            ResetTarget::Timer(first) => (first..first + count).for_each(|t| self.mem.reset_timer(t)),
            ResetTarget::Counter(first) => (first..first + count).for_each(|c| self.mem.reset_counter(c)),
            ResetTarget::Word(area, address) => {
                let start = access::effective_index(self.mem, address);
                let clamped = start.clamp(0, i64::from(area.count() - count));
                if clamped != start {
                    self.mem.record_error(OperationError::WriteOutOfRange, line);
                }
                let start = clamped as usize;
                self.mem.words_mut(area)[start..start + count as usize].fill(0);
            }
        }
    }
}
