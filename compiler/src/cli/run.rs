//! `ladderc run`: scans a program and prints watched devices after each scan
//! — for a number of scans, or driven by a stimulus file's directives —
//! as a table, CSV or JSON, with operation errors as they occur, scan-time
//! statistics and a VCD waveform on request.

use super::{output, status};
use clap::{Args, ValueEnum};
use ladder_engine::scenario::{
    drive, instantiate, parse_stimulus, Directive, Engine, EngineError, EngineKind, Observer, Step, ERROR_CODE,
    ERROR_FLAG, ERROR_LINE,
};
use ladder_engine::watch::parse_watch;
use ladder_engine::waveform::{Recorder, Signal};
use ladder_front::diagnostics::Shown;
use ladder_front::host_device::{parse_device, parse_value, HostDevice};
use ladder_front::program::{BitRef, CheckedProgram, Op, Output};
use ladder_runtime::{BitArea, Device, Width};
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[derive(Args, Debug)]
pub struct RunArgs {
    /// The program: IL or a GX Works2 CSV export (`-` reads standard input).
    program: PathBuf,
    /// Number of scans (without --stimulus, whose scan directives decide).
    #[arg(long, default_value_t = 1, conflicts_with = "stimulus")]
    scans: u32,
    /// Milliseconds each scan reports as elapsed (a stimulus may change it).
    #[arg(long, default_value_t = 10)]
    scan_ms: u32,
    /// Write a device before the first scan, e.g. `--set X0=1 --set D10=H7F`.
    #[arg(long = "set", value_name = "DEV=VALUE")]
    sets: Vec<String>,
    /// Force X, Y, M, T or C before the first scan, e.g. `--force X0=1`.
    #[arg(long = "force", value_name = "DEV=0|1")]
    forces: Vec<String>,
    /// Drive the program with a scenario file's set/set32/force/unforce/
    /// scan-ms/scan/print directives; its expect lines are checked too.
    #[arg(long, value_name = "FILE")]
    stimulus: Option<PathBuf>,
    /// Devices to print, comma-separated: `Y0,D10`, ranges `Y0..Y7`,
    /// `D100..D109`, 32-bit values `D10:32` (default: the Y coils the
    /// program drives).
    #[arg(long, value_delimiter = ',', value_name = "DEV,...")]
    watch: Vec<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// How words are shown.
    #[arg(long, value_enum, default_value_t = Radix::Dec)]
    radix: Radix,
    /// Write the watched devices as a VCD waveform (1 ms timescale, the
    /// reported elapsed time as time axis), e.g. for GTKWave.
    #[arg(long, value_name = "OUT.vcd")]
    vcd: Option<PathBuf>,
    /// Print the minimum, average and maximum time of a scan at the end.
    #[arg(long)]
    stats: bool,
    /// Engine that runs the program.
    #[arg(long, value_enum, default_value_t = RunEngine::Jit)]
    engine: RunEngine,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Format {
    Table,
    Csv,
    /// One JSON object per scan, a line each.
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum RunEngine {
    Interp,
    Jit,
}

pub fn run(args: &RunArgs, shown: Shown) -> u8 {
    let (program, source) = match super::compile_file_with_source(&args.program, shown) {
        Ok(compiled) => compiled,
        Err(code) => return code,
    };
    let comments = ladder_front::gxdev::listing::device_comments(&source.text);
    let watched = match watch_list(args, &program) {
        Ok(watched) => watched,
        Err(message) => {
            say_err!("error: {message}");
            return status::UNUSABLE;
        }
    };
    let steps = match stimulus(args) {
        Ok(steps) => steps,
        Err(message) => {
            say_err!("{message}");
            return status::UNUSABLE;
        }
    };
    let mut inputs = vec![args.program.as_path()];
    inputs.extend(args.stimulus.as_deref());
    let vcd = match args.vcd.as_deref().map(|path| output::prepare(path, &inputs)) {
        None => None,
        Some(Ok(target)) => Some(target),
        Some(Err(error)) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    let kind = match args.engine {
        RunEngine::Interp => EngineKind::Interp,
        RunEngine::Jit => EngineKind::Jit,
    };
    let engine = match instantiate(kind, &program, &[]) {
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
    let mut engine = Timed {
        engine,
        times: ScanTimes::default(),
    };
    if let Err(message) = prepare(&mut engine, args) {
        say_err!("error: {message}");
        return status::UNUSABLE;
    }
    let comment_of = |signal: &Signal| {
        ladder_front::gxdev::listing::canonical_device(&signal.name).and_then(|name| comments.get(&name))
    };
    // The device comments above the table, one line each.
    if args.format == Format::Table {
        for signal in &watched {
            if let Some(comment) = comment_of(signal) {
                say!("# {}: {comment}", signal.name);
            }
        }
    }
    let mut printer = Printer::new(args, watched.clone());
    printer.place = source.listing_of.clone();
    if let Some(target) = &vcd {
        // A comment joins the signal's name where the name may hold it
        // (VCD names hold no blanks).
        let named = watched
            .iter()
            .map(|signal| match comment_of(signal) {
                Some(comment) => Signal {
                    name: format!("{}_{}", signal.name, vcd_word(comment)),
                    ..signal.clone()
                },
                None => signal.clone(),
            })
            .collect();
        printer.recorder = Some((Recorder::new(named), target.clone()));
    }
    let failures = drive(&steps, &mut engine, &mut printer);
    let mut code = status::OK;
    for (line, message) in &failures {
        let file = args
            .stimulus
            .as_ref()
            .map_or("--scans".into(), |p| p.display().to_string());
        say_err!("{file}:{line}: {message}");
        code = status::FAILED;
    }
    if let Some((recorder, target)) = &printer.recorder {
        let written = recorder
            .to_vcd()
            .and_then(|bytes| output::write_atomically(target, &bytes));
        if let Err(error) = written {
            say_err!("error: cannot write {}: {error}", target.display());
            code = status::FAILED;
        }
    }
    if args.stats {
        say_err!("{}", statistics(&engine.times));
    }
    code
}

/// A comment as part of a VCD name: blanks and the characters VCD viewers
/// take for hierarchy or bit ranges become `_`.
fn vcd_word(comment: &str) -> String {
    comment
        .chars()
        .map(|c| {
            if c.is_whitespace() || c.is_control() || "[]:.$".contains(c) {
                '_'
            } else {
                c
            }
        })
        .collect()
}

/// The watched devices.
fn watch_list(args: &RunArgs, program: &CheckedProgram) -> Result<Vec<Signal>, String> {
    let names: Vec<String> = if args.watch.is_empty() {
        driven_outputs(program)
    } else {
        args.watch.clone()
    };
    let mut watched = Vec::new();
    for name in names {
        watched.extend(parse_watch(&name).map_err(|e| format!("--watch: {e}"))?);
    }
    if watched.is_empty() {
        say_err!("note: the program drives no Y coil by number; name the devices to show with --watch");
    }
    Ok(watched)
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
            Op::Output(
                Output::Timer { .. }
                | Output::Counter { .. }
                | Output::Reset { .. }
                | Output::StateJump { .. }
                | Output::MasterControl { .. }
                | Output::App(_),
            )
            | Op::Load { .. }
            | Op::And(_)
            | Op::Or(_)
            | Op::Logic(_)
            | Op::Jump { .. }
            | Op::Call { .. }
            | Op::Line(_) => None,
        })
        .filter_map(|bit| match bit {
            BitRef::Device(BitArea::Y, address) if address.is_fixed() => Some(address.index),
            BitRef::Device(..) | BitRef::WordBit(..) => None,
        })
        .collect();
    outputs.sort_unstable();
    outputs.dedup();
    outputs.into_iter().map(|n| BitArea::Y.device_name(n)).collect()
}

/// The directives to run: a stimulus file's, or `--scans` scans of
/// `--scan-ms`.
fn stimulus(args: &RunArgs) -> Result<Vec<Step>, String> {
    let Some(path) = &args.stimulus else {
        return Ok(vec![
            Step {
                directive: Directive::ScanMs(args.scan_ms),
                line: 0,
            },
            Step {
                directive: Directive::Scan(args.scans),
                line: 0,
            },
        ]);
    };
    let bytes = ladder_front::source::read_bounded(path).map_err(|e| format!("error: {e}"))?;
    let text = String::from_utf8_lossy(&bytes);
    let mut steps = vec![Step {
        directive: Directive::ScanMs(args.scan_ms),
        line: 0,
    }];
    steps.extend(
        parse_stimulus(path, &text).map_err(|e| format!("{}:{}: error: {}", path.display(), e.line, e.message))?,
    );
    Ok(steps)
}

/// `--set` and `--force`, before the first scan. A device set twice is an
/// error: the later value would silently replace the earlier.
fn prepare(engine: &mut dyn Engine, args: &RunArgs) -> Result<(), String> {
    let mut seen: Vec<HostDevice> = Vec::new();
    for set in &args.sets {
        let device = apply_set(engine, set).map_err(|message| format!("--set {set}: {message}"))?;
        if seen.contains(&device) {
            return Err(format!("--set {set}: the device is already set by an earlier --set"));
        }
        seen.push(device);
    }
    for force in &args.forces {
        let (name, value) = force
            .split_once('=')
            .ok_or_else(|| format!("--force {force}: expected DEV=0 or DEV=1"))?;
        let device = parse_device(name.trim(), false).map_err(|e| format!("--force {force}: {e}"))?;
        let on = parse_value(value.trim(), device).map_err(|e| format!("--force {force}: {e}"))? != 0;
        let Device::Bit(
            area @ (BitArea::X | BitArea::Y | BitArea::M | BitArea::TimerContact | BitArea::CounterContact),
            index,
        ) = device.device
        else {
            return Err(format!("--force {force}: X, Y, M, T and C can be forced"));
        };
        if device.width != Width::Single || !device.is_bit() {
            return Err(format!("--force {force}: X, Y, M, T and C can be forced"));
        }
        engine
            .force(area, index, on)
            .map_err(|e| format!("--force {force}: {e}"))?;
    }
    Ok(())
}

fn apply_set(engine: &mut dyn Engine, set: &str) -> Result<HostDevice, String> {
    let (name, value) = set.split_once('=').ok_or("expected DEV=VALUE")?;
    let name = name.trim();
    let (bare, double) = match name.strip_suffix(":32") {
        Some(bare) => (bare, true),
        None => (name, false),
    };
    let device = parse_device(bare, double)?;
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
    engine.write(device, value)?;
    Ok(device)
}

/// An engine whose scans are timed.
struct Timed<'p> {
    engine: Box<dyn Engine + 'p>,
    times: ScanTimes,
}

/// Minimum, total and maximum of the scan times (constant memory however
/// long the run).
#[derive(Default)]
struct ScanTimes {
    count: u64,
    total: Duration,
    min: Option<Duration>,
    max: Duration,
}

impl Engine for Timed<'_> {
    fn read(&mut self, device: HostDevice) -> Result<i32, String> {
        self.engine.read(device)
    }
    fn write(&mut self, device: HostDevice, value: i32) -> Result<(), String> {
        self.engine.write(device, value)
    }
    fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), String> {
        self.engine.force(area, index, on)
    }
    fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), String> {
        self.engine.unforce(area, index)
    }
    fn pulse(&mut self, input: u32, count: u32) -> Result<(), String> {
        self.engine.pulse(input, count)
    }
    fn set_clock(&mut self, time: ladder_runtime::calendar::CalendarTime) -> Result<(), String> {
        self.engine.set_clock(time)
    }
    fn scan(&mut self, elapsed_ms: u32) -> Result<(), String> {
        let start = Instant::now();
        let result = self.engine.scan(elapsed_ms);
        let took = start.elapsed();
        let times = &mut self.times;
        times.count += 1;
        times.total += took;
        times.min = Some(times.min.map_or(took, |min| min.min(took)));
        times.max = times.max.max(took);
        result
    }
}

/// `--stats`: what one scan took (the whole scan, input refresh to output
/// image, as the engine runs it).
fn statistics(times: &ScanTimes) -> String {
    let Some(min) = times.min else {
        return "scan time: no scans".to_string();
    };
    let average = times.total.as_secs_f64() / times.count as f64;
    format!(
        "scan time over {} scans: min {:.3} µs, average {:.3} µs, max {:.3} µs",
        times.count,
        min.as_secs_f64() * 1e6,
        average * 1e6,
        times.max.as_secs_f64() * 1e6
    )
}

/// Prints the watched devices after every scan.
struct Printer {
    format: Format,
    radix: Radix,
    watched: Vec<Signal>,
    widths: Vec<usize>,
    /// The operation error last seen (code, line), to report new ones.
    error: Option<(u16, u16)>,
    recorder: Option<(Recorder, PathBuf)>,
    /// How an error's D8069 reads: `line 12`, or `MAIN.wpg step 125` for a
    /// GX Developer project (D8069 holds the step there).
    place: Option<String>,
}

impl Printer {
    fn new(args: &RunArgs, watched: Vec<Signal>) -> Printer {
        let scan_width = if args.stimulus.is_some() {
            6
        } else {
            args.scans.to_string().len().max(4)
        };
        let widths = std::iter::once(scan_width)
            .chain(watched.iter().map(|signal| {
                let value_width = match (signal.device.bits(), args.radix) {
                    _ if signal.real => 13,
                    (1, _) => 1,
                    (16, Radix::Dec) => 6,
                    (16, Radix::Hex) => 5,
                    (_, Radix::Dec) => 11,
                    (_, Radix::Hex) => 9,
                };
                signal.name.len().max(value_width)
            }))
            .collect();
        let printer = Printer {
            format: args.format,
            radix: args.radix,
            watched,
            widths,
            error: None,
            recorder: None,
            place: None,
        };
        let headers: Vec<String> = std::iter::once("scan".to_string())
            .chain(printer.watched.iter().map(|signal| signal.name.clone()))
            .collect();
        match printer.format {
            Format::Table | Format::Csv => say!("{}", printer.line(headers)),
            Format::Json => {}
        }
        printer
    }

    fn line(&self, cells: Vec<String>) -> String {
        match self.format {
            Format::Csv | Format::Json => cells.join(","),
            Format::Table => cells
                .iter()
                .zip(&self.widths)
                .map(|(cell, width)| format!("{cell:>width$}"))
                .collect::<Vec<_>>()
                .join("  "),
        }
    }

    /// A new operation error since the last scan: (code, line).
    fn new_error(&mut self, engine: &mut dyn Engine) -> Result<Option<(u16, u16)>, String> {
        let now = (engine.read(ERROR_FLAG)? != 0)
            .then(|| -> Result<(u16, u16), String> {
                Ok((engine.read(ERROR_CODE)? as u16, engine.read(ERROR_LINE)? as u16))
            })
            .transpose()?;
        let new = now.filter(|&error| self.error != Some(error));
        self.error = now;
        Ok(new)
    }
}

impl Observer for Printer {
    fn started(&mut self, engine: &mut dyn Engine) -> Result<(), String> {
        self.error = self.new_error(engine)?;
        match &mut self.recorder {
            Some((recorder, _)) => recorder.sample(engine, 0),
            None => Ok(()),
        }
    }

    fn scanned(&mut self, engine: &mut dyn Engine, scan: u64, time_ms: u64) -> Result<(), String> {
        let mut values = Vec::with_capacity(self.watched.len());
        for signal in &self.watched {
            values.push(engine.read(signal.device)?);
        }
        let error = self.new_error(engine)?;
        match self.format {
            Format::Table | Format::Csv => {
                let cells = std::iter::once(scan.to_string())
                    .chain(
                        values
                            .iter()
                            .zip(&self.watched)
                            .map(|(v, signal)| signal.show(*v, |v, d| show(v, d, self.radix))),
                    )
                    .collect();
                say!("{}", self.line(cells));
                if let Some((code, line)) = error {
                    match &self.place {
                        Some(file) => say_err!("scan {scan}: operation error {code:04X}H at {file} step {line}"),
                        None => say_err!("scan {scan}: operation error {code:04X}H at line {line}"),
                    }
                }
            }
            Format::Json => {
                let devices: serde_json::Map<String, serde_json::Value> = self
                    .watched
                    .iter()
                    .zip(&values)
                    .map(|(signal, value)| {
                        let shown = match (self.radix, signal.device.bits()) {
                            _ if signal.real => serde_json::Value::from(f64::from(f32::from_bits(*value as u32))),
                            (Radix::Dec, _) | (Radix::Hex, 1) => serde_json::Value::from(*value),
                            (Radix::Hex, _) => serde_json::Value::from(show(*value, signal.device, self.radix)),
                        };
                        (signal.name.clone(), shown)
                    })
                    .collect();
                let mut object = serde_json::json!({ "scan": scan, "time_ms": time_ms, "devices": devices });
                if let Some((code, line)) = error {
                    object["error"] = serde_json::json!({ "code": format!("{code:04X}H"), "line": line });
                }
                say!("{object}");
            }
        }
        match &mut self.recorder {
            Some((recorder, _)) => recorder.sample(engine, time_ms),
            None => Ok(()),
        }
    }

    fn printed(&mut self, line: u32, scan: u64, values: Vec<(String, HostDevice, i32)>) {
        let shown: Vec<String> = values
            .into_iter()
            .map(|(name, device, value)| format!("{name} = {}", show(value, device, self.radix)))
            .collect();
        say_err!("line {line} after scan {scan}: {}", shown.join(", "));
    }
}

/// How `run` shows words: signed decimal or unsigned hex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Radix {
    #[default]
    Dec,
    Hex,
}

/// A value as `run` shows it: bits 0/1; words signed in decimal, or
/// unsigned `H..` in hex.
pub fn show(value: i32, device: HostDevice, radix: Radix) -> String {
    match (device.bits(), radix) {
        (1, _) | (_, Radix::Dec) => value.to_string(),
        (16, Radix::Hex) => format!("H{:04X}", value as u16),
        (_, Radix::Hex) => format!("H{:08X}", value as u32),
    }
}
