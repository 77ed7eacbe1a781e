//! `ladderc serve`: a soft PLC. A scan thread runs the program at a fixed
//! period with the real elapsed time (so timers run in real time) and
//! publishes the image after every scan; the servers (Modbus TCP and RTU,
//! MELSEC, HTTP, OPC UA) read that copy and queue writes, answered once applied;
//! remote I/O modules (`--io`) are polled as its inputs and outputs.
//! Ctrl-C or SIGTERM stops it cleanly and prints the scan statistics. This
//! file is the crate root: the options, and `serve`, the start-up in its
//! steps (retain file, listeners, scan thread, helper threads, servers,
//! stop).

pub mod access;
pub mod acks;
mod change;
mod connections;
mod control;
#[cfg(feature = "fuzzing")]
#[doc(hidden)]
pub mod fuzzing;
pub mod guard;
mod http;
mod listeners;
mod melsec;
mod modbus;
pub mod modbus_rtu;
pub mod modbus_tcp;
mod opcua;
mod opcua_nodes;
mod realtime;
pub mod remote_io;
pub mod retain;
mod retained;
mod scan;
mod scan_lock;
mod shared;
mod stop;
mod tls;
mod view;
mod watch;

use shared::{Shared, Stats};

use ladder_engine::EngineKind;
use ladder_front::program::CheckedProgram;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

/// What the servers hold at most, so that no client can make the soft PLC
/// take memory or places without end (`serve --help` names the flags).
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Host writes (devices) waiting to be applied; beyond, Modbus
    /// exception 06, MELSEC's busy end code, HTTP 503, OPC UA
    /// BadTooManyOperations.
    pub queued_writes: usize,
    /// Modbus TCP connections, and how long one may be idle.
    pub modbus: modbus_tcp::ConnectionLimits,
    /// MELSEC TCP connections (and UDP datagrams being answered), and how
    /// long a connection may be idle.
    pub melsec: modbus_tcp::ConnectionLimits,
    /// HTTP connections at once, how long one may be idle, how long a
    /// write may wait for a client that does not read.
    pub http: guard::Bounds,
    /// Event streams at once.
    pub event_streams: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            queued_writes: shared::DEFAULT_QUEUED_WRITES,
            modbus: modbus_tcp::ConnectionLimits::default(),
            melsec: modbus_tcp::ConnectionLimits::default(),
            http: guard::Bounds {
                connections: guard::MOST_CONNECTIONS,
                idle: guard::IDLE,
                stall: guard::STALL,
            },
            event_streams: shared::MOST_EVENT_STREAMS,
        }
    }
}

/// How `serve` runs.
#[derive(Clone, Debug)]
pub struct ServeOptions {
    pub period: Duration,
    pub modbus: Option<SocketAddr>,
    /// MELSEC frames on this TCP address (and with `melsec_udp` its UDP
    /// port).
    pub melsec: Option<SocketAddr>,
    pub melsec_udp: bool,
    /// A Modbus RTU slave on this serial line.
    pub modbus_rtu: Option<modbus_rtu::Line>,
    pub http: Option<SocketAddr>,
    pub read_only: bool,
    pub engine: EngineKind,
    /// Online change when this program file changes on disk.
    pub watch_file: Option<std::path::PathBuf>,
    /// How long the file must stay unchanged before it is taken.
    pub watch_settle: Duration,
    /// Latched devices kept in this file (`--retain`).
    pub retain: Option<retain::RetainFile>,
    /// The latched devices (`--latch`, else FX3U's): what the retain file
    /// keeps, and what STOP→RUN does not clear.
    pub latched: Vec<retain::LatchRange>,
    /// How often the retain file is written (and once more at stop).
    pub retain_interval: Duration,
    /// SCHED_FIFO and locked memory for the scan thread (`--realtime`).
    pub realtime: bool,
    /// Networks beyond loopback whose Modbus clients may write.
    pub modbus_write_from: Vec<ipnet::IpNet>,
    /// Who may read and write over HTTP.
    pub access: access::Access,
    /// What the servers hold at most (connections, queued writes, streams).
    pub limits: Limits,
    /// HTTPS: the certificate chain and the private key (PEM files).
    pub tls: Option<(std::path::PathBuf, std::path::PathBuf)>,
    /// Serve OPC UA on this address.
    pub opcua: Option<SocketAddr>,
    /// The devices OPC UA publishes.
    pub opcua_devices: Vec<ladder_engine::waveform::Signal>,
    /// Remote I/O modules polled as the X inputs and Y outputs (`--io`).
    pub remote_io: Option<remote_io::RemoteIo>,
}

/// Runs the program until Ctrl-C or SIGTERM; `Err` is a message for an
/// unusable setup (a port in use, an engine that cannot run).
pub fn serve(
    program: CheckedProgram,
    source: &ladder_front::source::SourceFile,
    options: &ServeOptions,
) -> Result<Stats, String> {
    let loaded = change::Loaded::new(program, source);
    let shared = Arc::new(Shared::default());
    // A retain file that cannot be read stops everything before a scan.
    let restored = match &options.retain {
        Some(file) => retained::restore(file)?,
        None => Vec::new(),
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| format!("cannot start the server runtime: {e}"))?;
    // Ctrl-C and SIGTERM are taken before any listener is announced: a
    // client may stop the server as soon as it knows the address, and a
    // signal that came before its handler would kill the process.
    let signals = runtime.block_on(async { stop::StopSignals::register() });
    if let Some(io) = &options.remote_io {
        remote_io::check_serial_server(io, options.modbus_rtu.as_ref().map(|line| line.path.as_str()))?;
    }
    // The listeners first: a port in use is an error before anything runs.
    let listeners = listeners::Listeners::open(&runtime, options, &shared)?;
    // The pollers before the first scan, which takes their inputs.
    let pollers = options
        .remote_io
        .as_ref()
        .map(|io| remote_io::start(&runtime, io, &shared, options.period));
    let scanner = scan::start(
        loaded,
        scan::Setup {
            kind: options.engine,
            period: options.period,
            realtime: options.realtime,
            restored,
            latched: options.latched.clone(),
        },
        &shared,
    )?;
    announce(&format!("scanning every {} ms", options.period.as_millis()));
    let saver = start_helpers(options, &shared);
    shared.limit_writes(options.limits.queued_writes);
    shared.limit_recorders(options.limits.event_streams);
    listeners.serve(&runtime, options, &shared, signals);
    shared.stop();
    // A scan thread that panicked stopped the server (`scan::start`); the
    // saver still writes the last published image before that is reported.
    let scanned = scanner.join();
    // No scan hands outputs over any more: the remote outputs go OFF.
    if let Some(pollers) = pollers {
        pollers.stop(&runtime);
    }
    // The saver writes once more after the last scan.
    if let Some(saver) = saver {
        saver.join().map_err(|_| "the retain thread failed".to_string())?;
    }
    scanned.map_err(|_| "the scan thread failed".to_string())?;
    Ok(shared.stats())
}

/// The threads beside the scan thread: the retain file's saver (returned,
/// to be joined: it writes once more at stop) and the `--watch-file`
/// watcher (it ends on its own when the server stops).
fn start_helpers(options: &ServeOptions, shared: &Arc<Shared>) -> Option<std::thread::JoinHandle<()>> {
    let saver = options
        .retain
        .as_ref()
        .map(|file| retained::start_saver(file, options.retain_interval, shared));
    if let Some(path) = options.watch_file.clone() {
        let native = options.engine == EngineKind::Jit;
        watch::start(path, shared, native, options.watch_settle);
    }
    saver
}

/// The devices `--opcua-devices` names, or the default set.
pub fn opcua_devices(list: Option<&str>) -> Result<Vec<ladder_engine::waveform::Signal>, String> {
    opcua::parse_devices(list.unwrap_or(opcua::DEFAULT_DEVICES))
}

/// A line on standard output for whoever started the server (tests read the
/// port from it); a closed output is not an error.
pub(crate) fn announce(line: &str) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}
