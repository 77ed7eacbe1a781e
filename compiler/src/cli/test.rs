//! `ladderc test`: scenario files, as SCENARIO.md describes.

use super::status;
use crate::scenario::{collect_files, parse_scenario, run_scenario, EngineKind};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

pub fn run(paths: &[PathBuf], engines: &[EngineKind]) -> u8 {
    run_to(&mut std::io::stdout().lock(), paths, engines)
}

/// `ladderc test` writing its report to `out` (failures, details, engine
/// lines, and the summary line last). Errors reading files go to stderr.
pub fn run_to(out: &mut dyn Write, paths: &[PathBuf], engines: &[EngineKind]) -> u8 {
    let mut unusable = false;
    let mut files = Vec::new();
    for path in paths {
        match collect_files(path) {
            Ok(found) => files.extend(found),
            Err(error) => {
                say_err!("error: cannot read {}: {error}", path.display());
                unusable = true;
            }
        }
    }
    if files.is_empty() && !unusable {
        let shown: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        say_err!("error: no scenario files (*.scn) in {}", shown.join(", "));
        return status::UNUSABLE;
    }
    let (mut passed, mut failed) = (0usize, 0usize);
    let mut ran: BTreeMap<EngineKind, usize> = BTreeMap::new();
    let mut skipped: BTreeMap<EngineKind, String> = BTreeMap::new();
    for file in &files {
        let Some((scenario, source)) = load(file) else {
            unusable = true;
            continue;
        };
        let outcome = run_scenario(&scenario, &source, engines);
        for failure in &outcome.failures {
            let _ = writeln!(out, "{failure}");
        }
        let _ = out.write_all(outcome.details.as_bytes());
        for kind in &outcome.ran {
            *ran.entry(*kind).or_default() += 1;
        }
        for (kind, reason) in &outcome.skipped {
            skipped.entry(*kind).or_insert_with(|| reason.clone());
        }
        // A scenario no engine could run is neither passed nor failed; the
        // skip lines say why.
        let ran_nothing = outcome.ran.is_empty() && !outcome.skipped.is_empty();
        if !outcome.failures.is_empty() {
            failed += 1;
        } else if !ran_nothing {
            passed += 1;
        }
    }
    let ran_names: Vec<&str> = ran.keys().map(|k| k.name()).collect();
    let engines_line = if ran_names.is_empty() {
        "none".to_string()
    } else {
        ran_names.join(", ")
    };
    let _ = writeln!(out, "engines: {engines_line}");
    for (kind, reason) in &skipped {
        let _ = writeln!(out, "skipped {}: {reason}", kind.name());
    }
    let _ = writeln!(out, "{passed} passed, {failed} failed");
    if unusable {
        status::UNUSABLE
    } else if failed > 0 {
        status::FAILED
    } else {
        status::OK
    }
}

/// Reads and parses a scenario and its program; reports and returns None
/// when either cannot be read or parsed.
fn load(file: &Path) -> Option<(crate::scenario::Scenario, crate::source::SourceFile)> {
    let text = match crate::source::read_bounded(file) {
        Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
        Err(error) => {
            say_err!("error: {error}");
            return None;
        }
    };

    let scenario = match parse_scenario(file, &text) {
        Ok(scenario) => scenario,
        Err(error) => {
            say_err!("{}:{}: error: {}", file.display(), error.line, error.message);
            return None;
        }
    };
    match crate::scenario::load_program(&scenario) {
        Ok(source) => Some((scenario, source)),
        Err(message) => {
            say_err!("{}: error: {message}", file.display());
            None
        }
    }
}
