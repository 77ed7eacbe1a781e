//! `ladderc serve`'s protocol edges, with raw frames on real connections:
//! Modbus requests the specification answers with an exception get it (and
//! the connection stays open); headers that cannot be right close the
//! connection at once; `--read-only` and peers without write permission get
//! exception 01 for every write, whatever its address or value. Access
//! control: HTTP tokens, writes from beyond loopback (a real non-loopback
//! address of this machine, where it has one), HTTPS with rustls.

use crate::common::server::{
    http, http_with, json, modbus_connect as connect, modbus_request as request, parse_response, Server,
};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

/// True when the server closed the connection (a read timeout is not a close).
fn closed(stream: &mut TcpStream) -> bool {
    let mut buffer = [0u8; 16];
    match stream.read(&mut buffer) {
        Ok(0) => true,
        Ok(_) => false,
        Err(e) => !matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut),
    }
}

#[test]
fn malformed_requests_get_exceptions_and_keep_the_connection() {
    let server = Server::start(&[]);
    let mut stream = connect(server.address);
    // FC05 with a value other than FF00/0000: exception 03.
    assert_eq!(request(&mut stream, &[0x05, 0, 0, 0x12, 0x34]), [0x85, 0x03]);
    // FC16 whose byte count does not match the quantity; FC15 likewise.
    assert_eq!(request(&mut stream, &[0x10, 0, 0, 0, 2, 3, 0, 1, 0]), [0x90, 0x03]);
    assert_eq!(request(&mut stream, &[0x0F, 0, 0, 0, 9, 1, 0xFF]), [0x8F, 0x03]);
    // A read of 0 or 126 registers; a PDU of the wrong length.
    assert_eq!(request(&mut stream, &[0x03, 0, 0, 0, 0]), [0x83, 0x03]);
    assert_eq!(request(&mut stream, &[0x03, 0, 0, 0, 126]), [0x83, 0x03]);
    assert_eq!(request(&mut stream, &[0x03, 0, 0, 0]), [0x83, 0x03]);
    // Unknown functions: 01; outside the map: 02.
    assert_eq!(request(&mut stream, &[0x2B, 0x0E, 1, 0]), [0xAB, 0x01]);
    assert_eq!(request(&mut stream, &[0x03, 0x40, 0, 0, 1]), [0x83, 0x02]);
    // The same connection still reads and writes.
    assert_eq!(
        request(&mut stream, &[0x06, 0, 10, 0x12, 0x34]),
        [0x06, 0, 10, 0x12, 0x34]
    );
    std::thread::sleep(Duration::from_millis(60));
    assert_eq!(request(&mut stream, &[0x03, 0, 10, 0, 1]), [0x03, 2, 0x12, 0x34]);
    server.stop();
}

#[test]
fn impossible_headers_close_the_connection_at_once() {
    let server = Server::start(&[]);
    // Lengths 0, 1 and above 254; a protocol id other than 0; each closes
    // its connection now, without waiting for bytes that never come.
    for header in [
        [0u8, 1, 0, 0, 0, 0, 1],
        [0, 1, 0, 0, 0, 1, 1],
        [0, 1, 0, 0, 0x01, 0x00, 1],
        [0, 1, 0, 0, 0xFF, 0xFF, 1],
        [0, 1, 0, 5, 0, 6, 1],
    ] {
        let mut stream = connect(server.address);
        stream.write_all(&header).unwrap();
        let started = std::time::Instant::now();
        assert!(closed(&mut stream), "{header:02x?}");
        assert!(
            started.elapsed() < Duration::from_secs(2),
            "{header:02x?} closed only after {:?}",
            started.elapsed()
        );
    }
    // Other clients are served.
    let mut stream = connect(server.address);
    assert_eq!(request(&mut stream, &[0x01, 0, 0, 0, 1]), [0x01, 1, 0]);
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn read_only_answers_every_write_with_01() {
    let server = Server::start(&["--read-only"]);
    let mut stream = connect(server.address);
    for pdu in [
        &[0x05u8, 0, 0, 0xFF, 0][..],
        &[0x05, 0, 0, 0x12, 0x34],
        &[0x05, 0xFF, 0xFF, 0xFF, 0],
        &[0x06, 0xFF, 0xFF, 0, 1],
        &[0x0F, 0xFF, 0xF0, 0, 9, 1, 0xFF],
        &[0x10, 0, 0, 0, 2, 3, 0, 1, 0],
        &[0x10, 0xFF, 0xF0, 0, 1, 2, 0, 1],
    ] {
        assert_eq!(request(&mut stream, pdu), [pdu[0] | 0x80, 0x01], "{pdu:02x?}");
    }
    assert_eq!(request(&mut stream, &[0x01, 0, 0, 0, 1]), [0x01, 1, 0], "reads go on");
    server.stop();
}

const TOKEN: &str = "c2f1e0d9b8a7f6e5d4c3";

fn token_file(dir: &std::path::Path, token: &str) -> String {
    let path = dir.join("token");
    std::fs::write(&path, format!("{token}\n")).unwrap();
    path.to_str().unwrap().to_string()
}

/// The status line of a request whose response does not end (an event
/// stream), read alone.
fn status_of_stream(address: SocketAddr, path: &str) -> u16 {
    let mut stream = connect(address);
    write!(stream, "GET {path} HTTP/1.1\r\nHost: {address}\r\n\r\n").unwrap();
    let mut buffer = [0u8; 64];
    let read = stream.read(&mut buffer).unwrap_or(0);
    parse_response(&String::from_utf8_lossy(&buffer[..read])).0
}

#[test]
fn with_a_token_file_writes_need_the_token() {
    let dir = tempfile::tempdir().unwrap();
    let file = token_file(dir.path(), TOKEN);
    let server = Server::start(&["--http", "127.0.0.1:0", "--token-file", &file]);
    let web = server.web.unwrap();
    let set = r#"{"device": "D7", "value": 5}"#;
    assert_eq!(http(web, "POST", "/api/set", set).0, 401, "no token");
    let wrong = "Authorization: Bearer c2f1e0d9b8a7f6e5d4c4";
    assert_eq!(
        http_with(web, "POST", "/api/set", set, &[wrong]).0,
        401,
        "a wrong token"
    );
    assert_eq!(
        http(web, "POST", "/api/program", "LD X0\nOUT Y1\n").0,
        401,
        "an upload without it"
    );
    assert_eq!(http(web, "POST", "/api/control", r#"{"action": "stop"}"#).0, 401);
    assert_eq!(http(web, "DELETE", "/api/breakpoints", "").0, 401);
    let right = format!("Authorization: Bearer {TOKEN}");
    let (status, body) = http_with(web, "POST", "/api/set", set, &[&right]);
    assert_eq!(status, 200, "{body}");
    std::thread::sleep(Duration::from_millis(60));
    // Reads stay open without --token-reads.
    let (status, body) = http(web, "GET", "/api/devices?watch=D7", "");
    assert_eq!(
        (status, json(&body)["devices"]["D7"].as_i64()),
        (200, Some(5)),
        "{body}"
    );
    server.stop();
}

#[test]
fn token_reads_closes_the_api_but_not_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let file = token_file(dir.path(), TOKEN);
    let server = Server::start(&["--http", "127.0.0.1:0", "--token-file", &file, "--token-reads"]);
    let web = server.web.unwrap();
    assert_eq!(http(web, "GET", "/api/devices", "").0, 401);
    assert_eq!(http(web, "GET", "/api/stats", "").0, 401);
    assert_eq!(http(web, "GET", "/api/program", "").0, 401);
    assert_eq!(status_of_stream(web, "/api/events?watch=Y0"), 401);
    let right = format!("Authorization: Bearer {TOKEN}");
    assert_eq!(http_with(web, "GET", "/api/devices", "", &[&right]).0, 200);
    assert_eq!(
        status_of_stream(web, &format!("/api/events?watch=Y0&access_token={TOKEN}")),
        200
    );
    let (status, page) = http(web, "GET", "/", "");
    assert_eq!(status, 200);
    assert!(page.contains("access token"), "the page asks for the token");
    server.stop();
}

#[test]
fn unusable_access_settings_stop_the_server_before_it_starts() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("plc.il");
    std::fs::write(&program, "LD X0\nOUT Y0\n").unwrap();
    let short = token_file(dir.path(), "secret");
    let missing = dir.path().join("nothing.pem");
    let cases: [(&[&str], &str); 4] = [
        (&["--token-file", &short], "at least 16"),
        (&["--token-reads"], "--token-file"),
        (&["--tls-cert", missing.to_str().unwrap()], "--tls-key"),
        (
            &[
                "--tls-cert",
                missing.to_str().unwrap(),
                "--tls-key",
                missing.to_str().unwrap(),
            ],
            "cannot read the certificate",
        ),
    ];
    for (flags, says) in cases {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_ladderc"))
            .args(["serve", program.to_str().unwrap(), "--http", "127.0.0.1:0"])
            .args(flags)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{flags:?}: {stderr}");
        assert!(stderr.contains(says), "{flags:?}: {stderr}");
    }
}

/// An address of this machine other than loopback, for a peer that is
/// "beyond loopback" without leaving the machine; None (and a printed
/// reason) where it has none.
fn own_network_address() -> Option<std::net::IpAddr> {
    // Connecting a UDP socket sends nothing; it only picks the route.
    let found = std::net::UdpSocket::bind("0.0.0.0:0")
        .and_then(|socket| socket.connect("192.0.2.255:9").map(|()| socket))
        .and_then(|socket| socket.local_addr())
        .map(|address| address.ip())
        .ok()
        .filter(|ip| !ip.is_loopback() && !ip.is_unspecified());
    if found.is_none() {
        eprintln!("skipped: this machine has no address beyond loopback to test remote peers with");
    }
    found
}

#[test]
fn peers_beyond_loopback_write_only_with_permission() {
    let Some(own) = own_network_address() else {
        return;
    };
    let bind = format!("{own}:0");
    let dir = tempfile::tempdir().unwrap();
    let file = token_file(dir.path(), TOKEN);
    let coil_on = [0x05u8, 0, 0, 0xFF, 0];
    // No permission: HTTP writes 403, Modbus writes 01; reads work.
    let server = Server::start(&["--allow-remote", "--modbus", &bind, "--http", &bind]);
    let web = server.web.unwrap();
    assert_eq!(web.ip(), own);
    let (status, body) = http(web, "POST", "/api/set", r#"{"device": "D7", "value": 5}"#);
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("--token-file"), "{body}");
    assert_eq!(http(web, "GET", "/api/stats", "").0, 200);
    let mut stream = connect(server.address);
    assert_eq!(request(&mut stream, &coil_on), [0x85, 0x01]);
    assert_eq!(request(&mut stream, &[0x01, 0, 0, 0, 1]), [0x01, 1, 0]);
    server.stop();
    // A network that does not hold the peer: still 01.
    let server = Server::start(&["--allow-remote", "--modbus", &bind, "--modbus-write-from", "10.0.0.0/8"]);
    let mut stream = connect(server.address);
    assert_eq!(request(&mut stream, &coil_on), [0x85, 0x01]);
    server.stop();
    // The peer's network, and the token: both write.
    let net = format!("{own}/32");
    let server = Server::start(&[
        "--allow-remote",
        "--modbus",
        &bind,
        "--modbus-write-from",
        &net,
        "--http",
        &bind,
        "--token-file",
        &file,
    ]);
    let mut stream = connect(server.address);
    assert_eq!(request(&mut stream, &coil_on), coil_on);
    let right = format!("Authorization: Bearer {TOKEN}");
    let set = r#"{"device": "D7", "value": 5}"#;
    assert_eq!(
        http_with(server.web.unwrap(), "POST", "/api/set", set, &[&right]).0,
        200
    );
    assert_eq!(http(server.web.unwrap(), "POST", "/api/set", set).0, 401);
    server.stop();
}

#[test]
fn https_serves_the_api_with_rustls() {
    use std::sync::Arc;
    let dir = tempfile::tempdir().unwrap();
    let certified = rcgen::generate_simple_self_signed(vec!["localhost".to_string(), "127.0.0.1".to_string()]).unwrap();
    let (cert, key) = (dir.path().join("cert.pem"), dir.path().join("key.pem"));
    std::fs::write(&cert, certified.cert.pem()).unwrap();
    std::fs::write(&key, certified.key_pair.serialize_pem()).unwrap();
    let server = Server::start(&[
        "--http",
        "127.0.0.1:0",
        "--tls-cert",
        cert.to_str().unwrap(),
        "--tls-key",
        key.to_str().unwrap(),
    ]);
    let web = server.web.unwrap();
    // Plain HTTP on the HTTPS port gets no HTTP answer.
    assert_ne!(http(web, "GET", "/api/stats", "").0, 200);
    let mut roots = rustls::RootCertStore::empty();
    roots.add(certified.cert.der().clone()).unwrap();
    let config = rustls::ClientConfig::builder_with_provider(Arc::new(rustls::crypto::ring::default_provider()))
        .with_safe_default_protocol_versions()
        .unwrap()
        .with_root_certificates(roots)
        .with_no_client_auth();
    let name = rustls::pki_types::ServerName::try_from("localhost").unwrap();
    let connection = rustls::ClientConnection::new(Arc::new(config), name).unwrap();
    let mut tls = rustls::StreamOwned::new(connection, connect(web));
    write!(
        tls,
        "GET /api/stats HTTP/1.1\r\nHost: localhost:{}\r\nConnection: close\r\n\r\n",
        web.port()
    )
    .unwrap();
    let mut response = Vec::new();
    let _ = tls.read_to_end(&mut response);
    let (status, body) = parse_response(&String::from_utf8_lossy(&response));
    assert_eq!(status, 200, "{body}");
    assert!(body.contains("\"scans\""), "{body}");
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn read_only_refuses_every_http_write_even_with_the_token() {
    let dir = tempfile::tempdir().unwrap();
    let file = token_file(dir.path(), TOKEN);
    let server = Server::start(&["--http", "127.0.0.1:0", "--read-only", "--token-file", &file]);
    let web = server.web.unwrap();
    let right = format!("Authorization: Bearer {TOKEN}");
    for (method, path, body) in [
        ("POST", "/api/set", r#"{"device": "D7", "value": 5}"#),
        ("POST", "/api/force", r#"{"device": "Y0", "value": 1}"#),
        ("POST", "/api/control", r#"{"action": "stop"}"#),
        ("POST", "/api/breakpoints", r#"{"condition": "D0 > 1"}"#),
        ("DELETE", "/api/breakpoints", ""),
        ("POST", "/api/stats/reset", ""),
        ("POST", "/api/program", "LD X0\nOUT Y1\n"),
    ] {
        let (status, answer) = http_with(web, method, path, body, &[&right]);
        assert_eq!(status, 403, "{method} {path}: {answer}");
        assert!(answer.contains("read-only"), "{method} {path}: {answer}");
    }
    assert_eq!(http(web, "GET", "/api/stats", "").0, 200, "reads go on");
    server.stop();
}
