//! `ladderc verify` end to end: the verdict lines and the summary on
//! stdout, exit statuses, witnesses that `ladderc test` passes on every
//! engine, the JUnit report, diagnostics of a broken file (exit 2, nothing
//! written), `explain` of the property codes.

use crate::cli::{ladderc, text};
use std::path::PathBuf;

/// A fresh folder of this test's own.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ladderc-verify-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const INTERLOCK: &str = "program <<
LD X0          // forward button
OR Y0
ANI X2         // stop
ANI Y1         // interlock
OUT Y0
LD X1          // reverse button
OR Y1
ANI X2
ANI Y0
OUT Y1
>>
scan-ms 10
never Y0 & Y1                        # proved
reach Y1                             # reached at scan 1
respond X2 -> !Y0 & !Y1 within 0     # proved
always X0 -> Y0                      # violated at scan 1
";

#[test]
fn verdicts_summary_witnesses_and_junit() {
    let dir = scratch("interlock");
    std::fs::write(dir.join("interlock.prop"), INTERLOCK).unwrap();
    let output = ladderc(
        &["verify", "interlock.prop", "--witness", "w", "--junit", "report.xml"],
        &dir,
    );
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert_eq!(
        text(&output.stdout),
        "interlock.prop:14: proved\ninterlock.prop:15: reached at scan 1\ninterlock.prop:16: proved\n\
         interlock.prop:17: violated at scan 1\n3 passed, 1 failed\n"
    );
    let mut written: Vec<String> = std::fs::read_dir(dir.join("w"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["interlock-15.scn", "interlock-17.scn"]);
    // The witnesses show what they claim on every engine.
    let test = ladderc(&["test", "w"], &dir);
    assert_eq!(
        test.status.code(),
        Some(0),
        "{}{}",
        text(&test.stdout),
        text(&test.stderr)
    );
    assert!(
        text(&test.stdout).contains("2 passed, 0 failed"),
        "{}",
        text(&test.stdout)
    );
    let junit = std::fs::read_to_string(dir.join("report.xml")).unwrap();
    assert!(
        junit.contains("tests=\"4\"") && junit.contains("failures=\"1\""),
        "{junit}"
    );
    assert!(junit.contains("violated at scan 1"), "{junit}");
}

#[test]
fn all_passed_is_exit_zero() {
    let dir = scratch("passed");
    let proved = INTERLOCK.replace("always X0 -> Y0", "always X0 & !X2 & !prev(Y1) & !X1 -> Y0");
    std::fs::write(dir.join("p.prop"), proved).unwrap();
    let output = ladderc(&["verify", "."], &dir);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
    assert!(
        text(&output.stdout).ends_with("4 passed, 0 failed\n"),
        "{}",
        text(&output.stdout)
    );
}

#[test]
fn unknown_is_counted_and_fails() {
    let dir = scratch("unknown");
    std::fs::write(
        dir.join("deep.prop"),
        "program <<\nLD X0\nOUT C0 K151\nLD C0\nOUT Y0\n>>\ninput X0\nnever Y0\n",
    )
    .unwrap();
    let output = ladderc(&["verify", "deep.prop", "--depth", "50"], &dir);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        text(&output.stdout),
        "deep.prop:8: unknown (depth 50 reached (--depth))\n0 passed, 0 failed, 1 unknown\n"
    );
}

#[test]
fn a_broken_file_is_diagnosed_and_nothing_written() {
    let dir = scratch("broken");
    std::fs::write(
        dir.join("bad.prop"),
        "program <<\nLD X0\nOUT Y0\n>>\nnever Y0 & M9000\nrespond X0 -> Y0 within\nalways X0 -> Y0\n",
    )
    .unwrap();
    let output = ladderc(&["verify", "bad.prop", "--witness", "w", "--junit", "r.xml"], &dir);
    assert_eq!(output.status.code(), Some(2));
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("error[E0050]") && stderr.contains("bad.prop:5:12"),
        "{stderr}"
    );
    assert!(
        stderr.contains("5 │ never Y0 & M9000\n  │            ^^^^^"),
        "{stderr}"
    );
    assert!(stderr.contains("error[E0049]: `within` without a number"), "{stderr}");
    assert!(!dir.join("w").exists(), "no witness folder for a broken file");
    assert!(!dir.join("r.xml").exists(), "no report for a broken file");
    let explained = ladderc(&["explain", "E0051"], &dir);
    assert_eq!(explained.status.code(), Some(0));
    assert!(
        text(&explained.stdout).contains("a bit used as a word"),
        "{}",
        text(&explained.stdout)
    );
}
