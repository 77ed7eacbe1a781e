//! Warnings: double coils outside STL blocks, writes to special relays
//! that the runtime rewrites every scan, and a program that drives nothing.

use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::program::{BitRef, Op, Output};
use crate::source::Span;
use ladder_runtime::special::{is_system_m, is_system_sm};
use ladder_runtime::BitArea;
use rustc_hash::FxHashMap;

/// What a coil drives, for spotting the same coil twice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum CoilKey {
    Bit(BitRef),
    Timer(u32),
    Counter(u32),
}

#[derive(Default)]
pub struct Lints {
    first_coil: FxHashMap<CoilKey, Span>,
    findings: Vec<Diagnostic>,
    /// The first instruction, and whether any writes a device.
    first: Option<Span>,
    drives: bool,
}

impl Lints {
    /// Looks at one emitted instruction.
    pub fn observe(&mut self, op: &Op, span: Span, in_stl_block: bool) {
        self.first.get_or_insert(span);
        let Op::Output(output) = op else {
            return;
        };
        self.drives = true;
        let coil = match output {
            Output::Coil(bit) => is_fixed(bit).then_some(CoilKey::Bit(*bit)),
            Output::Timer { timer, .. } => Some(CoilKey::Timer(*timer)),
            Output::Counter { counter, .. } => Some(CoilKey::Counter(*counter)),
            Output::Set { .. }
            | Output::Reset { .. }
            | Output::Pulse { .. }
            | Output::StateJump { .. }
            | Output::MasterControl { .. }
            | Output::App(_) => None,
        };
        if let (Some(key), false) = (coil, in_stl_block) {
            match self.first_coil.get(&key) {
                Some(&first) => self.findings.push(
                    Diagnostic::new(Code::DoubleCoil, span, "double coil")
                        .with_label("this coil is also driven elsewhere")
                        .with_related(first, "first driven here"),
                ),
                None => {
                    self.first_coil.insert(key, span);
                }
            }
        }
        for bit in output.written_bits() {
            let BitRef::Device(area, address) = bit else {
                continue;
            };
            let system = match area {
                BitArea::M => is_system_m(address.index),
                BitArea::Sm => is_system_sm(address.index),
                BitArea::X | BitArea::Y | BitArea::S | BitArea::TimerContact | BitArea::CounterContact => false,
            };
            if system && address.is_fixed() {
                self.findings.push(
                    Diagnostic::new(
                        Code::SystemRelayWrite,
                        span,
                        format!(
                            "{} is rewritten by the runtime every scan",
                            area.device_name(address.index)
                        ),
                    )
                    .with_label("this write lasts only until the next scan starts"),
                );
            }
        }
    }

    pub fn finish(&mut self, diagnostics: &mut Diagnostics) {
        // After an error the program is not complete anyway (E0017 says
        // the same of a rung without an output).
        if !self.drives && !diagnostics.iter().any(|d| d.is_error()) {
            let (span, message, label) = match self.first {
                None => (Span::new(0, 0), "the program is empty", "no instruction in the file"),
                Some(first) => (
                    first,
                    "the program drives nothing",
                    "no instruction of the program writes a device",
                ),
            };
            self.findings
                .push(Diagnostic::new(Code::DrivesNothing, span, message).with_label(label));
        }
        for finding in self.findings.drain(..) {
            diagnostics.push(finding);
        }
    }
}

fn is_fixed(bit: &BitRef) -> bool {
    match bit {
        BitRef::Device(_, address) | BitRef::WordBit(_, address, _) => address.is_fixed(),
    }
}
