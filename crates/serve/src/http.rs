//! The HTTP side of `ladderc serve` (axum): a live monitor page served by
//! the binary itself, a JSON API for scripts, and server-sent events that
//! push device values to the page. Like Modbus, it reads the image the
//! latest scan published and queues writes for the next scan.

use super::shared::{HostWrite, Shared};
use axum::extract::{DefaultBodyLimit, Query, State};
use axum::http::StatusCode;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use ladder_engine::waveform::Signal;
use ladder_front::host_device::{parse_device, parse_value, HostDevice};
use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
use ladder_runtime::{BitArea, Device, Memory};
use serde_json::{json, Value};
use std::sync::Arc;
use std::time::Duration;

/// Request bodies larger than this are refused (413).
const BODY_LIMIT: usize = 64 * 1024;
/// Uploaded programs larger than this are refused (413).
const PROGRAM_LIMIT: usize = 8 * 1024 * 1024;
/// How often the event stream sends the watched devices.
const PUSH_PERIOD: Duration = Duration::from_millis(100);
/// The most devices one request may watch.
pub const MOST_WATCHED: usize = 256;

#[derive(Clone)]
pub struct App {
    pub shared: Arc<Shared>,
    /// Programs run as native code: online change compiles them here.
    native: bool,
}

pub fn router(shared: Arc<Shared>, native: bool) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/api/devices", get(devices))
        .route("/api/events", get(events))
        .route("/api/stats", get(stats))
        .route("/api/set", post(set))
        .route("/api/force", post(force))
        .route("/api/unforce", post(unforce))
        .route("/api/forces", get(forces))
        .route("/api/unforce-all", post(unforce_all))
        .route("/api/stats/reset", post(reset_stats))
        .route("/api/ladder", get(super::debug::ladder))
        .route("/api/ladder/state", get(super::debug::ladder_state))
        .route("/api/ladder/outline", get(super::debug::ladder_outline))
        .route("/api/ladder/rungs", get(super::debug::ladder_rungs))
        .route(
            "/api/control",
            get(super::debug::control).post(super::debug::set_control),
        )
        .route(
            "/api/breakpoints",
            get(super::debug::breakpoints)
                .post(super::debug::add_breakpoint)
                .delete(super::debug::remove_breakpoints),
        )
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .route(
            "/api/program",
            post(program)
                .get(running_program)
                .layer(DefaultBodyLimit::max(PROGRAM_LIMIT)),
        )
        .with_state(App { shared, native })
}

/// The answer to a write when the queue of writes for the next scan is
/// full (the PLC is paused, or a client writes faster than it scans).
fn busy() -> Response {
    let mut response = error(
        StatusCode::SERVICE_UNAVAILABLE,
        "too many writes are waiting for the next scan; try again",
    );
    response.headers_mut().insert(
        axum::http::header::RETRY_AFTER,
        axum::http::HeaderValue::from_static("1"),
    );
    response
}

/// A JSON error with its HTTP status.
pub fn error(status: StatusCode, message: impl Into<String>) -> Response {
    (status, Json(json!({ "error": message.into() }))).into_response()
}

#[derive(serde::Deserialize)]
struct Watch {
    /// Devices as `ladderc run --watch` takes them, comma-separated
    /// (`Y0..Y7,D10:32,D20:float`), each optionally shown `:hex` or `:bin`.
    watch: Option<String>,
}

/// How a watched value is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Dec,
    Hex,
    Bin,
}

/// One watched device: its name as the request wrote it, the device, and
/// how to show it.
struct Watched {
    name: String,
    signal: Signal,
    format: Format,
}

/// The devices a request names (default: Y0-Y7): at most `MOST_WATCHED`.
fn watched(watch: &Watch) -> Result<Vec<Watched>, String> {
    let list = watch.watch.clone().unwrap_or_else(|| "Y0..Y7".into());
    let mut out = Vec::new();
    for entry in list.split(',').map(str::trim).filter(|e| !e.is_empty()) {
        let lower = entry.to_ascii_lowercase();
        let (bare, format) = match () {
            () if lower.ends_with(":hex") => (&entry[..entry.len() - 4], Format::Hex),
            () if lower.ends_with(":bin") => (&entry[..entry.len() - 4], Format::Bin),
            () if lower.ends_with(":dec") => (&entry[..entry.len() - 4], Format::Dec),
            () => (entry, Format::Dec),
        };
        for signal in ladder_engine::watch::parse_watch(bare)? {
            let suffix = match format {
                Format::Dec => "",
                Format::Hex => ":hex",
                Format::Bin => ":bin",
            };
            out.push(Watched {
                name: format!("{}{suffix}", signal.name),
                signal,
                format,
            });
            if out.len() > MOST_WATCHED {
                return Err(format!("at most {MOST_WATCHED} devices can be watched at once"));
            }
        }
    }
    Ok(out)
}

/// A value as the page shows it, and as JSON: a number (a real number for
/// `:float`), and its text in the requested format.
fn value_of(watched: &Watched, raw: i32) -> (Value, String) {
    if watched.signal.real {
        let real = f32::from_bits(raw as u32);
        return (json!(real), format!("{real:?}"));
    }
    let bits = watched.signal.device.bits();
    let unsigned = if bits == 16 {
        u64::from(raw as u16)
    } else {
        u64::from(raw as u32)
    };
    let text = match (watched.format, bits) {
        (_, 1) | (Format::Dec, _) => raw.to_string(),
        (Format::Hex, 16) => format!("H{unsigned:04X}"),
        (Format::Hex, _) => format!("H{unsigned:08X}"),
        (Format::Bin, 16) => format!("{unsigned:016b}"),
        (Format::Bin, _) => format!("{unsigned:032b}"),
    };
    (json!(raw), text)
}

/// The watched devices, the scan count, the operation error, the switch
/// and the forced devices, as JSON. The values are copied out under the
/// image's lock and the JSON built after it is released, so a reader holds
/// up the scan thread's publishing as little as possible.
fn snapshot(shared: &Shared, watched: &[Watched]) -> Value {
    let (values, scan, error, forced) = {
        let image: &Memory = &shared.image();
        let values: Vec<i32> = watched
            .iter()
            .map(|w| {
                image
                    .read_device(w.signal.device.device, w.signal.device.width)
                    .unwrap_or(0)
            })
            .collect();
        let error = (image.m[M_OPERATION_ERROR as usize] != 0)
            .then(|| (image.d[D_ERROR_CODE as usize] as u16, image.d[D_ERROR_LINE as usize]));
        (values, image.scan_count, error, super::view::forces(image))
    };
    let mut devices = serde_json::Map::new();
    let mut text = serde_json::Map::new();
    for (w, raw) in watched.iter().zip(values) {
        let (value, shown) = value_of(w, raw);
        devices.insert(w.name.clone(), value);
        text.insert(w.name.clone(), Value::from(shown));
    }
    let names: Vec<&str> = watched.iter().map(|w| w.name.as_str()).collect();
    let error = error.map(|(code, line)| json!({ "code": format!("{code:04X}H"), "line": line }));
    let forced: Vec<Value> = forced
        .into_iter()
        .map(|(name, on)| json!({ "device": name, "value": u8::from(on) }))
        .collect();
    json!({
        "scan": scan,
        "names": names,
        "devices": devices,
        "text": text,
        "error": error,
        "forced": forced,
        "control": super::debug::control_json(shared),
    })
}

async fn page() -> Html<&'static str> {
    Html(include_str!("monitor.html"))
}

async fn devices(
    State(app): State<App>,
    watch: Result<Query<Watch>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(watch)) = watch else {
        return error(StatusCode::BAD_REQUEST, "the query is not `watch=DEVICES`");
    };
    match watched(&watch) {
        Ok(watched) => Json(snapshot(&app.shared, &watched)).into_response(),
        Err(message) => error(StatusCode::BAD_REQUEST, message),
    }
}

/// Pushes the watched devices every `PUSH_PERIOD`, with the values they
/// had after every scan since the previous push (`samples`: `[scan, ms,
/// values...]`), so that a trend misses no scan.
async fn events(
    State(app): State<App>,
    watch: Result<Query<Watch>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(watch)) = watch else {
        return error(StatusCode::BAD_REQUEST, "the query is not `watch=DEVICES`");
    };
    let watched = match watched(&watch) {
        Ok(watched) => watched,
        Err(message) => return error(StatusCode::BAD_REQUEST, message),
    };
    let Some(recorder) = app.shared.record(watched.iter().map(|w| w.signal.device).collect()) else {
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            "too many event streams are open (--max-event-streams); close one and try again",
        );
    };
    let ticks = tokio_stream::wrappers::IntervalStream::new(tokio::time::interval(PUSH_PERIOD));
    // A client that took nothing for a while was dropped: its stream ends.
    let alive = Arc::clone(&recorder);
    let ticks = futures_util::StreamExt::take_while(ticks, move |_| std::future::ready(!alive.dropped()));
    let stream = futures_util::StreamExt::map(ticks, move |_| {
        let mut value = snapshot(&app.shared, &watched);
        let (samples, lost) = recorder.take();
        let samples: Vec<Value> = samples
            .into_iter()
            .map(|s| {
                let mut row = vec![json!(s.scan), json!(s.time_ms)];
                row.extend(s.values.iter().zip(&watched).map(|(&raw, w)| value_of(w, raw).0));
                Value::Array(row)
            })
            .collect();
        value["samples"] = Value::Array(samples);
        value["lost"] = json!(lost);
        Ok::<_, std::convert::Infallible>(Event::default().data(value.to_string()))
    });
    Sse::new(stream).keep_alive(KeepAlive::default()).into_response()
}

async fn reset_stats(State(app): State<App>) -> Response {
    app.shared.reset_stats();
    Json(json!({ "reset": true })).into_response()
}

async fn forces(State(app): State<App>) -> Json<Value> {
    let forced = super::view::forces(&app.shared.image());
    let list: Vec<Value> = forced
        .into_iter()
        .map(|(name, on)| json!({ "device": name, "value": u8::from(on) }))
        .collect();
    Json(json!({ "forces": list }))
}

/// Unforces every forced device (at the next scan).
async fn unforce_all(State(app): State<App>) -> Response {
    let forced = super::view::forces(&app.shared.image());
    let mut writes = Vec::new();
    for (name, _) in &forced {
        if let Ok(device) = parse_device(name, false) {
            if let Ok((area, index)) = forceable(device) {
                writes.push(HostWrite::Unforce(area, index));
            }
        }
    }
    let count = writes.len();
    if !app.shared.queue(writes) {
        return busy();
    }
    Json(json!({ "unforced": count })).into_response()
}

async fn stats(State(app): State<App>) -> Json<Value> {
    let stats = app.shared.stats();
    let window = app.shared.jitter_percentiles();
    let micros = |d: Duration| d.as_secs_f64() * 1e6;
    let average_jitter = if stats.scans == 0 {
        Duration::ZERO
    } else {
        stats.jitter_total.div_f64(stats.scans as f64)
    };
    Json(json!({
        "scans": stats.scans,
        "last_us": micros(stats.last),
        "min_us": micros(stats.min.unwrap_or_default()),
        "average_us": micros(stats.average()),
        "max_us": micros(stats.max),
        "jitter_us": micros(stats.jitter),
        "jitter_average_us": micros(average_jitter),
        "jitter_window": {
            "scans": window.samples,
            "p50_us": micros(window.p50),
            "p99_us": micros(window.p99),
            "max_us": micros(window.max),
        },
        "overruns": stats.overruns,
    }))
}

#[derive(serde::Deserialize)]
struct Write {
    device: String,
    value: Option<Value>,
}

/// The device of a write request and its value (as text or number).
fn parse_write(body: &Write) -> Result<(HostDevice, Option<i32>), String> {
    // `D20:32` names the pair, as in the watch list; `D20:float` the pair
    // holding a real number (as OPC UA writes it).
    let name = body.device.trim();
    if let Some(bare) = name.strip_suffix(":float") {
        let device = parse_device(bare, true)?;
        let value = match &body.value {
            None | Some(Value::Null) => None,
            Some(Value::Number(n)) => n.as_f64(),
            Some(Value::String(text)) => Some(f64::from(ladder_engine::scenario::parse::real(text.trim())?)),
            Some(other) => return Err(format!("`{other}` is not a real number")),
        };
        return Ok((device, value.map(|v| (v as f32).to_bits() as i32)));
    }
    let device = match name.strip_suffix(":32") {
        Some(bare) => parse_device(bare, true)?,
        None => parse_device(name, false)?,
    };
    let value = match &body.value {
        None | Some(Value::Null) => None,
        Some(Value::String(text)) if text.trim().is_empty() => None,
        Some(Value::Number(n)) => Some(parse_value(&n.to_string(), device)?),
        Some(Value::String(text)) => Some(parse_value(text, device)?),
        Some(Value::Bool(on)) => Some(i32::from(*on)),
        Some(other) => return Err(format!("`{other}` is not a value")),
    };
    Ok((device, value))
}

/// The forceable bit of a request: X, Y, M, T or C.
fn forceable(device: HostDevice) -> Result<(BitArea, u32), String> {
    match device.device {
        Device::Bit(
            area @ (BitArea::X | BitArea::Y | BitArea::M | BitArea::TimerContact | BitArea::CounterContact),
            n,
        ) => Ok((area, n)),
        Device::Bit(..) | Device::Word(..) | Device::WordBit(..) | Device::Digits(..) | Device::WideCounter(_) => {
            Err("X, Y, M, T and C can be forced".to_string())
        }
    }
}

/// Runs a write request: refused when read-only, 400 when malformed,
/// else queued for the next scan.
fn queue(
    app: &App,
    body: Result<Json<Write>, axum::extract::rejection::JsonRejection>,
    make: impl FnOnce(HostDevice, Option<i32>) -> Result<HostWrite, String>,
) -> Response {
    let Json(body) = match body {
        Ok(body) => body,
        Err(rejection) => return error(rejection.status(), rejection.body_text()),
    };
    match parse_write(&body).and_then(|(device, value)| make(device, value)) {
        Ok(write) => {
            if !app.shared.queue(vec![write]) {
                return busy();
            }
            Json(json!({ "queued": body.device })).into_response()
        }
        Err(message) => error(StatusCode::BAD_REQUEST, message),
    }
}

async fn set(State(app): State<App>, body: Result<Json<Write>, axum::extract::rejection::JsonRejection>) -> Response {
    queue(&app, body, |device, value| {
        Ok(HostWrite::Set(device, value.ok_or("a value is needed")?))
    })
}

async fn force(State(app): State<App>, body: Result<Json<Write>, axum::extract::rejection::JsonRejection>) -> Response {
    queue(&app, body, |device, value| {
        let (area, index) = forceable(device)?;
        Ok(HostWrite::Force(area, index, value.ok_or("a value is needed")? != 0))
    })
}

async fn unforce(
    State(app): State<App>,
    body: Result<Json<Write>, axum::extract::rejection::JsonRejection>,
) -> Response {
    queue(&app, body, |device, _| {
        let (area, index) = forceable(device)?;
        Ok(HostWrite::Unforce(area, index))
    })
}

/// Online change: the body is the new program's text. It is compiled here
/// (not in the scan thread); one that does not compile is refused (422,
/// with its diagnostics) and the running program goes on. Otherwise it
/// replaces the running one between two scans, and the answer comes once
/// it runs.
/// The running program: its name, SHA-256, when it was loaded, its text.
async fn running_program(State(app): State<App>) -> Response {
    match app.shared.identity() {
        Some(identity) => Json(json!({
            "name": identity.name,
            "sha256": identity.sha256,
            "loaded_at": identity.loaded_at_text(),
            "text": identity.text,
            "changes": app.shared.swaps(),
        }))
        .into_response(),
        None => error(StatusCode::SERVICE_UNAVAILABLE, "no program runs yet"),
    }
}

#[derive(serde::Deserialize)]
struct Upload {
    /// `allow_empty=1`: a program that drives nothing is meant.
    allow_empty: Option<String>,
}

/// Content types a browser page may send without asking the server first
/// (a CORS "simple" request): a program upload never has one of them (nor
/// none), so no page of another origin can make one unasked.
const SIMPLE_CONTENT_TYPES: [&str; 3] = ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data"];

async fn program(
    State(app): State<App>,
    headers: axum::http::HeaderMap,
    query: Result<Query<Upload>, axum::extract::rejection::QueryRejection>,
    body: Result<axum::body::Bytes, axum::extract::rejection::BytesRejection>,
) -> Response {
    let content_type = headers
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|value| value.to_str().ok())
        .map(|value| value.split(';').next().unwrap_or("").trim().to_ascii_lowercase());
    if content_type
        .as_deref()
        .is_none_or(|kind| kind.is_empty() || SIMPLE_CONTENT_TYPES.contains(&kind))
    {
        return error(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "send the program with `Content-Type: application/octet-stream` (e.g. curl -H \
             'Content-Type: application/octet-stream' --data-binary @prog.il URL/api/program); a type a browser \
             page may send unasked is refused",
        );
    }
    let allow_empty = matches!(query, Ok(Query(Upload { allow_empty: Some(ref v) })) if v == "1" || v == "true");
    let bytes = match body {
        Ok(bytes) => bytes,
        Err(rejection) => return error(rejection.status(), rejection.body_text()),
    };
    let native = app.native;
    let compiled = tokio::task::spawn_blocking(move || {
        // Decoded as the command line reads files (a byte-order mark, UTF-16).
        let source = ladder_front::source::SourceFile::from_bytes("<upload>", &bytes);
        let (program, diagnostics) = ladder_front::check::compile_source(&source);
        let shown = || {
            ladder_front::diagnostics::render_all(&source, &diagnostics, ladder_front::diagnostics::Shown::default())
        };
        match program {
            Some(_) if !allow_empty && super::drives_nothing(&diagnostics) => Err((
                "the program drives nothing (W0004); the running one goes on (`?allow_empty=1` if it is meant)",
                shown(),
            )),
            Some(program) => super::change::Loaded::new(program, &source)
                .precompile(native)
                .map_err(|e| ("the program cannot be compiled to native code", e)),
            None => Err(("the program does not compile; the running one goes on", shown())),
        }
    })
    .await;
    let loaded = match compiled {
        Ok(Ok(loaded)) => loaded,
        Ok(Err((message, diagnostics))) => {
            return (
                StatusCode::UNPROCESSABLE_ENTITY,
                Json(json!({ "error": message, "diagnostics": diagnostics })),
            )
                .into_response()
        }
        Err(_) => return error(StatusCode::INTERNAL_SERVER_ERROR, "compiling failed"),
    };
    let before = app.shared.swaps();
    if !app.shared.offer(loaded) {
        return error(StatusCode::CONFLICT, "another program is being swapped in; try again");
    }
    // The answer comes once the new program has run a scan.
    let mut swapped_at = None;
    for _ in 0..1000 {
        let scan = app.shared.image().scan_count;
        match swapped_at {
            None if app.shared.swaps() > before => swapped_at = Some(scan),
            Some(at) if scan > at => return Json(json!({ "swapped": true, "scan": scan })).into_response(),
            None | Some(_) => {}
        }
        if app.shared.stopping() {
            break;
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    if swapped_at.is_none() && app.shared.take_program().is_some() {
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            "the program was not swapped in (withdrawn)",
        );
    }
    Json(json!({ "swapped": true, "scan": app.shared.image().scan_count })).into_response()
}
