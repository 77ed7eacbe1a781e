//! `ladderc serve` left running: retained devices survive SIGTERM and
//! `kill -9` (at most one save interval lost), a damaged, cut-short or
//! foreign retain file is refused and left as it was, the latched ranges
//! follow `--latch` (or a project's `//@ latch` line); the statistics have a resettable window with
//! percentiles; D8010-D8012 show the scan time.

use crate::common::server::{http, json, Server};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// D200 (latched on an FX3U) and D0 (not) count scans; C100 (latched)
/// counts the 0.1 s clock; M600 (latched) is set by X0.
const COUNTING: &str = "LD M8000\nINC D200\nINC D0\nLD M8012\nOUT C100 K30000\nLD X0\nSET M600\n";

fn value(web: std::net::SocketAddr, device: &str) -> i64 {
    let body = json(&http(web, "GET", &format!("/api/devices?watch={device}"), "").1);
    body["devices"][device]
        .as_i64()
        .unwrap_or_else(|| panic!("{device} in {body}"))
}

fn start(retain: &Path, extra: &[&str]) -> Server {
    let mut args = vec!["--http", "127.0.0.1:0", "--retain", retain.to_str().unwrap()];
    args.extend_from_slice(extra);
    Server::start_program(COUNTING, &args)
}

/// Waits until a scan has run after a restart (the image is published).
fn first_scans(web: std::net::SocketAddr) {
    let deadline = Instant::now() + Duration::from_secs(10);
    while json(&http(web, "GET", "/api/devices?watch=D0", "").1)["scan"].as_u64() < Some(2) {
        assert!(Instant::now() < deadline, "no scan after start");
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn latched_devices_survive_kill_9_losing_at_most_one_interval() {
    let dir = tempfile::tempdir().unwrap();
    let retain = dir.path().join("plc.retain");
    // 10 ms scans, a save every 100 ms: one interval is 10 scans.
    let interval_scans = 10;
    let mut before = 0;
    for round in 0..4 {
        let server = start(&retain, &["--retain-ms", "100"]);
        let web = server.web.unwrap();
        first_scans(web);
        // D0 (not latched) and D200 (latched) both count every scan: read
        // together, their difference is what was restored.
        let both = json(&http(web, "GET", "/api/devices?watch=D0,D200", "").1);
        let (d0, d200) = (
            both["devices"]["D0"].as_i64().unwrap(),
            both["devices"]["D200"].as_i64().unwrap(),
        );
        let restored = d200 - d0;
        if round > 0 {
            // Never below the value last seen minus what one interval (and
            // a late save) holds.
            assert!(restored > 0, "round {round}: D200 was not restored ({both})");
            assert!(
                restored + 3 * interval_scans >= before,
                "round {round}: D200 restored as {restored}, {before} was read just before kill -9"
            );
            assert_eq!(value(web, "M600"), 1, "M600 set in the first round stays set");
        } else {
            http(web, "POST", "/api/set", r#"{"device": "X0", "value": 1}"#);
        }
        std::thread::sleep(Duration::from_millis(250 + 50 * round as u64));
        before = value(web, "D200");
        server.kill();
    }
    assert!(before > 80, "D200 counted on through the restarts: {before}");
}

#[test]
fn a_clean_stop_saves_and_a_restart_restores_counters_and_relays() {
    let dir = tempfile::tempdir().unwrap();
    let retain = dir.path().join("plc.retain");
    // No save before the stop: the interval is an hour.
    let server = start(&retain, &["--retain-ms", "3600000"]);
    let web = server.web.unwrap();
    http(web, "POST", "/api/set", r#"{"device": "X0", "value": 1}"#);
    std::thread::sleep(Duration::from_millis(400));
    let (counted, stopped_at) = (value(web, "CN100"), value(web, "D200"));
    assert!(counted >= 2, "CN100 counts the 0.1 s clock: {counted}");
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
    let server = start(&retain, &[]);
    let web = server.web.unwrap();
    first_scans(web);
    assert!(value(web, "CN100") >= counted);
    assert!(value(web, "D200") >= stopped_at);
    assert_eq!(value(web, "M600"), 1);
    server.stop();
}

#[test]
fn latch_chooses_the_kept_ranges() {
    let dir = tempfile::tempdir().unwrap();
    let retain = dir.path().join("plc.retain");
    let server = start(&retain, &["--latch", "D0-D9"]);
    let web = server.web.unwrap();
    std::thread::sleep(Duration::from_millis(200));
    let d0 = value(web, "D0");
    server.stop();
    let server = start(&retain, &["--latch", "D0-D9"]);
    let web = server.web.unwrap();
    first_scans(web);
    assert!(value(web, "D0") >= d0, "D0 kept with --latch D0-D9");
    assert!(value(web, "D200") < d0, "D200 not kept with --latch D0-D9");
    server.stop();
}

#[test]
fn a_narrower_latch_restores_only_its_ranges_and_a_cut_short_save_is_cleaned_up() {
    let dir = tempfile::tempdir().unwrap();
    let retain = dir.path().join("plc.retain");
    // Saved with FX3U's ranges: D200-D7999 among them.
    let server = start(&retain, &[]);
    let web = server.web.unwrap();
    first_scans(web);
    assert_eq!(
        http(web, "POST", "/api/set", r#"{"device":"D300","value":"77"}"#).0,
        200
    );
    let deadline = Instant::now() + Duration::from_secs(5);
    while value(web, "D300") != 77 {
        assert!(Instant::now() < deadline, "D300 is written");
        std::thread::sleep(Duration::from_millis(10));
    }
    server.stop();
    // A save cut short by a kill leaves its temporary file.
    let leftover = dir.path().join("plc.retain.tmp");
    std::fs::write(&leftover, b"half a save").unwrap();
    let server = start(&retain, &["--latch", "D200-D299"]);
    let web = server.web.unwrap();
    first_scans(web);
    assert_eq!(value(web, "D300"), 0, "D300 is not latched now: not restored");
    assert!(value(web, "D200") > 0, "D200 is latched: restored");
    let said = server.said.join("\n");
    assert!(said.contains("restored D200-D299"), "{said}");
    assert!(said.contains("D300-D7999") && said.contains("not restored"), "{said}");
    assert!(said.contains("removed") && !leftover.exists(), "{said}");
    server.stop();
    // `none`: nothing comes back.
    let server = start(&retain, &["--latch", "none"]);
    let web = server.web.unwrap();
    first_scans(web);
    assert!(value(web, "D200") < 100, "D200 restarted with --latch none");
    server.stop();
}

/// `serve --retain FILE` where FILE cannot be used: the exit status, what
/// it said; the server must end by itself.
fn refused(retain: &Path) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("plc.il");
    std::fs::write(&program, COUNTING).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args([
            "serve",
            program.to_str().unwrap(),
            "--modbus",
            "127.0.0.1:0",
            "--retain",
        ])
        .arg(retain)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(20);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the server started with an unusable retain file");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn a_cut_short_damaged_or_foreign_file_is_refused_and_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let retain = dir.path().join("plc.retain");
    let server = start(&retain, &[]);
    std::thread::sleep(Duration::from_millis(100));
    server.stop();
    let good = std::fs::read(&retain).expect("the stop wrote the file");

    let cases: [(&str, Vec<u8>, &str); 4] = [
        ("cut short", good[..good.len() / 2].to_vec(), "is cut short"),
        ("header only", good[..10].to_vec(), "not a ladderc retain file"),
        (
            "damaged",
            {
                let mut damaged = good.clone();
                let middle = damaged.len() / 2;
                damaged[middle] ^= 0x55;
                damaged
            },
            "checksum does not match",
        ),
        ("foreign", b"D200=5\n".to_vec(), "not a ladderc retain file"),
    ];
    for (what, bytes, says) in cases {
        std::fs::write(&retain, &bytes).unwrap();
        let (code, stderr) = refused(&retain);
        assert_eq!(code, Some(2), "{what}: {stderr}");
        assert!(stderr.contains(says), "{what}: {stderr}");
        assert!(stderr.contains("nothing was restored"), "{what}: {stderr}");
        assert_eq!(std::fs::read(&retain).unwrap(), bytes, "{what}: the file was changed");
    }
}

#[test]
fn a_latch_list_that_names_other_devices_is_an_error() {
    let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(["serve", "nonexistent.il", "--retain", "x.retain", "--latch", "Y0-Y7"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("only M, S, T, C, D and R devices can be latched"),
        "{stderr}"
    );
}

#[test]
fn statistics_have_a_resettable_window_and_d8010_shows_the_scan_time() {
    let server = Server::start_program(COUNTING, &["--http", "127.0.0.1:0", "--scan-ms", "10"]);
    let web = server.web.unwrap();
    std::thread::sleep(Duration::from_millis(500));
    let stats = json(&http(web, "GET", "/api/stats", "").1);
    let window = &stats["jitter_window"];
    assert!(window["scans"].as_u64().unwrap() >= 20, "{stats}");
    let (p50, p99, max) = (
        window["p50_us"].as_f64().unwrap(),
        window["p99_us"].as_f64().unwrap(),
        window["max_us"].as_f64().unwrap(),
    );
    assert!(p50 <= p99 && p99 <= max, "{stats}");
    assert!(stats["jitter_average_us"].as_f64().unwrap() <= max, "{stats}");
    // D8010: the latest scan's time in 0.1 ms; with 10 ms scans about 100.
    // Scans are due on a fixed grid, so the scan after one that started
    // late (a busy machine) reports less than the period: only the largest
    // (D8012) must reach it.
    let d8010 = value(web, "D8010");
    assert!((10..=400).contains(&d8010), "D8010 = {d8010}");
    let (d8011, d8012) = (value(web, "D8011"), value(web, "D8012"));
    assert!(
        d8011 <= d8010 && d8010 <= d8012,
        "D8011 {d8011}, D8010 {d8010}, D8012 {d8012}"
    );
    assert!(d8012 >= 95, "D8012 = {d8012}");
    let (status, _) = http(web, "POST", "/api/stats/reset", "");
    assert_eq!(status, 200);
    let after = json(&http(web, "GET", "/api/stats", "").1);
    assert!(
        after["scans"].as_u64().unwrap() < stats["scans"].as_u64().unwrap(),
        "{after}"
    );
    assert!(after["jitter_window"]["scans"].as_u64().unwrap() < 20, "{after}");
    server.stop();
}

#[test]
fn a_projects_latch_line_chooses_the_kept_ranges_unless_latch_says_otherwise() {
    // A GX Developer project's listing carries its parameters' latched
    // ranges as `//@ latch`.
    let program = format!("//@ cpu FX2N\n//@ latch D0-D9\n{COUNTING}");
    let dir = tempfile::tempdir().unwrap();
    let retain = dir.path().join("plc.retain");
    let args = |extra: &[&'static str]| {
        let mut args = vec!["--http", "127.0.0.1:0", "--retain", retain.to_str().unwrap()];
        args.extend_from_slice(extra);
        args.into_iter().map(str::to_string).collect::<Vec<_>>()
    };
    let run = |extra: &[&'static str]| {
        let owned = args(extra);
        let borrowed: Vec<&str> = owned.iter().map(String::as_str).collect();
        Server::start_program(&program, &borrowed)
    };
    let server = run(&[]);
    let web = server.web.unwrap();
    std::thread::sleep(Duration::from_millis(200));
    let d0 = value(web, "D0");
    server.stop();
    let server = run(&[]);
    let web = server.web.unwrap();
    first_scans(web);
    assert!(value(web, "D0") >= d0, "D0 kept by the program's //@ latch D0-D9");
    assert!(value(web, "D200") < d0, "D200 not kept by //@ latch D0-D9");
    server.stop();
    let server = run(&["--latch", "D200-D299"]);
    let web = server.web.unwrap();
    first_scans(web);
    assert!(value(web, "D0") < d0, "--latch D200-D299 wins over //@ latch");
    server.stop();
}
