//! `ladderc serve` left to clients that misbehave, each on the real binary:
//! idle Modbus connections time out and make room for a working client,
//! writes while paused apply at once (memory stays flat) and a request of
//! more devices than the queue of writes holds is refused as "busy"
//! (Modbus exception 06, HTTP 503), event
//! streams are bounded in number and a client that stops reading is
//! dropped; and the switch: a resume after a long step goes on at once,
//! STOP→RUN starts over as an FX does, RUN ends a pause.

use crate::common::server::{http, json, modbus_connect as connect, modbus_request as request, Server};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

/// FC16: writes `values` from holding register `address` (D`address`).
fn write_registers(stream: &mut TcpStream, address: u16, values: &[i16]) -> Vec<u8> {
    let mut pdu = vec![0x10];
    pdu.extend(address.to_be_bytes());
    pdu.extend((values.len() as u16).to_be_bytes());
    pdu.push((2 * values.len()) as u8);
    for value in values {
        pdu.extend(value.to_be_bytes());
    }
    request(stream, &pdu)
}

/// Whether the server has closed `stream` (waiting up to `within`).
fn closed_within(stream: &mut TcpStream, within: Duration) -> bool {
    stream.set_read_timeout(Some(within)).unwrap();
    let mut buffer = [0u8; 16];
    match stream.read(&mut buffer) {
        Ok(0) => true,
        Ok(_) => false,
        Err(e) => !matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut),
    }
}

fn value(web: SocketAddr, device: &str) -> i64 {
    let body = json(&http(web, "GET", &format!("/api/devices?watch={device}"), "").1);
    body["devices"][device]
        .as_i64()
        .unwrap_or_else(|| panic!("{device} in {body}"))
}

fn scan(web: SocketAddr) -> u64 {
    json(&http(web, "GET", "/api/devices?watch=D0", "").1)["scan"]
        .as_u64()
        .unwrap()
}

fn control(web: SocketAddr, body: &str) -> serde_json::Value {
    let (status, answer) = http(web, "POST", "/api/control", body);
    assert_eq!(status, 200, "{body}: {answer}");
    json(&answer)
}

/// The resident memory of a process, in kB.
fn resident_kb(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmRSS:"))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|kb| kb.parse().ok())
        .unwrap_or(0)
}

#[test]
fn idle_modbus_connections_make_room_and_time_out() {
    let server = Server::start(&["--max-modbus-connections", "4", "--modbus-idle-s", "3"]);
    let read_d0 = [0x03, 0, 0, 0, 1];
    // Four clients connect and say nothing: every place is taken.
    let mut idle: Vec<TcpStream> = (0..4).map(|_| connect(server.address)).collect();
    std::thread::sleep(Duration::from_millis(1300));
    // A fifth gets the place of one of them and is served.
    let mut working = connect(server.address);
    assert_eq!(
        request(&mut working, &read_d0)[..2],
        [0x03, 2],
        "the newcomer is served"
    );
    let gave_way = idle
        .iter_mut()
        .map(|s| closed_within(s, Duration::from_millis(300)))
        .filter(|&closed| closed)
        .count();
    assert_eq!(gave_way, 1, "one idle connection made room");
    // The others are closed when they have been idle for the idle time;
    // the working client, which goes on asking, is not.
    let until = Instant::now() + Duration::from_secs(3);
    while Instant::now() < until {
        assert_eq!(request(&mut working, &read_d0)[..2], [0x03, 2]);
        std::thread::sleep(Duration::from_millis(250));
    }
    for stream in &mut idle {
        assert!(
            closed_within(stream, Duration::from_secs(2)),
            "an idle connection timed out"
        );
    }
    assert_eq!(request(&mut working, &read_d0)[..2], [0x03, 2], "still served");
    // Four clients that work keep their places: a fifth is refused.
    let mut busy: Vec<TcpStream> = (0..3).map(|_| connect(server.address)).collect();
    for stream in &mut busy {
        assert_eq!(request(stream, &read_d0)[..2], [0x03, 2]);
    }
    let mut fifth = connect(server.address);
    assert!(
        closed_within(&mut fifth, Duration::from_secs(3)),
        "no place for a fifth"
    );
    assert_eq!(
        request(&mut working, &read_d0)[..2],
        [0x03, 2],
        "the working clients stay"
    );
    server.stop();
}

#[test]
fn writes_while_paused_apply_at_once_and_more_than_the_queue_holds_is_busy() {
    let server = Server::start(&["--http", "127.0.0.1:0", "--max-queued-writes", "8"]);
    let web = server.web.unwrap();
    assert_eq!(control(web, r#"{"action":"pause"}"#)["paused"], true);
    // A write is answered once the scan in progress (if any: it began
    // before the pause) has ended and published: no scan follows it.
    let mut modbus = connect(server.address);
    assert_eq!(write_registers(&mut modbus, 40, &[1])[0], 0x10);
    let paused_at = scan(web);
    let before = resident_kb(server.child.id());
    // 20,000 writes of the same four registers, each answered once
    // applied: read back at once, with no scan.
    for round in 0..20_000i32 {
        let value = (round % 30_000) as i16;
        let answer = write_registers(&mut modbus, 0, &[value, value, value, value]);
        assert_eq!(answer[0], 0x10, "write {round} is taken: {answer:?}");
        if round % 1000 == 0 {
            let [high, low] = value.to_be_bytes();
            assert_eq!(request(&mut modbus, &[0x03, 0, 3, 0, 1]), [0x03, 2, high, low]);
        }
    }
    let grown = resident_kb(server.child.id()).saturating_sub(before);
    assert!(grown < 16 * 1024, "RSS grew by {grown} kB for writes of four devices");
    // A request of nine devices, where eight may wait: "busy" (exception
    // 06), and none of it applied.
    assert_eq!(
        write_registers(&mut modbus, 20, &[1, 2, 3, 4, 5, 6, 7, 8, 9]),
        [0x90, 0x06],
        "FC16 of nine devices"
    );
    assert_eq!(
        request(&mut modbus, &[0x0F, 0x03, 0xE8, 0, 9, 2, 0xFF, 0x01]),
        [0x8F, 0x06],
        "FC15 of nine relays"
    );
    assert_eq!(value(web, "D20"), 0, "the refused write did not happen");
    assert_eq!(value(web, "M0"), 0, "the refused write did not happen");
    // Over HTTP: nine forced inputs, unforced in one request: 503.
    for n in 0..9 {
        let body = format!(r#"{{"device": "X{n:o}", "value": 1}}"#);
        let (status, answer) = http(web, "POST", "/api/force", &body);
        assert_eq!(status, 200, "{answer}");
    }
    let (status, body) = http(web, "POST", "/api/unforce-all", "");
    assert_eq!(status, 503, "{body}");
    assert!(body.contains("waiting"), "{body}");
    assert_eq!(
        json(&http(web, "GET", "/api/forces", "").1)["forces"]
            .as_array()
            .map(Vec::len),
        Some(9)
    );
    // Eight devices are taken, and applied at once.
    assert_eq!(write_registers(&mut modbus, 20, &[1, 2, 3, 4, 5, 6, 7, 8])[0], 0x10);
    assert_eq!(value(web, "D27"), 8);
    assert_eq!(scan(web), paused_at, "no scan ran while paused");
    control(web, r#"{"action":"resume"}"#);
    let deadline = Instant::now() + Duration::from_secs(5);
    while scan(web) == paused_at {
        assert!(Instant::now() < deadline, "the scans go on after a resume");
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(value(web, "D0"), 19_999, "the last write of D0");
    server.stop();
}

/// Opens an event stream and reads its status line only.
fn open_stream(web: SocketAddr, watch: &str) -> (TcpStream, u16) {
    let mut stream = connect(web);
    write!(stream, "GET /api/events?watch={watch} HTTP/1.1\r\nHost: {web}\r\n\r\n").unwrap();
    let mut line = Vec::new();
    let mut byte = [0u8; 1];
    while !line.ends_with(b"\r\n") && stream.read(&mut byte).map(|n| n == 1).unwrap_or(false) {
        line.push(byte[0]);
    }
    let status = String::from_utf8_lossy(&line)
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    (stream, status)
}

#[test]
fn event_streams_are_bounded_and_a_client_that_stops_reading_is_dropped() {
    let server = Server::start(&["--http", "127.0.0.1:0", "--max-event-streams", "2", "--scan-ms", "1"]);
    let web = server.web.unwrap();
    let many = "D0..D255";
    let (mut reading, status) = open_stream(web, "D0");
    assert_eq!(status, 200);
    let (silent, status) = open_stream(web, many);
    assert_eq!(status, 200);
    assert_eq!(open_stream(web, "D0").1, 503, "a third stream is refused");
    // The silent client never reads again: its buffers fill, the server
    // stops getting rid of its events, and it is dropped; its place frees.
    let pid = server.child.id();
    let started = Instant::now();
    let mut buffer = vec![0u8; 64 * 1024];
    reading.set_read_timeout(Some(Duration::from_millis(200))).unwrap();
    let mut peak = 0;
    let freed = loop {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the silent client was never dropped"
        );
        let _ = reading.read(&mut buffer);
        peak = peak.max(resident_kb(pid));
        let (stream, status) = open_stream(web, "D0");
        if status == 200 {
            break stream;
        }
        drop(stream);
        std::thread::sleep(Duration::from_millis(500));
    };
    println!(
        "the silent client was dropped after {:.1} s; peak RSS {} kB",
        started.elapsed().as_secs_f64(),
        peak
    );
    assert!(peak < 200 * 1024, "peak RSS {peak} kB");
    drop((silent, freed));
    server.stop();
}

#[test]
fn a_resume_after_many_steps_scans_at_once() {
    let server = Server::start(&["--http", "127.0.0.1:0", "--scan-ms", "20"]);
    let web = server.web.unwrap();
    control(web, r#"{"action":"pause"}"#);
    // A scan under way when the pause came still publishes: count from
    // when the count stands still.
    let mut at = scan(web);
    loop {
        std::thread::sleep(Duration::from_millis(60));
        let now = scan(web);
        if now == at {
            break;
        }
        at = now;
    }
    control(web, r#"{"action":"step","scans":300}"#);
    let deadline = Instant::now() + Duration::from_secs(20);
    while scan(web) < at + 300 {
        assert!(Instant::now() < deadline, "the steps run");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(scan(web), at + 300, "paused again after the steps");
    control(web, r#"{"action":"resume"}"#);
    let resumed = scan(web);
    std::thread::sleep(Duration::from_millis(500));
    // 25 periods; before the fix none for 300 periods (6 s).
    let scans = scan(web) - resumed;
    assert!(scans >= 10, "{scans} scans in the 500 ms after the resume");
    server.stop();
}

#[test]
fn stop_then_run_starts_over_as_an_fx_does_and_run_ends_a_pause() {
    // D1 is 7 after the first scan; D0 (not latched) and D200 (latched)
    // count scans.
    let program = "LD M8002\nMOV K7 D1\nLD M8000\nINC D0\nINC D200\n";
    let server = Server::start_program(program, &["--http", "127.0.0.1:0"]);
    let web = server.web.unwrap();
    while value(web, "D0") < 20 {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(http(web, "POST", "/api/set", r#"{"device":"D1","value":"0"}"#).0, 200);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(value(web, "D1"), 0);
    assert_eq!(control(web, r#"{"action":"stop"}"#)["mode"], "stop");
    std::thread::sleep(Duration::from_millis(100));
    let (d0, d200) = (value(web, "D0"), value(web, "D200"));
    control(web, r#"{"action":"run"}"#);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(value(web, "D1"), 7, "M8002 was ON for the first scan after RUN");
    let (after0, after200) = (value(web, "D0"), value(web, "D200"));
    assert!(after0 < d0, "D0 (not latched) started over: {d0} -> {after0}");
    assert!(after200 > d200, "D200 (latched) went on: {d200} -> {after200}");
    // RUN also ends a pause.
    assert_eq!(control(web, r#"{"action":"pause"}"#)["paused"], true);
    let answer = control(web, r#"{"action":"run"}"#);
    assert_eq!(answer["paused"], false, "{answer}");
    let at = scan(web);
    std::thread::sleep(Duration::from_millis(200));
    assert!(scan(web) > at, "scanning again");
    server.stop();
}

#[test]
fn breakpoints_that_can_never_hold_are_refused_and_floats_are_set_over_http() {
    let server = Server::start(&["--http", "127.0.0.1:0"]);
    let web = server.web.unwrap();
    for condition in ["D0 > 40000", "D0 < -32768", "D0 >= 32768", "D0:32 > 2147483647"] {
        let (status, body) = http(
            web,
            "POST",
            "/api/breakpoints",
            &format!(r#"{{"condition":"{condition}"}}"#),
        );
        assert_eq!(status, 400, "{condition}: {body}");
        assert!(body.contains("never"), "{condition}: {body}");
    }
    for condition in ["D0 > 32000", "D0:32 > 40000", "D0 == 65535"] {
        let (status, body) = http(
            web,
            "POST",
            "/api/breakpoints",
            &format!(r#"{{"condition":"{condition}"}}"#),
        );
        assert_eq!(status, 200, "{condition}: {body}");
    }
    let (status, body) = http(web, "POST", "/api/set", r#"{"device":"D20:float","value":"-1.5"}"#);
    assert_eq!(status, 200, "{body}");
    std::thread::sleep(Duration::from_millis(100));
    let read = json(&http(web, "GET", "/api/devices?watch=D20:float,D20:32", "").1);
    assert_eq!(read["text"]["D20:float"], "-1.5", "{read}");
    assert_eq!(
        read["devices"]["D20:32"],
        i64::from((-1.5f32).to_bits() as i32),
        "{read}"
    );
    server.stop();
}
