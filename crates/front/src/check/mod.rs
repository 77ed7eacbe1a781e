//! Front end, second stage: `ParsedProgram` to `CheckedProgram`.
//!
//! Rejects what a vendor programming tool rejects and reports every
//! independent error in one run. An instruction whose operands are bad still
//! takes part in the rung structure, so one typo gives one error.

mod app;
mod blocks;
mod compile;
pub mod cpu;
mod devices;
mod index_registers;
mod lints;
pub mod operands;
mod parts;
mod rung;
mod words;

use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::isa::app::{Keeps, Runs};
use crate::isa::{self, AppArgs, AppForm, BitClass, BitSpec, Mnemonic, Role, Sense};
use crate::program::*;
use crate::source::Span;
use crate::syntax::{self, InstructionSyntax, ParsedProgram, Statement, StatementKind};
use blocks::{BlockTracker, PendingJump};
use devices::Resolved;
use ladder_runtime::device::{EDGE_SLOT_COUNT, SORT_INSTANCES, STATE_INSTANCES};
use ladder_runtime::{BitArea, Width, WordArea};
use operands::Coil;
use rung::RungTracker;
use rustc_hash::FxHashMap;

pub use compile::{compile_source, compile_source_on};

/// Checks a parsed program. The program is complete only when the
/// diagnostics hold no errors.
pub fn check(parsed: &ParsedProgram, name: &str, source_len: usize) -> (CheckedProgram, Diagnostics) {
    let mut checker = Checker {
        // Seed 001: a program with STLE pairs every STL with its own STLE.
        stle_pairing: parsed
            .statements
            .iter()
            .any(|statement| matches!(&statement.kind, StatementKind::Instruction(i) if i.mnemonic == "STLE")),
        ..Checker::default()
    };
    for (position, statement) in parsed.statements.iter().enumerate() {
        checker.statement(position, statement);
    }
    let eof = Span::new(source_len, source_len);
    checker.end_of_program(eof);
    let main_end = checker.parts.main_end.unwrap_or(checker.instructions.len());
    for (jump, target) in checker.blocks.resolve_jumps(&mut checker.diagnostics) {
        // A jump in the main program to a label after FEND (possible only
        // for one after END) ends the main program.
        let target = if jump < main_end { target.min(main_end) } else { target };
        if let Op::Jump { target: pending, .. } = &mut checker.instructions[jump].op {
            *pending = target;
        }
    }
    checker.resolve_calls();
    checker.lints.finish(&mut checker.diagnostics);
    let program = CheckedProgram {
        name: name.to_string(),
        instructions: checker.instructions,
        stl_blocks: checker.stl_blocks,
        subroutines: checker.parts.subroutines,
        main_end,
        edge_slots: checker.next_slot,
    };
    (program, checker.diagnostics)
}

#[derive(Default)]
struct Checker {
    diagnostics: Diagnostics,
    rung: RungTracker,
    blocks: BlockTracker,
    lints: lints::Lints,
    instructions: Vec<Instruction>,
    stl_blocks: Vec<StlBlock>,
    parts: parts::Parts,
    /// Block id (from the tracker) to index in `stl_blocks`.
    emitted_blocks: FxHashMap<usize, usize>,
    next_slot: u32,
    next_job: u32,
    next_instance: u32,
    /// END was seen: later statements are checked but not executed.
    ended: bool,
    warned_after_end: bool,
    /// The program contains STLE: every STL is closed by its own STLE, and
    /// an STL while a block is open is an error (seed 001), instead of
    /// closing the block FX style.
    stle_pairing: bool,
}

/// What the current statement is, for emission.
struct Site {
    line: u32,
    span: Span,
}

impl Checker {
    fn report(&mut self, diagnostic: Diagnostic) {
        self.diagnostics.push(diagnostic);
    }

    /// Keeps the value of a resolution, reporting its error.
    fn ok<T>(&mut self, resolved: Resolved<T>) -> Option<T> {
        resolved.map_err(|d| self.report(d)).ok()
    }

    fn statement(&mut self, position: usize, statement: &Statement) {
        if self.ended && !self.warned_after_end {
            self.warned_after_end = true;
            self.report(
                Diagnostic::new(Code::CodeAfterEnd, statement.span, "code after END is never executed")
                    .with_label("from here on"),
            );
        }
        let site = Site {
            line: statement.line,
            span: statement.span,
        };
        if self.parts.outside_any_part() && !self.ended {
            let allowed = match &statement.kind {
                StatementKind::Label { .. } => true,
                StatementKind::Instruction(syntax) => matches!(
                    isa::lookup(&syntax.mnemonic),
                    Some(Mnemonic::Bit(BitSpec {
                        class: BitClass::End | BitClass::Nop | BitClass::Network,
                        ..
                    }))
                ),
            };
            if !allowed {
                self.outside_part(site.span);
            }
        }
        match &statement.kind {
            StatementKind::Label { number } => self.label(*number, position, &site),
            StatementKind::Instruction(syntax) => match isa::lookup(&syntax.mnemonic) {
                Some(Mnemonic::Bit(spec)) => self.instruction(spec, syntax, position, &site),
                Some(Mnemonic::App(form)) => self.app(form, syntax, &site),
                None => {
                    let diagnostic = if isa::fx::unsupported_fx(&syntax.mnemonic) {
                        Diagnostic::new(
                            Code::UnsupportedFx,
                            syntax.mnemonic_span,
                            format!("FX instruction `{}` is not supported", syntax.mnemonic),
                        )
                        .with_label("ladderc does not implement this FX instruction")
                        .with_note("docs/language.md lists the supported instructions")
                    } else {
                        let diagnostic = Diagnostic::new(
                            Code::UnknownMnemonic,
                            syntax.mnemonic_span,
                            format!("unknown instruction `{}`", syntax.mnemonic),
                        )
                        .with_label("not an instruction of the dialect");
                        match (isa::fx::idiom(&syntax.mnemonic), isa::fx::suggestion(&syntax.mnemonic)) {
                            (Some(hint), _) => diagnostic.with_note(hint),
                            (None, Some(near)) => diagnostic.with_note(format!("did you mean `{near}`?")),
                            (None, None) => diagnostic,
                        }
                    };
                    self.report(diagnostic);
                    self.rung.poison(syntax.mnemonic_span);
                }
            },
        }
    }

    fn label(&mut self, number: u32, position: usize, site: &Site) {
        self.rung.close(site.span, &mut self.diagnostics);
        if number > operands::LAST_LABEL {
            self.report(
                Diagnostic::new(Code::DeviceRange, site.span, format!("label P{number} is out of range"))
                    .with_label("labels are P0..P4095"),
            );
            return;
        }
        if self.parts.outside_any_part() && !self.ended {
            self.subroutine_label(number, site.span);
        }
        let target = self.instructions.len();
        self.blocks
            .label(number, position, target, site.span, &mut self.diagnostics);
        self.emit(Op::Line(Line::Label { number }), site);
    }

    /// END or the end of the file: everything open is an error.
    fn end_of_program(&mut self, span: Span) {
        self.rung.close(span, &mut self.diagnostics);
        self.blocks.close(&mut self.diagnostics);
        self.blocks.close_loops(&mut self.diagnostics);
        self.close_subroutine();
    }

    fn emit(&mut self, op: Op, site: &Site) -> Option<usize> {
        if self.ended {
            return None;
        }
        let index = self.instructions.len();
        let in_block = self
            .blocks
            .context()
            .stl_block
            .and_then(|id| self.emitted_blocks.get(&id).copied());
        if let (Some(block), Op::Output(output)) = (in_block, &op) {
            // What the block's one-time reset runs with its power OFF, and
            // the previous-scan slots it clears.
            let block = &mut self.stl_blocks[block];
            match output {
                Output::Coil(_) | Output::Timer { .. } | Output::Counter { .. } => block.reset_outputs.push(index),
                Output::Pulse { slot, .. } => {
                    block.reset_outputs.push(index);
                    block.reset_slots.push(*slot);
                }
                Output::App(app) => {
                    // Instructions that run every scan see the reset as a
                    // scan with their rung OFF (a sort stops, a timer clears).
                    match app.args.op().spec().runs {
                        Runs::EveryScan => block.reset_outputs.push(index),
                        Runs::WhenOn => {}
                    }
                    if let Some(slot) = app.pulse_slot {
                        block.reset_slots.push(slot);
                    }
                }
                Output::Set { .. } | Output::Reset { .. } | Output::StateJump { .. } | Output::MasterControl { .. } => {
                }
            }
        }
        if let (Some(block), Op::Call { slot: Some(slot), .. }) = (in_block, &op) {
            self.stl_blocks[block].reset_slots.push(*slot);
        }
        self.lints.observe(&op, site.span, in_block.is_some());
        self.instructions.push(Instruction {
            op,
            line: site.line,
            span: site.span,
            step: None,
        });
        Some(index)
    }

    /// A fresh job for a SORT, SORT2 or DSORT2.
    fn job(&mut self, span: Span) -> u32 {
        let job = self.next_job;
        if job == SORT_INSTANCES {
            self.report(
                Diagnostic::new(Code::TooManyJobs, span, "too many sort instructions")
                    .with_label(format!("a program holds at most {SORT_INSTANCES} SORT/SORT2/DSORT2")),
            );
        }
        self.next_job = self.next_job.saturating_add(1);
        job.min(SORT_INSTANCES - 1)
    }

    /// A fresh instance state for an instruction that keeps one.
    fn instance(&mut self, span: Span) -> u32 {
        let instance = self.next_instance;
        if instance == STATE_INSTANCES {
            self.report(
                Diagnostic::new(Code::TooManyJobs, span, "too many instructions that keep a state")
                    .with_label(format!(
                        "a program holds at most {STATE_INSTANCES} pulse, positioning, high-speed compare and timing instructions"
                    )),
            );
        }
        self.next_instance = self.next_instance.saturating_add(1);
        instance.min(STATE_INSTANCES - 1)
    }

    /// A fresh previous-scan slot for an edge instruction.
    fn slot(&mut self, span: Span) -> u32 {
        let slot = self.next_slot;
        if slot == EDGE_SLOT_COUNT {
            self.report(
                Diagnostic::new(Code::TooManyEdges, span, "too many edge instructions")
                    .with_label("slot 16385 needed here"),
            );
        }
        self.next_slot = self.next_slot.saturating_add(1);
        slot.min(EDGE_SLOT_COUNT - 1)
    }

    /// The operands when there are `required..=most` of them and all could
    /// be read; otherwise reports a wrong count and gives None (the
    /// instruction still shapes the rung).
    fn counted_operands<'s>(
        &mut self,
        syntax: &'s InstructionSyntax,
        required: usize,
        most: usize,
        site: &Site,
    ) -> Option<&'s [syntax::Operand]> {
        let count = syntax.operands.len();
        let counts_ok = (required..=most).contains(&count);
        if !counts_ok && !syntax.malformed {
            let expected = if required == most {
                format!("{required}")
            } else {
                format!("{required} to {most}")
            };
            self.report(
                Diagnostic::new(
                    Code::OperandCount,
                    site.span,
                    format!(
                        "{} takes {expected} operand{}, found {count}",
                        syntax.mnemonic,
                        if expected == "1" { "" } else { "s" }
                    ),
                )
                .with_label("wrong number of operands"),
            );
        }
        (counts_ok && !syntax.malformed).then_some(syntax.operands.as_slice())
    }

    fn instruction(&mut self, spec: &'static BitSpec, syntax: &InstructionSyntax, position: usize, site: &Site) {
        let operands = self.counted_operands(syntax, spec.required, spec.most, site);
        // After END nothing runs (W0001 says so): program structure there
        // is not judged.
        let structure = matches!(
            spec.class,
            BitClass::MainEnd
                | BitClass::Call { .. }
                | BitClass::SubroutineReturn
                | BitClass::LoopStart
                | BitClass::LoopEnd
        );
        if self.ended && structure {
            return;
        }
        let span = site.span;
        match spec.class {
            BitClass::Contact(role, sense) => self.contact(role, sense, operands, site),
            BitClass::AliasContact(sense) => {
                let role = if self.rung.at_rung_start() {
                    Role::Load
                } else {
                    Role::And
                };
                self.contact(role, sense, operands, site);
            }
            BitClass::AliasConstant(value) => {
                let role = if self.rung.at_rung_start() {
                    Role::Load
                } else {
                    Role::And
                };
                let new_rung = self.structure_contact(role, span);
                if let Some([device]) = operands {
                    self.ok(operands::bit_source(device));
                }
                self.emit_contact(role, new_rung, Contact::Constant(value), site);
            }
            BitClass::Compare(role, op) => {
                let new_rung = self.structure_contact(role, span);
                let width = spec.width;
                if let Some([left, right]) = operands {
                    let left = self.ok(words::word_source(left, width));
                    let right = self.ok(words::word_source(right, width));
                    if let (Some(left), Some(right)) = (left, right) {
                        self.emit_contact(role, new_rung, Contact::Compare { op, width, left, right }, site);
                    }
                }
            }
            BitClass::BlockAnd => {
                self.rung.combine(span, &mut self.diagnostics);
                self.emit(Op::Logic(Logic::AndBlock), site);
            }
            BitClass::BlockOr => {
                self.rung.combine(span, &mut self.diagnostics);
                self.emit(Op::Logic(Logic::OrBlock), site);
            }
            BitClass::BranchPush => {
                self.rung.push(span, &mut self.diagnostics);
                self.emit(Op::Logic(Logic::BranchPush), site);
            }
            BitClass::BranchRead => {
                self.rung.read(span, false, &mut self.diagnostics);
                self.emit(Op::Logic(Logic::BranchRead), site);
            }
            BitClass::BranchPop => {
                self.rung.read(span, true, &mut self.diagnostics);
                self.emit(Op::Logic(Logic::BranchPop), site);
            }
            BitClass::Invert => {
                self.rung.series(span, &mut self.diagnostics);
                self.emit(Op::Logic(Logic::Invert), site);
            }
            BitClass::ResultEdge(sense) => {
                self.rung.series(span, &mut self.diagnostics);
                let slot = self.slot(span);
                self.emit(
                    Op::Logic(Logic::ResultEdge {
                        falling: sense == Sense::Falling,
                        slot,
                    }),
                    site,
                );
            }
            BitClass::Out => {
                self.state_power(site);
                self.rung.output(span, &mut self.diagnostics);
                if let Some(operands) = operands {
                    self.out(operands, site);
                }
            }
            BitClass::Set => {
                self.state_power(site);
                self.rung.output(span, &mut self.diagnostics);
                if let Some(operands) = operands {
                    self.set(operands, site);
                }
            }
            BitClass::Reset => {
                self.state_power(site);
                self.rung.output(span, &mut self.diagnostics);
                if let Some(operands) = operands {
                    self.reset(operands, site);
                }
            }
            BitClass::Pulse(sense) => {
                self.state_power(site);
                self.rung.output(span, &mut self.diagnostics);
                if let Some([target]) = operands {
                    if let Some(target) = self.ok(operands::bit_target(target)) {
                        let slot = self.slot(span);
                        self.emit(Op::Output(Output::Pulse { target, sense, slot }), site);
                    }
                }
            }
            BitClass::StateJump => {
                self.state_power(site);
                self.rung.output(span, &mut self.diagnostics);
                if let Some([state]) = operands {
                    if let Some(state) = self.ok(operands::state(state)) {
                        self.emit(Op::Output(Output::StateJump { state }), site);
                    }
                }
            }
            BitClass::MasterControl => {
                self.rung.output(span, &mut self.diagnostics);
                if let Some([level, relay]) = operands {
                    let level = self.ok(operands::nest_level(level));
                    let relay = self.ok(operands::bit_target(relay));
                    if let (Some(level), Some(relay)) = (level, relay) {
                        // The MC takes the rung result under the outer levels
                        // before its own level opens.
                        self.emit(Op::Output(Output::MasterControl { level, relay }), site);
                        self.blocks.mc(level, span, &mut self.diagnostics);
                    }
                }
            }
            BitClass::MasterControlReset => {
                self.rung.close(span, &mut self.diagnostics);
                if let Some([level]) = operands {
                    if let Some(level) = self.ok(operands::nest_level(level)) {
                        if self.blocks.mcr(level, span, &mut self.diagnostics) {
                            self.emit(Op::Line(Line::MasterControlReset { level }), site);
                        }
                    }
                }
            }
            BitClass::Jump => {
                self.state_power(site);
                self.rung.output(span, &mut self.diagnostics);
                if let Some([label]) = operands {
                    if let Some(label) = self.ok(operands::label(label)) {
                        let context = self.blocks.context();
                        if let Some(instruction) = self.emit(
                            Op::Jump {
                                target: usize::MAX,
                                label,
                            },
                            site,
                        ) {
                            self.blocks.jump(PendingJump {
                                label,
                                position,
                                instruction,
                                context,
                                span,
                            });
                        }
                    }
                }
            }
            BitClass::Stl => self.stl(operands, site),
            BitClass::StlEnd { fx_return } => self.close_block(if fx_return { "RET" } else { "STLE" }, site),
            BitClass::MainEnd => self.main_end(site),
            BitClass::Call { pulse } => self.call(pulse, operands, site),
            BitClass::SubroutineReturn => self.subroutine_return(site),
            BitClass::LoopStart => self.loop_start(operands, site),
            BitClass::LoopEnd => self.loop_end(site),
            BitClass::Nop => {}
            BitClass::Network | BitClass::RungEnd => self.rung.close(span, &mut self.diagnostics),
            BitClass::End => {
                self.end_of_program(span);
                self.ended = true;
            }
        }
    }

    /// An application instruction: it takes the rung result like an output.
    fn app(&mut self, form: AppForm, syntax: &InstructionSyntax, site: &Site) {
        self.state_power(site);
        self.rung.output(site.span, &mut self.diagnostics);
        let spec = form.op.spec();
        let count = spec.operands.len();
        let Some(operands) = self.counted_operands(syntax, count, count, site) else {
            return;
        };
        let mut resolver = app::AppResolver {
            mnemonic: &syntax.mnemonic,
            operands: operands.iter(),
            width: form.width,
            diagnostics: &mut self.diagnostics,
        };
        let Some(args) = AppArgs::resolve(form.op, &mut resolver) else {
            return;
        };
        let pulse_slot = form.pulse.then(|| self.slot(site.span));
        let job = match spec.keeps {
            Keeps::SortJob => Some(self.job(site.span)),
            Keeps::State => Some(self.instance(site.span)),
            Keeps::Nothing => None,
        };
        self.emit(
            Op::Output(Output::App(AppInstruction {
                width: form.width,
                args,
                pulse_slot,
                job,
            })),
            site,
        );
    }

    /// Feeds a contact to the rung tracker; returns true when it starts a rung.
    fn structure_contact(&mut self, role: Role, span: Span) -> bool {
        match role {
            Role::Load => self.rung.load(span, &mut self.diagnostics),
            Role::And | Role::Or => {
                self.rung.series(span, &mut self.diagnostics);
                false
            }
        }
    }

    fn contact(&mut self, role: Role, sense: Sense, operands: Option<&[syntax::Operand]>, site: &Site) {
        let new_rung = self.structure_contact(role, site.span);
        let Some([device]) = operands else {
            return;
        };
        let Some(bit) = self.ok(operands::bit_source(device)) else {
            return;
        };
        let contact = match sense {
            Sense::Open | Sense::Closed => Contact::Level {
                bit,
                closed: sense == Sense::Closed,
            },
            Sense::Rising | Sense::Falling => Contact::Edge {
                bit,
                falling: sense == Sense::Falling,
                slot: self.slot(site.span),
            },
        };
        self.emit_contact(role, new_rung, contact, site);
    }

    fn emit_contact(&mut self, role: Role, new_rung: bool, contact: Contact, site: &Site) {
        let op = match role {
            Role::Load => Op::Load {
                contact,
                new_rung,
                mc_levels: self.blocks.context().mc_mask(),
            },
            Role::And => Op::And(contact),
            Role::Or => Op::Or(contact),
        };
        self.emit(op, site);
    }

    fn out(&mut self, operands: &[syntax::Operand], site: &Site) {
        let Some((coil, preset)) = operands.split_first() else {
            return;
        };
        let Some(coil) = self.ok(operands::coil(coil)) else {
            return;
        };
        let preset = preset.first();
        let op = match (coil, preset) {
            // Inside a block, OUT of a state is a transfer, exactly as SET.
            (Coil::Bit(target @ BitRef::Device(BitArea::S, _)), None) if self.blocks.current_state().is_some() => {
                Output::Set {
                    target,
                    count: 1,
                    transfer_from: self.transfer_source(target, 1),
                    written_out: true,
                }
            }
            (Coil::Bit(target), None) => Output::Coil(target),
            (Coil::Bit(_), Some(extra)) => {
                self.report(
                    Diagnostic::new(
                        Code::OperandCount,
                        extra.span,
                        "only timer and counter coils take a preset",
                    )
                    .with_label("unexpected operand"),
                );
                return;
            }
            (Coil::Timer(_) | Coil::Counter(_), None) => {
                self.report(
                    Diagnostic::new(Code::MissingPreset, site.span, "timer or counter coil without a preset")
                        .with_label("add the preset, e.g. K10 or D100"),
                );
                return;
            }
            (Coil::Timer(timer), Some(preset)) => {
                let Some(preset) = self.ok(operands::preset(preset, Width::Single)) else {
                    return;
                };
                Output::Timer { timer, preset }
            }
            (Coil::Counter(counter), Some(preset)) => {
                let width = ladder_runtime::device::counter_width(counter);
                let Some(preset) = self.ok(operands::preset(preset, width)) else {
                    return;
                };
                Output::Counter { counter, preset }
            }
        };
        self.emit(Op::Output(op), site);
    }

    fn count(&mut self, operands: &[syntax::Operand], first: u32, area_len: u32) -> Option<u32> {
        match operands.get(1) {
            None => Some(1),
            Some(count) => self.ok(operands::device_count(count, first, area_len)),
        }
    }

    fn set(&mut self, operands: &[syntax::Operand], site: &Site) {
        let Some(first) = operands.first() else {
            return;
        };
        let Some(target) = self.ok(operands::bit_target(first)) else {
            return;
        };
        let Some(count) = self.counted_bits(target, operands) else {
            return;
        };
        let transfer_from = self.transfer_source(target, count);
        self.emit(
            Op::Output(Output::Set {
                target,
                count,
                transfer_from,
                written_out: false,
            }),
            site,
        );
    }

    /// A SET (or OUT) of states inside the block of another state moves
    /// out of that block: the state to turn OFF at the next scan.
    fn transfer_source(&self, target: BitRef, count: u32) -> Option<u32> {
        let (Some(source), BitRef::Device(BitArea::S, address)) = (self.blocks.current_state(), target) else {
            // Outside a state's block, or not a state.
            return None;
        };
        let covers_source = address.is_fixed() && (address.index..address.index + count).contains(&source);
        (!covers_source).then_some(source)
    }

    /// The count of a SET/RST on bits; word bits take no count.
    fn counted_bits(&mut self, target: BitRef, operands: &[syntax::Operand]) -> Option<u32> {
        match target {
            BitRef::Device(area, address) => self.count(operands, address.index, area.count()),
            BitRef::WordBit(..) => match operands.get(1) {
                None => Some(1),
                Some(extra) => {
                    self.report(
                        Diagnostic::new(Code::OperandKind, extra.span, "a bit of a word takes no device count")
                            .with_label("unexpected count"),
                    );
                    None
                }
            },
        }
    }

    fn reset(&mut self, operands: &[syntax::Operand], site: &Site) {
        use syntax::{OperandSyntax, Prefix};
        let Some(first) = operands.first() else {
            return;
        };
        let target = match &first.syntax {
            OperandSyntax::Device(d) if d.digits.is_none() && d.bit.is_none() => match d.prefix {
                Prefix::T | Prefix::Ts | Prefix::C | Prefix::Cs => {
                    let timer = matches!(d.prefix, Prefix::T | Prefix::Ts);
                    let Some(coil) = self.ok(operands::coil(first)) else {
                        return;
                    };
                    let (number, area) = match coil {
                        Coil::Timer(n) | Coil::Counter(n) => (
                            n,
                            if timer {
                                BitArea::TimerContact
                            } else {
                                BitArea::CounterContact
                            },
                        ),
                        Coil::Bit(_) => return,
                    };
                    let Some(count) = self.count(operands, number, area.count()) else {
                        return;
                    };
                    let target = if timer {
                        ResetTarget::Timer(number)
                    } else {
                        ResetTarget::Counter(number)
                    };
                    self.emit(Op::Output(Output::Reset { target, count }), site);
                    return;
                }
                Prefix::D | Prefix::Sd | Prefix::R | Prefix::V | Prefix::Z | Prefix::U => {
                    let Some(WordRef::Word(area, address)) = self.ok(words::word_destination(first, Width::Single, 1))
                    else {
                        return;
                    };
                    if area == WordArea::Index && operands.len() > 1 {
                        self.report(
                            Diagnostic::new(Code::OperandKind, site.span, "RST of an index register takes no count")
                                .with_label("index registers are reset one at a time"),
                        );
                        return;
                    }
                    let Some(count) = self.count(operands, address.index, area.count()) else {
                        return;
                    };
                    self.emit(
                        Op::Output(Output::Reset {
                            target: ResetTarget::Word(area, address),
                            count,
                        }),
                        site,
                    );
                    return;
                }
                Prefix::X
                | Prefix::Y
                | Prefix::M
                | Prefix::S
                | Prefix::Sm
                | Prefix::Tn
                | Prefix::Cn
                | Prefix::P
                | Prefix::N => self.ok(operands::bit_target(first)),
            },
            OperandSyntax::Device(_) | OperandSyntax::Constant(_) | OperandSyntax::Real(_) => {
                self.ok(operands::bit_target(first))
            }
        };
        let Some(target) = target else { return };
        let Some(count) = self.counted_bits(target, operands) else {
            return;
        };
        self.emit(
            Op::Output(Output::Reset {
                target: ResetTarget::Bit(target),
                count,
            }),
            site,
        );
    }
}

#[cfg(test)]
mod tests;
