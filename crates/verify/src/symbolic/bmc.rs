//! Bounded model checking and k-induction over the unrolled scan.
//!
//! BMC asks, for k = 1, 2, ..., whether some inputs make `bad` ON after
//! scan k from power-up; a model gives the inputs of every scan (the
//! witness). k-induction asks whether k good scans in a row, from any
//! state, can be followed by a bad one: if not, and BMC found nothing up
//! to k, the property holds. Without simple-path constraints it is sound
//! but need not succeed: IC3 (`pdr.rs`) proves what it cannot.

use super::sat::Unroller;
use super::system::System;
use std::time::Instant;

/// What an engine established.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Answer {
    Holds,
    /// Inputs per scan (frame): each model input's bits, then the
    /// elapsed time's, as unsigned numbers.
    Fails(Vec<Frame>),
    Unknown(String),
}

/// The choices of one scan of a counterexample.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub inputs: Vec<u64>,
    pub elapsed: Option<u64>,
}

/// BMC and k-induction, one depth at a time.
pub struct Bmc<'a> {
    system: &'a System,
    base: Unroller<'a>,
    step: Unroller<'a>,
    /// Frames of `step` already assumed good.
    good: usize,
}

impl<'a> Bmc<'a> {
    pub fn new(system: &'a System, deadline: Instant) -> Bmc<'a> {
        Bmc {
            system,
            base: Unroller::new(&system.aig, deadline, true),
            step: Unroller::new(&system.aig, deadline, false),
            good: 0,
        }
    }

    /// Can `bad` be ON after scan k (BMC), and, with `induction`, can k
    /// good scans from any state be followed by a bad one? `None`: no
    /// answer at this depth.
    pub fn step(&mut self, k: u32, induction: bool) -> Option<Answer> {
        let k = k as usize;
        let bad = self.base.lit(k, self.system.bad);
        match self.base.solve(&[bad]) {
            None => return Some(Answer::Unknown(timeout())),
            Some(true) => return Some(Answer::Fails(trace(&mut self.base, self.system, k))),
            // Never bad after scan k: a fact for the deeper questions.
            Some(false) => self.base.add_clause(&[!bad]),
        }
        if induction {
            while self.good < k {
                let good = !self.step.lit(self.good, self.system.bad);
                self.step.add_clause(&[good]);
                self.good += 1;
            }
            let bad_k = self.step.lit(k, self.system.bad);
            match self.step.solve(&[bad_k]) {
                None => return Some(Answer::Unknown(timeout())),
                Some(false) => return Some(Answer::Holds),
                Some(true) => {}
            }
        }
        None
    }
}

/// The inputs of a counterexample found by BMC in `k` scans.
pub fn trace(unroller: &mut Unroller, system: &System, k: usize) -> Vec<Frame> {
    // Encode every input bit before reading the model: a bit the query
    // did not reach may take either value (the witness replays it).
    let mut frames = Vec::with_capacity(k);
    for f in 0..k {
        for word in &system.inputs {
            for &bit in word {
                unroller.lit(f, bit);
            }
        }
        if let Some(word) = &system.elapsed {
            for &bit in word {
                unroller.lit(f, bit);
            }
        }
    }
    let bad = unroller.lit(k, system.bad);
    // Solving again with the same question keeps the model current.
    if unroller.solve(&[bad]) != Some(true) {
        return Vec::new();
    }
    for f in 0..k {
        let inputs = system.inputs.iter().map(|w| unroller.word_value(f, w)).collect();
        let elapsed = system.elapsed.as_ref().map(|w| unroller.word_value(f, w));
        frames.push(Frame { inputs, elapsed });
    }
    frames
}

/// Why an engine stopped without an answer at the `--timeout`.
pub fn timeout() -> String {
    "the time limit was reached".to_string()
}
