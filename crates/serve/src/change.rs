//! Online change: a new program replaces the running one between two scans,
//! keeping the device image — devices, forces, timers and counters, STL
//! states and their blocks' flags (by state number). The previous-scan
//! values of edge instructions (LDP, PLS, MOVP, ...) are carried by
//! instruction identity: an edge instruction of the new program takes the
//! value of the old one with the same text (mnemonic and operands, the n-th
//! of equal texts); new edge instructions start OFF. Instance states
//! (pulse outputs, high-speed compares, HOUR, PID, ...) move the same way;
//! an output driven by an instruction that is gone is released.
//!
//! A new program comes as text (an upload over HTTP, `--watch-file`):
//! `accept` compiles it off the scan thread and refuses one that does not
//! compile or drives nothing, so the running program goes on.

use ladder_front::diagnostics::{render_all, Code, Diagnostic, Shown};
use ladder_front::isa::app::Keeps;
use ladder_front::program::{CheckedProgram, Contact, Logic, Op, Output};
use ladder_front::source::SourceFile;
use ladder_runtime::Memory;
use std::collections::HashMap;

/// A compiled program with what online change needs to know of it.
pub struct Loaded {
    pub program: CheckedProgram,
    /// Each edge slot and the identity of its instruction.
    pub slots: Vec<(u32, String)>,
    /// Each instance state and the identity of its instruction.
    pub instances: Vec<(u32, String)>,
    /// The program already compiled to native code, off the scan thread.
    pub native: Option<ladder_codegen::JitProgram>,
    /// Its drawing for the monitor page.
    pub view: std::sync::Arc<super::view::LadderView>,
    /// Which program it is (`GET /api/program`, the log of online changes).
    pub identity: std::sync::Arc<Identity>,
}

/// A program's identity: its file name, the SHA-256 of its text, the text,
/// and when it was loaded.
pub struct Identity {
    pub name: String,
    pub sha256: String,
    pub text: String,
    /// Seconds since 1970-01-01 UTC.
    pub loaded_at: u64,
}

impl Identity {
    pub fn of(source: &SourceFile) -> Identity {
        use sha2::Digest as _;
        let digest = sha2::Sha256::digest(source.text.as_bytes());
        Identity {
            name: source.name.clone(),
            sha256: digest.iter().map(|b| format!("{b:02x}")).collect(),
            text: source.text.clone(),
            loaded_at: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
        }
    }

    /// `2026-11-23 21:40:05 UTC`.
    pub fn loaded_at_text(&self) -> String {
        // The runtime's calendar counts from 1980-01-01.
        const FROM_1970_TO_1980: u64 = 315_532_800;
        let seconds = self
            .loaded_at
            .saturating_sub(FROM_1970_TO_1980)
            .min(u64::from(u32::MAX)) as u32;
        let t = ladder_runtime::calendar::CalendarTime::from_seconds(seconds);
        format!(
            "{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC",
            t.year, t.month, t.day, t.hour, t.minute, t.second
        )
    }
}

impl Loaded {
    pub fn new(program: CheckedProgram, source: &SourceFile) -> Loaded {
        let mut seen: HashMap<String, u32> = HashMap::new();
        let mut slots = Vec::new();
        let mut instances = Vec::new();
        for instruction in &program.instructions {
            let instance = if let Op::Output(Output::App(app)) = &instruction.op {
                app.job.filter(|_| app.args.op().spec().keeps == Keeps::State)
            } else {
                None
            };
            let slot = edge_slot(&instruction.op);
            if slot.is_none() && instance.is_none() {
                continue;
            }
            let text: String = source
                .slice(instruction.span)
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
                .to_ascii_uppercase();
            let nth = seen.entry(text.clone()).or_default();
            *nth += 1;
            let key = format!("{text}#{nth}");
            if let Some(slot) = slot {
                slots.push((slot, key.clone()));
            }
            if let Some(instance) = instance {
                instances.push((instance, key));
            }
        }
        Loaded {
            view: std::sync::Arc::new(super::view::LadderView::new(&program, source)),
            identity: std::sync::Arc::new(Identity::of(source)),
            program,
            slots,
            instances,
            native: None,
        }
    }

    /// Compiles the native code now (in the caller's thread), so that the
    /// swap between two scans costs no compile time.
    /// Does nothing for the interpreter (`native` false).
    pub fn precompile(mut self, native: bool) -> Result<Loaded, String> {
        if native {
            self.native = Some(
                ladder_engine::pipeline::Lowered::new(&self.program)
                    .jit()
                    .map_err(|e| e.to_string())?,
            );
        }
        Ok(self)
    }
}

/// Why a new program is refused; the running one goes on.
#[derive(Debug)]
pub enum Refusal {
    /// It does not compile: its diagnostics, rendered.
    DoesNotCompile(String),
    /// It drives nothing (W0004) and was not said to be meant: its
    /// diagnostics, rendered.
    DrivesNothing(String),
    /// The native code generator failed on it: why.
    Native(String),
}

/// A new program's text for online change: compiled (in the caller's
/// thread, not the scan thread), refused when it does not compile or, unless
/// `allow_empty`, drives nothing, and compiled to native code when `native`
/// (see `Loaded::precompile`). `name` is the name its diagnostics give.
pub fn accept(name: impl Into<String>, bytes: &[u8], allow_empty: bool, native: bool) -> Result<Loaded, Refusal> {
    // Decoded as the command line reads files (a byte-order mark, UTF-16).
    accept_source(&SourceFile::from_bytes(name, bytes), allow_empty, native)
}

/// `accept` for a source file already read (a GX Developer project's
/// listing, which keeps the steps of its instructions, or the one error
/// that it cannot be decoded).
pub fn accept_source(source: &SourceFile, allow_empty: bool, native: bool) -> Result<Loaded, Refusal> {
    let (program, diagnostics) = ladder_front::check::compile_source(source);
    let shown = || render_all(source, &diagnostics, Shown::default());
    match program {
        Some(_) if !allow_empty && drives_nothing(&diagnostics) => Err(Refusal::DrivesNothing(shown())),
        Some(program) => Loaded::new(program, source).precompile(native).map_err(Refusal::Native),
        None => Err(Refusal::DoesNotCompile(shown())),
    }
}

/// An empty program, or one that writes no device (W0004): refused for
/// online change unless the upload says it is meant.
fn drives_nothing(diagnostics: &[Diagnostic]) -> bool {
    diagnostics.iter().any(|d| d.code == Code::DrivesNothing)
}

/// The previous-scan slot an instruction owns, if any.
fn edge_slot(op: &Op) -> Option<u32> {
    match op {
        Op::Load { contact, .. } | Op::And(contact) | Op::Or(contact) => match contact {
            Contact::Edge { slot, .. } => Some(*slot),
            Contact::Level { .. } | Contact::Constant(_) | Contact::Compare { .. } => None,
        },
        Op::Logic(Logic::ResultEdge { slot, .. }) => Some(*slot),
        Op::Output(Output::Pulse { slot, .. }) => Some(*slot),
        Op::Output(Output::App(app)) => app.pulse_slot,
        Op::Call { slot, .. } => *slot,
        Op::Output(
            Output::Coil(_)
            | Output::Timer { .. }
            | Output::Counter { .. }
            | Output::Set { .. }
            | Output::Reset { .. }
            | Output::StateJump { .. }
            | Output::MasterControl { .. },
        )
        | Op::Logic(
            Logic::AndBlock | Logic::OrBlock | Logic::BranchPush | Logic::BranchRead | Logic::BranchPop | Logic::Invert,
        )
        | Op::Jump { .. }
        | Op::Line(_) => None,
    }
}

/// The image the new program starts from: the old one, with the edge
/// slots moved to where the same instructions are now.
pub fn carry_over(image: &Memory, old: &Loaded, new: &Loaded) -> Box<Memory> {
    let mut next = Box::new(*image);
    next.edge_slot.fill(0);
    let old_slots: HashMap<&str, u32> = old.slots.iter().map(|(slot, key)| (key.as_str(), *slot)).collect();
    for (slot, key) in &new.slots {
        if let Some(&before) = old_slots.get(key.as_str()) {
            next.edge_slot[*slot as usize] = image.edge_slot[before as usize];
        }
    }
    // Sort jobs belong to instructions that may be gone: they start again.
    next.sort_state.fill(0);
    next.sort_scans.fill(0);
    // Instance states follow their instructions; a pulse output keeps its
    // driver only if the driver is still there.
    next.instance.fill(Default::default());
    let old_instances: HashMap<&str, u32> = old.instances.iter().map(|(i, key)| (key.as_str(), *i)).collect();
    let mut moved: HashMap<u32, u32> = HashMap::new();
    for (instance, key) in &new.instances {
        if let Some(&before) = old_instances.get(key.as_str()) {
            next.instance[*instance as usize] = image.instance[before as usize];
            moved.insert(before + 1, instance + 1);
        }
    }
    for (output, owner) in next.pulse_owner.iter_mut().enumerate() {
        if *owner != 0 {
            *owner = moved.get(owner).copied().unwrap_or(0);
            if *owner == 0 {
                next.m[(ladder_runtime::pulse::M_BUSY + 10 * output as u32) as usize] = 0;
                next.pulse_remainder[output] = 0;
            }
        }
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(text: &str) -> Loaded {
        let source = SourceFile::new("t.il", text);
        let (program, diagnostics) = ladder_front::check::compile_source(&source);
        Loaded::new(program.unwrap_or_else(|| panic!("{diagnostics:?}")), &source)
    }

    #[test]
    fn edge_values_follow_their_instructions() {
        let old = load("LDP X0\nOUT Y0\nLDP X1\nOUT Y1\n");
        let new = load("LDP X5\nOUT Y5\nLDP  x1\nOUT Y1\nLDP X0\nOUT Y0\n");
        let mut image = Memory::new_boxed();
        image.edge_slot[0] = 1; // LDP X0
        image.edge_slot[1] = 0; // LDP X1
        image.d[3] = 77;
        let next = carry_over(&image, &old, &new);
        assert_eq!(&next.edge_slot[..3], [0, 0, 1], "X5 new, X1 kept, X0 moved to slot 2");
        assert_eq!(next.d[3], 77, "devices kept");
    }

    #[test]
    fn pulse_outputs_follow_their_instructions_or_stop() {
        let old = load("LD X0\nDRVI K1000 K100 Y0 Y4\nLD X1\nPLSY K10 K0 Y1\n");
        let new = load("LD X1\nPLSY K10 K0 Y1\n");
        let mut image = Memory::new_boxed();
        image.instance[0].phase = 1; // DRVI running on Y0
        image.instance[1].phase = 1; // PLSY running on Y1
        image.pulse_owner = [1, 2, 0, 0];
        image.m[8340] = 1;
        image.m[8350] = 1;
        let next = carry_over(&image, &old, &new);
        assert_eq!(next.pulse_owner, [0, 1, 0, 0], "DRVI gone, PLSY is instance 0 now");
        assert_eq!((next.m[8340], next.m[8350]), (0, 1));
        assert_eq!(next.instance[0].phase, 1);
    }
}
