//! The soft PLC's steady period: the scan thread's wake-up latency (start
//! of a scan minus its due time) and scan time of `ladderc serve`, with a
//! plant program of 100 units at a 10 ms period, measured idle and under
//! load (10 event streams of 256 devices each and 16 Modbus clients
//! polling 125 registers as fast as they are answered), each with normal
//! priority and with `--realtime`. The figures are the server's own
//! statistics (`GET /api/stats`, reset at the start of each phase): p50,
//! p99 and maximum of the wake-up latency over the phase, its average, the
//! maximum scan time and overruns. OpenPLC's runtime publishes the same
//! kind of figure (wake-up latency 26 µs maximum, 7 µs average). A last
//! phase of each runs the server with remote I/O (`--io`): 8 modules
//! polled every 10 ms, 16 inputs to X and 16 coils from Y each, served by
//! minimal Modbus TCP responders in this process (`modules`), to show the
//! pollers cost the scan thread's wake-up nothing.
//!
//! Not a criterion benchmark: what is measured is a distribution over
//! wall-clock time, not the time of a repeatable iteration. It builds the
//! release binary it measures. `LADDERC_JITTER_SECONDS` sets the length of
//! each phase (default 20).
//!
//! cargo bench -p ladderc-benches --bench serve_jitter

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

fn main() {
    // `cargo bench` passes `--bench`; a filter argument is ignored.
    let seconds: u64 = std::env::var("LADDERC_JITTER_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let binary = build_release();
    let dir = std::env::temp_dir().join(format!("ladderc-jitter-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let program = dir.join("plant.il");
    std::fs::write(&program, ladderc_benches::plant(100)).unwrap();
    println!("serve_jitter: plant(100), 10 ms period, {seconds} s per phase");
    println!(
        "{:<28} {:>9} {:>9} {:>9} {:>9} {:>11} {:>9} {:>9}",
        "phase", "scans", "p50 µs", "p99 µs", "max µs", "average µs", "scan max", "overruns"
    );
    for realtime in [false, true] {
        let mut server = start(&binary, &program, realtime);
        std::thread::sleep(Duration::from_millis(500));
        for loaded in [false, true] {
            let stop = Arc::new(AtomicBool::new(false));
            let served = Arc::new(AtomicU64::new(0));
            let clients = if loaded {
                load(&server, &stop, &served)
            } else {
                Vec::new()
            };
            std::thread::sleep(Duration::from_millis(300));
            request(server.web, "POST", "/api/stats/reset");
            std::thread::sleep(Duration::from_secs(seconds));
            let stats = request(server.web, "GET", "/api/stats");
            stop.store(true, Ordering::Relaxed);
            for client in clients {
                let _ = client.join();
            }
            let phase = format!(
                "{} {}",
                if realtime { "realtime" } else { "normal" },
                if loaded { "loaded" } else { "idle" }
            );
            report(&phase, &stats);
            if loaded {
                println!(
                    "{:<28} {} Modbus requests answered ({:.0}/s)",
                    "",
                    served.load(Ordering::Relaxed),
                    served.load(Ordering::Relaxed) as f64 / seconds as f64
                );
            }
        }
        for line in server.realtime_lines.drain(..) {
            println!("  {line}");
        }
        let _ = server.child.kill();
        let _ = server.child.wait();
        remote_io_phase(&binary, &program, &dir, realtime, seconds);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn build_release() -> std::path::PathBuf {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--release", "-p", "ladderc", "--bin", "ladderc"])
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the release binary builds");
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|_| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
    target.join("release/ladderc")
}

struct Server {
    child: Child,
    modbus: SocketAddr,
    web: SocketAddr,
    realtime_lines: Vec<String>,
}

fn start(binary: &std::path::Path, program: &std::path::Path, realtime: bool) -> Server {
    start_with(binary, program, realtime, &[])
}

fn start_with(binary: &std::path::Path, program: &std::path::Path, realtime: bool, extra: &[&str]) -> Server {
    let mut command = Command::new(binary);
    command
        .arg("serve")
        .arg(program)
        .args(["--scan-ms", "10", "--modbus", "127.0.0.1:0", "--http", "127.0.0.1:0"])
        .args(extra);
    if realtime {
        command.arg("--realtime");
    }
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("ladderc serve starts");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let (mut modbus, mut web, mut realtime_lines) = (None, None, Vec::new());
    for line in lines.by_ref() {
        let line = line.unwrap();
        if let Some(a) = line.strip_prefix("modbus listening on ") {
            modbus = a.parse().ok();
        } else if let Some(a) = line.strip_prefix("http listening on ") {
            web = a.parse().ok();
        } else if line.starts_with("realtime: ") {
            realtime_lines.push(line);
        } else if line.starts_with("scanning every") {
            break;
        }
    }
    Server {
        child,
        modbus: modbus.expect("a Modbus address"),
        web: web.expect("an HTTP address"),
        realtime_lines,
    }
}

/// 10 event streams of 256 devices and 16 Modbus pollers, until `stop`.
fn load(server: &Server, stop: &Arc<AtomicBool>, served: &Arc<AtomicU64>) -> Vec<std::thread::JoinHandle<()>> {
    let mut clients = Vec::new();
    for _ in 0..10 {
        let (web, stop) = (server.web, Arc::clone(stop));
        clients.push(std::thread::spawn(move || {
            let mut stream = TcpStream::connect(web).unwrap();
            stream.set_read_timeout(Some(Duration::from_millis(500))).unwrap();
            write!(stream, "GET /api/events?watch=D0..D255 HTTP/1.1\r\nHost: {web}\r\n\r\n").unwrap();
            let mut buffer = vec![0u8; 64 * 1024];
            while !stop.load(Ordering::Relaxed) {
                let _ = stream.read(&mut buffer);
            }
        }));
    }
    for client in 0..16u16 {
        let (modbus, stop, served) = (server.modbus, Arc::clone(stop), Arc::clone(served));
        clients.push(std::thread::spawn(move || {
            let mut stream = TcpStream::connect(modbus).unwrap();
            stream.set_nodelay(true).unwrap();
            let mut response = [0u8; 9 + 250];
            let mut transaction = client.wrapping_mul(4096);
            while !stop.load(Ordering::Relaxed) {
                transaction = transaction.wrapping_add(1);
                let [t0, t1] = transaction.to_be_bytes();
                stream.write_all(&[t0, t1, 0, 0, 0, 6, 1, 0x03, 0, 0, 0, 125]).unwrap();
                stream.read_exact(&mut response).unwrap();
                served.fetch_add(1, Ordering::Relaxed);
            }
        }));
    }
    clients
}

/// One HTTP request; the JSON body.
fn request(web: SocketAddr, method: &str, path: &str) -> serde_json::Value {
    let mut stream = TcpStream::connect(web).unwrap();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {web}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut text = String::new();
    stream.read_to_string(&mut text).unwrap();
    let body = text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    serde_json::from_str(body).unwrap_or(serde_json::Value::Null)
}

fn report(phase: &str, stats: &serde_json::Value) {
    let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
    let window = &stats["jitter_window"];
    println!(
        "{:<28} {:>9} {:>9.1} {:>9.1} {:>9.1} {:>11.1} {:>9.1} {:>9}",
        phase,
        stats["scans"],
        f(&window["p50_us"]),
        f(&window["p99_us"]),
        f(&stats["jitter_us"]),
        f(&stats["jitter_average_us"]),
        f(&stats["max_us"]),
        stats["overruns"]
    );
}

/// Remote I/O modules polled every 10 ms.
const MODULES: usize = 8;

/// The server idle but for `MODULES` remote I/O modules at 10 ms each.
fn remote_io_phase(
    binary: &std::path::Path,
    program: &std::path::Path,
    dir: &std::path::Path,
    realtime: bool,
    seconds: u64,
) {
    let stop = Arc::new(AtomicBool::new(false));
    let served = Arc::new(AtomicU64::new(0));
    let mut file = String::new();
    for k in 0..MODULES {
        let port = modules::serve(Arc::clone(&stop), Arc::clone(&served));
        // Octal X and Y: 16 each, X0-X17, X20-X37, ...
        file.push_str(&format!(
            "[[device]]\ntcp = \"127.0.0.1:{port}\"\nperiod_ms = 10\ntimeout_ms = 100\n\
             [[device.input]]\ndiscrete_inputs = 0\ncount = 16\nto = \"X{:o}\"\n\
             [[device.output]]\ncoils = 0\ncount = 16\nfrom = \"Y{:o}\"\n",
            16 * k,
            16 * k
        ));
    }
    let io = dir.join("io.toml");
    std::fs::write(&io, file).unwrap();
    let mut server = start_with(binary, program, realtime, &["--io", io.to_str().unwrap()]);
    std::thread::sleep(Duration::from_millis(800));
    request(server.web, "POST", "/api/stats/reset");
    let before = served.load(Ordering::Relaxed);
    std::thread::sleep(Duration::from_secs(seconds));
    let stats = request(server.web, "GET", "/api/stats");
    let devices = request(server.web, "GET", "/api/io");
    let requests = served.load(Ordering::Relaxed) - before;
    stop.store(true, Ordering::Relaxed);
    let phase = format!("{} + {MODULES} modules", if realtime { "realtime" } else { "normal" });
    report(&phase, &stats);
    let connected = devices["devices"]
        .as_array()
        .map_or(0, |all| all.iter().filter(|d| d["connected"] == true).count());
    println!(
        "{:<28} {requests} module requests ({:.0}/s), {connected} of {MODULES} connected",
        "",
        requests as f64 / seconds as f64
    );
    let _ = server.child.kill();
    let _ = server.child.wait();
}

/// Minimal Modbus TCP modules for the remote I/O phase: any unit, reads
/// answered with inputs that change every second, writes acknowledged.
mod modules {
    use std::io::{Read, Write};
    use std::net::{TcpListener, TcpStream};
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    use std::sync::Arc;
    use std::time::Instant;

    /// A module on a free loopback port (returned), until `stop`.
    pub fn serve(stop: Arc<AtomicBool>, served: Arc<AtomicU64>) -> u16 {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        std::thread::spawn(move || {
            for stream in listener.incoming() {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                if let Ok(stream) = stream {
                    let (stop, served) = (Arc::clone(&stop), Arc::clone(&served));
                    std::thread::spawn(move || answer(stream, &stop, &served));
                }
            }
        });
        port
    }

    fn answer(mut stream: TcpStream, stop: &AtomicBool, served: &AtomicU64) {
        let _ = stream.set_nodelay(true);
        let start = Instant::now();
        let mut header = [0u8; 7];
        while !stop.load(Ordering::Relaxed) {
            if stream.read_exact(&mut header).is_err() {
                return;
            }
            let length = usize::from(u16::from_be_bytes([header[4], header[5]])).saturating_sub(1);
            let mut pdu = vec![0u8; length];
            if length == 0 || stream.read_exact(&mut pdu).is_err() {
                return;
            }
            let word = |at: usize| {
                u16::from_be_bytes([pdu.get(at).copied().unwrap_or(0), pdu.get(at + 1).copied().unwrap_or(0)])
            };
            let reply: Vec<u8> = match pdu[0] {
                0x01 | 0x02 => {
                    let bytes = usize::from(word(3)).div_ceil(8);
                    let on = if start.elapsed().as_secs().is_multiple_of(2) {
                        0x55
                    } else {
                        0xAA
                    };
                    let mut reply = vec![pdu[0], bytes as u8];
                    reply.extend(std::iter::repeat_n(on, bytes));
                    reply
                }
                0x03 | 0x04 => {
                    let count = usize::from(word(3));
                    let mut reply = vec![pdu[0], (2 * count) as u8];
                    reply.extend(std::iter::repeat_n(0u8, 2 * count));
                    reply
                }
                0x05 | 0x06 => pdu.get(..5).unwrap_or(&pdu).to_vec(),
                0x0F | 0x10 => pdu.get(..5).unwrap_or(&pdu).to_vec(),
                other => vec![other | 0x80, 0x01],
            };
            let mut frame = header.to_vec();
            let [high, low] = u16::try_from(reply.len() + 1).unwrap_or(0).to_be_bytes();
            frame[4] = high;
            frame[5] = low;
            frame.extend(reply);
            if stream.write_all(&frame).is_err() {
                return;
            }
            served.fetch_add(1, Ordering::Relaxed);
        }
    }
}
