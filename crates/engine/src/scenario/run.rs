//! Running one scenario: compile its program once, then drive each engine
//! through the directives and compare.

use super::drive::{drive, Observer};
use super::parse::{Directive, ProgramSource, Scenario};
use crate::waveform::{Recorder, Signal};
use crate::{instantiate, instantiate_lowered, Engine, EngineError, EngineKind};
use ladder_front::check::compile_source;
use ladder_front::diagnostics::render_all;
use ladder_front::host_device::{format_value, HostDevice};
use ladder_front::program::{BitRef, CheckedProgram, Op, Output};
use ladder_front::source::SourceFile;
use ladder_runtime::{Device, Width};
use std::path::{Path, PathBuf};

/// Which runs keep their waveform.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Waveforms {
    #[default]
    None,
    /// Runs with a failed expectation.
    Failing,
    All,
}

/// How scenarios are run.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunOptions {
    pub waveforms: Waveforms,
    /// Keep the image at each failed expectation (for the HTML report).
    pub snapshots: bool,
}

/// The most images one engine run keeps for the report.
const MOST_SNAPSHOTS: usize = 8;

/// The image as an engine left it when an expectation failed.
#[derive(Clone)]
pub struct Snapshot {
    pub line: u32,
    /// After this many scans, at this time.
    pub scan: u64,
    pub time_ms: u64,
    pub message: String,
    pub image: Box<ladder_runtime::Memory>,
}

impl std::fmt::Debug for Snapshot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Snapshot")
            .field("line", &self.line)
            .field("scan", &self.scan)
            .field("time_ms", &self.time_ms)
            .field("message", &self.message)
            .finish_non_exhaustive()
    }
}

/// What one engine did with a scenario.
#[derive(Clone, Debug)]
pub struct EngineRun {
    pub kind: EngineKind,
    /// The output of `print` directives, a line each.
    pub printed: Vec<String>,
    /// The waveform, when the options keep it for this run.
    pub waveform: Option<Recorder>,
    /// The image at each failed expectation, when the options ask for them.
    pub snapshots: Vec<Snapshot>,
}

/// One failed expectation (or a scenario that could not run).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    pub path: PathBuf,
    /// Line of the scenario file.
    pub line: u32,
    /// Engine name, or "check" for compile-time expectations.
    pub engine: String,
    pub message: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}: [{}] {}",
            self.path.display(),
            self.line,
            self.engine,
            self.message
        )
    }
}

#[derive(Clone, Debug, Default)]
pub struct ScenarioOutcome {
    pub failures: Vec<Failure>,
    /// Engines that could not run, with the reason.
    pub skipped: Vec<(EngineKind, String)>,
    /// Engines that ran the scenario.
    pub ran: Vec<EngineKind>,
    /// Rendered diagnostics worth showing (a program that did not compile).
    pub details: String,
    /// Each engine that ran, in order.
    pub engines: Vec<EngineRun>,
}

/// Every `*.scn` under `path` (recursively, sorted), or `path` itself.
pub fn collect_files(path: &Path) -> std::io::Result<Vec<PathBuf>> {
    if !path.is_dir() {
        std::fs::metadata(path)?;
        return Ok(vec![path.to_path_buf()]);
    }
    let mut files = Vec::new();
    let mut pending = vec![path.to_path_buf()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir)? {
            let entry_path = entry?.path();
            if entry_path.is_dir() {
                pending.push(entry_path);
            } else if entry_path.extension().is_some_and(|e| e == "scn") {
                files.push(entry_path);
            }
        }
    }
    files.sort();
    Ok(files)
}

/// Loads the scenario's program. `Err` means it cannot be read (exit 2).
pub fn load_program(scenario: &Scenario) -> Result<SourceFile, String> {
    match &scenario.program {
        ProgramSource::File(path) => SourceFile::read(path).map_err(|e| e.to_string()),
        ProgramSource::Inline { text, .. } => Ok(SourceFile::new(
            format!("{} (program)", scenario.path.display()),
            text.clone(),
        )),
    }
}

/// The program's diagnostics as text; for an inline program each also says
/// which line of the scenario file it is on.
fn render_program_diagnostics(
    scenario: &Scenario,
    source: &SourceFile,
    diagnostics: &[ladder_front::diagnostics::Diagnostic],
) -> String {
    let shown = ladder_front::diagnostics::Shown::default();
    let ProgramSource::Inline { first_line, .. } = &scenario.program else {
        return render_all(source, diagnostics, shown);
    };
    let located: Vec<_> = diagnostics
        .iter()
        .cloned()
        .map(|diagnostic| {
            let line = first_line + source.line_of(diagnostic.span.start) - 1;
            let place = format!("line {line} of {}", scenario.path.display());
            diagnostic.with_note(place)
        })
        .collect();
    render_all(source, &located, shown)
}

/// Runs a scenario on `engines`; `source` is its loaded program.
pub fn run_scenario(
    scenario: &Scenario,
    source: &SourceFile,
    engines: &[EngineKind],
    options: RunOptions,
) -> ScenarioOutcome {
    let mut outcome = ScenarioOutcome::default();
    let (program, diagnostics) = compile_source(source);
    let fail = |outcome: &mut ScenarioOutcome, line: u32, engine: &str, message: String| {
        outcome.failures.push(Failure {
            path: scenario.path.clone(),
            line,
            engine: engine.to_string(),
            message,
        });
    };
    let first_error = diagnostics.iter().find(|d| d.is_error());
    if let Some((expected_line, expected_code, at)) = scenario.expected_reject() {
        match first_error {
            None => fail(
                &mut outcome,
                at,
                "check",
                format!("expected the program to be rejected at line {expected_line}, but it compiled"),
            ),
            Some(error) => {
                let line = source.line_of(error.span.start);
                let code_ok = expected_code.is_none_or(|code| code == error.code);
                if line != expected_line || !code_ok {
                    let expected = match expected_code {
                        Some(code) => format!("{code} at program line {expected_line}"),
                        None => format!("program line {expected_line}"),
                    };
                    fail(
                        &mut outcome,
                        at,
                        "check",
                        format!(
                            "expected the first error at {expected}, got line {line}: {} {}",
                            error.code, error.message
                        ),
                    );
                    outcome.details = render_program_diagnostics(scenario, source, &diagnostics);
                }
            }
        }
        return outcome;
    }
    let Some(program) = program else {
        let line = first_error.map_or(1, |e| source.line_of(e.span.start));
        fail(
            &mut outcome,
            1,
            "check",
            format!("the program does not compile (first error at program line {line})"),
        );
        outcome.details = render_program_diagnostics(scenario, source, &diagnostics);
        return outcome;
    };
    let signals = match options.waveforms {
        Waveforms::None => None,
        Waveforms::Failing | Waveforms::All => Some(waveform_signals(scenario, &program)),
    };
    let observe = |kind: EngineKind| ScenarioObserver {
        kind,
        printed: Vec::new(),
        recorder: signals.clone().map(Recorder::new),
        snapshots: options.snapshots.then(Vec::new),
    };
    let host_devices = scenario.host_devices();
    // Lowered once for every native engine (and not at all for the
    // interpreter alone).
    let native = engines.iter().any(|&kind| kind != EngineKind::Interp);
    let lowered = native.then(|| crate::pipeline::Lowered::new(&program));
    for &kind in engines {
        let instance = match &lowered {
            Some(lowered) => instantiate_lowered(kind, lowered, &host_devices),
            None => instantiate(kind, &program, &host_devices),
        };
        match instance {
            Ok(mut engine) => {
                outcome.ran.push(kind);
                let mut observer = observe(kind);
                let failures = drive(&scenario.steps, engine.as_mut(), &mut observer);
                let failed = !failures.is_empty();
                for failure in failures {
                    fail(&mut outcome, failure.0, kind.name(), failure.1);
                }
                outcome.engines.push(EngineRun {
                    kind,
                    printed: observer.printed,
                    waveform: observer
                        .recorder
                        .filter(|_| failed || options.waveforms == Waveforms::All),
                    snapshots: observer.snapshots.unwrap_or_default(),
                });
            }
            Err(EngineError::Unavailable(reason)) => outcome.skipped.push((kind, reason)),
            Err(EngineError::Failed(reason)) => {
                outcome.ran.push(kind);
                fail(&mut outcome, 1, kind.name(), format!("the engine failed: {reason}"));
            }
        }
    }
    outcome
}

/// Records a run for the report: `print` lines and, when asked, the
/// waveform.
struct ScenarioObserver {
    kind: EngineKind,
    printed: Vec<String>,
    recorder: Option<Recorder>,
    snapshots: Option<Vec<Snapshot>>,
}

impl Observer for ScenarioObserver {
    fn started(&mut self, engine: &mut dyn Engine) -> Result<(), String> {
        match &mut self.recorder {
            Some(recorder) => recorder.sample(engine, 0),
            None => Ok(()),
        }
    }

    fn scanned(&mut self, engine: &mut dyn Engine, _: u64, time_ms: u64) -> Result<(), String> {
        match &mut self.recorder {
            Some(recorder) => recorder.sample(engine, time_ms),
            None => Ok(()),
        }
    }

    fn printed(&mut self, line: u32, scan: u64, values: Vec<(String, HostDevice, i32)>) {
        let shown: Vec<String> = values
            .into_iter()
            .map(|(name, device, value)| format!("{name} = {}", format_value(value, device)))
            .collect();
        self.printed.push(format!(
            "line {line} [{}] after scan {scan}: {}",
            self.kind.name(),
            shown.join(", ")
        ));
    }

    fn failed(&mut self, engine: &mut dyn Engine, line: u32, (scan, time_ms): (u64, u64), message: &str) {
        let Some(snapshots) = &mut self.snapshots else { return };
        if snapshots.len() >= MOST_SNAPSHOTS {
            return;
        }
        if let Some(image) = engine.image() {
            snapshots.push(Snapshot {
                line,
                scan,
                time_ms,
                message: message.to_string(),
                image: Box::new(*image),
            });
        }
    }
}

/// What a test's waveform shows: every device the scenario sets, forces,
/// expects or prints, then the coils the program drives at fixed numbers.
fn waveform_signals(scenario: &Scenario, program: &CheckedProgram) -> Vec<Signal> {
    let mut signals: Vec<Signal> = Vec::new();
    let mut add_signal = |signal: Signal| match signals.iter_mut().find(|known| known.device == signal.device) {
        // A pair also expected as a real number is shown as one.
        Some(known) => known.real |= signal.real,
        None => signals.push(signal),
    };
    let bit = |area, index| HostDevice {
        device: Device::Bit(area, index),
        width: Width::Single,
    };
    for step in &scenario.steps {
        match &step.directive {
            Directive::Set { device, .. } | Directive::Expect { device, .. } => add_signal(Signal::of(*device)),
            Directive::ExpectReal { device, .. } => add_signal(Signal {
                real: true,
                ..Signal::of(*device)
            }),
            Directive::Pulse { input, .. } => add_signal(Signal::of(bit(ladder_runtime::BitArea::X, *input))),
            Directive::Force { area, index, .. } | Directive::Unforce { area, index } => {
                add_signal(Signal::of(bit(*area, *index)))
            }
            Directive::Print(devices) => devices.iter().for_each(|(_, device)| add_signal(Signal::of(*device))),
            Directive::ScanMs(_)
            | Directive::Scan(_)
            | Directive::ExpectError(_)
            | Directive::ExpectReject { .. }
            | Directive::Clock(_) => {}
        }
    }
    for instruction in &program.instructions {
        if let Op::Output(Output::Coil(BitRef::Device(area, address))) = &instruction.op {
            if address.is_fixed() {
                add_signal(Signal::of(bit(*area, address.index)));
            }
        }
    }
    for signal in &mut signals {
        if signal.real {
            signal.name = signal.name.replace(":32", ":float");
        }
    }
    signals
}
