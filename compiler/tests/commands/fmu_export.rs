//! `ladderc build --emit fmu` checked by FMPy (from PyPI) as importers
//! check FMUs: every example and the GX Works2 sample validate as FMI 3.0
//! and 2.0; FMPy stepping the traffic light at 100 ms sees the lamps
//! `ladderc run --scans 70 --scan-ms 100` prints, scan by scan; an input
//! signal drives a seal-in as the program says; the FMU state saved,
//! serialised and restored replays the same steps, and steps shorter than
//! the scan period carry over. Without FMPy the tests say why they skip.

use crate::common::tools::{ensure_python_module, ladderc, scratch, skip, workspace};
use std::path::{Path, PathBuf};

const CHECKS: &str = include_str!("fmpy_checks.py");

fn fmpy_ready(test: &str) -> bool {
    match ensure_python_module("fmpy", "fmpy") {
        Ok(()) => true,
        Err(why) => {
            skip(test, &why);
            false
        }
    }
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Builds `program` as an FMU with `extra` arguments into `dir`.
fn build(program: &Path, dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let fmu = dir.join(name);
    let mut args = vec![
        "build",
        program.to_str().unwrap(),
        "--emit",
        "fmu",
        "-o",
        fmu.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let output = ladderc(&args);
    assert!(output.status.success(), "{name}: {}", text(&output.stderr));
    fmu
}

/// Runs a check of `fmpy_checks.py`: its JSON answer.
fn check(dir: &Path, args: &[&str]) -> serde_json::Value {
    let script = dir.join("fmpy_checks.py");
    std::fs::write(&script, CHECKS).unwrap();
    let output = std::process::Command::new("python3")
        .arg(&script)
        .args(args)
        .output()
        .unwrap();
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{args:?}: {stdout}{}", text(&output.stderr));
    serde_json::from_str(stdout.lines().last().unwrap_or("")).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

#[test]
fn every_example_and_the_gx_works2_sample_validate_as_fmi_3_and_2() {
    if !fmpy_ready("every_example_and_the_gx_works2_sample_validate_as_fmi_3_and_2") {
        return;
    }
    let dir = scratch("fmu_validate");
    let mut programs: Vec<PathBuf> = std::fs::read_dir(workspace().join("examples"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|x| x == "il"))
        .collect();
    programs.push(workspace().join("testsuite/programs/gxworks2/gxworks2_fx2n_main.csv"));
    assert!(programs.len() >= 3, "{programs:?}");
    let mut fmus = Vec::new();
    for program in &programs {
        let stem = program.file_stem().unwrap().to_string_lossy().into_owned();
        for fmi in ["3", "2"] {
            fmus.push(build(
                program,
                dir.path(),
                &format!("{stem}.fmi{fmi}.fmu"),
                &["--fmi", fmi],
            ));
        }
    }
    let mut args = vec!["validate"];
    args.extend(fmus.iter().map(|fmu| fmu.to_str().unwrap()));
    let problems = check(dir.path(), &args);
    for fmu in &fmus {
        assert_eq!(
            problems[fmu.to_str().unwrap()],
            serde_json::json!([]),
            "{}",
            fmu.display()
        );
    }
}

#[test]
fn fmpy_steps_the_traffic_light_as_ladderc_run_scans_it() {
    if !fmpy_ready("fmpy_steps_the_traffic_light_as_ladderc_run_scans_it") {
        return;
    }
    let dir = scratch("fmu_traffic_light");
    let program = workspace().join("examples/traffic_light.il");
    let run = ladderc(&[
        "run",
        program.to_str().unwrap(),
        "--scans",
        "70",
        "--scan-ms",
        "100",
        "--watch",
        "Y0..Y2",
        "--format",
        "csv",
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let expected: Vec<Vec<i64>> = text(&run.stdout)
        .lines()
        .skip(1)
        .map(|line| line.split(',').skip(1).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(expected.len(), 70);
    for fmi in ["3", "2"] {
        let fmu = build(
            &program,
            dir.path(),
            &format!("light{fmi}.fmu"),
            &["--fmi", fmi, "--scan-ms", "100"],
        );
        let seen = check(dir.path(), &["lamps", fmu.to_str().unwrap(), "70"]);
        assert_eq!(seen, serde_json::json!(expected), "FMI {fmi}");
    }
}

#[test]
fn an_input_signal_drives_a_seal_in_and_the_state_replays() {
    if !fmpy_ready("an_input_signal_drives_a_seal_in_and_the_state_replays") {
        return;
    }
    let dir = scratch("fmu_seal_in");
    let program = dir.path().join("seal_in.il");
    std::fs::write(&program, "LD X0\nOR Y0\nANI X1\nOUT Y0\n").unwrap();
    for fmi in ["3", "2"] {
        let fmu = build(&program, dir.path(), &format!("seal{fmi}.fmu"), &["--fmi", fmi]);
        let rows = check(dir.path(), &["seal_in", fmu.to_str().unwrap()]);
        for row in rows.as_array().unwrap() {
            let (time, y0) = (row[0].as_f64().unwrap(), row[1].as_i64().unwrap());
            // X0 from 0.2 s to 0.3 s sets it; X1 from 0.6 s resets it; the
            // scan of the step after each edge takes it.
            let expected = i64::from((0.205..0.605).contains(&time));
            assert_eq!(y0, expected, "FMI {fmi}, t = {time}: {rows}");
        }
    }
    let light = workspace().join("examples/traffic_light.il");
    for fmi in ["3", "2"] {
        let fmu = build(&light, dir.path(), &format!("light{fmi}.fmu"), &["--fmi", fmi]);
        let seen = check(dir.path(), &["state", fmu.to_str().unwrap()]);
        assert_eq!(seen["again"], seen["first"], "FMI {fmi}: restored, the same steps");
        assert_eq!(
            seen["from_bytes"], seen["first"],
            "FMI {fmi}: deserialised, the same steps"
        );
        // Green comes on with scan 31; half steps reach it at the sixth.
        let mut half = vec![serde_json::json!([1, 0, 0]); 5];
        half.push(serde_json::json!([1, 0, 1]));
        assert_eq!(seen["half_steps"], serde_json::json!(half), "FMI {fmi}");
        assert_eq!(seen["first"][2], serde_json::json!([1, 0, 1]), "FMI {fmi}: {seen}");
        assert_eq!(seen["foreign_state"], "refused", "FMI {fmi}: a state not of this FMU");
    }
}

#[test]
fn inputs_are_what_the_program_only_reads_and_outputs_what_it_or_the_scan_writes() {
    if !fmpy_ready("inputs_are_what_the_program_only_reads_and_outputs_what_it_or_the_scan_writes") {
        return;
    }
    let dir = scratch("fmu_causality");
    let light = build(
        &workspace().join("examples/traffic_light.il"),
        dir.path(),
        "light.fmu",
        &[],
    );
    let seen = check(dir.path(), &["causality", light.to_str().unwrap()]);
    for (name, causality) in [
        ("time", "independent"),
        ("scan_period", "parameter"),
        ("X0", "input"),
        ("Y0", "output"),
        // The scan writes the special relays and the timers.
        ("SM0", "output"),
        ("M8002", "output"),
        ("T0", "output"),
        ("TN0", "output"),
        ("S0", "output"),
    ] {
        assert_eq!(seen[name], causality, "{name}: {seen}");
    }
    // BMOV and FMOV write through a runtime helper's destination: outputs;
    // what they only read stays an input.
    let program = dir.path().join("moves.il");
    std::fs::write(
        &program,
        "LD X0\nBMOV D0 D100 K4\nLD X1\nFMOV K7 D200 K3\nLD= D50 K1\nOUT Y0\n",
    )
    .unwrap();
    let moves = build(&program, dir.path(), "moves.fmu", &[]);
    let seen = check(dir.path(), &["causality", moves.to_str().unwrap()]);
    for (name, causality) in [
        ("D0", "input"),
        ("D3", "input"),
        ("D100", "output"),
        ("D103", "output"),
        ("D200", "output"),
        ("D202", "output"),
        ("D50", "input"),
    ] {
        assert_eq!(seen[name], causality, "{name}: {seen}");
    }
}

#[test]
fn pairs_and_reals_the_program_uses_as_such_are_variables() {
    if !fmpy_ready("pairs_and_reals_the_program_uses_as_such_are_variables") {
        return;
    }
    let dir = scratch("fmu_wide");
    let program = dir.path().join("wide.il");
    std::fs::write(&program, "LD M8000\nDMOV D0 D10\nDEADD D20 E1.5 D22\n").unwrap();
    for fmi in ["3", "2"] {
        let fmu = build(&program, dir.path(), &format!("wide{fmi}.fmu"), &["--fmi", fmi]);
        // D0:32 = 100000 and D20:float = 2.25 as inputs; the program copies
        // the pair and adds 1.5 to the real.
        let seen = check(dir.path(), &["wide", fmu.to_str().unwrap()]);
        assert_eq!(
            seen,
            serde_json::json!({"D10:32": 100000.0, "D22:float": 3.75, "D10": -31072.0, "D11": 1.0}),
            "FMI {fmi}"
        );
    }
}

#[test]
fn a_failed_fmu_build_writes_nothing_and_keeps_what_was_there() {
    let dir = scratch("fmu_refused");
    let bad = dir.path().join("bad.il");
    std::fs::write(&bad, "LD X0\nOUT Q7\n").unwrap();
    let fmu = dir.path().join("bad.fmu");
    std::fs::write(&fmu, b"an older FMU").unwrap();
    let output = ladderc(&[
        "build",
        bad.to_str().unwrap(),
        "--emit",
        "fmu",
        "-o",
        fmu.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert_eq!(std::fs::read(&fmu).unwrap(), b"an older FMU");
    let good = workspace().join("examples/motor_start_stop.il");
    for (args, message) in [
        (&["--target", "aarch64-unknown-linux-gnu"][..], "built for this machine"),
        (&["--scan-ms", "0"][..], "--scan-ms is 1 to 60000"),
        (&["-o", "-"][..], "an FMU is a file"),
        (&["--image", "compact"][..], "do not go with --emit fmu"),
    ] {
        let mut all = vec!["build", good.to_str().unwrap(), "--emit", "fmu"];
        all.extend_from_slice(args);
        let output = ladderc(&all);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(
            text(&output.stderr).contains(message),
            "{args:?}: {}",
            text(&output.stderr)
        );
    }
    let output = ladderc(&["build", good.to_str().unwrap(), "--fmi", "2", "-o", "-"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("go with --emit fmu"));
}

#[test]
fn a_closed_loop_with_a_plant_fmu_fills_and_empties_the_tank() {
    let test = "a_closed_loop_with_a_plant_fmu_fills_and_empties_the_tank";
    let example = workspace().join("examples/cosim");
    // The controller passes its own scenario on every engine first.
    let scenario = ladderc(&["test", example.join("tank.scn").to_str().unwrap()]);
    assert_eq!(scenario.status.code(), Some(0), "{}", text(&scenario.stdout));
    if !fmpy_ready(test) {
        return;
    }
    if let Err(why) = ensure_python_module("pythonfmu", "pythonfmu") {
        skip(test, &why);
        return;
    }
    let dir = scratch("fmu_closed_loop");
    let controller = build(
        &example.join("tank.il"),
        dir.path(),
        "tank.fmu",
        &["--fmi", "2", "--scan-ms", "100"],
    );
    let plant = std::process::Command::new("python3")
        .args(["-m", "pythonfmu", "build", "-f"])
        .arg(example.join("tank_plant.py"))
        .arg("-d")
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(plant.status.success(), "pythonfmu: {}", text(&plant.stderr));
    let output = std::process::Command::new("python3")
        .arg(example.join("tank_loop.py"))
        .arg(&controller)
        .arg(dir.path().join("TankPlant.fmu"))
        .arg("20")
        .output()
        .unwrap();
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", text(&output.stderr));
    let run: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap_or("")).unwrap();
    let level: Vec<f64> = run["level"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let inlet = run["inlet"].as_array().unwrap();
    let outlet = run["outlet"].as_array().unwrap();
    assert!(level.len() >= 199, "{}", level.len());
    // Never both valves at once.
    assert!(inlet
        .iter()
        .zip(outlet)
        .all(|(i, o)| i.as_i64().unwrap() + o.as_i64().unwrap() <= 1));
    // Filled to the high switch (and the few steps past it the switch, the
    // scan and the valve take, never to overflowing), then drained to the
    // low switch, again and again.
    let peak = level.iter().cloned().fold(0.0, f64::max);
    assert!(peak > 0.9 && peak < 1.0, "peak {peak}");
    let after_first_fill = level.iter().position(|&l| l > 0.9).expect("filled");
    let trough = level[after_first_fill..].iter().cloned().fold(1.0, f64::min);
    assert!(trough > 0.0 && trough <= 0.1, "trough {trough}");
    let rises = level.windows(2).filter(|w| w[0] < 0.5 && w[1] >= 0.5).count();
    assert!(rises >= 3, "the tank filled {rises} times in 20 s: {level:?}");
}
