//! The HTTP side of `ladderc serve` (axum): a live monitor page served by
//! the binary itself, a JSON API for scripts, and server-sent events that
//! push device values to the page. Like Modbus, it reads the image the
//! latest scan published and queues writes for the next scan.

use super::shared::{HostWrite, Shared};
use crate::host_device::{parse_device, parse_value, HostDevice};
use crate::waveform::device_name;
use axum::extract::{DefaultBodyLimit, Query, State};
use axum::http::StatusCode;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
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

#[derive(Clone)]
struct App {
    shared: Arc<Shared>,
    read_only: bool,
    /// Programs run as native code: online change compiles them here.
    native: bool,
}

pub fn router(shared: Arc<Shared>, read_only: bool, native: bool) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/api/devices", get(devices))
        .route("/api/events", get(events))
        .route("/api/stats", get(stats))
        .route("/api/set", post(set))
        .route("/api/force", post(force))
        .route("/api/unforce", post(unforce))
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .route(
            "/api/program",
            post(program).layer(DefaultBodyLimit::max(PROGRAM_LIMIT)),
        )
        .with_state(App {
            shared,
            read_only,
            native,
        })
}

/// A JSON error with its HTTP status.
fn error(status: StatusCode, message: impl Into<String>) -> Response {
    (status, Json(json!({ "error": message.into() }))).into_response()
}

#[derive(serde::Deserialize)]
struct Watch {
    /// Devices, comma-separated (`Y0,Y1,D0,TN0`).
    watch: Option<String>,
}

/// The devices a request names (default: Y0-Y7).
fn watched(watch: &Watch) -> Result<Vec<(String, HostDevice)>, String> {
    let list = watch.watch.clone().unwrap_or_else(|| "Y0,Y1,Y2,Y3,Y4,Y5,Y6,Y7".into());
    list.split(',')
        .map(str::trim)
        .filter(|name| !name.is_empty())
        .take(256)
        .map(|name| parse_device(name, false).map(|device| (device_name(device), device)))
        .collect()
}

/// The watched devices, the scan count and the operation error, as JSON.
/// The values are copied out under the image's lock and the JSON built
/// after it is released, so a reader holds up the scan thread's publishing
/// as little as possible.
fn snapshot(shared: &Shared, watched: &[(String, HostDevice)]) -> Value {
    let (values, scan, error) = {
        let image: &Memory = &shared.image();
        let values: Vec<i32> = watched
            .iter()
            .map(|(_, device)| image.read_device(device.device, device.width).unwrap_or(0))
            .collect();
        let error = (image.m[M_OPERATION_ERROR as usize] != 0)
            .then(|| (image.d[D_ERROR_CODE as usize] as u16, image.d[D_ERROR_LINE as usize]));
        (values, image.scan_count, error)
    };
    let devices: serde_json::Map<String, Value> = watched
        .iter()
        .zip(values)
        .map(|((name, _), value)| (name.clone(), Value::from(value)))
        .collect();
    let error = error.map(|(code, line)| json!({ "code": format!("{code:04X}H"), "line": line }));
    json!({ "scan": scan, "devices": devices, "error": error })
}

async fn page() -> Html<&'static str> {
    Html(include_str!("monitor.html"))
}

async fn devices(State(app): State<App>, Query(watch): Query<Watch>) -> Response {
    match watched(&watch) {
        Ok(watched) => Json(snapshot(&app.shared, &watched)).into_response(),
        Err(message) => error(StatusCode::BAD_REQUEST, message),
    }
}

async fn events(State(app): State<App>, Query(watch): Query<Watch>) -> Response {
    let watched = match watched(&watch) {
        Ok(watched) => watched,
        Err(message) => return error(StatusCode::BAD_REQUEST, message),
    };
    let ticks = tokio_stream::wrappers::IntervalStream::new(tokio::time::interval(PUSH_PERIOD));
    let stream = futures_util::StreamExt::map(ticks, move |_| {
        let value = snapshot(&app.shared, &watched);
        Ok::<_, std::convert::Infallible>(Event::default().data(value.to_string()))
    });
    Sse::new(stream).keep_alive(KeepAlive::default()).into_response()
}

async fn stats(State(app): State<App>) -> Json<Value> {
    let stats = app.shared.stats();
    let micros = |d: Duration| d.as_secs_f64() * 1e6;
    Json(json!({
        "scans": stats.scans,
        "last_us": micros(stats.last),
        "min_us": micros(stats.min.unwrap_or_default()),
        "average_us": micros(stats.average()),
        "max_us": micros(stats.max),
        "jitter_us": micros(stats.jitter),
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
    let device = parse_device(body.device.trim(), false)?;
    let value = match &body.value {
        None => None,
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
    if app.read_only {
        return error(StatusCode::FORBIDDEN, "the server is read-only");
    }
    let Json(body) = match body {
        Ok(body) => body,
        Err(rejection) => return error(rejection.status(), rejection.body_text()),
    };
    match parse_write(&body).and_then(|(device, value)| make(device, value)) {
        Ok(write) => {
            app.shared.queue(vec![write]);
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
async fn program(State(app): State<App>, text: String) -> Response {
    if app.read_only {
        return error(StatusCode::FORBIDDEN, "the server is read-only");
    }
    let native = app.native;
    let compiled = tokio::task::spawn_blocking(move || {
        let source = crate::source::SourceFile::new("<upload>", text);
        let (program, diagnostics) = crate::check::compile_source(&source);
        match program {
            Some(program) => super::change::Loaded::new(program, &source).precompile(native),
            None => Err(crate::diagnostics::render_all(
                &source,
                &diagnostics,
                crate::diagnostics::Shown::default(),
            )),
        }
    })
    .await;
    let loaded = match compiled {
        Ok(Ok(loaded)) => loaded,
        Ok(Err(diagnostics)) => return (
            StatusCode::UNPROCESSABLE_ENTITY,
            Json(
                json!({ "error": "the program does not compile; the running one goes on", "diagnostics": diagnostics }),
            ),
        )
            .into_response(),
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
