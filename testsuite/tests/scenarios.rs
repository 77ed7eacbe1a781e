//! Every scenario in `scenarios/` as tests of their own, one per scenario
//! file and engine, named after the file's path: run one file on one engine
//! with `cargo test -p ladderc-testsuite -- fx_structure::fx_station::jit`,
//! one engine with `-- ::c_compact`, a folder with `-- scenario::seeds::`.
//! A scenario that expects its program to be rejected is one test
//! (`...::check`). Engines that need a C compiler are ignored, with the
//! reason printed, where the machine has none.
//!
//! A custom harness (libtest-mimic) because the tests are found at run
//! time, not written as functions.

use ladder_engine::aot::toolchain::c_compiler;
use ladder_engine::scenario::{
    collect_files, load_program, parse_scenario, run_scenario, EngineKind, RunOptions, Scenario, ScenarioOutcome,
};
use libtest_mimic::{Arguments, Failed, Trial};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn scenarios_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

/// `scenario::seeds::stl::example1_set_transfer` for
/// `scenarios/seeds/stl/example1_set_transfer.scn`.
fn test_name(file: &Path) -> String {
    let relative = file.strip_prefix(scenarios_dir()).unwrap_or(file).with_extension("");
    let parts: Vec<String> = relative
        .components()
        .map(|part| part.as_os_str().to_string_lossy().replace(['-', '.', ' '], "_"))
        .collect();
    format!("scenario::{}", parts.join("::"))
}

fn engine_name(kind: EngineKind) -> String {
    kind.name().replace('-', "_")
}

/// What a failed run shows: each failed expectation with its line, then the
/// details (diagnostics) and what `print` directives printed.
fn report(file: &Path, outcome: &ScenarioOutcome) -> Result<(), Failed> {
    if outcome.failures.is_empty() {
        return Ok(());
    }
    let mut text = String::new();
    for failure in &outcome.failures {
        text.push_str(&format!(
            "{}:{}: [{}] {}\n",
            file.display(),
            failure.line,
            failure.engine,
            failure.message
        ));
    }
    text.push_str(&outcome.details);
    for run in &outcome.engines {
        for line in &run.printed {
            text.push_str(line);
            text.push('\n');
        }
    }
    Err(text.into())
}

fn run(file: &Path, scenario: &Scenario, engines: &[EngineKind]) -> Result<(), Failed> {
    let source = load_program(scenario).map_err(|e| format!("{}: cannot read the program: {e}", file.display()))?;
    let outcome = run_scenario(scenario, &source, engines, RunOptions::default());
    if let Some((kind, reason)) = outcome.skipped.first() {
        return Err(format!("{}: engine {} unavailable: {reason}", file.display(), kind.name()).into());
    }
    if outcome.failures.is_empty() && outcome.ran.len() != engines.len() && scenario.expected_reject().is_none() {
        return Err(format!("{}: ran {:?}, expected {engines:?}", file.display(), outcome.ran).into());
    }
    report(file, &outcome)
}

fn trials() -> Vec<Trial> {
    let files = collect_files(&scenarios_dir()).expect("the scenario folder");
    let no_c_compiler = c_compiler().err();
    if let Some(reason) = &no_c_compiler {
        println!("aot, c and c-compact are ignored: {reason}");
    }
    let mut trials = Vec::new();
    for file in &files {
        let name = test_name(file);
        let text = std::fs::read_to_string(file).unwrap_or_default();
        let scenario = match parse_scenario(file, &text) {
            Ok(scenario) => Arc::new(scenario),
            Err(error) => {
                let message = format!("{}:{}: {}", file.display(), error.line, error.message);
                trials.push(Trial::test(format!("{name}::parse"), move || Err(message.into())));
                continue;
            }
        };
        if scenario.expected_reject().is_some() {
            let file = file.clone();
            trials.push(Trial::test(format!("{name}::check"), move || {
                run(&file, &scenario, &[EngineKind::Interp])
            }));
            continue;
        }
        for kind in EngineKind::ALL {
            let needs_c = match kind {
                EngineKind::Interp | EngineKind::Jit => false,
                EngineKind::Aot | EngineKind::C | EngineKind::CCompact => true,
            };
            let (file, scenario) = (file.clone(), Arc::clone(&scenario));
            let trial = Trial::test(format!("{name}::{}", engine_name(kind)), move || {
                run(&file, &scenario, &[kind])
            });
            trials.push(trial.with_ignored_flag(needs_c && no_c_compiler.is_some()));
        }
    }
    trials.push(suite_checks(files));
    trials
}

/// The suite as a whole: it is all there, and every scenario that expects
/// a rejection names the diagnostic code it expects.
fn suite_checks(files: Vec<PathBuf>) -> Trial {
    Trial::test("suite::every_reject_names_its_code_and_the_suite_is_whole", move || {
        if files.len() < 100 {
            return Err(format!("expected the whole suite, found {} scenario files", files.len()).into());
        }
        let mut missing = Vec::new();
        for file in &files {
            let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
            let scenario =
                parse_scenario(file, &text).map_err(|e| format!("{}:{}: {}", file.display(), e.line, e.message))?;
            if let Some((_, None, line)) = scenario.expected_reject() {
                missing.push(format!("{}:{line}", file.display()));
            }
        }
        if missing.is_empty() {
            Ok(())
        } else {
            Err(format!(
                "`expect reject LINE` without its code (E0013, ...):\n{}",
                missing.join("\n")
            )
            .into())
        }
    })
}

fn main() {
    let arguments = Arguments::from_args();
    libtest_mimic::run(&arguments, trials()).exit();
}
