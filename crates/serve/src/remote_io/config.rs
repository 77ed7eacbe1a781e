//! The remote I/O file of `serve --io FILE` (TOML): the Modbus TCP and RTU
//! devices to poll, and per device the ranges that map its discrete inputs
//! and input registers to X and D, and Y, M and D to its coils and holding
//! registers. Parsed with serde and checked here, every error naming the
//! file's line; docs/serve.md describes the format with a complete example.

use ladder_front::host_device::parse_device;
use ladder_modbus::rtu::Format;
use ladder_runtime::{BitArea, Device as Place, WordArea};
use serde::Deserialize;
use std::net::{SocketAddr, ToSocketAddrs};
use std::time::Duration;
use toml::Spanned;

/// The most devices one file may name.
pub const MOST_DEVICES: usize = 64;
/// The most ranges (inputs and outputs together) of one device.
pub const MOST_RANGES: usize = 32;
/// The most values (bits and registers, inputs and outputs) one file maps:
/// every scan walks them, so they stay a small part of a period.
pub const MOST_VALUES: u32 = 4096;
/// Modbus limits per request: bits and registers read, bits and registers
/// written. A longer range is split into several requests.
pub const READ_BITS: u16 = 2000;
pub const READ_REGISTERS: u16 = 125;
pub const WRITE_BITS: u16 = 1968;
pub const WRITE_REGISTERS: u16 = 123;
/// Where a device's status relay and error count are when the file does
/// not name them: M7600 and D7900 for the first device, on by one for each
/// next (FX3U's M and D end at M7679 and D7999).
pub const DEFAULT_STATUS: u32 = 7600;
pub const DEFAULT_ERRORS: u32 = 7900;
/// The first special M and D (M8000, D8000): the runtime's, never written
/// by the remote I/O.
const FIRST_SPECIAL: u32 = 8000;

/// The remote I/O: every device and its map.
#[derive(Clone, Debug, PartialEq)]
pub struct RemoteIo {
    pub devices: Vec<Device>,
}

/// How a device is reached.
#[derive(Clone, Debug, PartialEq)]
pub enum Link {
    Tcp(SocketAddr),
    Rtu { path: String, format: Format },
}

/// What a lost device's inputs read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnLoss {
    /// The values of the last complete poll.
    Hold,
    /// OFF and 0.
    Clear,
}

/// One remote I/O module (or a gateway's unit).
#[derive(Clone, Debug, PartialEq)]
pub struct Device {
    pub name: String,
    pub link: Link,
    pub unit: u8,
    pub period: Duration,
    pub timeout: Duration,
    /// Failed requests in a row beyond which the device is lost.
    pub retries: u32,
    /// All outputs are written at least this often, changed or not.
    pub keepalive: Duration,
    pub on_loss: OnLoss,
    /// M number: ON while the device answers.
    pub status: u32,
    /// D number: failed requests and connection attempts (saturates at
    /// 32767).
    pub errors: u32,
    pub inputs: Vec<Input>,
    pub outputs: Vec<Output>,
}

/// The module's tables a device's inputs come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputTable {
    /// Discrete inputs, to X.
    DiscreteInputs,
    /// Input registers, to D.
    InputRegisters,
}

/// The module's tables outputs go to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputTable {
    /// Coils, from Y or M.
    Coils,
    /// Holding registers, from D.
    HoldingRegisters,
}

/// `count` of the module's `table` from `address`, into X or D from `to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Input {
    pub table: InputTable,
    pub address: u16,
    pub count: u16,
    /// The first X or D (device number).
    pub to: u32,
}

/// `count` devices from `area`/`from`, to the module's `table` from
/// `address`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Output {
    pub table: OutputTable,
    pub address: u16,
    pub count: u16,
    pub from: Source,
}

/// Where outputs come from in the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    Bits(BitArea, u32),
    Words(u32),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(default)]
    device: Vec<Spanned<RawDevice>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDevice {
    name: Option<String>,
    tcp: Option<String>,
    rtu: Option<String>,
    unit: Option<u8>,
    period_ms: Option<u64>,
    timeout_ms: Option<u64>,
    retries: Option<u32>,
    keepalive_ms: Option<u64>,
    on_loss: Option<String>,
    status: Option<String>,
    errors: Option<String>,
    #[serde(default)]
    input: Vec<Spanned<RawInput>>,
    #[serde(default)]
    output: Vec<Spanned<RawOutput>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInput {
    discrete_inputs: Option<u16>,
    input_registers: Option<u16>,
    count: u16,
    to: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawOutput {
    coils: Option<u16>,
    holding_registers: Option<u16>,
    count: u16,
    from: String,
}

/// Reads and checks the file; `Err` names the file and the line.
pub fn load(path: &std::path::Path) -> Result<RemoteIo, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    parse(&text).map_err(|message| format!("{}:{message}", path.display()))
}

/// Parses the file's text; `Err` starts with the line number (`12: ...`).
pub fn parse(text: &str) -> Result<RemoteIo, String> {
    let raw: RawFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |span| line_of(text, span.start));
        format!("{line}: {}", e.message())
    })?;
    if raw.device.is_empty() {
        return Err("1: no [[device]] in the file".to_string());
    }
    if raw.device.len() > MOST_DEVICES {
        return Err(format!("1: {} devices; at most {MOST_DEVICES}", raw.device.len()));
    }
    let mut devices: Vec<Device> = Vec::with_capacity(raw.device.len());
    let mut lines = Vec::with_capacity(raw.device.len());
    let mut values = 0u32;
    for (index, spanned) in raw.device.iter().enumerate() {
        let line = line_of(text, spanned.span().start);
        let raw = spanned.get_ref();
        let mut device = device(index, raw).map_err(|m| format!("{line}: {m}"))?;
        if raw.input.len() + raw.output.len() > MOST_RANGES {
            return Err(format!("{line}: at most {MOST_RANGES} ranges per device"));
        }
        let at = |span: std::ops::Range<usize>, m: String| format!("{}: {m}", line_of(text, span.start));
        for spanned in &raw.input {
            device
                .inputs
                .push(input(spanned.get_ref()).map_err(|m| at(spanned.span(), m))?);
        }
        for spanned in &raw.output {
            let next = output(spanned.get_ref()).map_err(|m| at(spanned.span(), m))?;
            if let Some(other) = device.outputs.iter().find(|o| writes_same(o, &next)) {
                return Err(at(
                    spanned.span(),
                    format!(
                        "this output writes module address {} which the output from {} writes too",
                        next.address.max(other.address),
                        source_name(other.from)
                    ),
                ));
            }
            device.outputs.push(next);
        }
        let counts = device
            .inputs
            .iter()
            .map(|i| i.count)
            .chain(device.outputs.iter().map(|o| o.count));
        values += counts.map(u32::from).sum::<u32>();
        if values > MOST_VALUES {
            return Err(format!(
                "{line}: the file maps {values} values so far; at most {MOST_VALUES}"
            ));
        }
        if devices.iter().any(|d| d.name == device.name) {
            return Err(format!("{line}: a second device named `{}`", device.name));
        }
        // Two devices for one module (the same address and unit) may not
        // write the same coil or register either.
        let module = devices
            .iter()
            .filter(|d| d.link == device.link && d.unit == device.unit);
        for other in module {
            if let Some(output) = device
                .outputs
                .iter()
                .find(|o| other.outputs.iter().any(|p| writes_same(o, p)))
            {
                return Err(format!(
                    "{line}: `{}` writes module address {} of the module `{}` writes too",
                    device.name, output.address, other.name
                ));
            }
        }
        if let Some(other) = devices.iter().find(|d| same_line(d, &device)) {
            if other.link != device.link {
                return Err(format!(
                    "{line}: `{}` is on the serial line of `{}` with another format",
                    device.name, other.name
                ));
            }
            if other.unit == device.unit {
                return Err(format!(
                    "{line}: `{}` has the unit id of `{}` on the same serial line",
                    device.name, other.name
                ));
            }
        }
        devices.push(device);
        lines.push(line);
    }
    check_overlaps(&devices, &lines)?;
    Ok(RemoteIo { devices })
}

/// The line (from 1) of byte `at` of `text`.
fn line_of(text: &str, at: usize) -> usize {
    text.get(..at).map_or(1, |before| before.matches('\n').count() + 1)
}

/// Whether two outputs write the same coil or holding register.
fn writes_same(a: &Output, b: &Output) -> bool {
    let end = |o: &Output| u32::from(o.address) + u32::from(o.count);
    a.table == b.table && u32::from(a.address) < end(b) && u32::from(b.address) < end(a)
}

fn source_name(source: Source) -> String {
    match source {
        Source::Bits(area, n) => area.device_name(n),
        Source::Words(n) => WordArea::D.device_name(n),
    }
}

/// Whether two devices are on one serial line (RS-485 multi-drop: one
/// poller serves their units in turn).
pub fn same_line(a: &Device, b: &Device) -> bool {
    match (&a.link, &b.link) {
        (Link::Rtu { path: p, .. }, Link::Rtu { path: q, .. }) => p == q,
        (Link::Tcp(_), Link::Tcp(_) | Link::Rtu { .. }) | (Link::Rtu { .. }, Link::Tcp(_)) => false,
    }
}

fn millis(
    value: Option<u64>,
    default: u64,
    name: &str,
    range: std::ops::RangeInclusive<u64>,
) -> Result<Duration, String> {
    let ms = value.unwrap_or(default);
    if range.contains(&ms) {
        Ok(Duration::from_millis(ms))
    } else {
        Err(format!("{name} is {} to {}", range.start(), range.end()))
    }
}

/// One device without its ranges, checked: `index` from 0 gives the
/// default name, status relay and error count.
fn device(index: usize, raw: &RawDevice) -> Result<Device, String> {
    let number = u32::try_from(index).unwrap_or(u32::MAX);
    let name = raw.name.clone().unwrap_or_else(|| format!("device{}", index + 1));
    if name.is_empty() || name.len() > 64 {
        return Err("a name is 1 to 64 characters".to_string());
    }
    let link = match (&raw.tcp, &raw.rtu) {
        (Some(address), None) => Link::Tcp(tcp_address(address)?),
        (None, Some(line)) => {
            let (path, format) = ladder_modbus::rtu::parse_port(line).map_err(|m| format!("rtu: {m}"))?;
            Link::Rtu { path, format }
        }
        (Some(_), Some(_)) => return Err(format!("`{name}` has both tcp and rtu; one")),
        (None, None) => return Err(format!("`{name}` needs tcp = \"HOST:PORT\" or rtu = \"TTY:BAUD,8N1\"")),
    };
    let unit = raw.unit.unwrap_or(1);
    if matches!(link, Link::Rtu { .. }) && !(1..=247).contains(&unit) {
        return Err("unit is 1 to 247 on a serial line".to_string());
    }
    let period = millis(raw.period_ms, 100, "period_ms", 1..=60_000)?;
    let timeout = millis(raw.timeout_ms, 500, "timeout_ms", 1..=60_000)?;
    let keepalive = millis(
        raw.keepalive_ms,
        u64::try_from(period.as_millis()).unwrap_or(100),
        "keepalive_ms",
        1..=3_600_000,
    )?;
    if keepalive < period {
        // The keep-alive is written by a poll: it cannot come more often.
        return Err(format!(
            "keepalive_ms ({}) is less than period_ms ({}); the outputs are rewritten at most once a poll",
            keepalive.as_millis(),
            period.as_millis()
        ));
    }
    let retries = raw.retries.unwrap_or(2);
    if retries > 100 {
        return Err("retries is 0 to 100".to_string());
    }
    let on_loss = match raw.on_loss.as_deref() {
        None | Some("hold") => OnLoss::Hold,
        Some("clear") => OnLoss::Clear,
        Some(other) => return Err(format!("on_loss is \"hold\" or \"clear\", not `{other}`")),
    };
    let status = match &raw.status {
        Some(text) => bit_device(text, &[BitArea::M], "status")?.1,
        None => DEFAULT_STATUS + number,
    };
    let errors = match &raw.errors {
        Some(text) => word_device(text, "errors")?,
        None => DEFAULT_ERRORS + number,
    };
    if status >= FIRST_SPECIAL || errors >= FIRST_SPECIAL {
        return Err("the status relay and the error count are below M8000 and D8000".to_string());
    }
    Ok(Device {
        name,
        link,
        unit,
        period,
        timeout,
        retries,
        keepalive,
        on_loss,
        status,
        errors,
        inputs: Vec::new(),
        outputs: Vec::new(),
    })
}

/// `HOST:PORT` or `HOST` (port 502), resolved once at start.
fn tcp_address(text: &str) -> Result<SocketAddr, String> {
    let with_port =
        if text.parse::<SocketAddr>().is_ok() || text.rsplit_once(':').is_some_and(|(_, p)| p.parse::<u16>().is_ok()) {
            text.to_string()
        } else {
            format!("{text}:502")
        };
    with_port
        .to_socket_addrs()
        .ok()
        .and_then(|mut all| all.next())
        .ok_or_else(|| format!("tcp: `{text}` is not an address (HOST:PORT)"))
}

/// A bit device of one of `areas`, as its area and number.
fn bit_device(text: &str, areas: &[BitArea], what: &str) -> Result<(BitArea, u32), String> {
    if let Ok(Place::Bit(area, n)) = parse_device(text, false).map(|d| d.device) {
        if areas.contains(&area) {
            return Ok((area, n));
        }
    }
    let names: Vec<&str> = areas.iter().map(|a| a.prefix()).collect();
    Err(format!("{what}: `{text}` is not a device of {}", names.join(" or ")))
}

/// A D device, as its number.
fn word_device(text: &str, what: &str) -> Result<u32, String> {
    if let Ok(Place::Word(WordArea::D, n)) = parse_device(text, false).map(|d| d.device) {
        return Ok(n);
    }
    Err(format!("{what}: `{text}` is not a D device"))
}

/// The module addresses `address..address+count` exist, and `count` is
/// not 0.
fn check_span(address: u16, count: u16) -> Result<(), String> {
    if count == 0 {
        return Err("count is at least 1".to_string());
    }
    if u32::from(address) + u32::from(count) > 65_536 {
        return Err("the range runs past Modbus address 65535".to_string());
    }
    Ok(())
}

/// `count` devices from `first` stay below `area_count`.
fn check_room(first: u32, count: u16, area_count: u32, text: &str) -> Result<(), String> {
    if first + u32::from(count) > area_count {
        return Err(format!("{count} devices from `{text}` run past the end of the area"));
    }
    Ok(())
}

fn input(raw: &RawInput) -> Result<Input, String> {
    let (table, address) = match (raw.discrete_inputs, raw.input_registers) {
        (Some(a), None) => (InputTable::DiscreteInputs, a),
        (None, Some(a)) => (InputTable::InputRegisters, a),
        (Some(_), Some(_)) | (None, None) => {
            return Err("an input has one of discrete_inputs = ADDRESS or input_registers = ADDRESS".to_string())
        }
    };
    check_span(address, raw.count)?;
    let to = match table {
        InputTable::DiscreteInputs => {
            let (_, n) = bit_device(&raw.to, &[BitArea::X], "to")?;
            check_room(n, raw.count, BitArea::X.count(), &raw.to)?;
            n
        }
        InputTable::InputRegisters => {
            let n = word_device(&raw.to, "to")?;
            check_room(n, raw.count, FIRST_SPECIAL, &raw.to)?;
            n
        }
    };
    Ok(Input {
        table,
        address,
        count: raw.count,
        to,
    })
}

fn output(raw: &RawOutput) -> Result<Output, String> {
    let (table, address) = match (raw.coils, raw.holding_registers) {
        (Some(a), None) => (OutputTable::Coils, a),
        (None, Some(a)) => (OutputTable::HoldingRegisters, a),
        (Some(_), Some(_)) | (None, None) => {
            return Err("an output has one of coils = ADDRESS or holding_registers = ADDRESS".to_string())
        }
    };
    check_span(address, raw.count)?;
    let from = match table {
        OutputTable::Coils => {
            let (area, n) = bit_device(&raw.from, &[BitArea::Y, BitArea::M], "from")?;
            check_room(n, raw.count, area.count(), &raw.from)?;
            Source::Bits(area, n)
        }
        OutputTable::HoldingRegisters => {
            let n = word_device(&raw.from, "from")?;
            check_room(n, raw.count, WordArea::D.count(), &raw.from)?;
            Source::Words(n)
        }
    };
    Ok(Output {
        table,
        address,
        count: raw.count,
        from,
    })
}

/// No X, D or M is written by two devices (their inputs, status relays and
/// error counts): the later would hide the earlier every scan.
fn check_overlaps(devices: &[Device], lines: &[usize]) -> Result<(), String> {
    let mut written: Vec<(Place, u32, &str)> = Vec::new();
    for (device, line) in devices.iter().zip(lines) {
        let mut mine = vec![
            (Place::Bit(BitArea::M, device.status), 1),
            (Place::Word(WordArea::D, device.errors), 1),
        ];
        for input in &device.inputs {
            mine.push(match input.table {
                InputTable::DiscreteInputs => (Place::Bit(BitArea::X, input.to), u32::from(input.count)),
                InputTable::InputRegisters => (Place::Word(WordArea::D, input.to), u32::from(input.count)),
            });
        }
        for (place, count) in mine {
            if let Some((_, _, other)) = written.iter().find(|(p, c, _)| overlap((*p, *c), (place, count))) {
                return Err(format!(
                    "{line}: `{}` writes {} which `{other}` writes too",
                    device.name,
                    name_of(place)
                ));
            }
            written.push((place, count, &device.name));
        }
    }
    Ok(())
}

/// Whether two runs of devices (first, count) share a device.
pub fn overlap((a, n): (Place, u32), (b, m): (Place, u32)) -> bool {
    let span = |place: Place| match place {
        Place::Bit(area, i) => Some((Some(area), None, i)),
        Place::Word(area, i) => Some((None, Some(area), i)),
        Place::Digits(..) | Place::WordBit(..) | Place::WideCounter(_) => None,
    };
    match (span(a), span(b)) {
        (Some((ab, aw, i)), Some((bb, bw, j))) => ab == bb && aw == bw && i < j + m && j < i + n,
        (Some(_), None) | (None, Some(_)) | (None, None) => false,
    }
}

/// A device's name as the program writes it (`X17`, `M7600`, `D7900`).
pub fn name_of(place: Place) -> String {
    match place {
        Place::Bit(area, n) => area.device_name(n),
        Place::Word(area, n) => area.device_name(n),
        Place::Digits(..) | Place::WordBit(..) | Place::WideCounter(_) => format!("{place:?}"),
    }
}

/// The requests that read or write `count` values from `address` with at
/// most `most` per request: (address, count, offset in the range).
pub fn split(address: u16, count: u16, most: u16) -> impl Iterator<Item = (u16, u16, usize)> {
    let most = most.max(1);
    (0..count.div_ceil(most)).map(move |k| {
        let offset = k * most;
        (
            address.wrapping_add(offset),
            most.min(count - offset),
            usize::from(offset),
        )
    })
}

#[cfg(test)]
#[path = "config_tests.rs"]
mod tests;
