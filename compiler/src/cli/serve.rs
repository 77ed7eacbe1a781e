//! `ladderc serve`: the program as a soft PLC (see `ladder_serve`).

use super::status;
use clap::{Args, ValueEnum};
use ladder_engine::scenario::EngineKind;
use ladder_front::diagnostics::Shown;
use ladder_serve::{serve, ServeOptions};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

/// The Modbus mapping, shown by `--help`.
const MAPPING: &str = "Modbus TCP mapping:
  discrete inputs 0-255        X0-X377 (read)
  coils 0-255                  Y0-Y377 (read/write)
  coils 1000-9511              M0-M8511 (read/write)
  coils 20000-20255            the input image X0-X377 (write to drive the inputs)
  holding registers 0-8511     D0-D8511 (read/write; 32-bit values low word first)
  input registers 0-511        timer current values T0-T511
  input registers 1000-1199    counter current values C0-C199
A write acts like a host write at the end of the scan in progress (at once
between scans, in STOP or paused) and is answered once applied.
HTTP (--http): / the live monitor page; GET /api/devices?watch=Y0,D0 and
/api/stats; GET /api/events?watch=... pushes the devices (server-sent events);
POST /api/set, /api/force, /api/unforce with {\"device\": \"Y0\", \"value\": 1};
POST /api/program with a new program's text swaps it in between two scans. Addresses outside these get
exception 02 (illegal data address), other functions exception 01 (illegal function).";

#[derive(Args, Debug)]
#[command(after_help = MAPPING)]
pub struct ServeArgs {
    /// The program: IL or a GX Works2 CSV export.
    program: PathBuf,
    /// The scan period in milliseconds (each scan reports the real time
    /// since the previous one).
    #[arg(long, default_value_t = 10)]
    scan_ms: u32,
    /// Serve Modbus TCP on this address (loopback unless --allow-remote).
    #[arg(long, value_name = "ADDRESS:PORT")]
    modbus: Option<SocketAddr>,
    /// Serve the MELSEC communication protocol (MC protocol) on this TCP
    /// address and the same UDP port: 1E frames as an FX3U-ENET-ADP
    /// answers them, 3E and 4E frames (SLMP) as an iQ-F does, binary and
    /// ASCII (loopback unless --allow-remote).
    #[arg(long, value_name = "ADDRESS:PORT")]
    melsec: Option<SocketAddr>,
    /// Answer MELSEC frames on the --melsec port's UDP twin too. UDP has no
    /// connection: an answer goes to whatever source a datagram names and
    /// writes are judged by it, so beyond loopback only on a trusted
    /// network.
    #[arg(long, requires = "melsec")]
    melsec_udp: bool,
    /// Serve the Modbus map as an RTU slave on this serial line
    /// (`/dev/ttyUSB0`, `/dev/ttyUSB0:9600,8N1`; 19200 8E1 unless given).
    #[arg(long, value_name = "TTY[:BAUD,FORMAT]")]
    modbus_rtu: Option<String>,
    /// The unit (slave address, 1-247) --modbus-rtu answers.
    #[arg(long, default_value_t = 1, value_name = "N")]
    modbus_unit: u8,
    /// Serve the live monitor page and the JSON API on this address
    /// (loopback unless --allow-remote).
    #[arg(long, value_name = "ADDRESS:PORT")]
    http: Option<SocketAddr>,
    /// Swap the program in online whenever its file changes (devices,
    /// timers, forces and edge values kept), once it has stopped changing
    /// for --watch-settle-ms and compiles.
    #[arg(long)]
    watch_file: bool,
    /// How long the program file must stay unchanged before --watch-file
    /// takes it (an editor may write a file in parts).
    #[arg(long, default_value_t = 3000, value_name = "MS")]
    watch_settle_ms: u64,
    /// Refuse every write (Modbus exception 01, HTTP 403).
    #[arg(long)]
    read_only: bool,
    /// Allow addresses other than loopback: anyone on the network could then
    /// write the machine's inputs and outputs.
    #[arg(long)]
    allow_remote: bool,
    /// Engine that runs the program.
    #[arg(long, value_enum, default_value_t = ServeEngine::Jit)]
    engine: ServeEngine,
    /// Keep the latched devices in this file: restored at start, written
    /// every --retain-ms and at stop (atomically, with a checksum). A file
    /// that cannot be read stops the server; it is never overwritten.
    #[arg(long, value_name = "FILE")]
    retain: Option<PathBuf>,
    /// How often the retain file is written, in milliseconds.
    #[arg(long, default_value_t = 1000, value_name = "MS")]
    retain_ms: u32,
    /// The latched ranges, as the FX parameters set them (default: a GX
    /// Developer project's param.wpa, the program's `//@ latch` line, else
    /// FX3U's M500-M7679, S500-S4095, T246-T255, C100-C199, C220-C255,
    /// D200-D7999 and all of R), e.g. `M500-M1023,D200-D511`, or `none`:
    /// what --retain keeps, and what STOP→RUN does not clear.
    #[arg(long, value_name = "RANGES")]
    latch: Option<String>,
    /// Run the scan thread at real-time priority (SCHED_FIFO) with the
    /// process's memory locked; says so and goes on where not permitted.
    #[arg(long)]
    realtime: bool,
    /// Modbus and MELSEC clients in these networks may write (and switch
    /// RUN/STOP over MELSEC) (`192.168.1.0/24`, an address alone,
    /// comma-separated); beyond loopback, nobody else may.
    #[arg(long, value_name = "ADDR/NET,...", value_delimiter = ',')]
    modbus_write_from: Vec<String>,
    /// HTTP writes need the token in this file (`Authorization: Bearer
    /// TOKEN`); without it, HTTP writes come only from loopback.
    #[arg(long, value_name = "FILE")]
    token_file: Option<PathBuf>,
    /// HTTP reads need the token too (the page itself stays open).
    #[arg(long, requires = "token_file")]
    token_reads: bool,
    /// A host name HTTP requests may name besides the address the server
    /// listens on (`NAME`: on any port, `NAME:PORT`: on that one;
    /// repeatable or comma-separated): the name a reverse proxy forwards,
    /// or the machine's own name. Other names are refused,
    /// so that a web page cannot reach the server through a name it
    /// controls (DNS rebinding).
    #[arg(long, value_name = "NAME[:PORT]")]
    allowed_host: Vec<String>,
    /// Host writes (devices) that may wait to be applied; a write
    /// beyond gets Modbus exception 06 (busy), HTTP 503 or OPC UA
    /// BadTooManyOperations. A write of a device already waiting replaces it.
    #[arg(long, default_value_t = ladder_serve::Limits::default().queued_writes, value_name = "N")]
    max_queued_writes: usize,
    /// Modbus TCP connections served at once; a new client gets the place
    /// of the connection idle longest (idle for a second at least).
    #[arg(long, default_value_t = ladder_serve::Limits::default().modbus.connections, value_name = "N")]
    max_modbus_connections: usize,
    /// A Modbus TCP connection that sends no request for this long is closed.
    #[arg(long, default_value_t = ladder_serve::Limits::default().modbus.idle.as_secs(), value_name = "SECONDS")]
    modbus_idle_s: u64,
    /// MELSEC TCP connections served at once; a new client gets the place
    /// of the connection idle longest (idle for a second at least). Also
    /// the UDP datagrams (`--melsec-udp`) being answered at once.
    #[arg(long, default_value_t = ladder_serve::Limits::default().melsec.connections, value_name = "N")]
    max_melsec_connections: usize,
    /// A MELSEC connection that sends no frame for this long is closed.
    #[arg(long, default_value_t = ladder_serve::Limits::default().melsec.idle.as_secs(), value_name = "SECONDS")]
    melsec_idle_s: u64,
    /// HTTP connections served at once; a new client gets the place of the
    /// connection idle longest (idle for a second at least).
    #[arg(long, default_value_t = ladder_serve::Limits::default().http.connections, value_name = "N")]
    max_http_connections: usize,
    /// An HTTP connection on which nothing moves for this long is closed.
    #[arg(long, default_value_t = ladder_serve::Limits::default().http.idle.as_secs(), value_name = "SECONDS")]
    http_idle_s: u64,
    /// Event streams (monitor pages, trends) served at once.
    #[arg(long, default_value_t = ladder_serve::Limits::default().event_streams, value_name = "N")]
    max_event_streams: usize,
    /// Serve HTTPS with this certificate chain (PEM); needs --tls-key.
    #[arg(long, value_name = "FILE", requires = "tls_key")]
    tls_cert: Option<PathBuf>,
    /// The private key (PEM) of --tls-cert.
    #[arg(long, value_name = "FILE", requires = "tls_cert")]
    tls_key: Option<PathBuf>,
    /// Serve OPC UA (opc.tcp, security policy None) on this address
    /// (loopback unless --allow-remote).
    #[arg(long, value_name = "ADDRESS:PORT")]
    opcua: Option<SocketAddr>,
    /// The devices OPC UA publishes, as --watch names them (`:32` and
    /// `:float` for pairs); default: X, Y, M0-M1023, M8000-M8099, S0-S999,
    /// T/TN and C/CN 0-255, D0-D1023, D8000-D8099, R0-R1023.
    #[arg(long, value_name = "DEV,...")]
    opcua_devices: Option<String>,
    /// Poll the remote I/O modules this TOML file names (Modbus TCP and
    /// RTU) as the program's inputs and outputs (docs/serve.md).
    #[arg(long, value_name = "FILE")]
    io: Option<PathBuf>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ServeEngine {
    Interp,
    Jit,
}

pub fn run(args: &ServeArgs, shown: Shown) -> u8 {
    let mut options = match options(args) {
        Ok(options) => options,
        Err(message) => {
            say_err!("error: {message}");
            return status::UNUSABLE;
        }
    };
    if let Some(address) = args.http {
        if !address.ip().is_loopback() && options.access.token.is_none() && !args.read_only {
            say_err!("note: no --token-file: HTTP writes are taken from loopback only");
        }
    }
    let source = match super::read_program(&args.program) {
        Ok(source) => source,
        Err(message) => {
            say_err!("error: {message}");
            return status::UNUSABLE;
        }
    };
    let (program, diagnostics) = ladder_front::check::compile_source(&source);
    super::write_raw(
        true,
        &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
    );
    let Some(program) = program else {
        return status::FAILED;
    };
    // The latched ranges of a GX Developer project's parameters (its
    // listing's `//@ latch` line), unless --latch says otherwise.
    if args.latch.is_none() {
        if let Some(list) = ladder_front::gxdev::listing::directives(&source.text).latch {
            match ladder_serve::retain::parse_latch_list(&list) {
                Ok(ranges) => {
                    if let Some(retain) = &mut options.retain {
                        retain.ranges = ranges.clone();
                    }
                    options.latched = ranges;
                }
                Err(message) => {
                    say_err!("error: the program's `//@ latch {list}`: {message}");
                    return status::UNUSABLE;
                }
            }
        }
    }
    if let Some(io) = &options.remote_io {
        for warning in remote_io_warnings(&program, io) {
            say_err!("warning: {warning}");
        }
    }
    match serve(program, &source, &options) {
        Ok(stats) => {
            say_err!(
                "{} scans: scan time min {:.1} µs, average {:.1} µs, max {:.1} µs; start jitter up to {:.2} ms; {} overruns",
                stats.scans,
                stats.min.unwrap_or_default().as_secs_f64() * 1e6,
                stats.average().as_secs_f64() * 1e6,
                stats.max.as_secs_f64() * 1e6,
                stats.jitter.as_secs_f64() * 1e3,
                stats.overruns
            );
            status::OK
        }
        Err(message) => {
            say_err!("error: {message}");
            status::UNUSABLE
        }
    }
}

/// The flags checked and made the server's options; `Err` is what the
/// first wrong flag is told (each is checked in this order, before the
/// program is read).
fn options(args: &ServeArgs) -> Result<ServeOptions, String> {
    check_addresses(args)?;
    if !(1..=60_000).contains(&args.scan_ms) {
        return Err("--scan-ms is 1 to 60000".to_string());
    }
    let ranges = match args.latch.as_deref() {
        None => ladder_serve::retain::fx3u_defaults(),
        Some(list) => ladder_serve::retain::parse_latch_list(list).map_err(|message| format!("--latch: {message}"))?,
    };
    if args.opcua_devices.is_some() && args.opcua.is_none() {
        return Err("--opcua-devices names what --opcua ADDRESS publishes; add --opcua".to_string());
    }
    if !(10..=3_600_000).contains(&args.retain_ms) {
        return Err("--retain-ms is 10 to 3600000".to_string());
    }
    let modbus_rtu = serial_line(args)?;
    let modbus_write_from = write_networks(&args.modbus_write_from)?;
    let opcua_devices = args
        .opcua
        .map(|_| ladder_serve::opcua_devices(args.opcua_devices.as_deref()))
        .transpose()
        .map_err(|message| format!("--opcua-devices: {message}"))?
        .unwrap_or_default();
    let token = args
        .token_file
        .as_deref()
        .map(ladder_serve::access::read_token_file)
        .transpose()?;
    Ok(ServeOptions {
        period: Duration::from_millis(u64::from(args.scan_ms)),
        modbus: args.modbus,
        melsec: args.melsec,
        melsec_udp: args.melsec_udp,
        modbus_rtu,
        http: args.http,
        read_only: args.read_only,
        watch_file: args.watch_file.then(|| args.program.clone()),
        watch_settle: Duration::from_millis(args.watch_settle_ms),
        retain: args.retain.clone().map(|path| ladder_serve::retain::RetainFile {
            path,
            ranges: ranges.clone(),
        }),
        latched: ranges,
        retain_interval: Duration::from_millis(u64::from(args.retain_ms)),
        realtime: args.realtime,
        modbus_write_from,
        access: ladder_serve::access::Access {
            token,
            token_reads: args.token_reads,
            read_only: args.read_only,
            hosts: args.http.map_or_else(Default::default, |address| {
                ladder_serve::access::Hosts::of(address, args.tls_cert.is_some(), &args.allowed_host)
            }),
        },
        limits: limits(args),
        tls: args.tls_cert.clone().zip(args.tls_key.clone()),
        opcua: args.opcua,
        opcua_devices,
        remote_io: args.io.as_deref().map(ladder_serve::remote_io::load).transpose()?,
        engine: match args.engine {
            ServeEngine::Interp => EngineKind::Interp,
            ServeEngine::Jit => EngineKind::Jit,
        },
    })
}

/// What the remote I/O writes that the program writes too (bits at fixed
/// addresses: coils, SET/RST, instructions that write bits).
fn remote_io_warnings(
    program: &ladder_front::program::CheckedProgram,
    io: &ladder_serve::remote_io::RemoteIo,
) -> Vec<String> {
    use ladder_front::program::{BitRef, Op};
    let written: std::collections::HashSet<(ladder_runtime::BitArea, u32)> = program
        .instructions
        .iter()
        .filter_map(|instruction| {
            if let Op::Output(output) = &instruction.op {
                Some(output.written_bits())
            } else {
                None
            }
        })
        .flatten()
        .filter_map(|bit| match bit {
            BitRef::Device(area, address) if address.is_fixed() => Some((area, address.index)),
            BitRef::Device(..) | BitRef::WordBit(..) => None,
        })
        .collect();
    ladder_serve::remote_io::warnings(io, &|place| {
        if let ladder_runtime::Device::Bit(area, n) = place {
            written.contains(&(area, n))
        } else {
            false
        }
    })
}

/// Every address served is loopback unless `--allow-remote`.
fn check_addresses(args: &ServeArgs) -> Result<(), String> {
    for (flag, address) in [
        ("--modbus", args.modbus),
        ("--http", args.http),
        ("--opcua", args.opcua),
        ("--melsec", args.melsec),
    ] {
        if let Some(address) = address {
            if !address.ip().is_loopback() && !args.allow_remote {
                return Err(format!(
                    "{flag} {address} is not a loopback address; add --allow-remote to serve the network"
                ));
            }
        }
    }
    Ok(())
}

/// `--modbus-rtu` and `--modbus-unit`: the serial line, if any.
fn serial_line(args: &ServeArgs) -> Result<Option<ladder_serve::modbus_rtu::Line>, String> {
    let line = args
        .modbus_rtu
        .as_deref()
        .map(ladder_modbus::rtu::parse_port)
        .transpose()
        .map_err(|message| format!("--modbus-rtu: {message}"))?;
    if !(1..=247).contains(&args.modbus_unit) {
        return Err("--modbus-unit is 1 to 247 (0 is the broadcast address)".to_string());
    }
    Ok(line.map(|(path, format)| ladder_serve::modbus_rtu::Line {
        path,
        format,
        unit: args.modbus_unit,
    }))
}

/// `--modbus-write-from`: networks, or addresses alone.
fn write_networks(texts: &[String]) -> Result<Vec<ipnet::IpNet>, String> {
    texts
        .iter()
        .map(|text| {
            text.trim()
                .parse::<ipnet::IpNet>()
                .or_else(|_| text.trim().parse::<std::net::IpAddr>().map(ipnet::IpNet::from))
                .map_err(|_| {
                    format!("--modbus-write-from: `{text}` is not an address or a network like 192.168.1.0/24")
                })
        })
        .collect()
}

/// What the servers hold at most, from the `--max-...` and `...-idle-s` flags.
fn limits(args: &ServeArgs) -> ladder_serve::Limits {
    ladder_serve::Limits {
        queued_writes: args.max_queued_writes,
        modbus: ladder_serve::modbus_tcp::ConnectionLimits {
            connections: args.max_modbus_connections,
            idle: Duration::from_secs(args.modbus_idle_s.max(1)),
        },
        melsec: ladder_serve::modbus_tcp::ConnectionLimits {
            connections: args.max_melsec_connections,
            idle: Duration::from_secs(args.melsec_idle_s.max(1)),
        },
        http: ladder_serve::guard::Bounds {
            connections: args.max_http_connections,
            idle: Duration::from_secs(args.http_idle_s.max(1)),
            stall: ladder_serve::guard::STALL,
        },
        event_streams: args.max_event_streams,
    }
}
