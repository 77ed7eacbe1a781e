//! Program structure beyond single rungs: STL blocks, master-control
//! regions, FOR/NEXT loops, the program part (main program or a
//! subroutine), labels and jumps.

use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::source::Span;
use rustc_hash::FxHashMap;

/// Loops nest up to this many levels.
pub const LOOP_DEPTH: usize = 5;

/// Where an instruction sits: its STL block, its open MC regions, its loops
/// and its program part.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Context {
    pub stl_block: Option<usize>,
    /// Open MC regions, outermost first: (level, region id).
    pub mc_regions: Vec<(u8, usize)>,
    /// Open loops, outermost first (loop ids).
    pub loops: Vec<usize>,
    /// The subroutine (its id), or None in the main program.
    pub subroutine: Option<usize>,
}

impl Context {
    /// The MC levels open here, as a bit mask.
    pub fn mc_mask(&self) -> u8 {
        self.mc_regions.iter().fold(0, |mask, &(level, _)| mask | (1 << level))
    }

    /// May a jump from `self` land in `target`? Leaving a block or region is
    /// fine; entering one is not.
    fn may_enter(&self, target: &Context) -> bool {
        let block_ok = target.stl_block.is_none() || target.stl_block == self.stl_block;
        let regions_ok = self.mc_regions.starts_with(&target.mc_regions);
        block_ok && regions_ok
    }

    /// The parts of the context a loop must not cross (everything but the
    /// loops themselves).
    fn without_loops(&self) -> Context {
        Context {
            loops: Vec::new(),
            ..self.clone()
        }
    }
}

struct OpenLoop {
    id: usize,
    /// The context at FOR, outside this loop.
    context: Context,
    /// Index of the LoopStart instruction.
    start: usize,
    span: Span,
}

struct OpenBlock {
    id: usize,
    state: u32,
    span: Span,
}

struct Label {
    /// Statement order position, to tell forward from backward jumps.
    position: usize,
    /// Index into the executable instruction list.
    target: usize,
    context: Context,
    span: Span,
}

/// A jump waiting for its label to be known.
pub struct PendingJump {
    pub label: u32,
    pub position: usize,
    /// Index of the Jump instruction to patch.
    pub instruction: usize,
    pub context: Context,
    pub span: Span,
}

#[derive(Default)]
pub struct BlockTracker {
    open_block: Option<OpenBlock>,
    blocks_started: usize,
    state_blocks: FxHashMap<u32, Span>,
    mc_open: Vec<(u8, usize, Span)>,
    regions_started: usize,
    labels: FxHashMap<u32, Label>,
    jumps: Vec<PendingJump>,
    loops: Vec<OpenLoop>,
    loops_started: usize,
    subroutine: Option<usize>,
}

impl BlockTracker {
    pub fn context(&self) -> Context {
        Context {
            stl_block: self.open_block.as_ref().map(|b| b.id),
            mc_regions: self.mc_open.iter().map(|&(level, id, _)| (level, id)).collect(),
            loops: self.loops.iter().map(|open| open.id).collect(),
            subroutine: self.subroutine,
        }
    }

    /// The open STL block's id, if any.
    pub fn open_block(&self) -> Option<usize> {
        self.open_block.as_ref().map(|b| b.id)
    }

    /// Where the open STL block starts.
    pub fn open_block_span(&self) -> Option<Span> {
        self.open_block.as_ref().map(|b| b.span)
    }

    /// Instructions from here on belong to subroutine `id` (None: to no
    /// part, between SRET and the next label).
    pub fn set_subroutine(&mut self, id: Option<usize>) {
        self.subroutine = id;
    }

    /// `FOR` at instruction `start`: false when nested too deep (reported).
    pub fn loop_start(&mut self, start: usize, span: Span, diagnostics: &mut Diagnostics) -> bool {
        if self.loops.len() == LOOP_DEPTH {
            diagnostics.push(
                Diagnostic::new(Code::LoopTooDeep, span, "FOR nested deeper than 5 levels")
                    .with_label("sixth open loop")
                    .with_related(self.loops[0].span, "the outermost loop starts here"),
            );
            return false;
        }
        let context = self.context();
        self.loops.push(OpenLoop {
            id: self.loops_started,
            context,
            start,
            span,
        });
        self.loops_started += 1;
        true
    }

    /// `NEXT`: the index of its FOR, when it pairs with one.
    pub fn loop_end(&mut self, span: Span, diagnostics: &mut Diagnostics) -> Option<usize> {
        let Some(open) = self.loops.pop() else {
            diagnostics.push(Diagnostic::new(Code::LoopPairing, span, "NEXT without FOR").with_label("no open loop"));
            return None;
        };
        if open.context.without_loops() != self.context().without_loops() {
            diagnostics.push(
                Diagnostic::new(
                    Code::LoopPairing,
                    span,
                    "the loop crosses an STL block or MC region boundary",
                )
                .with_label("this NEXT is in another block or region than its FOR")
                .with_related(open.span, "the FOR"),
            );
            return None;
        }
        Some(open.start)
    }

    /// The end of a program part (FEND, SRET, END): loops still open are
    /// errors at their FOR.
    pub fn close_loops(&mut self, diagnostics: &mut Diagnostics) {
        for open in self.loops.drain(..) {
            diagnostics.push(
                Diagnostic::new(Code::LoopPairing, open.span, "FOR without NEXT")
                    .with_label("this loop is never closed"),
            );
        }
    }

    /// The state of the open STL block.
    pub fn current_state(&self) -> Option<u32> {
        self.open_block.as_ref().map(|b| b.state)
    }

    /// Reports `what` (STL, MC, MCR) inside a subroutine; true when it is.
    fn in_subroutine(&self, what: &str, span: Span, diagnostics: &mut Diagnostics) -> bool {
        if self.subroutine.is_none() {
            return false;
        }
        diagnostics.push(
            Diagnostic::new(Code::NotInSubroutine, span, format!("{what} inside a subroutine"))
                .with_label("subroutines cannot hold STL blocks or MC regions"),
        );
        true
    }

    /// `STL Sn` (the checker closed any open block first): returns the new
    /// block's id. `state` is None when the operand was already reported as
    /// invalid.
    pub fn stl(&mut self, state: Option<u32>, span: Span, diagnostics: &mut Diagnostics) -> usize {
        self.in_subroutine("STL", span, diagnostics);
        if let Some(&(level, _, mc_span)) = self.mc_open.last() {
            diagnostics.push(
                Diagnostic::new(Code::NotInStl, span, "STL inside a master-control region")
                    .with_label("a state block may not start inside MC/MCR")
                    .with_related(mc_span, format!("MC N{level} opened here")),
            );
        }
        if let Some(state) = state {
            if let Some(&first) = self.state_blocks.get(&state) {
                diagnostics.push(
                    Diagnostic::new(Code::DuplicateState, span, format!("S{state} already has a block"))
                        .with_label("second block of this state")
                        .with_related(first, "first block here"),
                );
            } else {
                self.state_blocks.insert(state, span);
            }
        }
        let id = self.blocks_started;
        self.blocks_started += 1;
        self.open_block = Some(OpenBlock {
            id,
            state: state.unwrap_or(u32::MAX),
            span,
        });
        id
    }

    /// STLE or RET (`name`): returns the id of the block it closes.
    pub fn stle(&mut self, name: &str, span: Span, diagnostics: &mut Diagnostics) -> Option<usize> {
        let closed = self.open_block.take().map(|b| b.id);
        if closed.is_none() {
            diagnostics.push(
                Diagnostic::new(Code::StrayStle, span, format!("{name} without STL")).with_label("no open state block"),
            );
        }
        closed
    }

    /// `MC Nk`: returns false when the MC is misplaced (already reported).
    pub fn mc(&mut self, level: u8, span: Span, diagnostics: &mut Diagnostics) -> bool {
        if self.in_subroutine("MC", span, diagnostics) {
            return false;
        }
        if let Some(open) = &self.open_block {
            diagnostics.push(
                Diagnostic::new(Code::NotInStl, span, "MC inside an STL block")
                    .with_label("not allowed between STL and STLE")
                    .with_related(open.span, "the block starts here"),
            );
            return false;
        }
        if let Some(&(top, _, top_span)) = self.mc_open.last() {
            if level <= top {
                diagnostics.push(
                    Diagnostic::new(Code::McPairing, span, format!("MC N{level} inside MC N{top}"))
                        .with_label(format!("nested levels must be higher than N{top}"))
                        .with_related(top_span, format!("MC N{top} opened here")),
                );
                return false;
            }
        }
        self.mc_open.push((level, self.regions_started, span));
        self.regions_started += 1;
        true
    }

    /// `MCR Nk`: closes level k and every deeper one; false when it is
    /// misplaced (already reported).
    pub fn mcr(&mut self, level: u8, span: Span, diagnostics: &mut Diagnostics) -> bool {
        if self.in_subroutine("MCR", span, diagnostics) {
            return false;
        }
        if let Some(open) = &self.open_block {
            diagnostics.push(
                Diagnostic::new(Code::NotInStl, span, "MCR inside an STL block")
                    .with_label("not allowed between STL and STLE")
                    .with_related(open.span, "the block starts here"),
            );
            return false;
        }
        match self.mc_open.iter().position(|&(open, _, _)| open == level) {
            Some(index) => {
                self.mc_open.truncate(index);
                true
            }
            None => {
                diagnostics.push(
                    Diagnostic::new(Code::McPairing, span, format!("MCR N{level} without MC N{level}"))
                        .with_label("no open master-control region of this level"),
                );
                false
            }
        }
    }

    pub fn label(&mut self, number: u32, position: usize, target: usize, span: Span, diagnostics: &mut Diagnostics) {
        if let Some(first) = self.labels.get(&number) {
            diagnostics.push(
                Diagnostic::new(Code::DuplicateLabel, span, format!("label P{number} defined twice"))
                    .with_label("second definition")
                    .with_related(first.span, "first definition"),
            );
            return;
        }
        self.labels.insert(
            number,
            Label {
                position,
                target,
                context: self.context(),
                span,
            },
        );
    }

    /// A label with this number exists (so far).
    pub fn has_label(&self, number: u32) -> bool {
        self.labels.contains_key(&number)
    }

    pub fn jump(&mut self, jump: PendingJump) {
        self.jumps.push(jump);
    }

    /// END or the end of the source: open blocks and regions are errors.
    pub fn close(&mut self, diagnostics: &mut Diagnostics) {
        if let Some(open) = self.open_block.take() {
            diagnostics.push(
                Diagnostic::new(
                    Code::UnclosedStl,
                    open.span,
                    format!("the block of STL S{} is never closed", open.state),
                )
                .with_label("close it with RET or STLE"),
            );
        }
        for (level, _, span) in self.mc_open.drain(..) {
            diagnostics.push(
                Diagnostic::new(Code::McPairing, span, format!("MC N{level} without MCR N{level}"))
                    .with_label("this region is never closed"),
            );
        }
    }

    /// Resolves every jump: (instruction index, target index) pairs.
    pub fn resolve_jumps(&mut self, diagnostics: &mut Diagnostics) -> Vec<(usize, usize)> {
        let mut resolved = Vec::new();
        for jump in self.jumps.drain(..) {
            let Some(label) = self.labels.get(&jump.label) else {
                diagnostics.push(
                    Diagnostic::new(
                        Code::MissingLabel,
                        jump.span,
                        format!("label P{} does not exist", jump.label),
                    )
                    .with_label("jump target missing"),
                );
                continue;
            };
            if label.context.subroutine != jump.context.subroutine {
                diagnostics.push(
                    Diagnostic::new(
                        Code::JumpAcrossSubroutine,
                        jump.span,
                        format!("jump to P{} in another program part", jump.label),
                    )
                    .with_label("CJ stays in the main program or in one subroutine")
                    .with_related(label.span, "the label is here")
                    .with_note("use CALL to run a subroutine"),
                );
            } else if label.position < jump.position {
                diagnostics.push(
                    Diagnostic::new(
                        Code::BackwardJump,
                        jump.span,
                        format!("backward jump to P{}", jump.label),
                    )
                    .with_label("only forward jumps are accepted")
                    .with_related(label.span, "the label is before the jump")
                    .with_note("to repeat instructions within a scan, use FOR/NEXT"),
                );
            } else if label.context.loops != jump.context.loops {
                diagnostics.push(
                    Diagnostic::new(
                        Code::JumpAcrossLoop,
                        jump.span,
                        format!("jump into or out of a loop: P{}", jump.label),
                    )
                    .with_label("this jump would enter or leave a FOR/NEXT loop")
                    .with_related(label.span, "the label is here"),
                );
            } else if !jump.context.may_enter(&label.context) {
                diagnostics.push(
                    Diagnostic::new(
                        Code::JumpIntoBlock,
                        jump.span,
                        format!("jump into a block: P{}", jump.label),
                    )
                    .with_label("this jump would enter an STL block or MC region")
                    .with_related(label.span, "the label is inside it"),
                );
            } else {
                resolved.push((jump.instruction, label.target));
            }
        }
        resolved
    }
}
