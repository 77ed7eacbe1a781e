//! `ladderc serve --modbus-rtu` on a pty pair made by socat (as a USB-RS485
//! adapter would carry the line), against pymodbus's serial client and raw
//! frames: reads and writes of the Modbus map, a request to another unit
//! and a frame with a bad CRC unanswered (and the next frame answered), a
//! broadcast write carried out and answered by nobody.

use crate::common::server::{modbus_connect, modbus_request, Server};
use crate::common::tools::{ensure, ensure_python_module, skip};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const CLIENT: &str = include_str!("modbus_rtu_client.py");

/// D101 follows D100, Y7 follows M5.
const PROGRAM: &str = "LD M8000\nMOV D100 D101\nLD M5\nOUT Y7\n";

/// A socat pty pair: `plc` for the server, `client` for the client.
pub(crate) struct PtyPair(Child);

impl PtyPair {
    pub(crate) fn open(plc: &Path, client: &Path) -> PtyPair {
        let link = |path: &Path| format!("pty,raw,echo=0,link={}", path.display());
        let child = Command::new("socat")
            .args([link(plc), link(client)])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("socat starts");
        let deadline = Instant::now() + Duration::from_secs(5);
        while !(plc.exists() && client.exists()) {
            assert!(Instant::now() < deadline, "socat made no pty pair");
            std::thread::sleep(Duration::from_millis(20));
        }
        PtyPair(child)
    }
}

impl Drop for PtyPair {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn a_serial_client_reads_and_writes_and_noise_goes_unanswered() {
    let test = "a_serial_client_reads_and_writes_and_noise_goes_unanswered";
    let ready = ensure("socat", &["-V"], &["socat"])
        .and_then(|()| ensure_python_module("serial", "pyserial"))
        .and_then(|()| ensure_python_module("pymodbus", "pymodbus"));
    if let Err(why) = ready {
        skip(test, &why);
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (plc, client) = (dir.path().join("plc"), dir.path().join("client"));
    let _pair = PtyPair::open(&plc, &client);
    let line = format!("{}:19200,8N1", plc.display());
    let server = Server::start_program(PROGRAM, &["--modbus-rtu", &line, "--modbus-unit", "3"]);
    let script = dir.path().join("client.py");
    std::fs::write(&script, CLIENT).unwrap();
    let output = Command::new("python3")
        .arg(&script)
        .args([client.to_str().unwrap(), "3"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "client failed: {stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let seen: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap_or("")).unwrap();
    assert_eq!(seen["D101"], 1234, "{seen}");
    assert_eq!(seen["Y7"], true, "{seen}");
    assert_eq!(
        seen["other_unit"], "ModbusIOException",
        "another unit's request is not answered: {seen}"
    );
    assert_eq!(seen["bad_crc_answer"], "", "a bad CRC is not answered: {seen}");
    // Unit 3, function 03, 2 bytes: 04D2 (D101), and a CRC that matches.
    assert_eq!(seen["next_answer"], "03030204d24319", "{seen}");
    assert_eq!(seen["next_answer_crc_ok"], true, "{seen}");
    assert_eq!(
        seen["broadcast_answer"], "",
        "a broadcast is answered by nobody: {seen}"
    );
    assert_eq!(seen["D102"], 77, "the broadcast write was carried out: {seen}");
    // The serial line and Modbus TCP are one map.
    let mut tcp = modbus_connect(server.address);
    assert_eq!(modbus_request(&mut tcp, &[0x03, 0, 102, 0, 1]), [0x03, 2, 0, 77]);
}

#[test]
fn a_serial_line_that_cannot_be_opened_stops_the_server_before_a_scan() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("plc.il");
    std::fs::write(&program, PROGRAM).unwrap();
    for (line, message) in [
        (
            "/nonexistent/tty:9600,8N1",
            "cannot open the serial line /nonexistent/tty",
        ),
        ("/dev/ttyS0:96k", "`96k` is not a baud rate"),
        ("/dev/ttyS0:9600,8X1", "is not a character format"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
            .args(["serve", program.to_str().unwrap(), "--modbus-rtu", line])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_ne!(output.status.code(), Some(0), "{line}: {stderr}");
        assert!(stderr.contains(message), "{line}: {stderr}");
        assert!(!String::from_utf8_lossy(&output.stdout).contains("scanning"), "{line}");
    }
    let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args([
            "serve",
            program.to_str().unwrap(),
            "--modbus-rtu",
            "/dev/null",
            "--modbus-unit",
            "0",
        ])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&output.stderr).contains("--modbus-unit is 1 to 247"));
}
