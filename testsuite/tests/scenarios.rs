//! Runs `ladderc test` over every scenario in `scenarios/`, so `cargo test`
//! covers them. The report of `ladderc test` is shown when something fails.

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

#[test]
fn every_scenario_passes_on_the_interpreter() {
    let (status, report) = run(&[EngineKind::Interp]);
    assert_eq!(status, 0, "ladderc test failed:\n{report}");
    let (passed, failed) = summary(&report);
    assert_eq!(failed, 0, "{report}");
    assert!(
        passed >= 100,
        "expected the whole suite, found {passed} scenarios:\n{report}"
    );
    assert!(report.contains("engines: interp\n"), "{report}");
}
