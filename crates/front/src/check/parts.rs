//! FX program structure in the checker: STL blocks closed FX style (by the
//! next STL or RET), outputs on a state's power, FEND and the subroutines
//! after it, CALL and its resolution (recursion and nesting depth), FOR/NEXT.

use super::{operands, words, Checker, Site};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{Contact, Line, Op, StlBlock, Subroutine};
use crate::source::Span;
use crate::syntax;
use ladder_runtime::Width;
use rustc_hash::FxHashMap;

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
    by_label: FxHashMap<u32, usize>,
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
        if let Some(index) = self.emit(Op::Line(Line::SubroutineReturn), site) {
            self.parts.subroutines[id].end = index;
        }
    }

    /// A subroutine still open at FEND, END or the end of the file.
    pub(super) fn close_subroutine(&mut self) {
        if let Some((_, span)) = self.parts.open.take() {
            self.report(
                Diagnostic::new(Code::MissingSret, span, "subroutine without SRET")
                    .with_label("this subroutine never ends")
                    .with_note("end it with SRET before FEND, END or the end of the file"),
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
        self.parts.main_end = self.emit(Op::Line(Line::MainEnd), site);
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
            Some([count]) => self.ok(words::word_source(count, Width::Single)),
            _ => None,
        };
        let start = self.instructions.len();
        if self.blocks.loop_start(start, site.span, &mut self.diagnostics) {
            if let Some(count) = count {
                self.emit(Op::Line(Line::LoopStart { count, end: usize::MAX }), site);
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
        if let Some(Op::Line(Line::LoopStart { end: for_end, .. })) =
            self.instructions.get_mut(start).map(|i| &mut i.op)
        {
            *for_end = end;
            self.emit(Op::Line(Line::LoopEnd { start }), site);
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
        if self.blocks.stle(name, site.span, &mut self.diagnostics).is_some()
            && self.emit(Op::Line(Line::StlEnd), site).is_some()
        {
            if let Some(block) = closed {
                self.stl_blocks[block].end = end;
            }
        }
    }

    /// `STL Sn`: closes an open block, opens the next.
    pub(super) fn stl(&mut self, operands: Option<&[syntax::Operand]>, site: &Site) {
        if let Some(open) = self.blocks.open_block_span().filter(|_| self.stle_pairing) {
            self.report(
                Diagnostic::new(Code::NestedStl, site.span, "STL inside an STL block")
                    .with_label("this program closes blocks with STLE: close the open block first")
                    .with_related(open, "the open block starts here"),
            );
        }
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
        if self.emit(Op::Line(Line::StlBegin { block }), site).is_some() {
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
        let mut edges = Vec::new();
        for call in &calls {
            match self.parts.by_label.get(&call.label) {
                Some(&id) => {
                    if let Op::Call { subroutine, .. } = &mut self.instructions[call.instruction].op {
                        *subroutine = id;
                    }
                    edges.push(CallEdge {
                        caller: call.caller,
                        callee: id,
                        span: call.span,
                    });
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
        for (edge, problem) in call_problems(self.parts.subroutines.len(), &edges) {
            let span = edges[edge].span;
            let diagnostic = match problem {
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

/// A CALL from a program part (None: the main program) to a subroutine.
#[derive(Clone, Copy, Debug)]
struct CallEdge {
    caller: Option<usize>,
    callee: usize,
    span: Span,
}

/// Every CALL (by index into `edges`) that closes a cycle, and every CALL
/// that runs at a level deeper than `CALL_DEPTH` on the deepest path from
/// the main program, each once. Linear in parts and calls: a depth-first
/// search from the main program's calls (then from the other parts) marks
/// the calls to a part still on its path as cycles; without them the graph
/// is acyclic, and the search's finishing order, reversed, is a topological
/// order in which each part's level is final before its calls are used.
fn call_problems(subroutines: usize, edges: &[CallEdge]) -> Vec<(usize, CallProblem)> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Active,
        Done,
    }
    let mut outgoing: Vec<Vec<usize>> = vec![Vec::new(); subroutines];
    let mut from_main = Vec::new();
    for (index, edge) in edges.iter().enumerate() {
        match edge.caller {
            Some(caller) => outgoing[caller].push(index),
            None => from_main.push(index),
        }
    }
    let mut problems = Vec::new();
    let mut cyclic = vec![false; edges.len()];
    let mut marks = vec![Mark::New; subroutines];
    let mut finished = Vec::with_capacity(subroutines);
    let roots = from_main.iter().map(|&e| edges[e].callee).chain(0..subroutines);
    for root in roots {
        if marks[root] != Mark::New {
            continue;
        }
        marks[root] = Mark::Active;
        let mut stack = vec![(root, 0usize)];
        while let Some((part, next)) = stack.last_mut() {
            let part = *part;
            let Some(&edge) = outgoing[part].get(*next) else {
                marks[part] = Mark::Done;
                finished.push(part);
                stack.pop();
                continue;
            };
            *next += 1;
            let callee = edges[edge].callee;
            match marks[callee] {
                Mark::Active => {
                    cyclic[edge] = true;
                    problems.push((edge, CallProblem::Recursion));
                }
                Mark::New => {
                    marks[callee] = Mark::Active;
                    stack.push((callee, 0));
                }
                Mark::Done => {}
            }
        }
    }
    // Levels: the main program is 0, a part one more than the deepest CALL
    // to it (capped, so that only the first CALL too deep is reported).
    let mut level: Vec<Option<u32>> = vec![None; subroutines];
    fn raise(callee: usize, at: u32, level: &mut [Option<u32>]) {
        let at = at.min(CALL_DEPTH + 1);
        if level[callee].is_none_or(|known| known < at) {
            level[callee] = Some(at);
        }
    }
    for &edge in &from_main {
        raise(edges[edge].callee, 1, &mut level);
    }
    for &part in finished.iter().rev() {
        let Some(at) = level[part] else { continue };
        for &edge in &outgoing[part] {
            if !cyclic[edge] {
                raise(edges[edge].callee, at + 1, &mut level);
            }
        }
    }
    for (index, edge) in edges.iter().enumerate() {
        let caller_level = edge.caller.map_or(Some(0), |caller| level[caller]);
        if caller_level == Some(CALL_DEPTH) {
            problems.push((index, CallProblem::TooDeep));
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edges(list: &[(Option<usize>, usize)]) -> Vec<CallEdge> {
        list.iter()
            .map(|&(caller, callee)| CallEdge {
                caller,
                callee,
                span: Span::default(),
            })
            .collect()
    }

    #[test]
    fn recursion_and_depth() {
        // main -> 0 -> 1 -> 0: the cycle closes at the call in 1.
        let cycle = edges(&[(None, 0), (Some(0), 1), (Some(1), 0)]);
        assert_eq!(call_problems(2, &cycle), vec![(2, CallProblem::Recursion)]);
        // main -> 0 -> 1 -> 2 -> 3 -> 4 is five levels; 4 -> 5 is the sixth.
        let chain: Vec<_> = (0..6usize).map(|n| (n.checked_sub(1), n)).collect();
        assert_eq!(call_problems(6, &edges(&chain[..5])), vec![]);
        assert_eq!(call_problems(6, &edges(&chain)), vec![(5, CallProblem::TooDeep)]);
        // The deepest path decides: 0 is called from main and from 3.
        let deep = edges(&[
            (None, 1),
            (Some(1), 2),
            (Some(2), 3),
            (Some(3), 0),
            (Some(0), 4),
            (Some(4), 5),
        ]);
        assert_eq!(call_problems(6, &deep), vec![(5, CallProblem::TooDeep)]);
        assert_eq!(
            call_problems(1, &edges(&[(Some(0), 0)])),
            vec![(0, CallProblem::Recursion)]
        );
    }

    #[test]
    fn many_calls_are_checked_in_linear_time() {
        // 200,000 calls of one subroutine to itself and 4,096 chained
        // subroutines: quadratic work here would take minutes.
        let selfish = edges(&vec![(Some(0), 0); 200_000]);
        assert_eq!(call_problems(1, &selfish).len(), 200_000);
        let chain: Vec<_> = (0..4096usize).map(|n| (n.checked_sub(1), n)).collect();
        assert_eq!(call_problems(4096, &edges(&chain)), vec![(5, CallProblem::TooDeep)]);
    }
}
