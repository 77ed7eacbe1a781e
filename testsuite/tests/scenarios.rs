//! Runs `ladderc test` over every scenario in `scenarios/`, so `cargo test`
//! covers them on every engine. The report of `ladderc test` is shown when
//! something fails.

use ladderc::cli::test::run_to;
use ladderc::scenario::EngineKind;
use std::path::PathBuf;

fn scenarios_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

fn run(engines: &[EngineKind]) -> (u8, String) {
    let mut report = Vec::new();
    let status = run_to(&mut report, &[scenarios_dir()], engines);
    (status, String::from_utf8_lossy(&report).into_owned())
}

fn summary(report: &str) -> (usize, usize) {
    let last = report.lines().last().expect("a summary line");
    let numbers: Vec<usize> = last
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|w| w.parse().ok())
        .collect();
    (numbers[0], numbers[1])
}

fn c_compiler_present() -> bool {
    ladderc::aot::toolchain::c_compiler().is_ok()
}

#[test]
fn every_scenario_passes_on_every_engine() {
    let (status, report) = run(&EngineKind::ALL);
    assert_eq!(status, 0, "ladderc test failed:\n{report}");
    let (passed, failed) = summary(&report);
    assert_eq!(failed, 0, "{report}");
    assert!(
        passed >= 100,
        "expected the whole suite, found {passed} scenarios:\n{report}"
    );
    if c_compiler_present() {
        assert!(
            report.contains("engines: interp, jit, aot, c, c-compact\n"),
            "aot and c must run where a C compiler exists:\n{report}"
        );
    } else {
        // Not a silent pass: say it, as `ladderc test` does.
        assert!(report.contains("skipped aot:"), "{report}");
        assert!(report.contains("skipped c:"), "{report}");
        println!("aot and c engines skipped: no C compiler on this machine");
    }
}

#[test]
fn every_reject_scenario_names_its_diagnostic_code() {
    let files = ladderc::scenario::collect_files(&scenarios_dir()).expect("the scenario folder");
    let mut missing = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let scenario = ladderc::scenario::parse_scenario(&file, &text).expect("scenarios parse");
        if let Some((_, None, line)) = scenario.expected_reject() {
            missing.push(format!("{}:{line}", file.display()));
        }
    }
    assert!(
        missing.is_empty(),
        "`expect reject LINE` without its code (E0013, ...):\n{}",
        missing.join("\n")
    );
}
