//! Watching a program run and reporting tests, through the real command
//! line: `run --stimulus`, `--vcd` (parsed back with the vcd crate, and
//! converted by GTKWave's vcd2fst where it installs), `--format json`,
//! `--watch` ranges, `--force`, operation errors as they occur, `--stats`;
//! `test --junit` (checked for the JUnit structure CI tools need), `test
//! --vcd`, and the `print` directive.

use crate::common::tools::{self, ladderc, scratch, workspace};
use std::path::Path;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

const FLASHER: &str = "LD X0\nANI T1\nOUT T0 K2\nLD T0\nOUT T1 K2\nOUT Y0\nLD X1\nMOV K1 D0[D1]\n";

/// The program and a stimulus: X0 ON from the first scan, X1 for one scan
/// with D1 far out of range (an operation error), one failing expectation.
fn files(dir: &Path) -> (String, String) {
    let program = dir.join("flasher.il");
    std::fs::write(&program, FLASHER).unwrap();
    let stimulus = dir.join("drive.scn");
    std::fs::write(
        &stimulus,
        "scan-ms 100\nset X0 1\nscan 3\nprint T0,TN0\nexpect Y0 1\nset X1 1\nset D1 9000\nscan\nexpect Y0 0  # fails: Y0 is still ON\n",
    )
    .unwrap();
    (program.display().to_string(), stimulus.display().to_string())
}

#[test]
fn a_stimulus_drives_the_run_and_its_expectations_are_checked() {
    let dir = scratch("stimulus");
    let (program, stimulus) = files(dir.path());
    let output = ladderc(&[
        "run",
        &program,
        "--stimulus",
        &stimulus,
        "--watch",
        "X0,Y0,TN0",
        "--engine",
        "interp",
    ]);
    assert_eq!(output.status.code(), Some(1), "a failed expectation");
    let stdout = text(&output.stdout);
    let rows: Vec<&str> = stdout.lines().collect();
    assert_eq!(rows.len(), 5, "a header and four scans:\n{stdout}");
    assert!(
        rows[3].ends_with("1   1      2") || rows[3].split_whitespace().eq(["3", "1", "1", "2"]),
        "{stdout}"
    );
    let stderr = text(&output.stderr);
    assert!(stderr.contains("drive.scn:9: expected Y0 = 0, got 1"), "{stderr}");
    assert!(stderr.contains("line 4 after scan 3: T0 = 1, TN0 = 2"), "{stderr}");
    assert!(stderr.contains("scan 4: operation error 4086H at line 8"), "{stderr}");
}

#[test]
fn json_output_is_one_object_per_scan() {
    let dir = scratch("json");
    let (program, _) = files(dir.path());
    let output = ladderc(&[
        "run",
        &program,
        "--scans",
        "3",
        "--scan-ms",
        "100",
        "--set",
        "X0=1",
        "--set",
        "X1=1",
        "--set",
        "D1=9000",
        "--format",
        "json",
        "--watch",
        "Y0,TN0..TN1",
        "--radix",
        "hex",
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let scans: Vec<serde_json::Value> = text(&output.stdout)
        .lines()
        .map(|line| serde_json::from_str(line).expect("a JSON object"))
        .collect();
    assert_eq!(scans.len(), 3);
    assert_eq!(scans[2]["scan"], 3);
    assert_eq!(scans[2]["time_ms"], 300);
    assert_eq!(scans[2]["devices"]["TN0"], "H0002");
    assert_eq!(scans[0]["error"]["code"], "4086H", "the error in the scan it occurred");
    assert!(scans[1].get("error").is_none(), "reported once: {}", scans[1]);
}

#[test]
fn forces_and_statistics() {
    let dir = scratch("force");
    let (program, _) = files(dir.path());
    let output = ladderc(&[
        "run", &program, "--scans", "2", "--force", "Y0=1", "--stats", "--watch", "Y0",
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(
        text(&output.stdout).lines().skip(1).all(|l| l.ends_with('1')),
        "{}",
        text(&output.stdout)
    );
    assert!(
        text(&output.stderr).contains("scan time over 2 scans: min"),
        "{}",
        text(&output.stderr)
    );
    let twice = ladderc(&["run", &program, "--set", "X0=1", "--set", "X0=0"]);
    assert_eq!(twice.status.code(), Some(2), "a device set twice is refused");
}

/// A signal's name and width.
type Signal = (String, u32);
/// A value change: time, signal name, value as 0/1 digits.
type Change = (u64, String, String);

/// The signals of a VCD file and its value changes.
// vcd's `Command` is non-exhaustive: the reader takes the few it checks.
#[allow(clippy::wildcard_enum_match_arm)]
fn parse_vcd(path: &Path) -> (Vec<Signal>, Vec<Change>) {
    let mut parser = vcd::Parser::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let header = parser.parse_header().unwrap();
    let mut names = std::collections::HashMap::new();
    let mut signals = Vec::new();
    for item in &header.items {
        if let vcd::ScopeItem::Scope(scope) = item {
            for inner in &scope.items {
                if let vcd::ScopeItem::Var(var) = inner {
                    names.insert(var.code, var.reference.clone());
                    signals.push((var.reference.clone(), var.size));
                }
            }
        }
    }
    let mut time = 0;
    let mut changes = Vec::new();
    for command in parser {
        match command.unwrap() {
            vcd::Command::Timestamp(t) => time = t,
            vcd::Command::ChangeScalar(code, value) => changes.push((time, names[&code].clone(), value.to_string())),
            vcd::Command::ChangeVector(code, value) => changes.push((
                time,
                names[&code].clone(),
                value.iter().map(|v| v.to_string()).collect(),
            )),
            _ => {}
        }
    }
    (signals, changes)
}

/// The last timestamp of a VCD file: where a viewer's time axis ends.
// vcd's `Command` is non-exhaustive: the reader takes the few it checks.
#[allow(clippy::wildcard_enum_match_arm)]
fn last_timestamp(path: &Path) -> u64 {
    let mut parser = vcd::Parser::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    parser.parse_header().unwrap();
    parser
        .filter_map(|command| match command.unwrap() {
            vcd::Command::Timestamp(t) => Some(t),
            _ => None,
        })
        .max()
        .unwrap_or(0)
}

fn check_with_gtkwave(test: &str, vcd: &Path) {
    match tools::ensure("vcd2fst", &["--help"], &["gtkwave"]) {
        Ok(()) => {
            let fst = vcd.with_extension("fst");
            let output = std::process::Command::new("vcd2fst")
                .arg(vcd)
                .arg(&fst)
                .output()
                .unwrap();
            assert!(output.status.success(), "{}", text(&output.stderr));
            assert!(
                std::fs::metadata(&fst).unwrap().len() > 0,
                "GTKWave's converter read the file"
            );
        }
        Err(why) => tools::skip(test, &why),
    }
}

#[test]
fn run_writes_a_waveform_gtkwave_reads() {
    let dir = scratch("vcd");
    let (program, stimulus) = files(dir.path());
    let vcd = dir.path().join("run.vcd");
    let output = ladderc(&[
        "run",
        &program,
        "--stimulus",
        &stimulus,
        "--watch",
        "Y0,TN0,D0:32",
        "--vcd",
        vcd.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1), "the stimulus has a failing expectation");
    let (signals, changes) = parse_vcd(&vcd);
    assert_eq!(signals, [("Y0".into(), 1), ("TN0".into(), 16), ("D0:32".into(), 32)]);
    // Y0 turns ON at t = 300 ms (the third 100 ms scan); TN0 counts 1, 2.
    assert!(changes.contains(&(0, "Y0".into(), "0".into())), "{changes:?}");
    assert!(changes.contains(&(300, "Y0".into(), "1".into())), "{changes:?}");
    assert!(
        changes.contains(&(300, "TN0".into(), format!("{:016b}", 2))),
        "{changes:?}"
    );
    assert!(
        !changes.iter().any(|(t, name, _)| *t == 200 && name == "Y0"),
        "only changes are written"
    );
    assert_eq!(
        last_timestamp(&vcd),
        400,
        "the waveform ends where the run ended (4 scans of 100 ms)"
    );
    check_with_gtkwave("run_writes_a_waveform_gtkwave_reads", &vcd);
}

#[test]
fn test_reports_junit_and_waveforms_of_failures() {
    let dir = scratch("junit");
    std::fs::write(dir.path().join("flasher.il"), FLASHER).unwrap();
    std::fs::write(
        dir.path().join("good.scn"),
        "program flasher.il\nscan-ms 100\nset X0 1\nscan 3\nprint TN0\nexpect Y0 1\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("bad.scn"),
        "program flasher.il\nset X0 1\nscan\nexpect Y0 1\n",
    )
    .unwrap();
    let junit = dir.path().join("report.xml");
    let waves = dir.path().join("waves");
    let output = ladderc(&[
        "test",
        dir.path().to_str().unwrap(),
        "--engine",
        "interp",
        "--junit",
        junit.to_str().unwrap(),
        "--vcd",
        waves.to_str().unwrap(),
        "-v",
    ]);
    assert_eq!(output.status.code(), Some(1));
    let stdout = text(&output.stdout);
    assert!(
        stdout.contains("[interp] after scan 3: TN0 = 2"),
        "print shown with -v:\n{stdout}"
    );
    let failing: Vec<_> = std::fs::read_dir(&waves).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(failing.len(), 1, "one waveform, of the failing scenario: {failing:?}");
    assert!(failing[0].to_string_lossy().ends_with("bad.interp.vcd"), "{failing:?}");
    let (signals, _) = parse_vcd(&failing[0]);
    assert!(
        signals.iter().any(|(n, _)| n == "X0") && signals.iter().any(|(n, _)| n == "Y0"),
        "{signals:?}"
    );
    check_junit(&std::fs::read_to_string(&junit).unwrap());
}

#[test]
fn test_html_shows_the_ladder_and_waveform_at_a_failure() {
    let dir = scratch("html");
    std::fs::write(dir.path().join("flasher.il"), FLASHER).unwrap();
    std::fs::write(
        dir.path().join("bad.scn"),
        "program flasher.il\nscan-ms 100\nset X0 1\nscan 3\nexpect Y0 0\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("good.scn"), "program flasher.il\nscan\nexpect Y0 0\n").unwrap();
    let pages = dir.path().join("pages");
    let output = ladderc(&[
        "test",
        dir.path().to_str().unwrap(),
        "--engine",
        "interp",
        "--html",
        pages.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let written: Vec<_> = std::fs::read_dir(&pages).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(written.len(), 1, "a page for the failing scenario only: {written:?}");
    assert!(written[0].to_string_lossy().ends_with("bad.interp.html"), "{written:?}");
    let page = std::fs::read_to_string(&written[0]).unwrap();
    assert!(page.contains("line 5: expected Y0 = 0, got 1"), "the failure");
    assert!(page.contains("(after scan 3, 300 ms)"), "when");
    // The ladder as the engine left it: LD X0 (instruction 0) closed, the
    // coil of Y0 ON, T0's current value under its coil.
    assert!(page.contains(r#"<g class="cell contact on" data-e="0">"#), "X0 closed");
    assert!(page.contains(r#"<g class="cell coil on" data-e="5">"#), "Y0 ON");
    assert!(page.contains("class=\"wave\""), "a waveform");
    assert!(page.contains(">X0<") && page.contains(">Y0<"), "its signals");
}

/// The structure JUnit consumers require: `testsuites` of `testsuite`
/// (name, tests, failures, errors) of `testcase` (name, classname), a
/// failure with its message.
// quick-xml's events: the reader takes the elements and passes over the rest.
#[allow(clippy::wildcard_enum_match_arm)]
fn check_junit(xml: &str) {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(xml);
    let (mut stack, mut suites, mut cases, mut failures) = (Vec::<String>::new(), 0, 0, Vec::new());
    loop {
        let event = reader.read_event().expect("well-formed XML");
        let (element, empty) = match &event {
            Event::Start(e) => (Some(e.clone()), false),
            Event::Empty(e) => (Some(e.clone()), true),
            Event::End(_) => {
                stack.pop();
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let Some(element) = element else { continue };
        let name = String::from_utf8_lossy(element.name().as_ref()).into_owned();
        let attribute = |key: &str| {
            element
                .attributes()
                .flatten()
                .find(|a| a.key.as_ref() == key.as_bytes())
                .map(|a| String::from_utf8_lossy(&a.value).into_owned())
        };
        let parent = stack.last().cloned().unwrap_or_default();
        match name.as_str() {
            "testsuites" => assert!(stack.is_empty()),
            "testsuite" => {
                assert_eq!(parent, "testsuites");
                for key in ["name", "tests", "failures", "errors"] {
                    assert!(attribute(key).is_some(), "testsuite without {key}");
                }
                suites += 1;
            }
            "testcase" => {
                assert_eq!(parent, "testsuite");
                assert!(attribute("name").is_some() && attribute("classname").is_some());
                cases += 1;
            }
            "failure" => {
                assert_eq!(parent, "testcase");
                failures.push(attribute("message").expect("a failure message"));
            }
            _ => {}
        }
        if !empty {
            stack.push(name);
        }
    }
    assert_eq!((suites, cases), (2, 2), "{xml}");
    assert_eq!(failures, ["expected Y0 = 1, got 0"], "{xml}");
    assert!(xml.contains("bad.scn:4: expected Y0 = 1, got 0"), "the line: {xml}");
}

/// The scenario files a JUnit report holds (a testsuite per file).
fn junit_files(xml: &str) -> Vec<String> {
    xml.split("<testsuite ")
        .skip(1)
        .filter_map(|suite| {
            let name = suite.split("name=\"").nth(1)?;
            Some(name[..name.find('"')?].to_string())
        })
        .collect()
}

#[test]
fn shards_split_a_suite_into_equal_disjoint_shares_with_a_report_each() {
    let dir = scratch("shards");
    let suite = workspace().join("testsuite/scenarios/fx_structure");
    let mut shares = Vec::new();
    for k in 1..=3 {
        let junit = dir.path().join(format!("shard{k}.xml"));
        let output = ladderc(&[
            "test",
            suite.to_str().unwrap(),
            "--engine",
            "interp",
            "--shard",
            &format!("{k}/3"),
            "--junit",
            junit.to_str().unwrap(),
        ]);
        let stdout = text(&output.stdout);
        assert_eq!(output.status.code(), Some(0), "{stdout}{}", text(&output.stderr));
        assert!(stdout.starts_with(&format!("shard {k}/3: ")), "{stdout}");
        shares.push(junit_files(&std::fs::read_to_string(&junit).unwrap()));
    }
    let total = std::fs::read_dir(&suite)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "scn"))
        .count();
    let mut all: Vec<&String> = shares.iter().flatten().collect();
    assert_eq!(all.len(), total, "every file in one shard: {shares:?}");
    all.sort();
    all.dedup();
    assert_eq!(all.len(), total, "no file in two shards: {shares:?}");
    let sizes: Vec<usize> = shares.iter().map(Vec::len).collect();
    assert!(
        sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1,
        "{sizes:?}"
    );
    // The same shard twice is the same share.
    let again = ladderc(&["test", suite.to_str().unwrap(), "--engine", "interp", "--shard", "2/3"]);
    assert!(text(&again.stdout).starts_with(&format!("shard 2/3: {} of {total}", sizes[1])));
    for wrong in ["0/3", "4/3", "3", "a/b"] {
        let output = ladderc(&["test", suite.to_str().unwrap(), "--shard", wrong]);
        assert_eq!(output.status.code(), Some(2), "{wrong}");
        assert!(text(&output.stderr).contains("is not a shard like 2/4"), "{wrong}");
    }
}
