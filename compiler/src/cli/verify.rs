//! `ladderc verify`: every property of every property file checked, one
//! verdict line each, the summary, witnesses and a JUnit report.

use super::status;
use ladder_verify::search::Limits;
use ladder_verify::{
    collect_files, emit_aiger as aiger_of, verify_file, witness_path, Engine, FileError, Options, PropertyReport,
};
use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(clap::Args, Debug)]
pub struct VerifyArgs {
    /// Property files, or folders (every *.prop in them, recursively).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Scans from power-up the search may go before it answers unknown.
    #[arg(long, default_value_t = 1_000_000)]
    pub depth: u32,
    /// Seconds each property may take before it is unknown.
    #[arg(long, default_value_t = 60)]
    pub timeout: u64,
    /// Write a scenario that replays every violation or reached condition
    /// here, as NAME-LINE.scn.
    #[arg(long)]
    pub witness: Option<PathBuf>,
    /// Write a JUnit report (one test case per property).
    #[arg(long)]
    pub junit: Option<PathBuf>,
    /// Which engines decide: the explicit-state search, then the SAT-based
    /// ones when it cannot answer (auto); either alone.
    #[arg(long, value_enum, default_value_t = EngineArg::Auto)]
    pub engine: EngineArg,
    /// Instead of checking: write one property (`--property LINE`) of one
    /// property file as a binary AIGER model to `-o FILE`, its output ON
    /// after a scan that breaks the property.
    #[arg(long, value_enum, requires_all = ["output", "property"])]
    pub emit: Option<EmitArg>,
    /// The file `--emit` writes.
    #[arg(short = 'o', long = "output", requires = "emit")]
    pub output: Option<PathBuf>,
    /// The line of the property `--emit` writes.
    #[arg(long, requires = "emit")]
    pub property: Option<u32>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum EngineArg {
    Auto,
    Explicit,
    Sat,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmitArg {
    Aiger,
}

pub fn run(args: &VerifyArgs) -> u8 {
    if let (Some(EmitArg::Aiger), Some(output), Some(line)) = (args.emit, &args.output, args.property) {
        return emit_aiger(&args.paths, output, line);
    }
    let options = Options {
        engine: match args.engine {
            EngineArg::Auto => Engine::Auto,
            EngineArg::Explicit => Engine::Explicit,
            EngineArg::Sat => Engine::Symbolic,
        },
        limits: Limits {
            depth: args.depth,
            timeout: Duration::from_secs(args.timeout),
            ..Limits::default()
        },
    };
    let mut files = Vec::new();
    for path in &args.paths {
        match collect_files(path) {
            Ok(found) => files.extend(found),
            Err(error) => {
                say_err!("error: {}: {error}", path.display());
                return status::UNUSABLE;
            }
        }
    }
    let (mut passed, mut failed, mut unknown) = (0usize, 0usize, 0usize);
    let mut unusable = false;
    let mut results: Vec<(PathBuf, Result<Vec<PropertyReport>, String>)> = Vec::new();
    for file in files {
        match verify_file(&file, &options) {
            Ok(reports) => {
                for report in &reports {
                    say!("{}:{}: {}", file.display(), report.line, report.verdict.text());
                    for warning in &report.warnings {
                        say_err!("{}:{}: warning: {warning}", file.display(), report.line);
                    }
                    match report.verdict.passed() {
                        Some(true) => passed += 1,
                        Some(false) => failed += 1,
                        None => unknown += 1,
                    }
                    if let (Some(dir), Some(text)) = (&args.witness, &report.witness) {
                        // The folder is made when there is a witness to write.
                        let target = witness_path(dir, &file, report.line);
                        let written = std::fs::create_dir_all(dir)
                            .and_then(|()| super::output::write_atomically(&target, text.as_bytes()));
                        if let Err(error) = written {
                            say_err!("error: cannot write {}: {error}", target.display());
                            unusable = true;
                        }
                    }
                }
                results.push((file, Ok(reports)));
            }
            Err(FileError::Read(message)) => {
                say_err!("error: {message}");
                unusable = true;
                results.push((file, Err(message)));
            }
            Err(FileError::Invalid(rendered)) => {
                super::write_raw(true, &rendered);
                unusable = true;
                results.push((file, Err(rendered)));
            }
        }
    }
    if unknown > 0 {
        say!("{passed} passed, {failed} failed, {unknown} unknown");
    } else {
        say!("{passed} passed, {failed} failed");
    }
    // A file that could not be checked writes no report (exit 2: nothing
    // written).
    if let (Some(path), false) = (&args.junit, unusable) {
        let inputs: Vec<&Path> = args.paths.iter().map(PathBuf::as_path).collect();
        if let Err(message) = write_junit(path, &results, &inputs) {
            say_err!("error: {message}");
            return status::UNUSABLE;
        }
    }
    if unusable {
        status::UNUSABLE
    } else if failed > 0 || unknown > 0 {
        status::FAILED
    } else {
        status::OK
    }
}

/// `--emit aiger`: one property of one file, written only when it can be
/// made whole (an existing file is left as it was otherwise).
fn emit_aiger(paths: &[PathBuf], output: &Path, line: u32) -> u8 {
    let [path] = paths else {
        say_err!("error: --emit aiger takes one property file");
        return status::UNUSABLE;
    };
    match aiger_of(path, line) {
        Ok((bytes, arbitrary)) => match super::output::write_atomically(output, &bytes) {
            Ok(()) => {
                if !arbitrary.is_empty() {
                    say_err!(
                        "warning: the model takes these as arbitrary (a counterexample may need them): {}",
                        arbitrary.join("; ")
                    );
                }
                status::OK
            }
            Err(error) => {
                say_err!("error: cannot write {}: {error}", output.display());
                status::UNUSABLE
            }
        },
        Err(FileError::Read(message)) => {
            say_err!("error: {message}");
            status::UNUSABLE
        }
        Err(FileError::Invalid(rendered)) => {
            super::write_raw(true, &rendered);
            status::UNUSABLE
        }
    }
}

/// A test suite per property file, a test case per property.
fn write_junit(
    path: &Path,
    results: &[(PathBuf, Result<Vec<PropertyReport>, String>)],
    inputs: &[&Path],
) -> Result<(), String> {
    let mut report = Report::new("ladderc verify");
    for (file, result) in results {
        let name = file.display().to_string();
        let mut suite = TestSuite::new(name.clone());
        match result {
            Err(message) => {
                let mut status = TestCaseStatus::non_success(NonSuccessKind::Error);
                status.set_message("the property file could not be checked");
                status.set_description(message.clone());
                suite.add_test_case(TestCase::new(name.clone(), status));
            }
            Ok(reports) => {
                for property in reports {
                    let verdict = property.verdict.text();
                    let status = match property.verdict.passed() {
                        Some(true) => TestCaseStatus::success(),
                        Some(false) => {
                            let mut status = TestCaseStatus::non_success(NonSuccessKind::Failure);
                            status.set_message(verdict.clone());
                            if let Some(witness) = &property.witness {
                                status.set_description(witness.clone());
                            }
                            status
                        }
                        None => {
                            let mut status = TestCaseStatus::non_success(NonSuccessKind::Error);
                            status.set_message(verdict.clone());
                            status
                        }
                    };
                    let mut case = TestCase::new(format!("{name}:{}", property.line), status);
                    case.set_classname(name.clone());
                    case.set_system_out(verdict);
                    suite.add_test_case(case);
                }
            }
        }
        report.add_test_suite(suite);
    }
    super::report::write_report(path, &report, inputs)
}
