//! Writes in the JSON API: set a device, force and unforce a bit, list the
//! forced devices, unforce them all; each queued, applied at the end of the
//! scan in progress (or at once when none runs), and answered once applied.

use super::{busy, error, not_applied, App};
use crate::acks::NotApplied;
use crate::shared::HostWrite;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use ladder_front::host_device::{parse_device, parse_value, HostDevice};
use ladder_runtime::{BitArea, Device};
use serde_json::{json, Value};

pub async fn forces(State(app): State<App>) -> Json<Value> {
    let forced = crate::view::forces(&app.shared.image());
    let list: Vec<Value> = forced
        .into_iter()
        .map(|(name, on)| json!({ "device": name, "value": u8::from(on) }))
        .collect();
    Json(json!({ "forces": list }))
}

/// Unforces every forced device.
pub async fn unforce_all(State(app): State<App>) -> Response {
    let forced = crate::view::forces(&app.shared.image());
    let mut writes = Vec::new();
    for (name, _) in &forced {
        if let Ok(device) = parse_device(name, false) {
            if let Ok((area, index)) = forceable(device) {
                writes.push(HostWrite::Unforce(area, index));
            }
        }
    }
    let count = writes.len();
    let Some(ticket) = app.shared.queue(writes) else {
        return busy();
    };
    match app.shared.applied(ticket).await {
        Ok(()) => Json(json!({ "unforced": count })).into_response(),
        Err(NotApplied::TimedOut | NotApplied::Stopping) => not_applied(),
    }
}

#[derive(serde::Deserialize)]
pub struct Write {
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
/// else queued and answered once applied.
async fn queue(
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
            // A device the remote I/O writes before every scan (`--io`).
            if let Some(message) = crate::remote_io::refused(&app.shared, &[write]) {
                return error(StatusCode::CONFLICT, message);
            }
            let Some(ticket) = app.shared.queue(vec![write]) else {
                return busy();
            };
            match app.shared.applied(ticket).await {
                Ok(()) => Json(json!({ "queued": body.device, "applied": true })).into_response(),
                Err(NotApplied::TimedOut | NotApplied::Stopping) => not_applied(),
            }
        }
        Err(message) => error(StatusCode::BAD_REQUEST, message),
    }
}

pub async fn set(
    State(app): State<App>,
    body: Result<Json<Write>, axum::extract::rejection::JsonRejection>,
) -> Response {
    queue(&app, body, |device, value| {
        Ok(HostWrite::Set(device, value.ok_or("a value is needed")?))
    })
    .await
}

pub async fn force(
    State(app): State<App>,
    body: Result<Json<Write>, axum::extract::rejection::JsonRejection>,
) -> Response {
    queue(&app, body, |device, value| {
        let (area, index) = forceable(device)?;
        Ok(HostWrite::Force(area, index, value.ok_or("a value is needed")? != 0))
    })
    .await
}

pub async fn unforce(
    State(app): State<App>,
    body: Result<Json<Write>, axum::extract::rejection::JsonRejection>,
) -> Response {
    queue(&app, body, |device, _| {
        let (area, index) = forceable(device)?;
        Ok(HostWrite::Unforce(area, index))
    })
    .await
}
