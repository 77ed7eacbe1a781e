//! The ladder of every program is the program: read back as IL, it
//! compiles to the same checked program (the same instructions, STL blocks,
//! subroutines), on every program of the scenarios and program files under
//! `testsuite/` and on random programs of the differential test's
//! generators.

mod common;

use common::tools::workspace;
use ladderc::check::compile_source;
use ladderc::program::{CheckedProgram, Op};
use ladderc::source::SourceFile;
use proptest::prelude::*;
use std::path::PathBuf;

/// What runs: the instructions without their spans and lines, and the
/// program's structure.
fn shape(program: &CheckedProgram) -> (Vec<Op>, Vec<(u32, usize, usize)>, Vec<(u32, usize, usize)>, usize) {
    (
        program.instructions.iter().map(|i| i.op.clone()).collect(),
        program.stl_blocks.iter().map(|b| (b.state, b.begin, b.end)).collect(),
        program.subroutines.iter().map(|s| (s.label, s.entry, s.end)).collect(),
        program.main_end,
    )
}

/// The IL of the program's ladder, and whether it compiles to the same
/// program (the difference, if not).
fn round_trip(name: &str, text: &str) -> Result<(), String> {
    let source = SourceFile::new(name, text);
    let (Some(program), _) = compile_source(&source) else {
        return Ok(()); // not a program (reject scenarios)
    };
    let ladder = ladderc::ladder::build(&program, &source);
    let il = ladderc::ladder::to_il(&ladder, &program);
    let again = SourceFile::new(format!("{name} (ladder)"), il.clone());
    let (back, diagnostics) = compile_source(&again);
    let Some(back) = back else {
        let shown = ladderc::diagnostics::render_all(&again, &diagnostics, ladderc::diagnostics::Shown::All);
        return Err(format!("{name}: the ladder's IL does not compile:\n{shown}\n{il}"));
    };
    if shape(&back) != shape(&program) {
        let (a, b) = (shape(&program).0, shape(&back).0);
        let first = a
            .iter()
            .zip(&b)
            .position(|(x, y)| x != y)
            .unwrap_or(a.len().min(b.len()));
        return Err(format!(
            "{name}: the ladder's IL is another program (first difference at instruction {first}: {:?} became {:?})\n{il}",
            a.get(first),
            b.get(first)
        ));
    }
    Ok(())
}

/// Every program under `testsuite/`: inline programs of scenarios and
/// program files (decoded as ladderc reads them).
fn programs() -> Vec<(String, String)> {
    let mut found = Vec::new();
    let mut pending = vec![workspace().join("testsuite")];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path: PathBuf = entry.unwrap().path();
            let name = path.display().to_string();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "il" || e == "csv") {
                found.push((name, SourceFile::read(&path).unwrap().text));
            } else if path.extension().is_some_and(|e| e == "scn") {
                let text = std::fs::read_to_string(&path).unwrap();
                if let Ok(scenario) = ladderc::scenario::parse_scenario(&path, &text) {
                    if let ladderc::scenario::ProgramSource::Inline { text, .. } = scenario.program {
                        found.push((name, text));
                    }
                }
            }
        }
    }
    found
}

#[test]
fn every_testsuite_program_is_its_ladder() {
    let programs = programs();
    assert!(programs.len() > 500, "{} programs", programs.len());
    let failures: Vec<String> = programs
        .iter()
        .filter_map(|(name, text)| round_trip(name, text).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {}:\n{}",
        failures.len(),
        programs.len(),
        failures.join("\n\n")
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_programs_are_their_ladders(text in common::program()) {
        prop_assert!(round_trip("random.il", &text).is_ok(), "{}", round_trip("random.il", &text).unwrap_err());
    }

    #[test]
    fn random_fx_programs_are_their_ladders(text in common::fx::fx_program()) {
        prop_assert!(round_trip("fx.il", &text).is_ok(), "{}", round_trip("fx.il", &text).unwrap_err());
    }

    #[test]
    fn random_memory_programs_are_their_ladders(text in common::memory_program()) {
        prop_assert!(round_trip("memory.il", &text).is_ok(), "{}", round_trip("memory.il", &text).unwrap_err());
    }
}
