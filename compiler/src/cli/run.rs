//! `ladderc run`: scans a program and prints watched devices after each scan.

use super::status;
use crate::diagnostics::Shown;
use crate::host_device::{parse_device, parse_value, HostDevice};
use crate::program::{BitRef, CheckedProgram, Op, Output};
use crate::scenario::{instantiate, Engine, EngineError, EngineKind};
use clap::{Args, ValueEnum};
use ladder_runtime::{BitArea, Device, Width};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct RunArgs {
    /// The program: IL or a GX Works2 CSV export (`-` reads standard input).
    program: PathBuf,
    /// Number of scans.
    #[arg(long, default_value_t = 1)]
    scans: u32,
    /// Milliseconds each scan reports as elapsed.
    #[arg(long, default_value_t = 10)]
    scan_ms: u32,
    /// Write a device before the first scan, e.g. `--set X0=1 --set D10=H7F`.
    #[arg(long = "set", value_name = "DEV=VALUE")]
    sets: Vec<String>,
    /// Devices to print, comma-separated (default: the Y coils the program drives).
    #[arg(long, value_delimiter = ',', value_name = "DEV,...")]
    watch: Vec<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// Engine that runs the program.
    #[arg(long, value_enum, default_value_t = RunEngine::Jit)]
    engine: RunEngine,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Format {
    Table,
    Csv,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum RunEngine {
    Interp,
    Jit,
}

pub fn run(args: &RunArgs, shown: Shown) -> u8 {
    let program = match super::compile_file(&args.program, shown) {
        Ok(program) => program,
        Err(code) => return code,
    };
    let watched = match watch_list(args, &program) {
        Ok(watched) => watched,
        Err(message) => {
            say_err!("error: {message}");
            return status::UNUSABLE;
        }
    };
    let kind = match args.engine {
        RunEngine::Interp => EngineKind::Interp,
        RunEngine::Jit => EngineKind::Jit,
    };
    let mut engine = match instantiate(kind, &program) {
        Ok(engine) => engine,
        Err(EngineError::Unavailable(reason)) => {
            say_err!("error: {reason}");
            return status::UNUSABLE;
        }
        Err(EngineError::Failed(reason)) => {
            say_err!("error: {reason}");
            return status::FAILED;
        }
    };
    for set in &args.sets {
        if let Err(message) = apply_set(engine.as_mut(), set) {
            say_err!("error: --set {set}: {message}");
            return status::UNUSABLE;
        }
    }
    match print_scans(engine.as_mut(), args, &watched) {
        Ok(()) => status::OK,
        Err(message) => {
            say_err!("error: {message}");
            status::FAILED
        }
    }
}

fn watch_list(args: &RunArgs, program: &CheckedProgram) -> Result<Vec<(String, HostDevice)>, String> {
    let names: Vec<String> = if args.watch.is_empty() {
        driven_outputs(program)
    } else {
        args.watch.clone()
    };
    names
        .into_iter()
        .map(|name| {
            let name = name.trim().to_string();
            let device = parse_device(&name, false).map_err(|e| format!("--watch: {e}"))?;
            Ok((name.to_ascii_uppercase(), device))
        })
        .collect()
}

/// The Y devices the program writes at fixed addresses, in order.
fn driven_outputs(program: &CheckedProgram) -> Vec<String> {
    let mut outputs: Vec<u32> = program
        .instructions
        .iter()
        .filter_map(|i| match &i.op {
            Op::Output(Output::Coil(bit) | Output::Set { target: bit, .. } | Output::Pulse { target: bit, .. }) => {
                Some(*bit)
            }
            _ => None,
        })
        .filter_map(|bit| match bit {
            BitRef::Device(BitArea::Y, address) if address.is_fixed() => Some(address.index),
            _ => None,
        })
        .collect();
    outputs.sort_unstable();
    outputs.dedup();
    outputs.into_iter().map(|n| BitArea::Y.device_name(n)).collect()
}

fn apply_set(engine: &mut dyn Engine, set: &str) -> Result<(), String> {
    let (name, value) = set.split_once('=').ok_or("expected DEV=VALUE")?;
    let name = name.trim();
    let device = parse_device(name, false)?;
    let value = parse_value(value.trim(), device).map_err(|error| match device.device {
        // `C0` names the contact; a count is the current value `CN0`.
        Device::Bit(area @ (BitArea::TimerContact | BitArea::CounterContact), n) => {
            let value_name = if area == BitArea::TimerContact { "TN" } else { "CN" };
            format!("{error}; {name} is the contact, its current value is {value_name}{n}")
        }
        Device::Bit(..) | Device::WordBit(..) | Device::Word(..) | Device::Digits(..) | Device::WideCounter(_) => error,
    })?;
    if let Device::Bit(area @ (BitArea::M | BitArea::Sm), n) = device.device {
        let rewritten = match area {
            BitArea::M => ladder_runtime::special::is_system_m(n),
            BitArea::Sm => ladder_runtime::special::is_system_sm(n),
            BitArea::X | BitArea::Y | BitArea::S | BitArea::TimerContact | BitArea::CounterContact => false,
        };
        if rewritten {
            say_err!("warning: {name} is set by the runtime at the start of every scan; this --set does not last");
        }
    }
    engine.write(device, value)
}

fn print_scans(engine: &mut dyn Engine, args: &RunArgs, watched: &[(String, HostDevice)]) -> Result<(), String> {
    let headers: Vec<&str> = std::iter::once("scan")
        .chain(watched.iter().map(|(n, _)| n.as_str()))
        .collect();
    let widths: Vec<usize> = headers
        .iter()
        .zip(std::iter::once(None).chain(watched.iter().map(|(_, d)| Some(*d))))
        .map(|(header, device)| {
            let value_width = match device.map(|d| (d.device, d.width)) {
                None => args.scans.to_string().len(),
                Some((Device::Bit(..) | Device::WordBit(..), _)) => 1,
                Some((_, Width::Single)) => 6,
                Some((_, Width::Double)) => 11,
            };
            header.len().max(value_width)
        })
        .collect();
    let line = |cells: Vec<String>| match args.format {
        Format::Csv => cells.join(","),
        Format::Table => cells
            .iter()
            .zip(&widths)
            .map(|(cell, width)| format!("{cell:>width$}"))
            .collect::<Vec<_>>()
            .join("  "),
    };
    say!("{}", line(headers.iter().map(|h| h.to_string()).collect()));
    for scan in 1..=args.scans {
        engine.scan(args.scan_ms)?;
        let mut cells = vec![scan.to_string()];
        for (_, device) in watched {
            cells.push(engine.read(*device)?.to_string());
        }
        say!("{}", line(cells));
    }
    Ok(())
}
