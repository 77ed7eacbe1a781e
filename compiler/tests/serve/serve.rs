//! `ladderc serve` as a soft PLC, started as a real process on loopback and
//! talked to by a real Modbus TCP client (tokio-modbus's): inputs written
//! through the input-image coils drive the program across scans, outputs and
//! registers are read back, bad addresses and functions get exception
//! responses, `--read-only` refuses writes, many clients poll at once while
//! the scan keeps its period, and SIGTERM stops it cleanly with statistics.

use crate::common;

use crate::common::server::{http, json, Server};

use std::io::BufReader;
use std::net::SocketAddr;
use std::process::Command;
use std::time::Duration;
use tokio_modbus::prelude::*;

async fn settle() {
    // Several scan periods: a write applies before the next scan, the image
    // is published after it.
    tokio::time::sleep(Duration::from_millis(60)).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_modbus_client_drives_the_program_across_scans() {
    let server = Server::start(&[]);
    let mut ctx = tcp::connect(server.address).await.unwrap();
    assert_eq!(ctx.read_coils(0, 1).await.unwrap().unwrap(), [false]);
    // X0 ON through the input image: Y0 seals in.
    ctx.write_single_coil(20000, true).await.unwrap().unwrap();
    settle().await;
    assert_eq!(ctx.read_discrete_inputs(0, 1).await.unwrap().unwrap(), [true]);
    ctx.write_single_coil(20000, false).await.unwrap().unwrap();
    settle().await;
    assert_eq!(ctx.read_coils(0, 1).await.unwrap().unwrap(), [true], "sealed in");
    // T0 times in real time: 100 ms units, preset 5.
    tokio::time::sleep(Duration::from_millis(600)).await;
    assert_eq!(ctx.read_input_registers(0, 1).await.unwrap().unwrap(), [5]);
    // X1 breaks the seal; X2 makes D5 = 123; X3 drives M10 (coil 1010).
    ctx.write_multiple_coils(20001, &[true, true, true])
        .await
        .unwrap()
        .unwrap();
    settle().await;
    assert_eq!(ctx.read_coils(0, 1).await.unwrap().unwrap(), [false]);
    assert_eq!(ctx.read_holding_registers(5, 1).await.unwrap().unwrap(), [123]);
    assert_eq!(ctx.read_coils(1010, 1).await.unwrap().unwrap(), [true]);
    // Holding registers are D: written, then read back after a scan.
    ctx.write_multiple_registers(100, &[7, 0xFFFF]).await.unwrap().unwrap();
    settle().await;
    assert_eq!(ctx.read_holding_registers(100, 2).await.unwrap().unwrap(), [7, 0xFFFF]);
    // Outside the mapping: illegal data address; other functions: illegal function.
    assert_eq!(
        ctx.read_coils(300, 1).await.unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    assert_eq!(
        ctx.read_holding_registers(8510, 5).await.unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    assert_eq!(ctx.write_single_coil(255, true).await.unwrap(), Ok(()));
    assert_eq!(
        ctx.read_write_multiple_registers(0, 1, 0, &[1]).await.unwrap(),
        Err(ExceptionCode::IllegalFunction)
    );
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains(" scans: scan time min"), "{stderr}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn read_only_refuses_every_write() {
    let server = Server::start(&["--read-only"]);
    let mut ctx = tcp::connect(server.address).await.unwrap();
    assert_eq!(
        ctx.write_single_coil(20000, true).await.unwrap(),
        Err(ExceptionCode::IllegalFunction)
    );
    assert_eq!(
        ctx.write_single_register(0, 1).await.unwrap(),
        Err(ExceptionCode::IllegalFunction)
    );
    assert_eq!(ctx.read_coils(0, 8).await.unwrap().unwrap(), [false; 8]);
    let (code, _) = server.stop();
    assert_eq!(code, Some(0));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn many_clients_poll_while_the_scan_keeps_its_period() {
    let server = Server::start(&[]);
    let address = server.address;
    let clients: Vec<_> = (0..20)
        .map(|_| {
            tokio::spawn(async move {
                let mut ctx = tcp::connect(address).await.unwrap();
                for _ in 0..1000 {
                    ctx.read_holding_registers(0, 100).await.unwrap().unwrap();
                }
            })
        })
        .collect();
    for client in clients {
        client.await.unwrap();
    }
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
    eprintln!("under 20 clients x 1000 requests: {stderr}");
    let overruns: u64 = stderr
        .split("; ")
        .find_map(|part| part.strip_suffix(" overruns\n").or(part.strip_suffix(" overruns")))
        .and_then(|n| n.trim().parse().ok())
        .expect("the overrun count");
    let scans: u64 = stderr
        .split_whitespace()
        .next()
        .and_then(|n| n.parse().ok())
        .expect("the scan count");
    // The test machine runs other tests at the same time: a scan may start
    // late now and then, but not as a rule.
    assert!(overruns * 20 <= scans, "the scan kept its period: {stderr}");
}

#[test]
fn a_non_loopback_address_needs_an_explicit_flag() {
    let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(["serve", "examples/motor_start_stop.il", "--modbus", "0.0.0.0:5020"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--allow-remote"));
}

#[test]
fn the_json_api_reads_writes_and_refuses_bad_requests() {
    let server = Server::start(&["--http", "127.0.0.1:0"]);
    let web = server.web.unwrap();
    let (status, body) = http(web, "POST", "/api/set", r#"{"device": "D7", "value": 9}"#);
    assert_eq!(status, 200, "{body}");
    let (status, _) = http(web, "POST", "/api/set", r#"{"device": "X2", "value": "on"}"#);
    assert_eq!(status, 200);
    std::thread::sleep(Duration::from_millis(80));
    let (status, body) = http(web, "GET", "/api/devices?watch=D7,D5,X2", "");
    assert_eq!(status, 200);
    let value = json(&body);
    assert_eq!(value["devices"]["D7"], 9);
    assert_eq!(value["devices"]["D5"], 123, "X2 ran MOV K123 D5: {body}");
    assert!(value["scan"].as_u64().unwrap() > 0);
    // Forcing Y0 ON holds it whatever the program does.
    let (status, _) = http(web, "POST", "/api/force", r#"{"device": "Y0", "value": 1}"#);
    assert_eq!(status, 200);
    std::thread::sleep(Duration::from_millis(80));
    assert_eq!(
        json(&http(web, "GET", "/api/devices?watch=Y0", "").1)["devices"]["Y0"],
        1
    );
    // Bad requests: clear errors, and the server keeps running.
    for (path, body, expected) in [
        ("/api/set", "{not json", 400),
        ("/api/set", r#"{"device": "Q5", "value": 1}"#, 400),
        ("/api/set", r#"{"device": "D0"}"#, 400),
        ("/api/force", r#"{"device": "D0", "value": 1}"#, 400),
        ("/api/devices?watch=M99999", "", 400),
    ] {
        let method = if body.is_empty() { "GET" } else { "POST" };
        let (status, answer) = http(web, method, path, body);
        assert_eq!(status, expected, "{path} {body}: {answer}");
        assert!(json(&answer)["error"].is_string(), "{answer}");
    }
    let huge = format!(r#"{{"device": "D0", "value": "{}"}}"#, "9".repeat(200_000));
    assert_eq!(http(web, "POST", "/api/set", &huge).0, 413, "a size cap on uploads");
    let (status, body) = http(web, "GET", "/api/stats", "");
    assert_eq!(status, 200);
    assert!(json(&body)["scans"].as_u64().unwrap() > 0);
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn values_are_pushed_as_server_sent_events() {
    use std::io::{BufRead, Write};
    let server = Server::start(&["--http", "127.0.0.1:0"]);
    let mut stream = std::net::TcpStream::connect(server.web.unwrap()).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    write!(
        stream,
        "GET /api/events?watch=Y0,TN0 HTTP/1.1\r\nHost: {}\r\n\r\n",
        server.web.unwrap()
    )
    .unwrap();
    let events: Vec<serde_json::Value> = BufReader::new(stream)
        .lines()
        .map_while(Result::ok)
        .filter_map(|line| line.strip_prefix("data: ").map(json))
        .take(3)
        .collect();
    assert_eq!(events.len(), 3);
    assert!(events[2]["scan"].as_u64() > events[0]["scan"].as_u64(), "{events:?}");
    assert!(events[0]["devices"].get("TN0").is_some());
    server.stop();
}

/// A program for the debugger: D0 counts scans, Y0 follows X0, S0 is the
/// active step while M0 is OFF.
const COUNTING: &str = "LD M8000\nINC D0\nLD X0\nOUT Y0\nLD M8002\nSET S0\nSTL S0\nLD M0\nSET S1\nSTLE\n";

impl Server {
    /// `program` served with `--http` and a Modbus port, 20 ms scans.
    fn start_with(program: &str) -> Server {
        Server::start_program(program, &["--http", "127.0.0.1:0", "--scan-ms", "20"])
    }
}

/// Waits until `check` holds, up to 5 s: what a scan or two makes true
/// comes true however busy the machine is.
fn eventually(what: &str, mut check: impl FnMut() -> bool) {
    let deadline = std::time::Instant::now() + Duration::from_secs(5);
    while !check() {
        assert!(std::time::Instant::now() < deadline, "{what}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn scan_of(web: SocketAddr) -> u64 {
    json(&http(web, "GET", "/api/devices?watch=D0", "").1)["scan"]
        .as_u64()
        .unwrap()
}

#[test]
fn stop_pause_step_and_breakpoints_through_the_api() {
    let server = Server::start_with(COUNTING);
    let web = server.web.unwrap();
    let control = |action: &str| json(&http(web, "POST", "/api/control", &format!(r#"{{"action": "{action}"}}"#)).1);
    // STOP: Y OFF, no scans, writes still apply.
    http(web, "POST", "/api/set", r#"{"device": "X0", "value": 1}"#);
    let y0 = || json(&http(web, "GET", "/api/devices?watch=Y0", "").1)["devices"]["Y0"].clone();
    eventually("Y0 follows X0", || y0() == 1);
    assert_eq!(control("stop")["mode"], "stop");
    eventually("STOP turns the outputs off", || y0() == 0);
    let stopped = json(&http(web, "GET", "/api/devices?watch=Y0,D0", "").1);
    assert_eq!(stopped["devices"]["Y0"], 0, "STOP turns the outputs off: {stopped}");
    http(web, "POST", "/api/set", r#"{"device": "D5", "value": 77}"#);
    std::thread::sleep(Duration::from_millis(150));
    let later = json(&http(web, "GET", "/api/devices?watch=D0,D5", "").1);
    assert_eq!(later["scan"], stopped["scan"], "no scan in STOP");
    assert_eq!(later["devices"]["D5"], 77, "a write applies in STOP");
    control("run");
    eventually("scans after RUN", || scan_of(web) > stopped["scan"].as_u64().unwrap());
    // Pause, then steps of exactly the scans asked for.
    control("pause");
    std::thread::sleep(Duration::from_millis(100));
    let paused = scan_of(web);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(scan_of(web), paused, "paused");
    for (scans, expected) in [(1, paused + 1), (3, paused + 4)] {
        http(
            web,
            "POST",
            "/api/control",
            &format!(r#"{{"action": "step", "scans": {scans}}}"#),
        );
        eventually("the steps ran", || scan_of(web) >= expected);
        // ...and no more than asked for.
        std::thread::sleep(Duration::from_millis(100));
        assert_eq!(scan_of(web), expected);
    }
    // A breakpoint pauses at the end of the scan where it turns true.
    let d0 = json(&http(web, "GET", "/api/devices?watch=D0", "").1)["devices"]["D0"]
        .as_i64()
        .unwrap();
    let target = d0 + 10;
    let (status, body) = http(
        web,
        "POST",
        "/api/breakpoints",
        &format!(r#"{{"condition": "D0 > {target}"}}"#),
    );
    assert_eq!(status, 200, "{body}");
    control("resume");
    let state = || json(&http(web, "GET", "/api/devices?watch=D0", "").1);
    eventually("the breakpoint pauses", || state()["control"]["paused"] == true);
    let state = state();
    assert_eq!(state["control"]["paused"], true, "{state}");
    assert_eq!(
        state["devices"]["D0"],
        target + 1,
        "paused at the first scan where D0 > {target}: {state}"
    );
    assert_eq!(state["control"]["hit"]["scan"], state["scan"], "{state}");
    for (body, expected) in [
        (r#"{"condition": "D0 >"}"#, 400),
        (r#"{"condition": "Q0 == 1"}"#, 400),
        (r#"{"condition": "M5 rises"}"#, 200),
    ] {
        let (status, answer) = http(web, "POST", "/api/breakpoints", body);
        assert_eq!(status, expected, "{body}: {answer}");
    }
    assert_eq!(http(web, "DELETE", "/api/breakpoints?id=999", "").0, 404);
    let (status, body) = http(web, "DELETE", "/api/breakpoints", "");
    assert_eq!(status, 200);
    assert_eq!(json(&body)["breakpoints"].as_array().map(Vec::len), Some(0));
    assert_eq!(http(web, "POST", "/api/control", r#"{"action": "jump"}"#).0, 400);
    assert_eq!(
        http(web, "POST", "/api/control", r#"{"action": "step", "scans": 0}"#).0,
        400
    );
    control("resume");
    server.stop();
}

#[test]
fn the_page_review_holds() {
    let server = Server::start_with(COUNTING);
    let web = server.web.unwrap();
    // Ranges, formats, 32-bit and float as `run --watch` takes them; T5 is T5.
    http(web, "POST", "/api/set", r#"{"device": "D10", "value": 255}"#);
    assert_eq!(
        http(web, "POST", "/api/set", r#"{"device": "D20:32", "value": 100000}"#).0,
        200
    );
    std::thread::sleep(Duration::from_millis(100));
    let (status, body) = http(
        web,
        "GET",
        "/api/devices?watch=Y0..Y2,T5,D10:hex,D10:bin,D20:32,D20:float",
        "",
    );
    assert_eq!(status, 200, "{body}");
    let value = json(&body);
    assert_eq!(
        value["names"],
        json(r#"["Y0","Y1","Y2","T5","D10:hex","D10:bin","D20:32","D20:float"]"#)
    );
    assert_eq!(value["text"]["D10:hex"], "H00FF");
    assert_eq!(value["text"]["D10:bin"], "0000000011111111");
    assert_eq!(value["devices"]["D20:32"], 100000, "not -31072: {body}");
    // An invalid name and too many devices are errors, not empty tables.
    let (status, body) = http(web, "GET", "/api/devices?watch=D0,Q7", "");
    assert_eq!(status, 400, "{body}");
    assert!(json(&body)["error"].as_str().unwrap().contains("Q7"), "{body}");
    let (status, body) = http(web, "GET", "/api/devices?watch=M0..M300", "");
    assert_eq!(status, 400);
    assert!(json(&body)["error"].as_str().unwrap().contains("256"), "{body}");
    // Forces: listed, one unforced with an empty value box, or all at once.
    for device in ["X0", "M7", "Y3"] {
        http(
            web,
            "POST",
            "/api/force",
            &format!(r#"{{"device": "{device}", "value": 1}}"#),
        );
    }
    std::thread::sleep(Duration::from_millis(100));
    let forces = json(&http(web, "GET", "/api/forces", "").1);
    assert_eq!(forces["forces"].as_array().map(Vec::len), Some(3), "{forces}");
    let (status, body) = http(web, "POST", "/api/unforce", r#"{"device": "M7", "value": ""}"#);
    assert_eq!(status, 200, "{body}");
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(
        json(&http(web, "GET", "/api/forces", "").1)["forces"]
            .as_array()
            .map(Vec::len),
        Some(2)
    );
    assert_eq!(json(&http(web, "POST", "/api/unforce-all", "{}").1)["unforced"], 2);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(json(&http(web, "GET", "/api/forces", "").1)["forces"], json("[]"));
    // Statistics reset.
    let (status, _) = http(web, "POST", "/api/stats/reset", "{}");
    assert_eq!(status, 200);
    assert!(json(&http(web, "GET", "/api/stats", "").1)["scans"].as_u64().unwrap() < 10);
    // 413 in JSON, for a program too.
    let huge = "LD X0\n".repeat(2_000_000);
    let (status, body) = http(web, "POST", "/api/program", &huge);
    assert_eq!(status, 413);
    assert!(json(&body)["error"].is_string(), "{body}");
    // The ladder and the states of its elements: Y0 ON after X0 ON.
    let (status, fragment) = http(web, "GET", "/api/ladder", "");
    assert_eq!(status, 200);
    assert!(
        fragment.contains("id=\"rung-0\"") && fragment.contains("INC"),
        "{fragment}"
    );
    http(web, "POST", "/api/set", r#"{"device": "X0", "value": 1}"#);
    std::thread::sleep(Duration::from_millis(100));
    let (status, body) = http(web, "GET", "/api/ladder/state?rungs=0,1,3", "");
    assert_eq!(status, 200, "{body}");
    let elements = json(&body)["elements"].as_array().unwrap().clone();
    // [instruction, on, forced, values]: LD X0 is instruction 2, OUT Y0 3.
    let on = |index: u64| elements.iter().find(|e| e[0] == index).map(|e| e[1].clone());
    assert_eq!(on(2), Some(json("1")), "{body}");
    assert_eq!(on(3), Some(json("1")), "{body}");
    assert_eq!(http(web, "GET", "/api/ladder/state?rungs=999", "").0, 400);
    server.stop();
}

#[test]
fn the_trend_gets_every_scan() {
    use std::io::{BufRead, Write};
    let server = Server::start_with(COUNTING);
    let mut stream = std::net::TcpStream::connect(server.web.unwrap()).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    write!(
        stream,
        "GET /api/events?watch=D0 HTTP/1.1\r\nHost: {}\r\n\r\n",
        server.web.unwrap()
    )
    .unwrap();
    let events: Vec<serde_json::Value> = BufReader::new(stream)
        .lines()
        .map_while(Result::ok)
        .filter_map(|line| line.strip_prefix("data: ").map(json))
        .take(6)
        .collect();
    // Every scan once, in order, across pushes: D0 counts scans, so the
    // samples' values are consecutive too.
    let samples: Vec<(u64, i64)> = events
        .iter()
        .flat_map(|e| e["samples"].as_array().cloned().unwrap_or_default())
        .map(|s| (s[0].as_u64().unwrap(), s[2].as_i64().unwrap()))
        .collect();
    assert!(samples.len() > 10, "{samples:?}");
    for pair in samples.windows(2) {
        assert_eq!(pair[1].0, pair[0].0 + 1, "a scan missing: {samples:?}");
        assert_eq!(pair[1].1, pair[0].1 + 1, "{samples:?}");
    }
    server.stop();
}

#[test]
fn the_monitor_page_is_a_live_ladder_in_a_real_browser() {
    let test = "the_monitor_page_is_a_live_ladder_in_a_real_browser";
    let server = Server::start_with(COUNTING);
    let web = server.web.unwrap();
    let mut browser = match common::browser::Browser::open(&format!("http://{web}/?watch=Y0,D0,X0"), 1500, 900) {
        Ok(browser) => browser,
        Err(why) => {
            eprintln!("SKIPPED {test}: {why}");
            println!("SKIPPED {test}: {why}");
            server.stop();
            return;
        }
    };
    let shots = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("monitor");
    std::fs::create_dir_all(&shots).unwrap();
    let wait = Duration::from_secs(10);
    // It sees the ladder: the rungs, with LD X0 (instruction 2) open.
    assert!(browser.wait_for("document.querySelectorAll('#ladder svg.ladder').length >= 4", wait));
    let contact = r#"document.querySelector('#ladder g.cell[data-e="2"]')"#;
    assert!(browser.wait_for(&format!("{contact} && !{contact}.classList.contains('on')"), wait));
    // The active step S0 (STL S0 is instruction 6) is highlighted.
    assert!(browser.wait_for(
        r#"document.querySelector('#ladder g.cell[data-e="6"]').classList.contains('on')"#,
        wait
    ));
    // A Modbus write of X0 closes the contact on the page.
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    runtime.block_on(async {
        let mut ctx = tcp::connect(server.address).await.unwrap();
        ctx.write_single_coil(20000, true).await.unwrap().unwrap();
    });
    assert!(
        browser.wait_for(&format!("{contact}.classList.contains('on')"), wait),
        "the contact of X0 turns ON after the Modbus write"
    );
    browser.screenshot(&shots.join("1-contact-on.png"));
    // A breakpoint typed into the page pauses the scans.
    let d0 = json(&http(web, "GET", "/api/devices?watch=D0", "").1)["devices"]["D0"]
        .as_i64()
        .unwrap();
    browser.eval(&format!(
        "document.getElementById('condition').value = 'D0 >= {}'; document.getElementById('break-form').requestSubmit(); true",
        d0 + 20
    ));
    assert!(browser.wait_for("document.getElementById('mode').textContent === 'PAUSED'", wait));
    assert!(browser.wait_for("document.getElementById('hit').textContent.includes('at scan')", wait));
    let shown_scan = "Number(document.getElementById('scan').textContent)";
    std::thread::sleep(Duration::from_millis(300));
    let paused_at = browser.eval(shown_scan).as_u64().unwrap();
    std::thread::sleep(Duration::from_millis(400));
    assert_eq!(
        browser.eval(shown_scan).as_u64().unwrap(),
        paused_at,
        "paused: the scan count stands"
    );
    assert_eq!(
        json(&http(web, "GET", "/api/devices?watch=D0", "").1)["devices"]["D0"],
        d0 + 20,
        "paused at the scan where D0 reached the condition"
    );
    browser.screenshot(&shots.join("2-breakpoint.png"));
    // Step: exactly one scan more.
    browser.eval("document.getElementById('step-count').value = '1'; document.getElementById('step').click(); true");
    assert!(browser.wait_for(&format!("{shown_scan} === {}", paused_at + 1), wait));
    std::thread::sleep(Duration::from_millis(400));
    assert_eq!(
        browser.eval(shown_scan).as_u64().unwrap(),
        paused_at + 1,
        "one step, one scan"
    );
    browser.screenshot(&shots.join("3-step.png"));
    browser.eval("document.getElementById('resume').click(); true");
    assert!(browser.wait_for("document.getElementById('mode').textContent === 'RUN'", wait));
    for shot in ["1-contact-on.png", "2-breakpoint.png", "3-step.png"] {
        let size = std::fs::metadata(shots.join(shot)).map(|m| m.len()).unwrap_or(0);
        assert!(size > 10_000, "{shot}: {size} bytes");
    }
    println!("screenshots in {}", shots.display());
    server.stop();
}

#[test]
fn online_change_swaps_programs_under_load_and_keeps_memory() {
    let server = Server::start(&["--http", "127.0.0.1:0"]);
    let web = server.web.unwrap();
    // Memory the new program must find: D7 from a host write, Y0 sealed in.
    assert_eq!(
        http(web, "POST", "/api/set", r#"{"device": "D7", "value": 4242}"#).0,
        200
    );
    assert_eq!(http(web, "POST", "/api/set", r#"{"device": "X0", "value": 1}"#).0, 200);
    std::thread::sleep(Duration::from_millis(60));
    assert_eq!(http(web, "POST", "/api/set", r#"{"device": "X0", "value": 0}"#).0, 200);
    std::thread::sleep(Duration::from_millis(60));
    // Clients poll the whole time.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let pollers: Vec<_> = (0..4)
        .map(|_| {
            let stop = std::sync::Arc::clone(&stop);
            std::thread::spawn(move || {
                let mut scans = Vec::new();
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    let (status, body) = http(web, "GET", "/api/devices?watch=D7", "");
                    assert_eq!(status, 200);
                    scans.push(json(&body)["scan"].as_u64().unwrap());
                }
                scans
            })
        })
        .collect();
    // A program that does not compile is refused; the old one goes on.
    let (status, body) = http(web, "POST", "/api/program", "LD X0\nOUTT Y0\n");
    assert_eq!(status, 422, "{body}");
    assert!(json(&body)["diagnostics"].as_str().unwrap().contains("E0001"), "{body}");
    // The new program: Y0 still sealed in by its own rung, D8 = D7 + 1.
    let new = "LD X0\nOR Y0\nANI X1\nOUT Y0\nLD SM0\nADD D7 K1 D8\n";
    let (status, body) = http(web, "POST", "/api/program", new);
    assert_eq!(status, 200, "{body}");
    assert_eq!(json(&body)["swapped"], true);
    std::thread::sleep(Duration::from_millis(60));
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    for poller in pollers {
        let scans = poller.join().unwrap();
        assert!(
            scans.windows(2).all(|w| w[0] <= w[1]),
            "the scan count never goes back: {scans:?}"
        );
    }
    let value = json(&http(web, "GET", "/api/devices?watch=D7,D8,Y0", "").1);
    assert_eq!(value["devices"]["D7"], 4242, "memory kept: {value}");
    assert_eq!(value["devices"]["D8"], 4243, "the new program runs: {value}");
    assert_eq!(value["devices"]["Y0"], 1, "the seal-in kept: {value}");
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn a_changed_program_file_is_swapped_in() {
    let server = Server::start(&["--http", "127.0.0.1:0", "--watch-file", "--watch-settle-ms", "200"]);
    let web = server.web.unwrap();
    let program = server.dir.path().join("plc.il");
    std::thread::sleep(Duration::from_millis(50));
    // A version that does not compile changes nothing.
    std::fs::write(&program, "LD X0\nOUTT Y0\n").unwrap();
    std::thread::sleep(Duration::from_millis(1000));
    std::fs::write(&program, "LD SM0\nMOV K99 D9\n").unwrap();
    let mut value = serde_json::Value::Null;
    for _ in 0..50 {
        std::thread::sleep(Duration::from_millis(100));
        value = json(&http(web, "GET", "/api/devices?watch=D9", "").1);
        if value["devices"]["D9"] == 99 {
            break;
        }
    }
    assert_eq!(value["devices"]["D9"], 99, "{value}");
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0));
    assert!(
        stderr.contains("does not compile; the running program goes on"),
        "{stderr}"
    );
}

#[test]
fn a_program_file_is_taken_only_once_it_has_stopped_changing() {
    let server = Server::start(&["--http", "127.0.0.1:0", "--watch-file", "--watch-settle-ms", "1000"]);
    let web = server.web.unwrap();
    let program = server.dir.path().join("plc.il");
    std::thread::sleep(Duration::from_millis(50));
    // An editor saves in two parts; the first part alone compiles (and
    // would run without the second's rungs).
    let first = "LD M8000\nOUT Y1\n";
    std::fs::write(&program, first).unwrap();
    std::thread::sleep(Duration::from_millis(500));
    std::fs::write(&program, format!("{first}LD M8000\nOUT Y2\n")).unwrap();
    let swapped = || {
        json(&http(web, "GET", "/api/control", "").1)["program"]
            .as_u64()
            .unwrap()
    };
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while swapped() == 0 {
        assert!(std::time::Instant::now() < deadline, "the whole file is taken");
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(
        swapped(),
        1,
        "one program swapped in: the whole file, not its first part"
    );
    let devices = json(&http(web, "GET", "/api/devices?watch=Y1,Y2", "").1);
    assert_eq!(
        (devices["devices"]["Y1"].as_i64(), devices["devices"]["Y2"].as_i64()),
        (Some(1), Some(1))
    );
    // Saved again unchanged: nothing is swapped.
    std::fs::write(&program, format!("{first}LD M8000\nOUT Y2\n")).unwrap();
    std::thread::sleep(Duration::from_millis(2000));
    assert_eq!(swapped(), 1, "the same text again is no change");
    server.stop();
}

/// An independent Modbus client: mbpoll from Debian's package.
#[test]
fn mbpoll_reads_and_writes_through_the_same_map() {
    let test = "mbpoll_reads_and_writes_through_the_same_map";
    if let Err(why) = common::tools::ensure("mbpoll", &["-V"], &["mbpoll"]) {
        common::tools::skip(test, &why);
        return;
    }
    let server = Server::start(&[]);
    let port = server.address.port().to_string();
    let mbpoll = |args: &[&str]| {
        let output = Command::new("mbpoll")
            .args(["-m", "tcp", "-a", "1", "-0", "-1", "-p", &port])
            .args(args)
            .output()
            .unwrap();
        String::from_utf8_lossy(&output.stdout).into_owned()
    };
    // Write D20 = 555 (holding register 20), then read it back.
    mbpoll(&["-r", "20", "-t", "4", "127.0.0.1", "555"]);
    std::thread::sleep(Duration::from_millis(60));
    let read = mbpoll(&["-r", "20", "-t", "4", "127.0.0.1"]);
    assert!(read.contains("[20]: \t555"), "{read}");
    // X2 through the input-image coil runs MOV K123 D5.
    mbpoll(&["-r", "20002", "-t", "0", "127.0.0.1", "1"]);
    std::thread::sleep(Duration::from_millis(60));
    let read = mbpoll(&["-r", "5", "-t", "4", "127.0.0.1"]);
    assert!(read.contains("[5]: \t123"), "{read}");
    server.stop();
}

/// A client that sends garbage loses its connection; the scan goes on and
/// other clients are served.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn malformed_frames_end_only_their_connection() {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let server = Server::start(&[]);
    let mut raw = tokio::net::TcpStream::connect(server.address).await.unwrap();
    raw.write_all(&[0xde, 0xad, 0xbe, 0xef, 0x00, 0x03, 0xff, 0xff, 0xff, 0xff])
        .await
        .unwrap();
    let mut buffer = [0u8; 64];
    let read = tokio::time::timeout(Duration::from_secs(5), raw.read(&mut buffer)).await;
    assert!(
        matches!(read, Ok(Ok(0)) | Ok(Err(_))),
        "the connection is closed: {read:?}"
    );
    let mut ctx = tcp::connect(server.address).await.unwrap();
    assert_eq!(ctx.read_coils(0, 1).await.unwrap().unwrap(), [false]);
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn a_long_period_does_not_delay_stopping() {
    let server = Server::start(&["--scan-ms", "10000"]);
    std::thread::sleep(Duration::from_millis(100));
    let started = std::time::Instant::now();
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        started.elapsed() < Duration::from_secs(2),
        "stopped in {:?}",
        started.elapsed()
    );
}

#[test]
fn a_program_that_drives_nothing_is_not_swapped_in() {
    let server = Server::start_with(COUNTING);
    let web = server.web.unwrap();
    let running = json(&http(web, "GET", "/api/program", "").1);
    assert_eq!(running["text"], COUNTING);
    assert_eq!(running["sha256"].as_str().map(str::len), Some(64), "{running}");
    for body in ["", "// LD X0\n// OUT Y0\n", "\n\n"] {
        let (status, answer) = http(web, "POST", "/api/program", body);
        assert_eq!(status, 422, "{body:?}: {answer}");
        assert!(json(&answer)["error"].as_str().unwrap().contains("W0004"), "{answer}");
    }
    let before = scan_of(web);
    std::thread::sleep(Duration::from_millis(150));
    assert!(scan_of(web) > before, "the running program goes on");
    assert_eq!(
        json(&http(web, "GET", "/api/program", "").1)["sha256"],
        running["sha256"]
    );
    // Meant: an explicit flag.
    let (status, answer) = http(web, "POST", "/api/program?allow_empty=1", "// nothing yet\n");
    assert_eq!(status, 200, "{answer}");
    let now = json(&http(web, "GET", "/api/program", "").1);
    assert_ne!(now["sha256"], running["sha256"]);
    assert_eq!(now["changes"], 1);
    server.stop();
}

#[test]
fn uploads_are_read_as_files_are() {
    use std::io::{Read, Write};
    let server = Server::start_with(COUNTING);
    let web = server.web.unwrap();
    // UTF-16 with a byte-order mark, as a Windows editor saves it.
    let text = "LD X0\r\nOUT Y1\r\n";
    let mut body = vec![0xFF, 0xFE];
    body.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
    let mut stream = std::net::TcpStream::connect(web).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    write!(
        stream,
        "POST /api/program HTTP/1.1\r\nHost: {web}\r\nContent-Type: application/octet-stream\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    )
    .unwrap();
    stream.write_all(&body).unwrap();
    let mut response = String::new();
    let _ = stream.read_to_string(&mut response);
    assert!(response.starts_with("HTTP/1.1 200"), "{response}");
    assert_eq!(json(&http(web, "GET", "/api/program", "").1)["text"], text);
    server.stop();
}
