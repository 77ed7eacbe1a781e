//! The `ladderc` binary end to end: exit statuses, diagnostics on stderr,
//! tables on stdout.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn ladderc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("ladderc runs")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ladderc-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn check_reports_location_code_and_underline() {
    let dir = temp_dir("check");
    std::fs::write(dir.join("bad.il"), "LD X0\n  LDD X1\nOUT Y0\n").unwrap();
    let output = ladderc(&["check", "bad.il"], &dir);
    assert_eq!(output.status.code(), Some(1));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("error[E0001]: unknown instruction `LDD`"), "{stderr}");
    assert!(stderr.contains("bad.il:2:3"), "{stderr}");
    assert!(stderr.contains("2 │   LDD X1\n  │   ^^^"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn check_accepts_good_programs_and_shows_warnings() {
    let dir = temp_dir("good");
    std::fs::write(dir.join("ok.il"), "LD X0\nOUT Y0\nEND\nLD X1\nOUT Y1\n").unwrap();
    let output = ladderc(&["check", "ok.il"], &dir);
    assert_eq!(output.status.code(), Some(0));
    assert!(text(&output.stderr).contains("warning[W0001]"));
}

#[test]
fn unreadable_files_exit_2() {
    let dir = temp_dir("missing");
    assert_eq!(ladderc(&["check", "nope.il"], &dir).status.code(), Some(2));
    assert_eq!(ladderc(&["run", "nope.il"], &dir).status.code(), Some(2));
    let output = ladderc(&["test", "nope.scn"], &dir);
    assert_eq!(output.status.code(), Some(2));
    std::fs::write(dir.join("bad.scn"), "program p.il\nfrobnicate\n").unwrap();
    let output = ladderc(&["test", "bad.scn"], &dir);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("bad.scn:2: error: unknown directive"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn run_prints_a_table_or_csv() {
    let dir = temp_dir("run");
    std::fs::write(dir.join("p.il"), "LD X0\nOUT Y0\nLD X0\nINC D0\n").unwrap();
    let output = ladderc(
        &["run", "p.il", "--scans", "3", "--set", "X0=1", "--watch", "Y0,D0"],
        &dir,
    );
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert_eq!(
        text(&output.stdout),
        "scan  Y0      D0\n   1   1       1\n   2   1       2\n   3   1       3\n"
    );
    let output = ladderc(
        &["run", "p.il", "--scans", "2", "--format", "csv", "--watch", "D0"],
        &dir,
    );
    assert_eq!(text(&output.stdout), "scan,D0\n1,0\n2,0\n");
    let output = ladderc(&["run", "p.il", "--scans", "1"], &dir);
    assert_eq!(
        text(&output.stdout),
        "scan  Y0\n   1   0\n",
        "default watch: the driven Y coils"
    );
    let output = ladderc(&["run", "p.il", "--set", "Q9=1"], &dir);
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn test_reports_failures_and_summary() {
    let dir = temp_dir("test");
    std::fs::write(
        dir.join("a.scn"),
        "program <<\nLD X0\nOUT Y0\n>>\nset X0 1\nscan\nexpect Y0 1\nexpect Y0 0\n",
    )
    .unwrap();
    std::fs::write(dir.join("b.scn"), "program <<\nLD X0\nOUT Y0\n>>\nscan\nexpect Y0 0\n").unwrap();
    let output = ladderc(&["test", ".", "--engine", "interp"], &dir);
    assert_eq!(output.status.code(), Some(1));
    let stdout = text(&output.stdout);
    assert!(stdout.contains("a.scn:8: [interp] expected Y0 = 0, got 1"), "{stdout}");
    assert_eq!(stdout.lines().last(), Some("1 passed, 1 failed"));
}

#[test]
fn explain_prints_the_explanation() {
    let dir = temp_dir("explain");
    let output = ladderc(&["explain", "E0010"], &dir);
    assert_eq!(output.status.code(), Some(0));
    assert!(text(&output.stdout).starts_with("E0010: ANB/ORB without two blocks"));
    assert_eq!(ladderc(&["explain", "E9999"], &dir).status.code(), Some(2));
}
