//! `ladderc serve`: a soft PLC. A scan thread runs the program at a fixed
//! period with the real elapsed time (so timers run in real time) and
//! publishes the image after every scan; a Modbus TCP server (tokio-modbus)
//! reads that copy and queues writes for the next scan. Ctrl-C or SIGTERM
//! stops it cleanly and prints the scan statistics.

pub mod access;
mod change;
mod connections;
mod control;
mod debug;
#[doc(hidden)]
pub mod fuzzing;
pub mod guard;
mod http;
mod melsec;
mod modbus;
pub mod modbus_rtu;
pub mod modbus_tcp;
mod opcua;
mod realtime;
pub mod retain;
mod scan_lock;
mod shared;
mod tls;
mod view;

use shared::{HostWrite, Shared, Stats};

use ladder_engine::{instantiate, Engine, EngineKind};
use ladder_front::host_device::HostDevice;
use ladder_front::program::CheckedProgram;
use ladder_runtime::{BitArea, Device, Width, WordArea};
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What the servers hold at most, so that no client can make the soft PLC
/// take memory or places without end (`serve --help` names the flags).
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Host writes (devices) waiting for the next scan; beyond, Modbus
    /// exception 06, HTTP 503, OPC UA BadTooManyOperations.
    pub queued_writes: usize,
    /// Modbus TCP connections, and how long one may be idle.
    pub modbus: modbus_tcp::ConnectionLimits,
    /// MELSEC TCP connections, and how long one may be idle.
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
        Some(file) => {
            if file.remove_leftover() {
                announce(&format!(
                    "retain: removed {}, left by a save that was cut short",
                    file.temporary().display()
                ));
            }
            match file.load()? {
                retain::Restored::Fresh => {
                    announce(&format!(
                        "retain: {} does not exist yet; the latched devices start cleared",
                        file.path.display()
                    ));
                    Vec::new()
                }
                retain::Restored::Values(records) => {
                    // Only what is latched now comes back (`--latch`).
                    let (records, dropped) = retain::within(records, &file.ranges);
                    let names = |ranges: &mut dyn Iterator<Item = retain::LatchRange>| {
                        ranges.map(|range| range.to_string()).collect::<Vec<_>>().join(", ")
                    };
                    announce(&format!(
                        "retain: restored {} from {}",
                        match names(&mut records.iter().map(|(range, _)| *range)) {
                            none if none.is_empty() => "nothing".to_string(),
                            some => some,
                        },
                        file.path.display()
                    ));
                    if !dropped.is_empty() {
                        announce(&format!(
                            "retain: the file also holds {}, which are not latched now (--latch): not restored",
                            names(&mut dropped.into_iter())
                        ));
                    }
                    records
                }
            }
        }
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
    let signals = runtime.block_on(async { StopSignals::register() });
    // The listeners first: a port in use is an error before anything runs.
    let listener = listen(&runtime, options.modbus, "Modbus", "modbus")?;
    let tls = options
        .tls
        .as_ref()
        .map(|(cert, key)| tls::config(cert, key))
        .transpose()?;
    let web = listen(
        &runtime,
        options.http,
        "HTTP",
        if tls.is_some() { "https" } else { "http" },
    )?;
    let opcua = match listen(&runtime, options.opcua, "OPC UA", "opcua")? {
        Some(listener) => Some(runtime.block_on(async {
            opcua::start(
                opcua::Setup {
                    listener,
                    devices: options.opcua_devices.clone(),
                    read_only: options.read_only,
                    token: options.access.token.clone(),
                    period: options.period,
                },
                Arc::clone(&shared),
            )
        })?),
        None => None,
    };
    let melsec = match listen(&runtime, options.melsec, "MELSEC", "melsec")? {
        // UDP on the port TCP has (the same number when it was 0).
        Some(listener) if options.melsec_udp => {
            let address = listener.local_addr().map_err(|e| e.to_string())?;
            let udp = runtime
                .block_on(tokio::net::UdpSocket::bind(address))
                .map_err(|e| format!("cannot listen for MELSEC on UDP {address}: {e}"))?;
            Some((listener, Some(udp)))
        }
        Some(listener) => Some((listener, None)),
        None => None,
    };
    // The serial line opens before a scan, so a wrong device stops here.
    let serial = options.modbus_rtu.as_ref().map(modbus_rtu::open).transpose()?;
    let (ready, started) = std::sync::mpsc::channel();
    let scanner = {
        let shared = Arc::clone(&shared);
        let latched = options.latched.clone();
        let (period, kind, realtime) = (options.period, options.engine, options.realtime);
        std::thread::spawn(move || {
            for line in realtime::prepare_scan_thread(realtime) {
                announce(&line);
            }
            scan_loop(loaded, kind, (period, realtime), (&restored, &latched), &shared, &ready)
        })
    };
    started
        .recv()
        .map_err(|_| "the scan thread ended before it started".to_string())??;
    announce(&format!("scanning every {} ms", options.period.as_millis()));
    let saver = options.retain.as_ref().map(|file| {
        let shared = Arc::clone(&shared);
        let file = file.clone();
        let interval = options.retain_interval;
        std::thread::spawn(move || keep_retained(&file, interval, &shared))
    });
    if let Some(path) = options.watch_file.clone() {
        let shared = Arc::clone(&shared);
        let native = options.engine == EngineKind::Jit;
        let settle = options.watch_settle;
        std::thread::spawn(move || watch_file(&path, &shared, native, settle));
    }
    let mut access = options.access.clone();
    // Listening on port 0 (any free port): the host names carry the port
    // the system chose.
    if let Some(bound) = web.as_ref().and_then(|web| web.local_addr().ok()) {
        if access.hosts.port == 0 {
            access.hosts.port = bound.port();
        }
    }
    let limits = options.limits;
    shared.limit_writes(limits.queued_writes);
    shared.limit_recorders(limits.event_streams);
    // Who may write over Modbus and MELSEC.
    let permission = connections::Permission {
        read_only: options.read_only,
        write_from: options.modbus_write_from.clone(),
    };
    if let Some(serial) = serial {
        let service = modbus::Service {
            shared: Arc::clone(&shared),
            may_write: !options.read_only,
        };
        std::thread::spawn(move || serial.serve(&service));
    }
    let native = options.engine == EngineKind::Jit;
    let served = Arc::clone(&shared);
    runtime.block_on(async move {
        if let Some(listener) = listener {
            let shared = Arc::clone(&served);
            let permission = permission.clone();
            tokio::spawn(modbus_tcp::serve(listener, limits.modbus, move |peer| {
                modbus::Service {
                    shared: Arc::clone(&shared),
                    may_write: permission.may_write(peer),
                }
            }));
        }
        if let Some((listener, udp)) = melsec {
            tokio::spawn(melsec::serve(
                listener,
                udp,
                limits.melsec,
                permission,
                Arc::clone(&served),
            ));
        }
        if let Some(web) = web {
            let app = http::router(Arc::clone(&served), native)
                .layer(axum::middleware::from_fn_with_state(Arc::new(access), access::check));
            match tls {
                Some(tls) => match web.into_std() {
                    Ok(web) => {
                        let app = app.into_make_service_with_connect_info::<SocketAddr>();
                        let guard = guard::GuardAcceptor::new(limits.http);
                        let server = axum_server::from_tcp_rustls(web, tls).map(|rustls| rustls.acceptor(guard));
                        tokio::spawn(async move {
                            let _ = server.serve(app).await;
                        });
                    }
                    Err(error) => {
                        use std::io::Write as _;
                        let _ = writeln!(std::io::stderr(), "https: {error}");
                    }
                },
                None => {
                    let app = app.into_make_service_with_connect_info::<guard::Peer>();
                    let web = guard::GuardedListener::new(web, limits.http);
                    tokio::spawn(async move {
                        let _ = axum::serve(web, app).await;
                    });
                }
            }
        }
        if let Some(opcua) = opcua {
            tokio::spawn(opcua);
        }
        wait_for_stop(&served, signals).await;
    });
    shared.stop();
    scanner.join().map_err(|_| "the scan thread failed".to_string())?;
    // The saver writes once more after the last scan.
    if let Some(saver) = saver {
        saver.join().map_err(|_| "the retain thread failed".to_string())?;
    }
    Ok(shared.stats())
}

/// The devices `--opcua-devices` names, or the default set.
pub fn opcua_devices(list: Option<&str>) -> Result<Vec<ladder_engine::waveform::Signal>, String> {
    opcua::parse_devices(list.unwrap_or(opcua::DEFAULT_DEVICES))
}

/// Binds `address` (when given) and says where it listens: `{what}
/// listening on ADDRESS`, the line tests read the port from.
fn listen(
    runtime: &tokio::runtime::Runtime,
    address: Option<SocketAddr>,
    protocol: &str,
    what: &str,
) -> Result<Option<tokio::net::TcpListener>, String> {
    let Some(address) = address else {
        return Ok(None);
    };
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(address))
        .map_err(|e| format!("cannot listen for {protocol} on {address}: {e}"))?;
    let bound = listener.local_addr().map_err(|e| e.to_string())?;
    announce(&format!("{what} listening on {bound}"));
    Ok(Some(listener))
}

/// `--retain`: writes the latched devices of the published image every
/// `interval` and once more when the server stops. Nothing is written
/// before the first scan has published an image (the restored values would
/// otherwise be overwritten by an empty image); a failed write is reported
/// once and tried again at the next interval.
fn keep_retained(file: &retain::RetainFile, interval: Duration, shared: &Shared) {
    let mut last_error = None;
    // What the file holds: an unchanged image is not written again (a
    // controller's flash wears with every write).
    let mut written: Option<Vec<u8>> = None;
    let mut next = Instant::now() + interval;
    loop {
        let stopping = shared.wait_stop_until(next);
        next += interval;
        if !shared.published() {
            if stopping {
                return;
            }
            continue;
        }
        let image = shared.image();
        let bytes = retain::encode(&image, &file.ranges);
        if written.as_ref() == Some(&bytes) {
            if stopping {
                return;
            }
            continue;
        }
        let result = file.write(&bytes).map_err(|e| e.to_string());
        if result.is_ok() {
            written = Some(bytes);
        }
        if let Err(error) = &result {
            if last_error.as_ref() != Some(error) {
                use std::io::Write as _;
                let _ = writeln!(
                    std::io::stderr(),
                    "retain: cannot write {}: {error}",
                    file.path.display()
                );
            }
        }
        last_error = result.err();
        if stopping {
            if last_error.is_none() {
                announce(&format!("retain: saved to {}", file.path.display()));
            }
            return;
        }
    }
}

/// `--watch-file`: when the program file changes, compiles it and offers it
/// for online change; a version that does not compile is reported on
/// stderr and the running program goes on.
fn watch_file(path: &std::path::Path, shared: &Shared, native: bool, settle: Duration) {
    // The length too: two writes within a coarse file-system clock tick.
    let modified = || std::fs::metadata(path).ok().map(|m| (m.modified().ok(), m.len()));
    let mut seen = modified();
    let mut taken: Option<Vec<u8>> = std::fs::read(path).ok();
    while !shared.stopping() {
        std::thread::sleep(Duration::from_millis(200));
        let now = modified();
        if now == seen {
            continue;
        }
        // A change: taken only once the file has stopped changing for
        // `settle` (an editor may write a file in parts; a part that
        // happens to compile must not run).
        let mut last = now;
        let mut still_since = Instant::now();
        while still_since.elapsed() < settle {
            if shared.stopping() {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
            let now = modified();
            if now != last {
                last = now;
                still_since = Instant::now();
            }
        }
        seen = last;
        let Ok(bytes) = std::fs::read(path) else {
            continue;
        };
        // Saved again as it was: nothing to change.
        if taken.as_deref() == Some(bytes.as_slice()) {
            continue;
        }
        taken = Some(bytes.clone());
        let source = ladder_front::source::SourceFile::from_bytes(path.display().to_string(), &bytes);
        let (program, diagnostics) = ladder_front::check::compile_source(&source);
        let shown =
            ladder_front::diagnostics::render_all(&source, &diagnostics, ladder_front::diagnostics::Shown::default());
        if program.is_some() && drives_nothing(&diagnostics) {
            use std::io::Write as _;
            let _ = writeln!(
                std::io::stderr(),
                "{shown}{}: drives nothing (W0004); the running program goes on",
                path.display()
            );
            continue;
        }
        match program {
            Some(program) => match change::Loaded::new(program, &source).precompile(native) {
                Ok(loaded) => {
                    if shared.offer(loaded) {
                        announce(&format!("{}: changed, swapping it in", path.display()));
                    }
                }
                Err(error) => {
                    use std::io::Write as _;
                    let _ = writeln!(std::io::stderr(), "{}: {error}", path.display());
                }
            },
            None => {
                use std::io::Write as _;
                let _ = writeln!(
                    std::io::stderr(),
                    "{shown}{}: does not compile; the running program goes on",
                    path.display()
                );
            }
        }
    }
}

/// An empty program, or one that writes no device (W0004): refused for
/// online change unless the upload says it is meant.
pub(crate) fn drives_nothing(diagnostics: &[ladder_front::diagnostics::Diagnostic]) -> bool {
    diagnostics
        .iter()
        .any(|d| d.code == ladder_front::diagnostics::Code::DrivesNothing)
}

/// A line on standard output for whoever started the server (tests read the
/// port from it); a closed output is not an error.
pub(crate) fn announce(line: &str) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}

/// The signals that stop the server, registered once.
struct StopSignals {
    #[cfg(unix)]
    terminate: Option<tokio::signal::unix::Signal>,
    #[cfg(unix)]
    interrupt: Option<tokio::signal::unix::Signal>,
}

impl StopSignals {
    /// Registers the handlers (inside the runtime). Where one cannot be
    /// registered, that signal keeps its default action.
    fn register() -> StopSignals {
        #[cfg(unix)]
        {
            use tokio::signal::unix::{signal, SignalKind};
            StopSignals {
                terminate: signal(SignalKind::terminate()).ok(),
                interrupt: signal(SignalKind::interrupt()).ok(),
            }
        }
        #[cfg(not(unix))]
        StopSignals {}
    }
}

/// Ctrl-C, SIGTERM, or the scan thread stopping on its own.
async fn wait_for_stop(shared: &Shared, signals: StopSignals) {
    #[cfg(unix)]
    let (terminate, interrupt) = {
        let wait = |signal: Option<tokio::signal::unix::Signal>| async move {
            match signal {
                Some(mut signal) => {
                    signal.recv().await;
                }
                None => std::future::pending::<()>().await,
            }
        };
        (wait(signals.terminate), wait(signals.interrupt))
    };
    #[cfg(not(unix))]
    let (terminate, interrupt) = {
        let StopSignals {} = signals;
        (std::future::pending::<()>(), async {
            let _ = tokio::signal::ctrl_c().await;
        })
    };
    let stopped = async {
        while !shared.stopping() {
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    };
    tokio::select! {
        () = interrupt => {}
        () = terminate => {}
        () = stopped => {}
    }
}

/// When the next scan is due, and the time to report to it.
struct Clock {
    period: Duration,
    due: Instant,
    previous: Instant,
    carried: Duration,
    /// With `--realtime`: how long before the due time the sleep ends; the
    /// rest is spun, so the scan starts when due and not when the OS's
    /// timer gets round to it (a few percent of one core).
    spin: Duration,
}

/// The scan thread: the engine lives here (compiled code need not be sent
/// between threads). Between two scans it swaps in a new program when one
/// is offered, keeping the image (see `change`); the scan count and the
/// clock go on.
fn scan_loop(
    first: change::Loaded,
    kind: EngineKind,
    (period, realtime): (Duration, bool),
    (restored, latched): (&[(retain::LatchRange, Vec<i32>)], &[retain::LatchRange]),
    shared: &Shared,
    ready: &std::sync::mpsc::Sender<Result<(), String>>,
) {
    let start = Instant::now();
    let mut clock = Clock {
        period,
        due: start,
        previous: start,
        carried: Duration::ZERO,
        spin: if realtime {
            realtime::SPIN.min(period / 10)
        } else {
            Duration::ZERO
        },
    };
    let mut loaded = first;
    let mut image: Option<Box<ladder_runtime::Memory>> = None;
    let mut started = false;
    loop {
        let (next, last_image) = {
            let native = loaded.native.take().filter(|_| kind == EngineKind::Jit);
            let built = match native {
                Some(native) => Ok(Box::new(ladder_engine::InProcess::new(native)) as Box<dyn Engine>),
                None => instantiate(kind, &loaded.program, &[]),
            };
            let mut engine = match built {
                Ok(engine) => engine,
                Err(error) => {
                    if !started {
                        let _ = ready.send(Err(format!("{error:?}")));
                    }
                    shared.stop();
                    return;
                }
            };
            if let Some(image) = image.take() {
                engine.load_image(&image);
            } else if !restored.is_empty() {
                // Power on with the battery-backed devices as they were.
                if let Some(first) = engine.image() {
                    let mut first = Box::new(*first);
                    retain::apply(&mut first, restored);
                    engine.load_image(&first);
                    shared.publish(&first);
                }
            }
            shared.set_view(std::sync::Arc::clone(&loaded.view));
            shared.set_identity(std::sync::Arc::clone(&loaded.identity));
            if shared.swaps() > 0 || engine.image().is_some_and(|m| m.scan_count > 0) {
                // Every online change in the log: which program, from when.
                let identity = &loaded.identity;
                announce(&format!(
                    "online change: {} (sha256 {}) loaded {}, running from scan {}",
                    identity.name,
                    identity.sha256,
                    identity.loaded_at_text(),
                    engine.image().map_or(0, |m| m.scan_count) + 1
                ));
            }
            if !started {
                started = true;
                let _ = ready.send(Ok(()));
            }
            let next = run(engine.as_mut(), &mut clock, shared, latched);
            (next, engine.image().map(|m| Box::new(*m)))
        };
        let (Some(next), Some(last_image)) = (next, last_image) else {
            return;
        };
        image = Some(change::carry_over(&last_image, &loaded, &next));
        loaded = next;
        shared.swapped();
    }
}

/// What the scan thread does when a scan is due, by the RUN/STOP switch
/// and the debugger.
enum Due {
    /// A scan reporting the elapsed time (running) or the period (a step).
    Scan { step: bool },
    /// STOP: writes apply, no scan; `entering` turns every Y OFF.
    Stopped { entering: bool },
    /// Paused: nothing until a step (writes wait for it).
    Paused,
}

/// Scans until stopped (None) or offered a new program (between two scans).
fn run(
    engine: &mut dyn Engine,
    clock: &mut Clock,
    shared: &Shared,
    latched: &[retain::LatchRange],
) -> Option<change::Loaded> {
    let mut was_stopped = false;
    while !shared.stopping() {
        // Sleeps until the absolute deadline of the next scan; a stop, a
        // program offered or a control change wakes it at once.
        loop {
            let generation = shared.generation();
            if shared.stopping() {
                return None;
            }
            if let Some(next) = shared.take_program() {
                return Some(next);
            }
            let now = Instant::now();
            if now >= clock.due || shared.control().step_waiting() {
                break;
            }
            let wake = clock.due.checked_sub(clock.spin).unwrap_or(clock.due);
            if now >= wake {
                std::hint::spin_loop();
                continue;
            }
            shared.sleep_until(wake, generation);
        }
        let due = {
            let mut control = shared.control();
            if control.stopped {
                Due::Stopped { entering: !was_stopped }
            } else if control.paused && control.steps == 0 {
                Due::Paused
            } else {
                let step = control.paused;
                if step {
                    control.steps -= 1;
                }
                Due::Scan { step }
            }
        };
        let began = Instant::now();
        match due {
            Due::Stopped { entering } => {
                was_stopped = true;
                for write in shared.take_writes() {
                    apply(engine, write);
                }
                if entering {
                    all_outputs_off(engine);
                }
                if let Some(image) = engine.image() {
                    shared.publish(image);
                }
                idle(clock, began);
                continue;
            }
            Due::Paused => {
                idle(clock, began);
                continue;
            }
            Due::Scan { .. } => {
                // STOP→RUN as an FX does it: the non-latched devices
                // cleared, and the first scan the first again (M8002).
                if was_stopped {
                    if let Some(image) = engine.image() {
                        let fresh = retain::restart(image, latched);
                        engine.load_image(&fresh);
                    }
                }
                was_stopped = false;
            }
        }
        let Due::Scan { step } = due else { continue };
        let late = began.saturating_duration_since(clock.due);
        let elapsed = if step {
            clock.carried = Duration::ZERO;
            clock.period
        } else {
            began - clock.previous + clock.carried
        };
        clock.previous = began;
        let elapsed_ms = elapsed.as_millis().min(u128::from(u32::MAX)) as u32;
        clock.carried = elapsed - Duration::from_millis(u64::from(elapsed_ms));
        for write in shared.take_writes() {
            apply(engine, write);
        }
        if engine.scan(elapsed_ms).is_err() {
            shared.stop();
            break;
        }
        if let Some(image) = engine.image() {
            shared.publish(image);
            shared.sample(image);
            shared.control().after_scan(image, u64::from(image.scan_count));
        }
        let took = began.elapsed();
        clock.due += clock.period;
        let overrun = !step && Instant::now() > clock.due;
        if step {
            // Steps run back to back: the next scan is due a period after
            // this one, not a period for every step taken (a resume after
            // `step 1000` would wait 1000 periods).
            idle(clock, Instant::now());
        } else if overrun {
            // Behind: the next scan starts now, not in a burst.
            clock.due = Instant::now();
        }
        shared.update_stats(|stats| {
            stats.scans += 1;
            stats.last = took;
            stats.min = Some(stats.min.map_or(took, |min| min.min(took)));
            stats.max = stats.max.max(took);
            stats.total += took;
            stats.jitter = stats.jitter.max(late);
            stats.jitter_total += late;
            stats.overruns += u64::from(overrun);
        });
        if !step {
            shared.record_latency(late);
        }
    }
    None
}

/// A period without a scan (stopped or paused): the next scan is due a
/// period later and reports one period, not the time it waited.
fn idle(clock: &mut Clock, now: Instant) {
    clock.due = now + clock.period;
    clock.previous = now + clock.period;
    clock.carried = Duration::ZERO;
}

/// STOP: every output OFF, as an FX turns its outputs off in STOP.
fn all_outputs_off(engine: &mut dyn Engine) {
    for n in 0..BitArea::Y.count() {
        let _ = engine.write(
            HostDevice {
                device: Device::Bit(BitArea::Y, n),
                width: Width::Single,
            },
            0,
        );
    }
}

/// A client's write as a host write (the same call a firmware host makes).
fn apply(engine: &mut dyn Engine, write: HostWrite) {
    let bit = |area, index| HostDevice {
        device: Device::Bit(area, index),
        width: Width::Single,
    };
    let _ = match write {
        HostWrite::Input(n, on) => engine.write(bit(BitArea::X, n), i32::from(on)),
        HostWrite::Output(n, on) => engine.write(bit(BitArea::Y, n), i32::from(on)),
        HostWrite::Relay(n, on) => engine.write(bit(BitArea::M, n), i32::from(on)),
        HostWrite::Data(n, value) => engine.write(
            HostDevice {
                device: Device::Word(WordArea::D, n),
                width: Width::Single,
            },
            i32::from(value),
        ),
        HostWrite::Set(device, value) => engine.write(device, value),
        HostWrite::Force(area, index, on) => engine.force(area, index, on),
        HostWrite::Unforce(area, index) => engine.unforce(area, index),
    };
}
