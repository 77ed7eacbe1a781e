//! FX program structure in the checker: STL blocks closed FX style (by the
//! next STL or RET), outputs on a state's power, FEND and the subroutines
//! after it, CALL and its resolution (recursion and nesting depth), FOR/NEXT.

use super::{operands, Checker, Site};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{Contact, Op, StlBlock, Subroutine};
use crate::source::Span;
use crate::syntax;
use ladder_runtime::Width;
use std::collections::HashMap;

/// Subroutine calls nest up to this many levels (the main program's CALL
/// is level 1).
pub const CALL_DEPTH: u32 = 5;

/// A CALL waiting for the subroutines to be known.
pub struct PendingCall {
    label: u32,
    /// Index of the Call instruction to patch.
    instruction: usize,
    /// The subroutine the CALL is in (None: the main program).
    caller: Option<usize>,
    span: Span,
}

/// What the checker knows about program parts.
#[derive(Default)]
pub struct Parts {
    /// FEND was seen: labels start subroutines.
    pub after_main_end: bool,
    pub main_end: Option<usize>,
    pub subroutines: Vec<Subroutine>,
    /// Subroutine id by label number.
    by_label: HashMap<u32, usize>,
    /// The subroutine being read and its label's span.
    open: Option<(usize, Span)>,
    /// Spans of subroutine labels, by id.
    label_spans: Vec<Span>,
    calls: Vec<PendingCall>,
    /// E0039 was reported for the current stretch outside any part.
    reported_outside: bool,
}

impl Parts {
    /// After FEND, outside any subroutine: nothing here would run.
    pub fn outside_any_part(&self) -> bool {
        self.after_main_end && self.open.is_none()
    }
}

impl Checker {
    /// An instruction after FEND and outside any subroutine (E0039), once
    /// per stretch.
    pub(super) fn outside_part(&mut self, span: Span) {
        if self.parts.reported_outside {
            return;
        }
        self.parts.reported_outside = true;
        self.report(
            Diagnostic::new(
                Code::OutsideSubroutine,
                span,
                "instruction after FEND outside a subroutine",
            )
            .with_label("this would never run")
            .with_note("after FEND, a subroutine starts at a label `Pn` and ends at SRET"),
        );
    }

    /// A label after FEND outside a subroutine starts one.
    pub(super) fn subroutine_label(&mut self, number: u32, span: Span) {
        let id = self.parts.subroutines.len();
        self.parts.subroutines.push(Subroutine {
            label: number,
            entry: self.instructions.len(),
            end: usize::MAX,
        });
        self.parts.label_spans.push(span);
        self.parts.by_label.entry(number).or_insert(id);
        self.parts.open = Some((id, span));
        self.parts.reported_outside = false;
        self.blocks.set_subroutine(Some(id));
    }

    /// SRET: the end of the open subroutine.
    pub(super) fn subroutine_return(&mut self, site: &Site) {
        self.rung.close(site.span, &mut self.diagnostics);
        self.blocks.close_loops(&mut self.diagnostics);
        let Some((id, _)) = self.parts.open.take() else {
            self.report(
                Diagnostic::new(Code::StraySret, site.span, "SRET outside a subroutine")
                    .with_label("no subroutine is open here")
                    .with_note("subroutines follow FEND: a label `Pn`, its instructions, SRET"),
            );
            return;
        };
        self.blocks.set_subroutine(None);
        if let Some(index) = self.emit(Op::SubroutineReturn, site) {
            self.parts.subroutines[id].end = index;
        }
    }

    /// A subroutine still open at FEND, END or the end of the file.
    pub(super) fn close_subroutine(&mut self) {
        if let Some((_, span)) = self.parts.open.take() {
            self.report(
                Diagnostic::new(Code::MissingSret, span, "subroutine without SRET")
                    .with_label("this subroutine never ends")
                    .with_note("end it with SRET before the next label, FEND or END"),
            );
            self.blocks.set_subroutine(None);
        }
    }

    /// FEND: the main program ends.
    pub(super) fn main_end(&mut self, site: &Site) {
        self.rung.close(site.span, &mut self.diagnostics);
        self.blocks.close(&mut self.diagnostics);
        self.blocks.close_loops(&mut self.diagnostics);
        self.close_subroutine();
        if self.parts.after_main_end {
            // A second FEND is an instruction outside any part (reported by
            // the caller); it does not end anything again.
            return;
        }
        self.parts.after_main_end = true;
        self.parts.main_end = self.emit(Op::MainEnd, site);
    }

    /// CALL/CALLP Pn.
    pub(super) fn call(&mut self, pulse: bool, operands: Option<&[syntax::Operand]>, site: &Site) {
        self.state_power(site);
        self.rung.output(site.span, &mut self.diagnostics);
        let Some([label]) = operands else {
            return;
        };
        let Some(label) = self.ok(operands::label(label)) else {
            return;
        };
        let slot = pulse.then(|| self.slot(site.span));
        let caller = self.blocks.context().subroutine;
        if let Some(instruction) = self.emit(
            Op::Call {
                subroutine: usize::MAX,
                slot,
            },
            site,
        ) {
            self.parts.calls.push(PendingCall {
                label,
                instruction,
                caller,
                span: site.span,
            });
        }
    }

    /// FOR n: on the main bus.
    pub(super) fn loop_start(&mut self, operands: Option<&[syntax::Operand]>, site: &Site) {
        self.loop_on_bus("FOR", site.span);
        let count = match operands {
            Some([count]) => self.ok(operands::word_source(count, Width::Single)),
            _ => None,
        };
        let start = self.instructions.len();
        if self.blocks.loop_start(start, site.span, &mut self.diagnostics) {
            if let Some(count) = count {
                self.emit(Op::LoopStart { count, end: usize::MAX }, site);
            }
        }
    }

    /// NEXT: closes the innermost loop.
    pub(super) fn loop_end(&mut self, site: &Site) {
        self.loop_on_bus("NEXT", site.span);
        let Some(start) = self.blocks.loop_end(site.span, &mut self.diagnostics) else {
            return;
        };
        let end = self.instructions.len();
        // The FOR is missing when its operand was bad (already reported).
        if let Some(Op::LoopStart { end: for_end, .. }) = self.instructions.get_mut(start).map(|i| &mut i.op) {
            *for_end = end;
            self.emit(Op::LoopEnd { start }, site);
        }
    }

    /// FOR and NEXT need the rung before them finished (E0042).
    fn loop_on_bus(&mut self, name: &str, span: Span) {
        if self.rung.has_pending_contacts() {
            self.report(
                Diagnostic::new(Code::LoopNotOnBus, span, format!("{name} after contacts"))
                    .with_label(format!("{name} stands on the main bus"))
                    .with_note("finish the rung with an output first; put conditions inside the loop"),
            );
            // One error: the contacts before are not also "without an output".
            self.rung.poison(span);
        }
        self.rung.close(span, &mut self.diagnostics);
    }

    /// Right after STL (or a label, POP, NETWORK) inside a block, an output
    /// has no rung of its own: it takes the state's power, which is ON
    /// whenever the block runs.
    pub(super) fn state_power(&mut self, site: &Site) {
        if self.blocks.current_state().is_none() || !self.rung.is_closed() {
            return;
        }
        self.rung.load(site.span, &mut self.diagnostics);
        let mc_levels = self.blocks.context().mc_mask();
        self.emit(
            Op::Load {
                contact: Contact::Constant(true),
                new_rung: true,
                mc_levels,
            },
            site,
        );
    }

    /// Closes the open STL block at STLE, RET or the next STL; `name` is
    /// the instruction that closes it.
    pub(super) fn close_block(&mut self, name: &str, site: &Site) {
        self.rung.close(site.span, &mut self.diagnostics);
        let end = self.instructions.len();
        let closed = self
            .blocks
            .open_block()
            .and_then(|id| self.emitted_blocks.get(&id).copied());
        if self.blocks.stle(name, site.span, &mut self.diagnostics).is_some() && self.emit(Op::StlEnd, site).is_some() {
            if let Some(block) = closed {
                self.stl_blocks[block].end = end;
            }
        }
    }

    /// `STL Sn`: closes an open block, opens the next.
    pub(super) fn stl(&mut self, operands: Option<&[syntax::Operand]>, site: &Site) {
        if self.blocks.open_block().is_some() {
            self.close_block("STL", site);
        }
        self.rung.close(site.span, &mut self.diagnostics);
        let state = match operands {
            Some([state]) => self.ok(operands::state(state)),
            _ => None,
        };
        let id = self.blocks.stl(state, site.span, &mut self.diagnostics);
        let begin = self.instructions.len();
        let block = self.stl_blocks.len();
        if self.emit(Op::StlBegin { block }, site).is_some() {
            self.emitted_blocks.insert(id, block);
            self.stl_blocks.push(StlBlock {
                state: state.unwrap_or(0),
                begin,
                end: begin,
                reset_outputs: Vec::new(),
                reset_slots: Vec::new(),
            });
        }
    }

    /// Resolves every CALL to its subroutine and checks the call graph:
    /// recursion (E0034) and nesting deeper than `CALL_DEPTH` (E0038).
    pub(super) fn resolve_calls(&mut self) {
        let calls = std::mem::take(&mut self.parts.calls);
        let mut edges: Vec<(Option<usize>, usize, usize)> = Vec::new();
        for call in &calls {
            match self.parts.by_label.get(&call.label) {
                Some(&id) => {
                    if let Op::Call { subroutine, .. } = &mut self.instructions[call.instruction].op {
                        *subroutine = id;
                    }
                    edges.push((call.caller, id, call.instruction));
                }
                None if self.blocks.has_label(call.label) => self.report(
                    Diagnostic::new(
                        Code::NotASubroutine,
                        call.span,
                        format!("P{} is not a subroutine", call.label),
                    )
                    .with_label("CALL needs a subroutine label")
                    .with_note("subroutines follow FEND: a label `Pn`, its instructions, SRET"),
                ),
                None => self.report(
                    Diagnostic::new(
                        Code::MissingLabel,
                        call.span,
                        format!("label P{} does not exist", call.label),
                    )
                    .with_label("CALL target missing"),
                ),
            }
        }
        let span_of = |instruction: usize| calls.iter().find(|c| c.instruction == instruction).map(|c| c.span);
        let graph = CallGraph::new(self.parts.subroutines.len(), &edges);
        for (instruction, error) in graph.problems() {
            let span = span_of(instruction).unwrap_or_default();
            let diagnostic = match error {
                CallProblem::Recursion => Diagnostic::new(Code::Recursion, span, "recursive subroutine call")
                    .with_label("this CALL leads back to a subroutine that is still running"),
                CallProblem::TooDeep => {
                    Diagnostic::new(Code::CallTooDeep, span, "subroutine calls nested deeper than 5")
                        .with_label("this CALL would be level 6")
                }
            };
            self.report(diagnostic);
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CallProblem {
    Recursion,
    TooDeep,
}

/// Calls between program parts: (caller, callee, CALL instruction).
struct CallGraph<'e> {
    subroutines: usize,
    edges: &'e [(Option<usize>, usize, usize)],
}

impl<'e> CallGraph<'e> {
    fn new(subroutines: usize, edges: &'e [(Option<usize>, usize, usize)]) -> CallGraph<'e> {
        CallGraph { subroutines, edges }
    }

    /// Every CALL that closes a cycle, and every CALL that runs at a level
    /// deeper than `CALL_DEPTH` (following the deepest path from the main
    /// program), each once.
    fn problems(&self) -> Vec<(usize, CallProblem)> {
        #[derive(Clone, Copy, PartialEq)]
        enum Mark {
            New,
            Active,
            Done,
        }
        // Depth-first from every part, iteratively (call chains can be as
        // long as there are labels): a call to an Active part closes a cycle.
        let mut problems = Vec::new();
        let mut marks = vec![Mark::New; self.subroutines];
        let mut cyclic = vec![false; self.edges.len()];
        for root in 0..self.subroutines {
            if marks[root] != Mark::New {
                continue;
            }
            let mut stack = vec![(root, 0usize)];
            marks[root] = Mark::Active;
            while let Some(&mut (part, ref mut next)) = stack.last_mut() {
                let outgoing = self
                    .edges
                    .iter()
                    .enumerate()
                    .filter(|(_, e)| e.0 == Some(part))
                    .nth(*next);
                *next += 1;
                match outgoing {
                    None => {
                        marks[part] = Mark::Done;
                        stack.pop();
                    }
                    Some((edge, &(_, callee, instruction))) => match marks[callee] {
                        Mark::Active => {
                            cyclic[edge] = true;
                            problems.push((instruction, CallProblem::Recursion));
                        }
                        Mark::New => {
                            marks[callee] = Mark::Active;
                            stack.push((callee, 0));
                        }
                        Mark::Done => {}
                    },
                }
            }
        }
        // Levels: the main program is level 0; a part runs at one more than
        // the deepest level of a CALL to it. Without the cyclic calls the
        // graph is acyclic, so relaxing the levels settles in as many rounds
        // as there are parts.
        let mut level: Vec<Option<u32>> = vec![None; self.subroutines];
        for _ in 0..=self.subroutines {
            let mut changed = false;
            for (edge, &(caller, callee, _)) in self.edges.iter().enumerate() {
                let caller_level = match caller {
                    None => Some(0),
                    Some(caller) => level[caller],
                };
                if let (Some(caller_level), false) = (caller_level, cyclic[edge]) {
                    let at = (caller_level + 1).min(CALL_DEPTH + 1);
                    if level[callee].is_none_or(|known| known < at) {
                        level[callee] = Some(at);
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        for &(caller, _, instruction) in self.edges {
            let caller_level = match caller {
                None => Some(0),
                Some(caller) => level[caller],
            };
            if caller_level.is_some_and(|l| l + 1 == CALL_DEPTH + 1) {
                problems.push((instruction, CallProblem::TooDeep));
            }
        }
        problems
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recursion_and_depth() {
        // main -> 0 -> 1 -> 0 (cycle at the call in 1).
        let edges = [(None, 0, 10), (Some(0), 1, 11), (Some(1), 0, 12)];
        assert_eq!(CallGraph::new(2, &edges).problems(), vec![(12, CallProblem::Recursion)]);
        // main -> 0 -> 1 -> 2 -> 3 -> 4 is five levels; 4 -> 5 is the sixth.
        let chain: Vec<_> = (0..6usize).map(|n| (n.checked_sub(1), n, 20 + n)).collect();
        assert_eq!(CallGraph::new(6, &chain[..5]).problems(), vec![]);
        assert_eq!(CallGraph::new(6, &chain).problems(), vec![(25, CallProblem::TooDeep)]);
        // Self-call.
        assert_eq!(
            CallGraph::new(1, &[(Some(0), 0, 3)]).problems(),
            vec![(3, CallProblem::Recursion)]
        );
    }
}
