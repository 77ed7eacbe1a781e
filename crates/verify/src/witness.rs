//! Witnesses: a found violation (or a reached condition) as a scenario
//! file that drives the program from power-up through the found scans and
//! checks, with `expect` lines, the devices the property names. Before it
//! is reported it is replayed on the reference interpreter through the
//! scenario runner, as `ladderc test` would run it: a witness that does not
//! replay is a bug of the verifier, reported as such, never as a verdict.

use crate::expr::read;
use crate::model::{input_device, Choice, Model};
use crate::property::{Claim, PropertyFile, ScanTime};
use crate::search::{check, Step};
use ladder_engine::scenario::{parse_scenario, run_scenario, ProgramSource, RunOptions};
use ladder_engine::EngineKind;
use ladder_front::host_device::HostDevice;
use ladder_front::source::SourceFile;
use ladder_runtime::{Device, Memory, Width, WordArea};
use std::fmt::Write as _;
use std::path::Path;

/// The scans after which a witness checks the property's devices.
fn checked_scans(claim: &Claim, last: u32) -> Vec<u32> {
    let mut named = Vec::new();
    for expr in claim.exprs() {
        expr.devices(&mut named);
    }
    let uses_prev = named.iter().any(|&(_, prev)| prev);
    match claim {
        Claim::Respond { within, .. } => {
            let first = last.saturating_sub(*within).max(1);
            let first = if uses_prev {
                first.saturating_sub(1).max(1)
            } else {
                first
            };
            (first..=last).collect()
        }
        Claim::Never(_) | Claim::Always(_) | Claim::Reach(_) if uses_prev && last > 1 => vec![last - 1, last],
        Claim::Never(_) | Claim::Always(_) | Claim::Reach(_) => vec![last],
    }
}

/// A device's name as a scenario writes it, and whether `set32`/`expect32`
/// takes it.
pub(crate) fn name(device: HostDevice) -> (String, bool) {
    let double = device.width == Width::Double;
    match device.device {
        Device::Bit(area, n) => (area.device_name(n), false),
        // A scenario's `T0` and `C0` are the contacts: the values are TN, CN.
        Device::Word(WordArea::TimerValue, n) => (format!("TN{n}"), false),
        Device::Word(WordArea::CounterValue, n) => (format!("CN{n}"), false),
        Device::Word(area, n) => (area.device_name(n), double),
        Device::WordBit(area, n, bit) => (format!("{}.{bit:X}", area.device_name(n)), false),
        Device::Digits(area, n, digits) => (format!("K{digits}{}", area.device_name(n)), digits > 4),
        Device::WideCounter(n) => (format!("CN{n}"), false),
    }
}

fn value_text(mem: &Memory, device: HostDevice) -> String {
    read(mem, device).to_string()
}

/// The scenario text of a witness. The choices are simulated once more
/// from power-up and the property checked on every scan of that run: `Err`
/// when it does not break (or, for reach, hold) exactly at the last one,
/// which would be a bug of the search.
pub fn scenario(
    model: &Model,
    file: &PropertyFile,
    program_text: &str,
    claim: &Claim,
    title: &str,
    path: &[Choice],
) -> Result<String, String> {
    let mut out = String::new();
    let _ = writeln!(out, "# {title}");
    let _ = writeln!(
        out,
        "# Written by `ladderc verify`: it drives the program from power-up"
    );
    let _ = writeln!(out, "# and checks what the property names. Replay with `ladderc test`.");
    match &file.program {
        ProgramSource::File(path) => {
            let absolute = std::path::absolute(path).unwrap_or_else(|_| path.clone());
            let _ = writeln!(out, "program {}", absolute.display());
        }
        ProgramSource::Inline { .. } => {
            out.push_str("program <<\n");
            out.push_str(program_text);
            if !program_text.ends_with('\n') {
                out.push('\n');
            }
            out.push_str(">>\n");
        }
    }
    if let ScanTime::Fixed(ms) = file.scan_time {
        let _ = writeln!(out, "scan-ms {ms}");
    }
    for &(area, index, on) in &file.forces {
        let _ = writeln!(out, "force {} {}", area.device_name(index), u8::from(on));
    }
    for &(device, value) in &file.inits {
        let (text, double) = name(device);
        let _ = writeln!(out, "set{} {text} {value}", if double { "32" } else { "" });
    }
    let mut named = Vec::new();
    for expr in claim.exprs() {
        expr.devices(&mut named);
    }
    let mut devices: Vec<HostDevice> = Vec::new();
    for (device, _) in named {
        if !devices.contains(&device) {
            devices.push(device);
        }
    }
    let checked = checked_scans(claim, path.len() as u32);
    let mut mem = model.power_up.clone();
    let mut previous: Vec<i64> = model
        .inputs
        .iter()
        .map(|&input| {
            let (device, width) = input_device(input);
            read(&mem, HostDevice { device, width })
        })
        .collect();
    let mut elapsed = None;
    let mut before = mem.clone();
    let mut monitor = 0;
    let mut seen = false;
    for (scan, choice) in path.iter().enumerate() {
        let scan = scan as u32 + 1;
        if let ScanTime::Range(..) = file.scan_time {
            if elapsed != Some(choice.elapsed_ms) {
                let _ = writeln!(out, "scan-ms {}", choice.elapsed_ms);
                elapsed = Some(choice.elapsed_ms);
            }
        }
        for ((input, &value), old) in model.inputs.iter().zip(&choice.values).zip(previous.iter_mut()) {
            if value != *old {
                let (device, width) = input_device(*input);
                let (text, double) = name(HostDevice { device, width });
                let _ = writeln!(out, "set{} {text} {value}", if double { "32" } else { "" });
                *old = value;
            }
        }
        *before = *mem;
        model.apply_inputs(&mut mem, choice);
        model.scan(&mut mem, choice.elapsed_ms);
        let found = match check(claim, &before, &mem, monitor, &mut seen) {
            Step::Found => true,
            Step::Monitor(next) => {
                monitor = next;
                false
            }
        };
        if found != (scan as usize == path.len()) {
            return Err(format!(
                "the property {} at scan {scan} of the found run of {} scans",
                if found { "breaks" } else { "does not break" },
                path.len()
            ));
        }
        let _ = writeln!(out, "scan");
        if checked.contains(&scan) {
            for &device in &devices {
                let (text, double) = name(device);
                let _ = writeln!(
                    out,
                    "expect{} {text} {}",
                    if double { "32" } else { "" },
                    value_text(&mem, device)
                );
            }
        }
    }
    Ok(out)
}

/// Replays a witness on the reference interpreter, as `ladderc test`
/// runs it; `Err` says how it failed.
pub fn replay(scenario_path: &Path, text: &str) -> Result<(), String> {
    let scenario = parse_scenario(scenario_path, text).map_err(|e| format!("line {}: {}", e.line, e.message))?;
    let source = match &scenario.program {
        ProgramSource::File(path) => SourceFile::read(path).map_err(|e| e.to_string())?,
        ProgramSource::Inline { text, .. } => {
            SourceFile::new(format!("{} (program)", scenario_path.display()), text.clone())
        }
    };
    let outcome = run_scenario(&scenario, &source, &[EngineKind::Interp], RunOptions::default());
    match outcome.failures.first() {
        None => Ok(()),
        Some(failure) => Err(format!("line {}: {}", failure.line, failure.message)),
    }
}
