//! `ladderc serve --io FILE` against pymodbus's server as the remote I/O
//! module (`remote_io_module.py`, whose control socket sets its inputs and
//! reads its outputs): over Modbus TCP an input on the module reaches X and
//! the program's output its coil within two poll periods, an input
//! register reaches D and a D the module's holding register; the module
//! killed, the status relay drops, inputs hold or clear as configured and
//! the scans go on at their period; the module back, the device recovers
//! by itself. Over RTU (a socat pty pair, two units on the line) the same
//! round trip. In STOP and paused the inputs are refreshed and a client's
//! write to Y reaches the coil; the server stopping writes the coils OFF.
//! Unchanged outputs are written by the keep-alive only, a change at once;
//! a module that stops answering (SIGSTOP) is lost after its timeouts
//! while the scans go on, and recovers by itself (SIGCONT). A wrong file
//! stops the server before a scan, naming its line; a program that writes
//! a status relay is warned about.

use crate::common::server::{http, json, Server};
use crate::common::tools::{ensure, ensure_python_module, skip};
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const MODULE: &str = include_str!("remote_io_module.py");

/// Y0 follows X0, Y1 follows X10, D20 is D10 + 1.
const PROGRAM: &str = "LD X0\nOUT Y0\nLD X10\nOUT Y1\nLD M8000\nADD D10 K1 D20\n";

/// The poll period of the tests' devices.
const PERIOD: Duration = Duration::from_millis(100);

/// pymodbus with its simulator datastore (3.16 on), or why not.
fn module_ready() -> Result<(), String> {
    ensure_python_module("pymodbus", "pymodbus")?;
    ensure_python_module("pymodbus.simulator", "pymodbus>=3.16")
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// The module's process and its control socket.
struct Module {
    child: Child,
    control: BufReader<TcpStream>,
}

impl Module {
    /// `python3 module.py MODE WHERE CONTROL_PORT`, once it says `ready`.
    fn start(script: &Path, mode: &str, place: &str, control: u16) -> Module {
        let mut child = Command::new("python3")
            .arg(script)
            .args([mode, place, &control.to_string()])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("python3 starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        assert_eq!(line.trim(), "ready", "the module did not start");
        let stream = TcpStream::connect(("127.0.0.1", control)).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        // A question is answered at once, not after a delayed ACK.
        stream.set_nodelay(true).unwrap();
        Module {
            child,
            control: BufReader::new(stream),
        }
    }

    fn ask(&mut self, line: &str) -> String {
        self.control
            .get_mut()
            .write_all(format!("{line}\n").as_bytes())
            .unwrap();
        let mut answer = String::new();
        self.control.read_line(&mut answer).unwrap();
        answer.trim().to_string()
    }

    fn coil(&mut self, n: u16) -> bool {
        self.ask(&format!("co {n}")) == "1"
    }

    /// Write requests so far that wrote coils from address `n`.
    fn coil_writes(&mut self, n: u16) -> u64 {
        self.ask(&format!("wc {n}")).parse().unwrap()
    }

    /// Sends `signal` (`STOP`, `CONT`) to the module's process.
    fn signal(&self, signal: &str) {
        let sent = Command::new("kill")
            .args([&format!("-{signal}"), &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(sent.success());
    }

    fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Module {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A helper process, killed when dropped.
struct Reaped(Child);

impl Drop for Reaped {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Polls `check` every 5 ms until it holds or `limit` passes; how long it
/// took.
fn until(limit: Duration, mut check: impl FnMut() -> bool) -> Option<Duration> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if check() {
            return Some(start.elapsed());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    None
}

/// Input 0 of the module turned ON and OFF five times (ending ON), each
/// time until its coil 0 follows (Y0 = X0): the median within two poll
/// periods (a poll, a scan, the write); every one within a second, as the
/// Python module answers late on a loaded test machine.
fn round_trips(module: &mut Module, link: &str) {
    let mut took = Vec::new();
    for on in [true, false, true, false, true] {
        assert_eq!(module.ask(&format!("di 0 {}", u8::from(on))), "ok");
        took.push(until(Duration::from_secs(3), || module.coil(0) == on).expect("the coil follows the input"));
    }
    let shown: Vec<u128> = took.iter().map(Duration::as_millis).collect();
    eprintln!(
        "{link}: input to coil in {shown:?} ms (poll period {} ms)",
        PERIOD.as_millis()
    );
    let mut sorted = took.clone();
    sorted.sort();
    assert!(sorted[2] <= 2 * PERIOD, "{link}: {shown:?} ms");
    assert!(sorted[4] <= Duration::from_secs(1), "{link}: {shown:?} ms");
}

/// The watched devices' values.
fn devices(web: SocketAddr, watch: &str) -> serde_json::Value {
    let (status, body) = http(web, "GET", &format!("/api/devices?watch={watch}"), "");
    assert_eq!(status, 200, "{body}");
    json(&body)["devices"].clone()
}

fn scans(web: SocketAddr) -> u64 {
    json(&http(web, "GET", "/api/stats", "").1)["scans"].as_u64().unwrap()
}

/// Two devices on one module: `held` (inputs to X0-X7, input register 3
/// to D10, Y0-Y7 to coils 0-7, D20 to holding register 2, inputs held when
/// lost) and `cleared` (the same inputs to X10-X17, cleared when lost).
fn tcp_file(port: u16) -> String {
    format!(
        r#"
[[device]]
name = "held"
tcp = "127.0.0.1:{port}"
period_ms = {period}
timeout_ms = 200
retries = 1
status = "M100"
errors = "D100"
[[device.input]]
discrete_inputs = 0
count = 8
to = "X0"
[[device.input]]
input_registers = 3
count = 1
to = "D10"
[[device.output]]
coils = 0
count = 8
from = "Y0"
[[device.output]]
holding_registers = 2
count = 1
from = "D20"

[[device]]
name = "cleared"
tcp = "127.0.0.1:{port}"
period_ms = {period}
timeout_ms = 200
retries = 1
on_loss = "clear"
status = "M101"
errors = "D101"
[[device.input]]
discrete_inputs = 0
count = 8
to = "X10"
"#,
        period = PERIOD.as_millis()
    )
}

#[test]
fn a_tcp_module_drives_x_takes_y_and_is_recovered_after_a_loss() {
    let test = "a_tcp_module_drives_x_takes_y_and_is_recovered_after_a_loss";
    if let Err(why) = module_ready() {
        skip(test, &why);
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("module.py");
    std::fs::write(&script, MODULE).unwrap();
    let (port, control) = (free_port(), free_port());
    let mut module = Module::start(&script, "tcp", &port.to_string(), control);
    let file = dir.path().join("io.toml");
    std::fs::write(&file, tcp_file(port)).unwrap();
    let server = Server::start_program(PROGRAM, &["--http", "127.0.0.1:0", "--io", file.to_str().unwrap()]);
    let web = server.web.unwrap();
    let connected = until(Duration::from_secs(5), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 1 && seen["M101"] == 1
    });
    assert!(
        connected.is_some(),
        "both devices connect: {}",
        http(web, "GET", "/api/io", "").1
    );
    // An input on the module reaches X and, through the program, the coil.
    round_trips(&mut module, "tcp");
    assert!(until(Duration::from_secs(1), || devices(web, "X10")["X10"] == 1).is_some());
    // An input register reaches D10, D20 = D10 + 1 the holding register.
    assert_eq!(module.ask("ir 3 41"), "ok");
    assert!(
        until(Duration::from_secs(3), || module.ask("hr 2") == "42").is_some(),
        "the holding register follows the input register"
    );
    let report = json(&http(web, "GET", "/api/io", "").1);
    assert_eq!(report["devices"][0]["name"], "held", "{report}");
    assert_eq!(report["devices"][0]["connected"], true, "{report}");
    assert!(report["devices"][0]["polls"].as_u64().unwrap() > 0, "{report}");
    // The module lost: status relays OFF, X0 held, X10 cleared.
    module.kill();
    let before = (Instant::now(), scans(web));
    let lost = until(Duration::from_secs(5), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 0 && seen["M101"] == 0
    });
    assert!(lost.is_some(), "the status relays drop");
    let seen = devices(web, "X0,X10,Y0,D100");
    assert_eq!(
        (seen["X0"].clone(), seen["X10"].clone()),
        (1.into(), 0.into()),
        "{seen}"
    );
    assert!(seen["D100"].as_i64().unwrap() > 0, "errors counted: {seen}");
    let report = json(&http(web, "GET", "/api/io", "").1);
    assert_eq!(report["devices"][1]["connected"], false, "{report}");
    assert!(report["devices"][1]["last_error"].is_string(), "{report}");
    // The scans go on at their period while the pollers fail.
    std::thread::sleep(Duration::from_secs(1));
    let (since, scanned) = (before.0.elapsed(), scans(web) - before.1);
    let expected = since.as_millis() as u64 / 10;
    eprintln!("{scanned} scans in {} ms with the module lost", since.as_millis());
    assert!(scanned * 10 >= expected * 8, "{scanned} scans, {expected} expected");
    // The module back (a fresh one, its inputs OFF): both reconnect alone.
    let mut module = Module::start(&script, "tcp", &port.to_string(), control);
    let back = until(Duration::from_secs(6), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 1 && seen["M101"] == 1
    });
    assert!(
        back.is_some(),
        "the devices recover: {}",
        http(web, "GET", "/api/io", "").1
    );
    eprintln!("recovered {} ms after the module came back", back.unwrap().as_millis());
    assert!(until(Duration::from_secs(1), || devices(web, "X0")["X0"] == 0).is_some());
    assert_eq!(module.ask("di 0 1"), "ok");
    assert!(
        until(Duration::from_secs(3), || module.coil(0)).is_some(),
        "outputs written again"
    );
}

#[test]
fn an_rtu_module_on_a_serial_line_drives_x_and_takes_y() {
    let test = "an_rtu_module_on_a_serial_line_drives_x_and_takes_y";
    let ready = ensure("socat", &["-V"], &["socat"])
        .and_then(|()| ensure_python_module("serial", "pyserial"))
        .and_then(|()| module_ready());
    if let Err(why) = ready {
        skip(test, &why);
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (plc, module_end) = (dir.path().join("plc"), dir.path().join("module"));
    let link = |path: &Path| format!("pty,raw,echo=0,link={}", path.display());
    // Killed when the test ends, passed or failed.
    let _socat = Reaped(
        Command::new("socat")
            .args([link(&plc), link(&module_end)])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    assert!(until(Duration::from_secs(5), || plc.exists() && module_end.exists()).is_some());
    let script = dir.path().join("module.py");
    std::fs::write(&script, MODULE).unwrap();
    let mut module = Module::start(&script, "rtu", module_end.to_str().unwrap(), free_port());
    let file = dir.path().join("io.toml");
    std::fs::write(
        &file,
        format!(
            "[[device]]\nrtu = \"{line}\"\nunit = 1\nperiod_ms = {period}\ntimeout_ms = 200\nstatus = \"M100\"\n\
             [[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"X0\"\n\
             [[device.output]]\ncoils = 0\ncount = 8\nfrom = \"Y0\"\n\
             [[device]]\nrtu = \"{line}\"\nunit = 2\nperiod_ms = {period}\ntimeout_ms = 200\nstatus = \"M101\"\n\
             [[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"X10\"\n",
            line = format_args!("{}:115200,8N1", plc.display()),
            period = PERIOD.as_millis()
        ),
    )
    .unwrap();
    let server = Server::start_program(PROGRAM, &["--http", "127.0.0.1:0", "--io", file.to_str().unwrap()]);
    let web = server.web.unwrap();
    // Two units on the line (RS-485 multi-drop; the module answers both).
    let connected = until(Duration::from_secs(5), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 1 && seen["M101"] == 1
    });
    assert!(connected.is_some(), "{}", http(web, "GET", "/api/io", "").1);
    round_trips(&mut module, "rtu");
    assert!(
        until(Duration::from_secs(1), || devices(web, "X10")["X10"] == 1).is_some(),
        "the second unit's input"
    );
    // The module stops answering: the requests time out on a line kept
    // open; back, it answers the requests queued meanwhile (late answers,
    // flushed before each new request) and both units recover.
    module.signal("STOP");
    assert!(
        until(Duration::from_secs(5), || devices(web, "M100")["M100"] == 0).is_some(),
        "lost while silent"
    );
    module.signal("CONT");
    assert!(
        until(Duration::from_secs(6), || {
            let seen = devices(web, "M100,M101");
            seen["M100"] == 1 && seen["M101"] == 1
        })
        .is_some(),
        "{}",
        http(web, "GET", "/api/io", "").1
    );
    assert_eq!(module.ask("di 0 0"), "ok");
    assert!(
        until(Duration::from_secs(3), || !module.coil(0)
            && devices(web, "X10")["X10"] == 0)
        .is_some(),
        "inputs and outputs flow again"
    );
    module.kill();
    assert!(
        until(Duration::from_secs(5), || {
            let seen = devices(web, "M100,M101");
            seen["M100"] == 0 && seen["M101"] == 0
        })
        .is_some(),
        "the status relays drop"
    );
}

#[test]
fn a_wrong_io_file_stops_the_server_before_a_scan() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("plc.il");
    std::fs::write(&program, PROGRAM).unwrap();
    let file = dir.path().join("io.toml");
    std::fs::write(
        &file,
        "[[device]]\ntcp = \"127.0.0.1:1502\"\n\n[[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"Y0\"\n",
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(["serve", program.to_str().unwrap(), "--io", file.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("io.toml:4: to: `Y0` is not a device of X"), "{stderr}");
    assert!(!String::from_utf8_lossy(&output.stdout).contains("scanning"));
}

#[test]
fn a_program_that_writes_a_status_relay_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("plc.il");
    // M7600 is the first device's default status relay (a program cannot
    // drive X, so a status relay is what it may write by mistake).
    std::fs::write(&program, "LD M0\nOUT M7600\n").unwrap();
    let file = dir.path().join("io.toml");
    std::fs::write(
        &file,
        format!(
            "[[device]]\ntcp = \"127.0.0.1:{}\"\n[[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"X0\"\n",
            free_port()
        ),
    )
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(["serve", program.to_str().unwrap(), "--io", file.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The lines read on a thread of their own, so a warning never printed
    // fails the test at the deadline rather than hanging it.
    let (lines, said_lines) = std::sync::mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if lines.send(line).is_err() {
                break;
            }
        }
    });
    let deadline = Instant::now() + Duration::from_secs(20);
    let mut said = Vec::new();
    while let Ok(line) = said_lines.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
        let warned = line.starts_with("warning: --io");
        said.push(line);
        if warned {
            break;
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    let warning = said.last().cloned().unwrap_or_default();
    assert!(
        warning.contains("the program writes M7600, which remote I/O device `device1` writes"),
        "{said:?}"
    );
}

/// Two devices on one module: `changes` (inputs 0-7 to X0-X7, Y0-Y7 to
/// coils 0-7, keep-alive a minute: written on change only) and
/// `keepalive` (M0-M7, never changed, to coils 16-23 every 300 ms).
fn writes_file(port: u16) -> String {
    format!(
        r#"
[[device]]
name = "changes"
tcp = "127.0.0.1:{port}"
period_ms = {period}
timeout_ms = 200
retries = 1
keepalive_ms = 60000
status = "M100"
errors = "D100"
[[device.input]]
discrete_inputs = 0
count = 8
to = "X0"
[[device.output]]
coils = 0
count = 8
from = "Y0"

[[device]]
name = "keepalive"
tcp = "127.0.0.1:{port}"
period_ms = {period}
timeout_ms = 200
retries = 1
keepalive_ms = 300
status = "M101"
errors = "D101"
[[device.output]]
coils = 16
count = 8
from = "M0"
"#,
        period = PERIOD.as_millis()
    )
}

/// The module, and the server polling it with `writes_file`, once both
/// devices answer; None (skipped) without pymodbus.
fn started(test: &str) -> Option<(tempfile::TempDir, Module, Server)> {
    if let Err(why) = module_ready() {
        skip(test, &why);
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("module.py");
    std::fs::write(&script, MODULE).unwrap();
    let port = free_port();
    let module = Module::start(&script, "tcp", &port.to_string(), free_port());
    let file = dir.path().join("io.toml");
    std::fs::write(&file, writes_file(port)).unwrap();
    let server = Server::start_program(PROGRAM, &["--http", "127.0.0.1:0", "--io", file.to_str().unwrap()]);
    let web = server.web.unwrap();
    let connected = until(Duration::from_secs(5), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 1 && seen["M101"] == 1
    });
    assert!(connected.is_some(), "{}", http(web, "GET", "/api/io", "").1);
    Some((dir, module, server))
}

fn control(web: SocketAddr, action: &str) -> serde_json::Value {
    json(&http(web, "POST", "/api/control", &format!(r#"{{"action": "{action}"}}"#)).1)
}

fn set(web: SocketAddr, device: &str, value: i32) {
    let (status, body) = http(
        web,
        "POST",
        "/api/set",
        &format!(r#"{{"device": "{device}", "value": {value}}}"#),
    );
    assert_eq!(status, 200, "{body}");
}

#[test]
fn stop_and_pause_refresh_the_remote_io_and_the_server_stopping_turns_outputs_off() {
    let test = "stop_and_pause_refresh_the_remote_io_and_the_server_stopping_turns_outputs_off";
    let Some((_dir, mut module, server)) = started(test) else {
        return;
    };
    let web = server.web.unwrap();
    // A mapped input is the module's to write: a client's write is refused.
    let (status, body) = http(web, "POST", "/api/set", r#"{"device": "X1", "value": 1}"#);
    assert_eq!(status, 409, "{body}");
    assert!(body.contains("X1 is written by remote I/O device `changes`"), "{body}");
    for (action, input, output) in [("stop", 1, 5), ("pause", 2, 6)] {
        let state = control(web, action);
        assert_eq!(
            (state["mode"] == "stop", state["paused"] == true),
            (action == "stop", action == "pause"),
            "{state}"
        );
        // The inputs are refreshed without scans (a CPU's I/O refresh).
        assert_eq!(module.ask(&format!("di {input} 1")), "ok");
        let x = format!("X{input}");
        assert!(
            until(Duration::from_secs(3), || devices(web, &x)[&x] == 1).is_some(),
            "{action}: the input reaches {x}"
        );
        // A client's write to a Y reaches the module at once.
        set(web, &format!("Y{output}"), 1);
        assert!(
            until(Duration::from_secs(2), || module.coil(output)).is_some(),
            "{action}: Y{output} reaches its coil"
        );
        control(web, "run");
    }
    // Paused again with Y6 ON: the server stopping writes the coils OFF.
    control(web, "pause");
    set(web, "Y6", 1);
    assert!(until(Duration::from_secs(2), || module.coil(6)).is_some());
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
    assert!(!module.coil(6), "the outputs are OFF once the server has stopped");
}

#[test]
fn keepalives_and_changes_are_written_and_a_silent_module_is_lost_and_recovers() {
    let test = "keepalives_and_changes_are_written_and_a_silent_module_is_lost_and_recovers";
    let Some((_dir, mut module, server)) = started(test) else {
        return;
    };
    let web = server.web.unwrap();
    // Nothing changes: `changes` writes nothing, `keepalive` every 300 ms.
    std::thread::sleep(Duration::from_millis(300));
    let before = (module.coil_writes(0), module.coil_writes(16));
    std::thread::sleep(Duration::from_millis(1500));
    let after = (module.coil_writes(0), module.coil_writes(16));
    eprintln!("writes in 1.5 s without a change: {before:?} to {after:?}");
    assert_eq!(after.0, before.0, "no change, no write");
    assert!((3..=7).contains(&(after.1 - before.1)), "{before:?} {after:?}");
    // A change is written at once, once.
    assert_eq!(module.ask("di 0 1"), "ok");
    assert!(until(Duration::from_secs(1), || module.coil(0)).is_some());
    std::thread::sleep(Duration::from_millis(3 * PERIOD.as_millis() as u64));
    assert_eq!(module.coil_writes(0), after.0 + 1, "one write for one change");
    // The module stops answering (its process stopped, its port open):
    // requests time out, the status relays drop, the scans go on.
    module.signal("STOP");
    let lost = until(Duration::from_secs(5), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 0 && seen["M101"] == 0
    });
    assert!(lost.is_some(), "{}", http(web, "GET", "/api/io", "").1);
    eprintln!(
        "lost {} ms after the module stopped answering",
        lost.unwrap().as_millis()
    );
    let errors = devices(web, "D100")["D100"].as_i64().unwrap();
    let before = (Instant::now(), scans(web));
    std::thread::sleep(Duration::from_secs(1));
    let (since, scanned) = (before.0.elapsed(), scans(web) - before.1);
    let expected = since.as_millis() as u64 / 10;
    assert!(scanned * 10 >= expected * 8, "{scanned} scans, {expected} expected");
    // One error per attempt: a timeout each, then backoffs of 100, 200,
    // 400 ms... (not a burst of connection attempts).
    let more = devices(web, "D100")["D100"].as_i64().unwrap() - errors;
    assert!((1..=6).contains(&more), "{more} errors in a second while lost");
    // The module answers again: both devices recover by themselves.
    module.signal("CONT");
    let back = until(Duration::from_secs(6), || {
        let seen = devices(web, "M100,M101");
        seen["M100"] == 1 && seen["M101"] == 1
    });
    assert!(back.is_some(), "{}", http(web, "GET", "/api/io", "").1);
    assert_eq!(module.ask("di 0 0"), "ok");
    assert!(
        until(Duration::from_secs(2), || !module.coil(0)).is_some(),
        "written again"
    );
}
