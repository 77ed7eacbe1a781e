//! A `ladderc serve` process for tests: started on loopback with an
//! ephemeral Modbus port (and HTTP when asked), its addresses read from the
//! lines it prints, stopped with SIGTERM (or killed); and a bare HTTP/1.1
//! client.

use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// Seal-in on X0/X1 to Y0, a timer, D5 = 123 while X2, M10 follows X3.
pub const PROGRAM: &str = "LD X0\nOR Y0\nANI X1\nOUT Y0\nLD Y0\nOUT T0 K5\nLD X2\nMOV K123 D5\nLD X3\nOUT M10\n";

pub struct Server {
    pub child: Child,
    pub address: SocketAddr,
    /// The HTTP address, when started with `--http`.
    pub web: Option<SocketAddr>,
    /// The OPC UA address, when started with `--opcua`.
    pub opcua: Option<SocketAddr>,
    /// The MELSEC address (TCP and UDP), when started with `--melsec`.
    pub melsec: Option<SocketAddr>,
    /// The directory of the program file (plc.il).
    pub dir: tempfile::TempDir,
    /// What it printed before its addresses (`retain: ...` lines).
    pub said: Vec<String>,
}

impl Server {
    pub fn start(extra: &[&str]) -> Server {
        Server::start_program(PROGRAM, extra)
    }

    pub fn start_program(text: &str, extra: &[&str]) -> Server {
        let dir = tempfile::tempdir().unwrap();
        let program = dir.path().join("plc.il");
        std::fs::write(&program, text).unwrap();
        Server::start_path(dir, &program, extra)
    }

    /// Serves `program` (a file or a GX Developer project, in `dir`).
    pub fn start_path(dir: tempfile::TempDir, program: &std::path::Path, extra: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ladderc"))
            .args(["serve", program.to_str().unwrap()])
            // Modbus on loopback unless the test names its address.
            .args(if extra.contains(&"--modbus") {
                &[][..]
            } else {
                &["--modbus", "127.0.0.1:0"][..]
            })
            // 10 ms scans unless the test asks for another period.
            .args(if extra.contains(&"--scan-ms") {
                &[][..]
            } else {
                &["--scan-ms", "10"][..]
            })
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("ladderc serve starts");
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        // The first line that names an address of each kind (retain and
        // realtime lines may come before them).
        let mut said = Vec::new();
        let mut find_line = |prefix: &str| -> String {
            for line in lines.by_ref() {
                let line = line.expect("text");
                if let Some(rest) = line.strip_prefix(prefix) {
                    return rest.to_string();
                }
                said.push(line.clone());
                assert!(
                    line.starts_with("retain: ") || line.starts_with("realtime: "),
                    "unexpected line before `{prefix}`: {line}"
                );
            }
            let output = child_output(&mut child);
            panic!("no `{prefix}` line; the server said: {output}")
        };
        let mut find = |prefix: &str| -> SocketAddr { find_line(prefix).parse().unwrap() };
        let address = find("modbus listening on ");
        let web = extra.contains(&"--http").then(|| {
            find(if extra.contains(&"--tls-cert") {
                "https listening on "
            } else {
                "http listening on "
            })
        });
        // Then OPC UA and MELSEC, in the order the server binds them. A
        // listener is bound when its line is printed.
        let opcua = extra.contains(&"--opcua").then(|| find("opcua listening on "));
        let melsec = extra.contains(&"--melsec").then(|| find("melsec listening on "));
        // A serial line is open (and served) once it is announced.
        if extra.contains(&"--modbus-rtu") {
            find_line("modbus-rtu on ");
        }
        Server {
            child,
            address,
            web,
            opcua,
            melsec,
            dir,
            said,
        }
    }

    /// SIGKILL, as a crash or a power cut ends it: nothing runs after.
    pub fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// SIGTERM, then the exit status and what it printed on stderr.
    pub fn stop(mut self) -> (Option<i32>, String) {
        Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .unwrap();
        let output = std::mem::replace(&mut self.child, Command::new("true").spawn().unwrap())
            .wait_with_output()
            .unwrap();
        (
            output.status.code(),
            String::from_utf8_lossy(&output.stderr).into_owned(),
        )
    }
}

/// A test that fails (panics) with its server running must not leave the
/// server behind: it would take CPU from every test after it.
impl Drop for Server {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// One HTTP/1.1 request on a fresh connection: (status, body).
pub fn http(address: SocketAddr, method: &str, path: &str, body: &str) -> (u16, String) {
    http_with(address, method, path, body, &[])
}

/// One request with extra header lines (`Authorization: Bearer ...`).
pub fn http_with(address: SocketAddr, method: &str, path: &str, body: &str, headers: &[&str]) -> (u16, String) {
    use std::io::{Read, Write};
    let extra: String = headers.iter().map(|h| format!("{h}\r\n")).collect();
    // The server answers only to its own name: the address, unless the test
    // names another host itself.
    let given = |name: &str| headers.iter().any(|h| h.to_ascii_lowercase().starts_with(name));
    let host = if given("host:") {
        String::new()
    } else {
        format!("Host: {address}\r\n")
    };
    let content_type = if given("content-type:") {
        ""
    } else {
        "Content-Type: application/json\r\n"
    };
    let request = format!(
        "{method} {path} HTTP/1.1\r\n{host}{extra}{content_type}Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    // A server may answer a body it refuses (413) before reading all of it
    // and close: the rest of the write then fails, and the answer can be
    // lost to the reset. Such a request is sent again (a few times).
    let mut last = (0, String::new());
    for _ in 0..5 {
        let mut stream = std::net::TcpStream::connect(address).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
        let written = stream.write_all(request.as_bytes());
        let mut response = String::new();
        let _ = stream.read_to_string(&mut response);
        last = parse_response(&response);
        if written.is_ok() || last.0 != 0 {
            return last;
        }
    }
    last
}

/// (status, body) of a whole HTTP/1.1 response.
pub fn parse_response(response: &str) -> (u16, String) {
    let status = response
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = response.split_once("\r\n\r\n").map_or("", |(_, b)| b).to_string();
    (status, body)
}

pub fn json(body: &str) -> serde_json::Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {body}"))
}

/// What a server that ended printed on stderr.
fn child_output(child: &mut Child) -> String {
    use std::io::Read as _;
    let _ = child.wait();
    let mut text = String::new();
    if let Some(stderr) = child.stderr.as_mut() {
        let _ = stderr.read_to_string(&mut text);
    }
    text
}

/// A Modbus TCP connection to a test server, reads timing out after 5 s.
pub fn modbus_connect(address: SocketAddr) -> std::net::TcpStream {
    let stream = std::net::TcpStream::connect(address).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    stream
}

/// Sends one request PDU (transaction 7, unit 1) and reads the response PDU.
pub fn modbus_request(stream: &mut std::net::TcpStream, pdu: &[u8]) -> Vec<u8> {
    use std::io::{Read, Write};
    let mut frame = vec![0, 7, 0, 0];
    frame.extend(((pdu.len() + 1) as u16).to_be_bytes());
    frame.push(1);
    frame.extend(pdu);
    stream.write_all(&frame).unwrap();
    let mut header = [0u8; 7];
    stream.read_exact(&mut header).expect("a response header");
    assert_eq!(&header[..4], &[0, 7, 0, 0], "transaction and protocol echoed");
    assert_eq!(header[6], 1, "unit echoed");
    let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
    let mut body = vec![0u8; length - 1];
    stream.read_exact(&mut body).expect("the response PDU");
    body
}

/// A program whose scans take about `target` in the interpreter, however
/// fast this machine and this build are: D0 counts scans, D1 counts the
/// turns of a loop whose length is measured here first (its time per
/// turn, from `/api/stats`, on a server of its own). Tests of writes that
/// come during a scan need scans that long; a fixed loop took 80 ms of a
/// 100 ms period in a debug build and may take 10 ms in a release one.
pub fn slow_program(target: Duration) -> String {
    let program = |outer: u32, inner: u32| {
        format!("LD M8000\nINC D0\nFOR K{outer}\nFOR K{inner}\nLD M8000\nINC D1\nNEXT\nNEXT\n")
    };
    let (outer, inner) = (3000u32, 100u32);
    let probe = Server::start_program(
        &program(outer, inner),
        &["--scan-ms", "1", "--engine", "interp", "--http", "127.0.0.1:0"],
    );
    let web = probe.web.expect("an HTTP address");
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    let stats = loop {
        let stats = json(&http(web, "GET", "/api/stats", "").1);
        if stats["scans"].as_u64().unwrap_or(0) >= 20 {
            break stats;
        }
        assert!(std::time::Instant::now() < deadline, "the probe scans: {stats}");
        std::thread::sleep(Duration::from_millis(20));
    };
    probe.stop();
    let average_us = stats["average_us"].as_f64().unwrap_or(0.0).max(1.0);
    let turn_us = average_us / f64::from(outer * inner);
    let turns = (target.as_secs_f64() * 1e6 / turn_us).max(1.0);
    // FOR counts up to K32767: the inner loop takes what the outer cannot.
    let inner = (turns / 30_000.0).ceil().clamp(1.0, 32_767.0);
    let outer = (turns / inner).round().clamp(1.0, 32_767.0);
    program(outer as u32, inner as u32)
}
