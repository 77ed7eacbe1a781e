//! The monitor's reads in the JSON API: the watched devices (`:hex`,
//! `:bin`, `:float` as the request asks), their values after every scan as
//! server-sent events, the scan statistics, and the remote I/O devices'
//! state.

use super::{error, App};
use crate::shared::Shared;
use axum::extract::{Query, State};
use axum::http::StatusCode;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::Json;
use ladder_engine::waveform::Signal;
use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
use ladder_runtime::Memory;
use serde_json::{json, Value};
use std::sync::Arc;
use std::time::Duration;

/// How often the event stream sends the watched devices.
const PUSH_PERIOD: Duration = Duration::from_millis(100);
/// The most devices one request may watch.
pub const MOST_WATCHED: usize = 256;

#[derive(serde::Deserialize)]
pub struct Watch {
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
        (Format::Dec | Format::Hex | Format::Bin, 1) | (Format::Dec, _) => raw.to_string(),
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
        (values, image.scan_count, error, crate::view::forces(image))
    };
    let mut devices = serde_json::Map::new();
    let mut text = serde_json::Map::new();
    for (w, raw) in watched.iter().zip(values) {
        let (value, shown) = value_of(w, raw);
        devices.insert(w.name.clone(), value);
        text.insert(w.name.clone(), Value::from(shown));
    }
    let names: Vec<&str> = watched.iter().map(|w| w.name.as_str()).collect();
    // The device comments of the watched devices (a GX Developer project's).
    let mut comments = serde_json::Map::new();
    if let Some(view) = shared.view() {
        for w in watched {
            let name = ladder_front::gxdev::listing::canonical_device(&w.name);
            if let Some(comment) = name.and_then(|n| view.comments.get(&n)) {
                comments.insert(w.name.clone(), Value::from(comment.as_str()));
            }
        }
    }
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
        "comments": comments,
        "error": error,
        "forced": forced,
        "control": super::debug::control_json(shared),
    })
}

pub async fn devices(
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
pub async fn events(
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

pub async fn reset_stats(State(app): State<App>) -> Response {
    app.shared.reset_stats();
    Json(json!({ "reset": true })).into_response()
}

pub async fn stats(State(app): State<App>) -> Json<Value> {
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

/// The remote I/O devices' state (`--io`): connected, errors, the latest
/// error, how long ago the latest complete poll ended.
pub async fn remote_io(State(app): State<App>) -> Json<Value> {
    Json(crate::remote_io::report(&app.shared))
}
