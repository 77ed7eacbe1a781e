//! The SAT-based engines: the scan and one property bit-blasted into an
//! AIG from the IR (`encode.rs`, `system.rs`), then bounded model checking
//! and k-induction (`bmc.rs`) and IC3/PDR (`pdr.rs`) over it with batsat
//! (`sat.rs`); `aiger.rs` writes the same system for other model checkers.
//! `verify` turns to these when the explicit-state search cannot answer
//! (too many inputs or states); a counterexample they find becomes choices
//! of the model's inputs, replayed on the interpreter like any other.

pub mod aig;
pub mod aiger;
pub mod bmc;
pub mod encode;
pub mod pdr;
pub mod sat;
pub mod system;
pub mod words;

use crate::model::{Choice, Model};
use crate::property::{Input, ScanTime};
use bmc::{Answer, Frame};
use std::time::Instant;

/// What the symbolic engines established of a system: BMC and
/// k-induction first (short counterexamples, k-inductive properties), then
/// IC3 a frame at a time, with BMC going deeper between its frames (deep
/// counterexamples, which IC3 finds slowly).
pub fn check(system: &System, depth: u32, deadline: Instant) -> Decision {
    let decided = |answer: Answer, by: String| Decision { answer, by };
    if system.bad == aig::Lit::FALSE {
        return decided(Answer::Holds, "the encoding (the claim folds to true)".to_string());
    }
    let mut bmc = bmc::Bmc::new(system, deadline);
    let mut ic3 = pdr::Ic3::new(system, deadline);
    let mut k = 0u32;
    loop {
        if k >= depth {
            return decided(
                Answer::Unknown(format!("depth {depth} reached (--depth)")),
                format!("BMC to {k}"),
            );
        }
        k += 1;
        if let Some(answer) = bmc.step(k, k <= INDUCTION_DEPTH) {
            let by = match answer {
                Answer::Holds => format!("{k}-induction"),
                Answer::Fails(_) | Answer::Unknown(_) => format!("BMC at {k}"),
            };
            return decided(answer, by);
        }
        if k <= INDUCTION_DEPTH {
            continue;
        }
        // IC3's frames are dearer than BMC's: one for every few of them.
        if k.is_multiple_of(IC3_EVERY) {
            let stepped = ic3.step();
            if std::env::var_os("LADDER_VERIFY_TRACE").is_some() {
                eprintln!("ic3: bmc {k}, {}", ic3.describe());
            }
            let frames = ic3.frames();
            match stepped {
                None => {}
                Some(pdr::Found::Holds) => return decided(Answer::Holds, format!("IC3 in {frames} frames")),
                Some(pdr::Found::FailsAt(length)) => {
                    // The shortest: BMC from here up to IC3's length.
                    for deeper in k + 1..=length as u32 {
                        if let Some(answer) = bmc.step(deeper, false) {
                            return decided(answer, format!("IC3, then BMC at {deeper}"));
                        }
                    }
                    let why = format!("IC3 found a counterexample of {length} scans that BMC did not");
                    return decided(Answer::Unknown(why), "IC3".to_string());
                }
                Some(pdr::Found::Unknown(why)) => return decided(Answer::Unknown(why), format!("IC3 at {frames}")),
            }
        }
    }
}

/// An answer and the engine that gave it (for reports and benchmarks).
pub struct Decision {
    pub answer: Answer,
    pub by: String,
}

/// BMC frames between two IC3 frames.
const IC3_EVERY: u32 = 4;

/// How deep BMC and k-induction go before IC3 takes over.
const INDUCTION_DEPTH: u32 = 12;

pub use system::System;

/// The model's choices for a counterexample's frames.
pub fn choices(model: &Model, frames: &[Frame]) -> Vec<Choice> {
    frames
        .iter()
        .map(|frame| Choice {
            values: model
                .inputs
                .iter()
                .zip(&frame.inputs)
                .map(|(input, &bits)| match *input {
                    Input::Bit(..) => i64::from(bits != 0),
                    Input::Word { device, .. } => signed(bits, device.bits()),
                })
                .collect(),
            elapsed_ms: match model.scan_time {
                ScanTime::Fixed(ms) => ms,
                ScanTime::Range(low, _) => frame.elapsed.map_or(low, |e| e as u32),
            },
        })
        .collect()
}

fn signed(bits: u64, width: u32) -> i64 {
    let shift = 64 - width.clamp(1, 64);
    ((bits << shift) as i64) >> shift
}

#[cfg(test)]
mod tests;
