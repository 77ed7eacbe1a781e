//! `ladderc test --junit`: the results as JUnit XML, the format CI systems
//! (GitLab, Jenkins, GitHub test reporters) read, as TcUnit and CODESYS Test
//! Manager report PLC tests.

use ladder_engine::scenario::ScenarioOutcome;
use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
use std::path::Path;

/// One scenario file's results for the report.
pub struct FileReport<'a> {
    pub path: &'a Path,
    /// None when the file or its program could not be read.
    pub outcome: Option<&'a ScenarioOutcome>,
    /// Why it could not be read.
    pub errors: &'a [String],
}

/// Writes the report: a testsuite per scenario file, a testcase per engine
/// that ran it (or `check` for a scenario that expects a rejection or whose
/// program does not compile), failures with the expected and actual value
/// and the scenario line, skipped engines as skipped cases.
pub fn write_junit(path: &Path, results: &[FileReport], inputs: &[&Path]) -> Result<(), String> {
    let mut report = Report::new("ladderc");
    for FileReport {
        path: file,
        outcome,
        errors,
    } in results
    {
        let name = file.display().to_string();
        let mut suite = TestSuite::new(name.clone());
        let stem = file
            .file_stem()
            .map_or(name.clone(), |s| s.to_string_lossy().into_owned());
        let Some(outcome) = outcome else {
            let mut status = TestCaseStatus::non_success(NonSuccessKind::Error);
            status.set_message(
                errors
                    .first()
                    .cloned()
                    .unwrap_or_else(|| "the scenario could not be read".into()),
            );
            status.set_description(errors.join("\n"));
            suite.add_test_case(TestCase::new(stem, status));
            report.add_test_suite(suite);
            continue;
        };
        let mut engines: Vec<String> = outcome.ran.iter().map(|k| k.name().to_string()).collect();
        if engines.is_empty() && outcome.skipped.is_empty() || outcome.failures.iter().any(|f| f.engine == "check") {
            engines.insert(0, "check".to_string());
        }
        for engine in engines {
            let failures: Vec<_> = outcome.failures.iter().filter(|f| f.engine == engine).collect();
            let status = if failures.is_empty() {
                TestCaseStatus::success()
            } else {
                let mut status = TestCaseStatus::non_success(NonSuccessKind::Failure);
                status.set_message(failures[0].message.clone());
                let lines: Vec<String> = failures
                    .iter()
                    .map(|f| format!("{}:{}: {}", f.path.display(), f.line, f.message))
                    .collect();
                status.set_description(lines.join("\n"));
                status
            };
            let mut case = TestCase::new(format!("{stem} [{engine}]"), status);
            case.set_classname(name.clone());
            let printed: Vec<&str> = outcome
                .engines
                .iter()
                .filter(|run| run.kind.name() == engine)
                .flat_map(|run| run.printed.iter().map(String::as_str))
                .collect();
            if !printed.is_empty() {
                case.set_system_out(printed.join("\n"));
            }
            if engine == "check" && !outcome.details.is_empty() {
                case.set_system_err(outcome.details.clone());
            }
            suite.add_test_case(case);
        }
        for (kind, reason) in &outcome.skipped {
            let mut status = TestCaseStatus::skipped();
            status.set_message(reason.clone());
            let mut case = TestCase::new(format!("{stem} [{}]", kind.name()), status);
            case.set_classname(name.clone());
            suite.add_test_case(case);
        }
        report.add_test_suite(suite);
    }
    write_report(path, &report, inputs)
}

/// Writes a JUnit report at `path`, never over one of `inputs`, whole or
/// not at all (`test --junit`, `verify --junit`).
pub fn write_report(path: &Path, report: &Report, inputs: &[&Path]) -> Result<(), String> {
    let xml = report
        .to_string()
        .map_err(|e| format!("cannot write the JUnit report: {e}"))?;
    let target = super::output::prepare(path, inputs).map_err(|e| e.to_string())?;
    super::output::write_atomically(&target, xml.as_bytes())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}
