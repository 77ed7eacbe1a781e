//! Every property file in `properties/` through `ladderc verify`'s checker:
//! each property must get the verdict its line's `# expect:` comment names,
//! and the witness of every violated or reached property must replay with
//! the scenario runner on every engine (the verifier replays it on the
//! interpreter before it reports it; this runs the compiled engines too).
//! One test per property file: `cargo test -p ladderc-testsuite --test
//! properties -- dialect::stl_transfer`. Each file also runs with the
//! SAT-based engines alone (`sat::dialect::stl_transfer`): every verdict
//! they reach must be the expected one (they may run out of time, or
//! decline a program they do not encode, but never disagree).

use ladder_engine::aot::toolchain::c_compiler;
use ladder_engine::scenario::{load_program, parse_scenario, run_scenario, EngineKind, RunOptions};
use ladder_verify::search::Limits;
use ladder_verify::{collect_files, verify_file, witness_path, Engine, Options};
use libtest_mimic::{Arguments, Failed, Trial};
use std::path::{Path, PathBuf};

fn properties_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("properties")
}

/// The verdict a property line expects: the text after `# expect:`.
fn expected(text: &str, line: u32) -> Option<String> {
    let line = text.lines().nth(line as usize - 1)?;
    let (_, after) = line.split_once("# expect:")?;
    Some(after.trim().to_string())
}

fn check(file: &Path, engines: &[EngineKind]) -> Result<(), Failed> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let reports = verify_file(file, &Options::default()).map_err(|e| format!("{}: {e:?}", file.display()))?;
    let annotated = text.lines().filter(|l| l.contains("# expect:")).count();
    if reports.len() != annotated {
        return Err(format!(
            "{}: {} properties, {annotated} `# expect:` lines",
            file.display(),
            reports.len()
        )
        .into());
    }
    let witnesses = tempfile::tempdir().map_err(|e| e.to_string())?;
    let mut problems = Vec::new();
    for report in &reports {
        let got = report.verdict.text();
        match expected(&text, report.line) {
            Some(want) if want == got => {}
            Some(want) => problems.push(format!(
                "{}:{}: expected {want}, got {got}",
                file.display(),
                report.line
            )),
            None => problems.push(format!(
                "{}:{}: no `# expect:` on the line",
                file.display(),
                report.line
            )),
        }
        let wants_witness = got.starts_with("violated") || got.starts_with("reached");
        match (&report.witness, wants_witness) {
            (Some(witness), true) => {
                let path = witness_path(witnesses.path(), file, report.line);
                std::fs::write(&path, witness).map_err(|e| e.to_string())?;
                let scenario = parse_scenario(&path, witness).map_err(|e| {
                    format!(
                        "{}:{}: witness line {}: {}",
                        file.display(),
                        report.line,
                        e.line,
                        e.message
                    )
                })?;
                let source = load_program(&scenario).map_err(|e| e.to_string())?;
                let outcome = run_scenario(&scenario, &source, engines, RunOptions::default());
                for failure in &outcome.failures {
                    problems.push(format!(
                        "{}:{}: the witness fails on {} at its line {}: {}\n{witness}",
                        file.display(),
                        report.line,
                        failure.engine,
                        failure.line,
                        failure.message
                    ));
                }
                if outcome.ran.len() != engines.len() {
                    problems.push(format!("{}: the witness ran on {:?}", file.display(), outcome.ran));
                }
            }
            (None, false) => {}
            (Some(_), false) => problems.push(format!("{}:{}: a witness for {got}", file.display(), report.line)),
            (None, true) => problems.push(format!("{}:{}: no witness for {got}", file.display(), report.line)),
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n").into())
    }
}

/// The file with the SAT-based engines alone: a decided verdict is the
/// expected one, with a witness that replays on the interpreter (the
/// verifier checks that before it reports).
fn check_sat(file: &Path) -> Result<(), Failed> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let options = Options {
        engine: Engine::Symbolic,
        limits: Limits {
            timeout: std::time::Duration::from_secs(3),
            ..Limits::default()
        },
    };
    let reports = verify_file(file, &options).map_err(|e| format!("{}: {e:?}", file.display()))?;
    let mut problems = Vec::new();
    for report in &reports {
        let got = report.verdict.text();
        if got.starts_with("unknown") {
            continue;
        }
        match expected(&text, report.line) {
            Some(want) if want == got => {}
            want => problems.push(format!(
                "{}:{}: expected {want:?}, the SAT-based engines say {got}",
                file.display(),
                report.line
            )),
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n").into())
    }
}

fn main() {
    let args = Arguments::from_args();
    let dir = properties_dir();
    let files = collect_files(&dir).expect("the properties folder");
    assert!(files.len() >= 12, "the property suite is there: {} files", files.len());
    let engines: Vec<EngineKind> = match c_compiler() {
        Ok(_) => EngineKind::ALL.to_vec(),
        Err(reason) => {
            println!("witnesses run on interp and jit only: {reason}");
            vec![EngineKind::Interp, EngineKind::Jit]
        }
    };
    let trials = files
        .into_iter()
        .flat_map(|file| {
            let relative = file.strip_prefix(&dir).unwrap_or(&file).with_extension("");
            let name = relative.to_string_lossy().replace(['/', '\\'], "::");
            let engines = engines.clone();
            let sat_file = file.clone();
            [
                Trial::test(name.clone(), move || check(&file, &engines)),
                Trial::test(format!("sat::{name}"), move || check_sat(&sat_file)),
            ]
        })
        .collect();
    libtest_mimic::run(&args, trials).exit();
}
