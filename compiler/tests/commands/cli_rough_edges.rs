//! Regression tests for rough edges of the command line, each found by
//! trying it as a user would.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn ladderc(args: &[&str], dir: &Path) -> Output {
    ladderc_with_input(args, dir, &[])
}

fn ladderc_with_input(args: &[&str], dir: &Path, input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("ladderc runs");
    let _ = child.stdin.take().expect("stdin").write_all(input);
    child.wait_with_output().expect("ladderc ends")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ladderc-edges-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn a_folder_without_scenarios_is_an_error() {
    let dir = temp_dir("empty");
    std::fs::create_dir_all(dir.join("none")).unwrap();
    let output = ladderc(&["test", "none"], &dir);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("no scenario files"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn a_closing_marker_with_trailing_blanks_closes_the_program() {
    let dir = temp_dir("marker");
    std::fs::write(
        dir.join("a.scn"),
        "program <<\nLD X0\nOUT Y0\n>>  \t\nset X0 1\nscan\nexpect Y0 1\n",
    )
    .unwrap();
    let output = ladderc(&["test", "a.scn", "--engine", "interp"], &dir);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
}

#[test]
fn inline_program_diagnostics_name_the_scenario_line() {
    let dir = temp_dir("inline");
    std::fs::write(
        dir.join("bad.scn"),
        "# a comment\nprogram <<\nLD X0\nOUTT Y0\n>>\nscan\n",
    )
    .unwrap();
    let output = ladderc(&["test", "bad.scn", "--engine", "interp"], &dir);
    let stdout = text(&output.stdout);
    assert!(stdout.contains("bad.scn (program):2:1"), "{stdout}");
    assert!(stdout.contains("line 4 of bad.scn"), "{stdout}");
}

#[test]
fn a_dash_is_standard_input_and_output() {
    let dir = temp_dir("dash");
    let program = b"LD X0\nOUT Y0\n";
    let object = ladderc_with_input(&["build", "-", "-o", "-"], &dir, program);
    assert_eq!(object.status.code(), Some(0), "{}", text(&object.stderr));
    assert!(object.stdout.starts_with(b"\x7fELF"), "an object file on stdout");
    assert!(!dir.join("-").exists() && !dir.join("-.o").exists());
    let run = ladderc_with_input(&["run", "-", "--set", "X0=1"], &dir, program);
    assert!(text(&run.stdout).contains("1   1"), "{}", text(&run.stdout));
    let check = ladderc_with_input(&["check", "-"], &dir, b"LD X0\nOUTT Y0\n");
    assert_eq!(check.status.code(), Some(1));
    assert!(text(&check.stderr).contains("<stdin>:2:1"), "{}", text(&check.stderr));
}

#[test]
fn an_unsupported_target_lists_the_supported_ones() {
    let dir = temp_dir("target");
    std::fs::write(dir.join("p.il"), "LD X0\nOUT Y0\n").unwrap();
    let output = ladderc(
        &["build", "p.il", "--target", "mips-unknown-linux-gnu", "-o", "p.o"],
        &dir,
    );
    assert_eq!(output.status.code(), Some(2), "a bad argument");
    let stderr = text(&output.stderr);
    for needle in [
        "aarch64-unknown-linux-gnu",
        "riscv64gc-unknown-linux-gnu",
        "thumbv7em-none-eabihf",
        "--emit c",
    ] {
        assert!(stderr.contains(needle), "{stderr}");
    }
    assert!(!dir.join("p.o").exists());
}

#[test]
fn explain_without_a_code_lists_every_code_and_completions_are_printed() {
    let dir = temp_dir("explain");
    let output = ladderc(&["explain"], &dir);
    assert_eq!(output.status.code(), Some(0));
    let stdout = text(&output.stdout);
    assert!(
        stdout.contains("E0001  unknown instruction") && stdout.contains("W0003"),
        "{stdout}"
    );
    let completions = ladderc(&["completions", "bash"], &dir);
    assert_eq!(completions.status.code(), Some(0));
    assert!(text(&completions.stdout).contains("ladderc"));
    for help in [&["test", "--help"][..], &["explain", "--help"]] {
        let output = ladderc(help, &dir);
        assert!(text(&output.stdout).contains("Scenario files") || text(&output.stdout).contains("A code such as"));
    }
}

#[test]
fn sets_that_cannot_work_say_why() {
    let dir = temp_dir("sets");
    std::fs::write(dir.join("p.il"), "LD X0\nOUT C0 K5\n").unwrap();
    let counter = ladderc(&["run", "p.il", "--set", "C0=5"], &dir);
    assert_eq!(counter.status.code(), Some(2));
    assert!(text(&counter.stderr).contains("CN0"), "{}", text(&counter.stderr));
    let system = ladderc(&["run", "p.il", "--set", "SM0=0"], &dir);
    assert_eq!(system.status.code(), Some(0));
    assert!(
        text(&system.stderr).contains("does not last"),
        "{}",
        text(&system.stderr)
    );
}

#[test]
fn a_malformed_operand_is_underlined_whole() {
    let dir = temp_dir("caret");
    std::fs::write(dir.join("p.il"), "LD Q110\nOUT Y0\n").unwrap();
    let output = ladderc(&["check", "p.il"], &dir);
    assert!(
        text(&output.stderr).contains("LD Q110\n  │    ^^^^ "),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn outputs_never_overwrite_scenarios_programs_or_stimuli() {
    let dir = temp_dir("outputs");
    std::fs::write(dir.join("p.il"), "LD X0\nOUT Y0\n").unwrap();
    std::fs::write(dir.join("a.scn"), "program p.il\nset X0 1\nscan\nexpect Y0 1\n").unwrap();
    for junit in ["a.scn", "p.il"] {
        let output = ladderc(&["test", "a.scn", "--engine", "interp", "--junit", junit], &dir);
        assert_eq!(output.status.code(), Some(2), "{junit}: {}", text(&output.stderr));
    }
    let output = ladderc(&["run", "p.il", "--stimulus", "a.scn", "--vcd", "a.scn"], &dir);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output.stderr));
    assert_eq!(
        std::fs::read_to_string(dir.join("a.scn")).unwrap(),
        "program p.il\nset X0 1\nscan\nexpect Y0 1\n"
    );
    assert_eq!(std::fs::read_to_string(dir.join("p.il")).unwrap(), "LD X0\nOUT Y0\n");
    // A folder that does not exist is refused before the run.
    let output = ladderc(&["run", "p.il", "--scans", "3", "--vcd", "missing/x.vcd"], &dir);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stdout).is_empty(), "nothing ran: {}", text(&output.stdout));
}

#[test]
fn a_suite_no_engine_could_run_is_not_a_pass() {
    let dir = temp_dir("noengine");
    std::fs::write(dir.join("a.scn"), "program <<\nLD X0\nOUT Y0\n>>\nscan\n").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(["test", "a.scn", "--engine", "aot"])
        .current_dir(&dir)
        .env("PATH", "/nonexistent")
        .env_remove("CC")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", text(&output.stdout));
    assert!(text(&output.stdout).contains("skipped aot"), "{}", text(&output.stdout));
}
