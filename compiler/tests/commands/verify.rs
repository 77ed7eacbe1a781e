//! `ladderc verify` end to end: the verdict lines and the summary on
//! stdout, exit statuses, witnesses that `ladderc test` passes on every
//! engine, the JUnit report, diagnostics of a broken file (exit 2, nothing
//! written), `explain` of the property codes; the SAT-based engines alone
//! (`--engine sat`) and `--emit aiger`, whose models ABC (`berkeley-abc`)
//! checks for the whole property suite: an independent check of the
//! encoding.

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

#[test]
fn the_sat_engines_alone_give_the_same_verdicts() {
    let dir = scratch("sat");
    std::fs::write(dir.join("interlock.prop"), INTERLOCK).unwrap();
    let output = ladderc(&["verify", "interlock.prop", "--engine", "sat", "--witness", "w"], &dir);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert_eq!(
        text(&output.stdout),
        "interlock.prop:14: proved\ninterlock.prop:15: reached at scan 1\ninterlock.prop:16: proved\n\
         interlock.prop:17: violated at scan 1\n3 passed, 1 failed\n"
    );
    let test = ladderc(&["test", "w"], &dir);
    assert_eq!(test.status.code(), Some(0), "{}", text(&test.stdout));
    // Sixteen inputs in the cone: too many for the explicit-state search
    // alone, decided when the SAT-based engines take over.
    let contacts: String = (0..16).map(|n| format!("AND X{n:o}\n")).collect();
    let wide = format!("program <<\nLD M8000\n{contacts}OUT Y0\nLD Y0\nOUT Y1\n>>\nnever Y1 & !Y0\nreach Y1\n");
    std::fs::write(dir.join("wide.prop"), wide).unwrap();
    let explicit = ladderc(&["verify", "wide.prop", "--engine", "explicit"], &dir);
    assert!(
        text(&explicit.stdout).contains("unknown (65536 choices"),
        "{}",
        text(&explicit.stdout)
    );
    let auto = ladderc(&["verify", "wide.prop"], &dir);
    assert_eq!(
        text(&auto.stdout),
        "wide.prop:23: proved\nwide.prop:24: reached at scan 1\n2 passed, 0 failed\n"
    );
}

#[test]
fn emit_aiger_writes_one_property_or_nothing() {
    let dir = scratch("aiger");
    std::fs::write(dir.join("interlock.prop"), INTERLOCK).unwrap();
    let output = ladderc(
        &[
            "verify",
            "interlock.prop",
            "--emit",
            "aiger",
            "-o",
            "m.aig",
            "--property",
            "14",
        ],
        &dir,
    );
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let model = std::fs::read(dir.join("m.aig")).unwrap();
    let header = String::from_utf8_lossy(&model[..model.iter().position(|&b| b == b'\n').unwrap()]).to_string();
    let fields: Vec<u32> = header
        .strip_prefix("aig ")
        .expect("a binary AIGER header")
        .split(' ')
        .map(|f| f.parse().unwrap())
        .collect();
    // M I L O A: three inputs (X0-X2), one output, M = I + L + A.
    assert_eq!((fields[1], fields[3]), (3, 1), "{header}");
    assert_eq!(fields[0], fields[1] + fields[2] + fields[4], "{header}");
    // No property on that line: one error, exit 2, the old file kept.
    let refused = ladderc(
        &[
            "verify",
            "interlock.prop",
            "--emit",
            "aiger",
            "-o",
            "m.aig",
            "--property",
            "3",
        ],
        &dir,
    );
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        text(&refused.stderr).contains("no property on line 3 (properties are on lines 14, 15, 16, 17)"),
        "{}",
        text(&refused.stderr)
    );
    assert_eq!(
        std::fs::read(dir.join("m.aig")).unwrap(),
        model,
        "the existing file is kept"
    );
    let without_output = ladderc(&["verify", "interlock.prop", "--emit", "aiger"], &dir);
    assert_eq!(without_output.status.code(), Some(2), "--emit needs -o and --property");
}

/// ABC's verdict on an AIGER model: `Ok(None)` proved, `Ok(Some(frame))`
/// the output asserted in that frame.
fn abc(command: &str, model: &std::path::Path) -> Result<Option<u32>, String> {
    let output = std::process::Command::new("berkeley-abc")
        .arg("-c")
        .arg(format!("read_aiger {}; {command}", model.display()))
        .output()
        .map_err(|e| e.to_string())?;
    let stdout = text(&output.stdout);
    if stdout.contains("Property proved") {
        return Ok(None);
    }
    let frame = stdout
        .split("was asserted in frame ")
        .nth(1)
        .and_then(|rest| rest.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok());
    frame.map(Some).ok_or(stdout)
}

#[test]
fn abc_agrees_with_every_exact_model_of_the_property_suite() {
    if let Err(why) = crate::common::tools::ensure("berkeley-abc", &["-c", "quit"], &["berkeley-abc"]) {
        crate::common::tools::skip("abc_agrees_with_every_exact_model_of_the_property_suite", &why);
        return;
    }
    let suite = crate::common::tools::workspace().join("testsuite/properties");
    let dir = scratch("abc");
    let mut files: Vec<PathBuf> = Vec::new();
    let mut folders = vec![suite.clone()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "prop") {
                files.push(path);
            }
        }
    }
    files.sort();
    let (mut exact, mut problems) = (0, Vec::new());
    for file in &files {
        let source = std::fs::read_to_string(file).unwrap();
        for (number, line) in source.lines().enumerate() {
            let Some((_, expected)) = line.split_once("# expect: ") else {
                continue;
            };
            let number = (number + 1).to_string();
            let model = dir.join(format!("{}-{number}.aig", file.file_stem().unwrap().to_string_lossy()));
            let place = format!("{}:{number}", file.display());
            let file_arg = file.to_string_lossy();
            let emitted = ladderc(
                &[
                    "verify",
                    &file_arg,
                    "--emit",
                    "aiger",
                    "-o",
                    &model.to_string_lossy(),
                    "--property",
                    &number,
                ],
                &dir,
            );
            let stderr = text(&emitted.stderr);
            if emitted.status.code() != Some(0) {
                // Only what the SAT-based engines do not encode is refused.
                if !stderr.contains("cannot be written as AIGER") {
                    problems.push(format!("{place}: {stderr}"));
                }
                continue;
            }
            let abc_verdict = match abc("pdr -T 120", &model) {
                Ok(verdict) => verdict,
                Err(output) => {
                    problems.push(format!("{place}: ABC said {output}"));
                    continue;
                }
            };
            let scan: Option<u32> = expected
                .trim()
                .rsplit(' ')
                .next()
                .and_then(|n| n.parse().ok())
                .filter(|_| expected.contains(" at scan "));
            if stderr.contains("arbitrary") {
                // An over-approximation: ABC's proof must still be one.
                if abc_verdict.is_none() && scan.is_some() {
                    problems.push(format!("{place}: ABC proves what ladderc finds broken ({expected})"));
                }
                continue;
            }
            exact += 1;
            match (abc_verdict, scan) {
                (None, None) => {}
                (Some(_), Some(scan)) => {
                    // PDR's counterexample need not be the shortest; BMC's is.
                    match abc(&format!("bmc3 -F {}", scan + 1), &model) {
                        Ok(Some(frame)) if frame == scan => {}
                        other => problems.push(format!("{place}: expected scan {scan}, ABC's bmc3 says {other:?}")),
                    }
                }
                (abc_verdict, _) => problems.push(format!("{place}: expected {expected}, ABC says {abc_verdict:?}")),
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(exact >= 45, "ABC checked {exact} exact models");
}
