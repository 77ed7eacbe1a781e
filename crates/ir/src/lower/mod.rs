//! Lowering: `CheckedProgram` to the SSA IR.
//!
//! Written apart from the interpreter on purpose: comparing the two engines
//! tests this translation. The logic stack is kept at compile time as SSA
//! values, so ANB/ORB/MPS/MRD/MPP produce no code at all.

mod access;
mod app;
mod coil;
mod operand;

use crate::{Builder, Cell, Function, Inst, Local, Program, Terminator, Type, Value};
use ladder_front::isa::app::Runs;
use ladder_front::isa::Sense;
use ladder_front::logic::{LogicStack, RungLogic};
use ladder_front::program::{BitRef, CheckedProgram, Contact, Instruction, Line, Op, Output, ResetTarget, StlBlock};
use ladder_runtime::helpers::Helper;
use ladder_runtime::{BitArea, OperationError, Width};
use std::collections::BTreeMap;

/// Lowers a checked program to the IR of its scan body and its
/// subroutines, each a function of its own.
pub fn lower(program: &CheckedProgram, coils: crate::Coils) -> Program {
    let main = lower_part(program, 0..program.main_end, coils);
    let subroutines = program
        .subroutines
        .iter()
        .map(|subroutine| lower_part(program, subroutine.entry..subroutine.end, coils))
        .collect();
    Program { main, subroutines }
}

/// The function of the instructions `range` (the main program, or a
/// subroutine without its SRET).
fn lower_part(program: &CheckedProgram, range: std::ops::Range<usize>, coils: crate::Coils) -> Function {
    let mut lowering = Lowering::new(program, coils);
    lowering.run(range);
    let (locals, loop_levels) = (lowering.locals, lowering.loop_levels);
    lowering.b.finish(locals, loop_levels)
}

struct Lowering<'p> {
    program: &'p CheckedProgram,
    b: Builder,
    /// The rung's power flow so far, and what ANB/ORB and MRD/MPP read.
    logic: LogicStack<Value>,
    /// The IR block that starts at each instruction index something jumps to
    /// (labels, the instruction after an STL block, the end).
    targets: BTreeMap<usize, crate::BlockId>,
    locals: u8,
    /// The first block of each open loop's body, innermost last.
    loops: Vec<crate::BlockId>,
    loop_levels: u8,
    coils: crate::Coils,
}

/// The lowering's rung values are IR values.
impl RungLogic for Lowering<'_> {
    type Value = Value;

    fn logic_stack(&mut self) -> &mut LogicStack<Value> {
        &mut self.logic
    }
    fn and(&mut self, a: Value, b: Value) -> Value {
        self.b.and(a, b)
    }
    fn or(&mut self, a: Value, b: Value) -> Value {
        self.b.or(a, b)
    }
    fn not(&mut self, value: Value) -> Value {
        self.b.not(value)
    }
    fn transition(&mut self, slot: u32, value: Value, falling: bool) -> Value {
        self.edge(slot, value, falling)
    }
    fn off(&mut self) -> Value {
        self.b.bit(false)
    }
    fn evaluate_contact(&mut self, contact: &Contact, line: u32) -> Value {
        self.contact(contact, line)
    }
    fn under_rails(&mut self, mc_levels: u8, passes: Value) -> Value {
        match self.rail(mc_levels) {
            Some(rail) => self.b.and(rail, passes),
            None => passes,
        }
    }
}

impl<'p> Lowering<'p> {
    fn new(program: &'p CheckedProgram, coils: crate::Coils) -> Lowering<'p> {
        let mut b = Builder::new();
        let result = b.bit(false);
        Lowering {
            program,
            b,
            logic: LogicStack::new(result),
            targets: BTreeMap::new(),
            locals: 0,
            loops: Vec::new(),
            loop_levels: 0,
            coils,
        }
    }

    fn run(&mut self, range: std::ops::Range<usize>) {
        let instructions = &self.program.instructions[range.clone()];
        for instruction in instructions {
            let target = match &instruction.op {
                Op::Jump { target, .. } => Some(*target),
                // An STL block that does not run is skipped to its end.
                Op::Line(Line::StlBegin { block }) => Some(self.program.stl_blocks[*block].end + 1),
                Op::Line(
                    Line::Label { .. }
                    | Line::MasterControlReset { .. }
                    | Line::StlEnd
                    | Line::MainEnd
                    | Line::SubroutineReturn
                    | Line::LoopStart { .. }
                    | Line::LoopEnd { .. },
                )
                | Op::Load { .. }
                | Op::And(_)
                | Op::Or(_)
                | Op::Logic(_)
                | Op::Output(_)
                | Op::Call { .. } => None,
            };
            if let Some(target) = target {
                if !self.targets.contains_key(&target) {
                    let block = self.b.create_block();
                    self.targets.insert(target, block);
                }
            }
            if let Op::Output(Output::MasterControl { level, .. }) = instruction.op {
                self.locals = self.locals.max(level + 1);
            }
        }
        // Every master-control level has power until its MC says otherwise.
        let on = self.b.bit(true);
        for level in 0..self.locals {
            self.b.effect(Inst::SetLocal {
                local: Local(level),
                value: on,
            });
        }
        for (index, instruction) in range.clone().zip(instructions) {
            self.enter_target(index);
            self.instruction(instruction);
        }
        self.enter_target(range.end);
        self.b.terminate(Terminator::Return);
    }

    /// A new rung structure: nothing of the logic stack crosses here.
    fn clear_logic(&mut self) {
        self.logic.result = self.b.bit(false);
        self.logic.clear();
    }

    /// FOR: the loop count (below 1 counts as 1) goes to the local of this
    /// nesting level; the body starts a block NEXT branches back to.
    fn loop_start(&mut self, count: ladder_front::program::WordRef, line: u32) {
        let count = self.compare_operand(count, Width::Single, line);
        let count = self.b.truncate(count, Type::I32);
        let one = self.b.constant(Type::I32, 1);
        let below_one = self.b.compare(crate::CompareOp::Lt, count, one);
        let count = self.b.select(below_one, one, count);
        let level = self.loops.len() as u8;
        self.loop_levels = self.loop_levels.max(level + 1);
        self.b.effect(Inst::StoreLoopCount { level, value: count });
        let body = self.b.create_block();
        self.b.jump_to(body);
        self.loops.push(body);
        self.clear_logic();
    }

    /// NEXT: back to the body while repetitions are left and the runtime's
    /// watchdog allows one more (it records 6509H when it does not).
    fn loop_end(&mut self, line: u32) {
        let Some(body) = self.loops.pop() else {
            return;
        };
        let level = self.loops.len() as u8;
        let left = self.b.push(Inst::LoadLoopCount { level });
        let one = self.b.constant(Type::I32, 1);
        let left = self.b.binary(crate::BinOp::Sub, left, one);
        self.b.effect(Inst::StoreLoopCount { level, value: left });
        let zero = self.b.constant(Type::I32, 0);
        let more = self.b.compare(crate::CompareOp::Gt, left, zero);
        let ask = self.b.create_block();
        let exit = self.b.create_block();
        self.b.terminate(Terminator::Branch {
            condition: more,
            then: ask,
            otherwise: exit,
        });
        self.b.switch_to(ask);
        let line = self.b.number(line);
        let allowed = self.b.call(Helper::LoopRepeat, vec![line]).unwrap_or(zero);
        let repeat = self.b.compare(crate::CompareOp::Ne, allowed, zero);
        self.b.terminate(Terminator::Branch {
            condition: repeat,
            then: body,
            otherwise: exit,
        });
        self.b.switch_to(exit);
        self.clear_logic();
    }

    /// Falls through into the block that starts at `index`, if any. Rungs
    /// never span such a point, so the logic stack starts empty there.
    fn enter_target(&mut self, index: usize) {
        if let Some(&block) = self.targets.get(&index) {
            self.b.jump_to(block);
            self.clear_logic();
        }
    }

    fn instruction(&mut self, instruction: &Instruction) {
        let line = instruction.error_line();
        match &instruction.op {
            Op::Load { .. } | Op::And(_) | Op::Or(_) | Op::Logic(_) => self.evaluate(&instruction.op, line),
            Op::Jump { target, .. } => {
                let continue_at = self.b.create_block();
                let taken = self.targets[target];
                self.b.terminate(Terminator::Branch {
                    condition: self.logic.result,
                    then: taken,
                    otherwise: continue_at,
                });
                self.b.switch_to(continue_at);
            }
            Op::Line(Line::StlBegin { block }) => {
                let program = self.program;
                self.stl_gate(&program.stl_blocks[*block]);
            }
            Op::Line(Line::Label { .. } | Line::MasterControlReset { .. } | Line::StlEnd) => {}
            Op::Output(output) => self.output(output, self.logic.result, line),
            Op::Call { subroutine, slot } => {
                let power = self.pulsed(*slot, self.logic.result);
                let subroutine = *subroutine as u32;
                self.b.if_then(power, |b| b.effect(Inst::CallSubroutine { subroutine }));
            }
            Op::Line(Line::LoopStart { count, .. }) => self.loop_start(*count, line),
            Op::Line(Line::LoopEnd { .. }) => self.loop_end(line),
            // Parts end before these: `lower_part` stops at FEND and SRET.
            Op::Line(Line::MainEnd | Line::SubroutineReturn) => {}
        }
    }

    /// The power rail of the master-control levels in `mask`.
    fn rail(&mut self, mask: u8) -> Option<Value> {
        let mut rail = None;
        for level in (0..8u8).filter(|level| mask & (1 << level) != 0) {
            let power = self.b.get_local(Local(level));
            rail = Some(match rail {
                Some(outer) => self.b.and(outer, power),
                None => power,
            });
        }
        rail
    }

    /// The STL gate: run the block while its state is ON; reset it once when
    /// the state is found OFF after the block ran; otherwise skip it.
    fn stl_gate(&mut self, block: &StlBlock) {
        let state = block.state;
        let skip_to = self.targets[&(block.end + 1)];
        let run = self.b.create_block();
        let inactive = self.b.create_block();
        let reset = self.b.create_block();
        let on = self.b.load_bit(BitArea::S, crate::Index::Fixed(state));
        self.b.terminate(Terminator::Branch {
            condition: on,
            then: run,
            otherwise: inactive,
        });

        self.b.switch_to(inactive);
        let was_active = self.b.load(Cell::BlockActive { state });
        self.b.terminate(Terminator::Branch {
            condition: was_active,
            then: reset,
            otherwise: skip_to,
        });

        self.b.switch_to(reset);
        self.b.mark_cold();
        let off = self.b.bit(false);
        self.b.store(Cell::BlockActive { state }, off);
        for &index in &block.reset_outputs {
            let instruction = &self.program.instructions[index];
            if let Op::Output(output) = &instruction.op {
                self.output(output, off, instruction.error_line());
            }
        }
        for &slot in &block.reset_slots {
            self.b.store(Cell::Slot { slot }, off);
        }
        self.b.terminate(Terminator::Jump(skip_to));

        self.b.switch_to(run);
        let on = self.b.bit(true);
        self.b.store(Cell::BlockActive { state }, on);
        self.logic.result = self.b.bit(false);
    }

    fn contact(&mut self, contact: &Contact, line: u32) -> Value {
        match *contact {
            Contact::Level { bit, closed } => {
                let value = self.read_bit(bit, line);
                if closed {
                    self.b.not(value)
                } else {
                    value
                }
            }
            Contact::Edge { bit, falling, slot } => {
                let now = self.read_bit(bit, line);
                self.edge(slot, now, falling)
            }
            Contact::Constant(on) => self.b.bit(on),
            Contact::Compare { op, width, left, right } => {
                let left = self.compare_operand(left, width, line);
                let right = self.compare_operand(right, width, line);
                self.b.compare(op.into(), left, right)
            }
        }
    }

    fn inline_coils(&self) -> bool {
        match self.coils {
            crate::Coils::Inline => true,
            crate::Coils::Calls => false,
        }
    }

    /// An edge against the slot's previous value; the slot keeps `now`.
    fn edge(&mut self, slot: u32, now: Value, falling: bool) -> Value {
        let before = self.b.load(Cell::Slot { slot });
        self.b.store(Cell::Slot { slot }, now);
        if falling {
            let off_now = self.b.not(now);
            self.b.and(off_now, before)
        } else {
            let not_before = self.b.not(before);
            self.b.and(now, not_before)
        }
    }

    /// An output instruction with `power` (the rung result, or OFF for the
    /// one-time reset of an STL block).
    fn output(&mut self, output: &Output, power: Value, line: u32) {
        match output {
            Output::Coil(bit) => self.write_bit(*bit, power, line),
            Output::Timer { timer, preset } => {
                let preset = self.preset(*preset, Width::Single);
                if self.inline_coils() && coil::inline_timer(*timer) {
                    coil::timer(&mut self.b, *timer, power, preset);
                } else {
                    let (timer, coil) = (self.b.number(*timer), self.b.extend(power, Type::I32, false));
                    self.b.call(Helper::TimerCoil, vec![timer, coil, preset]);
                }
            }
            Output::Counter { counter, preset } => {
                let width = ladder_runtime::device::counter_width(*counter);
                let preset = self.preset(*preset, width);
                if self.inline_coils() && coil::inline_counter(*counter) {
                    coil::counter(&mut self.b, *counter, power, preset);
                } else {
                    let (counter, coil) = (self.b.number(*counter), self.b.extend(power, Type::I32, false));
                    self.b.call(Helper::CounterCoil, vec![counter, coil, preset]);
                }
            }
            Output::Set {
                target,
                count,
                transfer_from: None,
                written_out: _,
            } if self.set_without_branch(*target, *count, power, true) => {}
            Output::Set {
                target,
                count,
                transfer_from,
                written_out: _,
            } => self.when(power, |this, _| {
                // A transfer happens once per step of the sequence.
                if transfer_from.is_some() {
                    this.b.mark_cold();
                }
                this.write_bits(*target, *count, true, line);
                if let Some(state) = transfer_from {
                    let state = this.b.number(*state);
                    this.b.call(Helper::ScheduleStateOff, vec![state]);
                }
            }),
            Output::Reset {
                target: ResetTarget::Bit(bit),
                count,
            } if self.set_without_branch(*bit, *count, power, false) => {}
            Output::Reset { target, count } => self.when(power, |this, _| this.reset(*target, *count, line)),
            Output::Pulse { target, sense, slot } => {
                let pulse = self.edge(*slot, power, *sense == Sense::Falling);
                self.write_bit(*target, pulse, line);
            }
            Output::StateJump { state } => {
                let state = crate::Index::Fixed(*state);
                let now = self.b.load_bit(BitArea::S, state);
                let next = self.b.or(now, power);
                self.b.store_bit(BitArea::S, state, next);
            }
            Output::MasterControl { level, relay } => {
                self.b.effect(Inst::SetLocal {
                    local: Local(*level),
                    value: power,
                });
                self.write_bit(*relay, power, line);
            }
            Output::App(app) => {
                let power = self.pulsed(app.pulse_slot, power);
                // A failed operand check leaves the body early, to `after`.
                match app.args.op().spec().runs {
                    Runs::WhenOn => self.when(power, |this, after| this.app(app, power, line, after)),
                    Runs::EveryScan => {
                        let after = self.b.create_block();
                        self.app(app, power, line, after);
                        self.b.jump_to(after);
                    }
                }
            }
        }
    }

    /// SET (`on`) or RST of a few devices at fixed numbers as plain logic,
    /// `m = m | power` or `m = m & !power`: rungs stay in one block, so what
    /// the memory pass knows flows through them. Writing back the value a
    /// device already holds is invisible (nothing else runs during the
    /// program). False, with nothing emitted, for any other target.
    fn set_without_branch(&mut self, target: BitRef, count: u32, power: Value, on: bool) -> bool {
        const MOST_BITS: u32 = 4;
        let BitRef::Device(area, address) = target else {
            return false;
        };
        if address.index_register.is_some() || count > MOST_BITS || address.index + count > area.count() {
            return false;
        }
        for n in address.index..address.index + count {
            let index = crate::Index::Fixed(n);
            let now = self.b.load_bit(area, index);
            let next = if on {
                self.b.or(now, power)
            } else {
                let off = self.b.not(power);
                self.b.and(now, off)
            };
            self.b.store_bit(area, index, next);
        }
        true
    }

    /// Runs `then` only while `condition` is ON; `then` gets the block where
    /// execution continues afterwards.
    fn when(&mut self, condition: Value, then: impl FnOnce(&mut Self, crate::BlockId)) {
        let body = self.b.create_block();
        let after = self.b.create_block();
        self.b.terminate(Terminator::Branch {
            condition,
            then: body,
            otherwise: after,
        });
        self.b.switch_to(body);
        then(self, after);
        self.b.jump_to(after);
    }

    fn reset(&mut self, target: ResetTarget, count: u32, line: u32) {
        match target {
            ResetTarget::Bit(bit) => self.write_bits(bit, count, false, line),
            ResetTarget::Timer(first) => {
                for timer in first..first + count {
                    let timer = self.b.number(timer);
                    self.b.call(Helper::ResetTimer, vec![timer]);
                }
            }
            ResetTarget::Counter(first) => {
                for counter in first..first + count {
                    let counter = self.b.number(counter);
                    self.b.call(Helper::ResetCounter, vec![counter]);
                }
            }
            ResetTarget::Word(area, address) => {
                let start = self.clamped_index(address, 0, area.count() - count, OperationError::WriteOutOfRange, line);
                self.b.effect(Inst::ClearWords { area, start, count });
            }
        }
    }

    /// A timer or counter preset as an I32.
    fn preset(&mut self, preset: ladder_front::program::WordRef, width: Width) -> Value {
        let (operand, _) = self.resolve(preset, width, operand::Units::Checked(1));
        let value = self.read(&operand, width);
        self.b.truncate(value, Type::I32)
    }
}
