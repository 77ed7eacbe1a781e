//! Rung structure: the checker's model of the logic stack. It knows where
//! rungs start and end, how many LD blocks wait for ANB/ORB and how deep the
//! MPS stack is, and reports what a vendor tool rejects.
//!
//! A rung starts at an LD-type instruction when no rung is open, or right
//! after an output instruction while no MPS branch is open. Anywhere else an
//! LD-type instruction starts a block that ANB/ORB must combine.

use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::source::Span;

/// Entries of the MPS stack.
pub const MPS_DEPTH: u32 = 11;

#[derive(Debug, Default)]
pub struct RungTracker {
    /// Span of the instruction that started the open rung.
    start: Option<Span>,
    outputs_seen: bool,
    last_was_output: bool,
    blocks: u32,
    branches: u32,
    /// The rung holds an unknown instruction: structural errors are skipped.
    poisoned: bool,
    /// The first contact (or MRD/MPP) after the rung's last output: it
    /// drives nothing unless another output follows.
    dangling: Option<Span>,
    /// The latest open MPS.
    last_push: Option<Span>,
    /// An LD-type instruction right after an output while a branch point
    /// was open: usually the start of a new rung with the MPP forgotten.
    block_after_branch: Option<Span>,
}

impl RungTracker {
    /// Would an LD-type instruction here start a new rung? (Decides the role
    /// of the alias contacts NOI/NCI/PTI/NTI/ATI/AFI.)
    pub fn at_rung_start(&self) -> bool {
        self.start.is_none() || self.last_was_output
    }

    /// No rung is open (at the start, after POP, NETWORK, STL, ...).
    pub fn is_closed(&self) -> bool {
        self.start.is_none()
    }

    /// Contacts wait for an output: the open rung is not finished.
    pub fn has_pending_contacts(&self) -> bool {
        self.start.is_some() && !self.poisoned && !(self.last_was_output && self.branches == 0)
    }

    /// An unknown instruction: its role is unknown, so the rung around it is
    /// not judged (no follow-up errors), but it is open afterwards.
    pub fn poison(&mut self, span: Span) {
        if self.start.is_none() {
            self.start = Some(span);
        }
        self.poisoned = true;
        self.last_was_output = false;
    }

    /// LD-type contact; returns true when it starts a new rung.
    pub fn load(&mut self, span: Span, diagnostics: &mut Diagnostics) -> bool {
        let new_rung = self.start.is_none() || (self.last_was_output && self.branches == 0);
        if new_rung {
            self.close(span, diagnostics);
            self.start = Some(span);
        } else {
            if self.last_was_output && self.branches > 0 && self.block_after_branch.is_none() {
                self.block_after_branch = Some(span);
            }
            self.blocks += 1;
            self.note_dangling(span);
        }
        self.last_was_output = false;
        new_rung
    }

    /// AND/OR-type contacts, INV, MEP/MEF: need an open rung.
    pub fn series(&mut self, span: Span, diagnostics: &mut Diagnostics) {
        // A contact already reported as having no rung is not also dangling.
        if self.require_rung(span, diagnostics) {
            self.note_dangling(span);
        }
        self.last_was_output = false;
    }

    /// After an output, a contact starts logic that needs another output.
    fn note_dangling(&mut self, span: Span) {
        if self.outputs_seen && self.dangling.is_none() {
            self.dangling = Some(span);
        }
    }

    /// ANB/ORB.
    pub fn combine(&mut self, span: Span, diagnostics: &mut Diagnostics) {
        if self.require_rung(span, diagnostics) {
            if self.blocks == 0 {
                diagnostics.push(
                    Diagnostic::new(Code::BlockUnderflow, span, "no block to combine")
                        .with_label("needs a block started by an LD-type instruction before it")
                        .with_related(self.start.unwrap_or(span), "the rung starts here"),
                );
            } else {
                self.blocks -= 1;
            }
        }
        self.last_was_output = false;
    }

    pub fn push(&mut self, span: Span, diagnostics: &mut Diagnostics) {
        if self.require_rung(span, diagnostics) {
            self.branches += 1;
            self.last_push = Some(span);
            if self.branches == MPS_DEPTH + 1 {
                diagnostics.push(
                    Diagnostic::new(Code::StackOverflow, span, "MPS nested deeper than 11")
                        .with_label("twelfth open MPS"),
                );
            }
        }
        self.last_was_output = false;
    }

    /// MRD (`pop` false) or MPP (`pop` true).
    pub fn read(&mut self, span: Span, pop: bool, diagnostics: &mut Diagnostics) {
        if self.branches == 0 {
            diagnostics.push(
                Diagnostic::new(
                    Code::StackUnderflow,
                    span,
                    format!("{} without MPS", if pop { "MPP" } else { "MRD" }),
                )
                .with_label("no open branch point"),
            );
        } else {
            if pop {
                self.branches -= 1;
            }
            self.note_dangling(span);
        }
        self.last_was_output = false;
    }

    /// An instruction that takes the rung result (OUT, SET, MOV, CJ, ...).
    pub fn output(&mut self, span: Span, diagnostics: &mut Diagnostics) {
        if self.start.is_none() {
            diagnostics.push(
                Diagnostic::new(Code::NoCondition, span, "output without a condition")
                    .with_label("no rung is open here")
                    .with_note("start the rung with a contact, e.g. `LD SM0` for always"),
            );
            return;
        }
        if self.blocks > 0 && !self.poisoned {
            diagnostics.push(self.pending_blocks(span, "this output"));
            self.blocks = 0;
            if self.block_after_branch.take().is_some() {
                // Reported as the missing MPP: not again at the rung's end.
                self.branches = 0;
            }
        }
        self.outputs_seen = true;
        self.last_was_output = true;
        self.dangling = None;
    }

    /// POP, NETWORK, STL, STLE, MCR, labels, END and the end of the source:
    /// the open rung, if any, must be complete.
    pub fn close(&mut self, span: Span, diagnostics: &mut Diagnostics) {
        let Some(start) = self.start.take() else {
            return;
        };
        if self.poisoned {
            // Nothing to judge.
        } else if self.blocks > 0 {
            diagnostics.push(
                self.pending_blocks(span, "the end of the rung")
                    .with_related(start, "the rung starts here"),
            );
        } else if self.branches > 0 {
            diagnostics.push(
                Diagnostic::new(Code::OpenBranch, span, "MPS without MPP at the end of the rung")
                    .with_label(format!(
                        "{} branch point{} still open",
                        self.branches,
                        if self.branches == 1 { "" } else { "s" }
                    ))
                    .with_related(start, "the rung starts here"),
            );
        } else if !self.outputs_seen {
            diagnostics.push(
                Diagnostic::new(Code::NoOutput, start, "rung without an output")
                    .with_label("these contacts drive nothing")
                    .with_related(span, "the rung ends here"),
            );
        } else if let Some(dangling) = self.dangling {
            diagnostics.push(
                Diagnostic::new(
                    Code::NoOutput,
                    dangling,
                    "contacts after the rung's last output drive nothing",
                )
                .with_label("no output follows this")
                .with_related(span, "the rung ends here"),
            );
        }
        *self = RungTracker::default();
    }

    fn pending_blocks(&self, span: Span, place: &str) -> Diagnostic {
        if let Some(block) = self.block_after_branch {
            // `MPS / AND X1 / OUT Y0 / LD X2 / OUT Y1`: the LD was meant to
            // start a new rung, but the branch point is still open.
            let diagnostic = Diagnostic::new(Code::OpenBranch, block, "MPS without MPP before a new rung")
                .with_label("this LD continues the rung because a branch point is still open")
                .with_note("end the branches with MPP before the next rung");
            return match self.last_push {
                Some(push) => diagnostic.with_related(push, "the open MPS"),
                None => diagnostic,
            };
        }
        Diagnostic::new(
            Code::PendingBlocks,
            span,
            format!(
                "{} block{} not combined before {place}",
                self.blocks,
                if self.blocks == 1 { "" } else { "s" }
            ),
        )
        .with_label("missing ANB or ORB")
    }

    /// Reports a contact or branch instruction with no open rung; opens one
    /// so the rest of the rung is checked without follow-up errors.
    fn require_rung(&mut self, span: Span, diagnostics: &mut Diagnostics) -> bool {
        if self.start.is_some() {
            return true;
        }
        diagnostics.push(
            Diagnostic::new(Code::NoRung, span, "no rung to continue")
                .with_label("needs an LD-type instruction before it"),
        );
        self.start = Some(span);
        false
    }
}
