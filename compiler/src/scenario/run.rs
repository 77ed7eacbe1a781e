//! Running one scenario: compile its program once, then drive each engine
//! through the directives and compare.

use super::engine::{instantiate, Engine, EngineError, EngineKind};
use super::parse::{Directive, ProgramSource, Scenario};
use crate::check::compile_source;
use crate::diagnostics::render_all;
use crate::host_device::{format_value, same_bits, HostDevice};
use crate::source::SourceFile;
use ladder_runtime::special::{D_ERROR_CODE, M_OPERATION_ERROR};
use ladder_runtime::{BitArea, Device, Width, WordArea};
use std::path::{Path, PathBuf};

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
    diagnostics: &[crate::diagnostics::Diagnostic],
) -> String {
    let shown = crate::diagnostics::Shown::default();
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
pub fn run_scenario(scenario: &Scenario, source: &SourceFile, engines: &[EngineKind]) -> ScenarioOutcome {
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
    for &kind in engines {
        match instantiate(kind, &program) {
            Ok(mut engine) => {
                outcome.ran.push(kind);
                for failure in drive(scenario, engine.as_mut()) {
                    fail(&mut outcome, failure.0, kind.name(), failure.1);
                }
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

const ERROR_FLAG: HostDevice = HostDevice {
    device: Device::Bit(BitArea::M, M_OPERATION_ERROR),
    width: Width::Single,
};
const ERROR_CODE: HostDevice = HostDevice {
    device: Device::Word(WordArea::D, D_ERROR_CODE),
    width: Width::Single,
};

/// Drives one engine through the directives: (scenario line, message) per
/// failed expectation. An engine fault ends the run with one failure.
fn drive(scenario: &Scenario, engine: &mut dyn Engine) -> Vec<(u32, String)> {
    let mut failures = Vec::new();
    let mut scan_ms = 10;
    for step in &scenario.steps {
        let result: Result<(), String> = (|| {
            match &step.directive {
                Directive::ScanMs(ms) => scan_ms = *ms,
                Directive::Set { device, value } => engine.write(*device, *value)?,
                Directive::Force { area, index, on } => engine.force(*area, *index, *on)?,
                Directive::Unforce { area, index } => engine.unforce(*area, *index)?,
                Directive::Scan(n) => {
                    for _ in 0..*n {
                        engine.scan(scan_ms)?;
                    }
                }
                Directive::Expect { device, name, value } => {
                    let actual = engine.read(*device)?;
                    if !same_bits(actual, *value, device.bits()) {
                        failures.push((
                            step.line,
                            format!(
                                "expected {name} = {}, got {}",
                                format_value(*value, *device),
                                format_value(actual, *device)
                            ),
                        ));
                    }
                }
                Directive::ExpectError(expected) => {
                    let flag = engine.read(ERROR_FLAG)? != 0;
                    let code = engine.read(ERROR_CODE)? as u16;
                    let actual = flag.then_some(code);
                    if actual != *expected {
                        let show = |c: Option<u16>| c.map_or("none".to_string(), |c| format!("{c:04X}H"));
                        failures.push((
                            step.line,
                            format!("expected error {}, got {}", show(*expected), show(actual)),
                        ));
                    }
                }
                Directive::ExpectReject { .. } => {}
            }
            Ok(())
        })();
        if let Err(fault) = result {
            failures.push((step.line, format!("engine fault: {fault}")));
            break;
        }
    }
    failures
}
