//! What a host does to a program between scans, for the differential test:
//! inputs, host writes, forces, and the elapsed time each scan reports —
//! including the extremes (0 ms, a whole `u32`). Every engine applies it
//! through the runtime's C API, the calls a firmware host makes, so the
//! engines differ only in the program code under test.

use ladder_runtime::capi::{self, LadderDevice};
use ladder_runtime::Memory;
use proptest::prelude::*;

/// One host call between scans.
#[derive(Clone, Debug)]
pub enum HostAction {
    /// `ladder_set_input(X, on)`.
    Input(u32, bool),
    /// `ladder_write(kind, number, value)`.
    Write(LadderDevice, u32, i32),
    /// `ladder_write_word_bit(D, number, bit, on)`: one bit of a word,
    /// often of a negative one.
    WriteWordBit(u32, u32, bool),
    /// `ladder_force(kind, number, on)`.
    Force(LadderDevice, u32, bool),
    /// `ladder_unforce(kind, number)`.
    Unforce(LadderDevice, u32),
    /// `ladder_add_pulses(x, count)`: edges for the high-speed counters.
    Pulses(u32, u32),
}

/// The host's calls before one scan, and the time that scan reports.
#[derive(Clone, Debug)]
pub struct Step {
    pub actions: Vec<HostAction>,
    pub elapsed_ms: u32,
}

fn written_device() -> impl Strategy<Value = (LadderDevice, u32, i32)> {
    let small = -3i32..12;
    prop_oneof![
        3 => (0u32..4, prop_oneof![small.clone(), Just(-1), Just(9000), Just(32767), Just(-32768)])
            .prop_map(|(n, v)| (LadderDevice::D, n, v)),
        1 => (prop_oneof![Just(10u32), Just(20), Just(8510)], small.clone()).prop_map(|(n, v)| (LadderDevice::D, n, v)),
        2 => (0u32..10, 0i32..2).prop_map(|(n, v)| (LadderDevice::M, n, v)),
        1 => (0u32..8, 0i32..2).prop_map(|(n, v)| (LadderDevice::Y, n, v)),
        1 => (1u32..4, 0i32..2).prop_map(|(n, v)| (LadderDevice::S, n, v)),
        1 => (prop_oneof![0u32..4, Just(200), Just(246), Just(250)], prop_oneof![0i32..6, Just(32767)])
            .prop_map(|(n, v)| (LadderDevice::Tn, n, v)),
        1 => (0u32..3, prop_oneof![0i32..4, Just(32767)]).prop_map(|(n, v)| (LadderDevice::Cn, n, v)),
        1 => (200u32..202, prop_oneof![-2i32..3, Just(i32::MAX), Just(i32::MIN)])
            .prop_map(|(n, v)| (LadderDevice::Cn, n, v)),
        1 => (prop_oneof![0u32..4, Just(200), Just(246)], 0i32..2).prop_map(|(n, v)| (LadderDevice::Ts, n, v)),
        1 => (0u32..3, 0i32..2).prop_map(|(n, v)| (LadderDevice::Cs, n, v)),
        1 => (prop_oneof![Just(LadderDevice::Z), Just(LadderDevice::V)], 0u32..2, prop_oneof![-3i32..12, Just(300), Just(-300)])
            .prop_map(|(kind, n, v)| (kind, n, v)),
    ]
}

fn forced_device() -> impl Strategy<Value = (LadderDevice, u32)> {
    prop_oneof![
        (Just(LadderDevice::X), 0u32..8),
        (Just(LadderDevice::Y), 0u32..8),
        (Just(LadderDevice::M), 0u32..10),
        (Just(LadderDevice::Ts), prop_oneof![0u32..4, Just(200), Just(246)]),
        (Just(LadderDevice::Cs), prop_oneof![0u32..3, Just(200)]),
    ]
}

fn action() -> impl Strategy<Value = HostAction> {
    prop_oneof![
        6 => (0u32..8, any::<bool>()).prop_map(|(x, on)| HostAction::Input(x, on)),
        3 => written_device().prop_map(|(kind, n, v)| HostAction::Write(kind, n, v)),
        1 => (0u32..4, prop_oneof![Just(15u32), Just(0), 1u32..15], any::<bool>())
            .prop_map(|(n, bit, on)| HostAction::WriteWordBit(n, bit, on)),
        1 => (forced_device(), any::<bool>()).prop_map(|((kind, n), on)| HostAction::Force(kind, n, on)),
        1 => forced_device().prop_map(|(kind, n)| HostAction::Unforce(kind, n)),
        2 => (0u32..8, prop_oneof![0u32..4, Just(1000), Just(u32::MAX)]).prop_map(|(x, n)| HostAction::Pulses(x, n)),
    ]
}

fn elapsed_ms() -> impl Strategy<Value = u32> {
    prop_oneof![
        6 => Just(10u32),
        4 => Just(100u32),
        6 => 0u32..250,
        1 => Just(0u32),
        1 => Just(u32::MAX),
        1 => prop_oneof![Just(65_535u32), Just(1 << 31), Just(i32::MAX as u32), Just(3_600_000)],
        1 => any::<u32>(),
    ]
}

pub fn step() -> impl Strategy<Value = Step> {
    (proptest::collection::vec(action(), 0..5), elapsed_ms())
        .prop_map(|(actions, elapsed_ms)| Step { actions, elapsed_ms })
}

/// Makes the host calls of `step` on `mem`.
pub fn apply(mem: &mut Memory, step: &Step) {
    let image: *mut capi::LadderMemory = (mem as *mut Memory).cast();
    for action in &step.actions {
        // SAFETY: `image` is a whole, exclusively borrowed image. The
        // statuses do not depend on the program, so they are not compared.
        unsafe {
            match *action {
                HostAction::Input(x, on) => capi::ladder_set_input(image, x, on),
                HostAction::Write(kind, n, v) => capi::ladder_write(image, kind as u32, n, v),
                HostAction::WriteWordBit(n, bit, on) => {
                    capi::ladder_write_word_bit(image, LadderDevice::D as u32, n, bit, i32::from(on))
                }
                HostAction::Force(kind, n, on) => capi::ladder_force(image, kind as u32, n, on),
                HostAction::Unforce(kind, n) => capi::ladder_unforce(image, kind as u32, n),
                HostAction::Pulses(x, n) => capi::ladder_add_pulses(image, x, n),
            };
        }
    }
}

/// The same calls as commands of the differential C driver (one per line).
pub fn driver_commands(step: &Step, out: &mut String) {
    use std::fmt::Write as _;
    for action in &step.actions {
        let _ = match *action {
            HostAction::Input(x, on) => writeln!(out, "I {x} {}", u8::from(on)),
            HostAction::Write(kind, n, v) => writeln!(out, "W {} {n} {v}", kind as u32),
            HostAction::WriteWordBit(n, bit, on) => {
                writeln!(out, "B {} {n} {bit} {}", LadderDevice::D as u32, u8::from(on))
            }
            HostAction::Force(kind, n, on) => writeln!(out, "F {} {n} {}", kind as u32, u8::from(on)),
            HostAction::Unforce(kind, n) => writeln!(out, "U {} {n}", kind as u32),
            HostAction::Pulses(x, n) => writeln!(out, "H {x} {n}"),
        };
    }
    let _ = writeln!(out, "S {}", step.elapsed_ms);
}

/// A device as a scenario names it (`X17`, `TN0`, `CN200`).
pub fn scenario_device(kind: LadderDevice, number: u32) -> String {
    let prefix = match kind {
        LadderDevice::X => return format!("X{number:o}"),
        LadderDevice::Y => return format!("Y{number:o}"),
        LadderDevice::M => "M",
        LadderDevice::S => "S",
        LadderDevice::Sm => "SM",
        LadderDevice::Ts => "TS",
        LadderDevice::Cs => "CS",
        LadderDevice::D => "D",
        LadderDevice::Sd => "SD",
        LadderDevice::R => "R",
        LadderDevice::Tn => "TN",
        LadderDevice::Cn => "CN",
        LadderDevice::V => "V",
        LadderDevice::Z => "Z",
        LadderDevice::U => return format!("U{}\\G{}", number / 32767, number % 32767),
    };
    format!("{prefix}{number}")
}

/// The scenario directives for `step`: host calls, the time, one scan.
/// (`ladder_write` of X and `set X` both set the input image.)
pub fn scenario_directives(step: &Step, scan_ms: &mut u32, out: &mut String) {
    use std::fmt::Write as _;
    for action in &step.actions {
        let _ = match *action {
            HostAction::Input(x, on) => writeln!(out, "set X{x:o} {}", u8::from(on)),
            HostAction::Write(kind, n, v) => writeln!(out, "set {} {v}", scenario_device(kind, n)),
            HostAction::WriteWordBit(n, bit, on) => writeln!(out, "set D{n}.{bit:X} {}", u8::from(on)),
            HostAction::Force(kind, n, on) => writeln!(out, "force {} {}", scenario_device(kind, n), u8::from(on)),
            HostAction::Unforce(kind, n) => writeln!(out, "unforce {}", scenario_device(kind, n)),
            HostAction::Pulses(x, n) => writeln!(out, "pulse X{x:o} {n}"),
        };
    }
    if step.elapsed_ms != *scan_ms {
        *scan_ms = step.elapsed_ms;
        let _ = writeln!(out, "scan-ms {scan_ms}");
    }
    let _ = writeln!(out, "scan");
}
