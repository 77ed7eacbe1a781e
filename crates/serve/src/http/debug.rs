//! The monitor's ladder and debugger in the JSON API: the drawing of the
//! running program and the states of the rungs on screen, the RUN/STOP
//! switch, pause and step, and breakpoints.

use super::{error, App};
use crate::shared::Shared;
use axum::extract::{Query, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::{json, Value};

/// The most scans one step request may ask for.
const MOST_STEPS: u32 = 1_000_000;

/// The switch and the debugger as JSON.
pub fn control_json(shared: &Shared) -> Value {
    let control = shared.control();
    let breakpoints: Vec<Value> = control
        .breakpoints
        .iter()
        .map(|b| json!({ "id": b.id, "condition": b.text }))
        .collect();
    let hit = control
        .hit
        .as_ref()
        .map(|h| json!({ "id": h.id, "condition": h.text, "scan": h.scan }));
    json!({
        "mode": if control.stopped { "stop" } else { "run" },
        "paused": control.paused,
        "steps_left": control.steps,
        "breakpoints": breakpoints,
        "hit": hit,
        "program": shared.swaps(),
    })
}

/// The running program's rungs, one `<svg>` each, as an HTML fragment;
/// `X-Ladder-Program` says which program (it changes with online change).
pub async fn ladder(State(app): State<App>) -> Response {
    let Some(view) = app.shared.view() else {
        return error(StatusCode::SERVICE_UNAVAILABLE, "no program runs yet");
    };
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8".to_string()),
            (
                header::HeaderName::from_static("x-ladder-program"),
                app.shared.swaps().to_string(),
            ),
        ],
        view.fragment(),
    )
        .into_response()
}

/// The most rung drawings one request may ask for.
const MOST_DRAWINGS: usize = 500;

/// What the page needs to place every rung before it has any drawing: the
/// program, the drawing's style, each rung's height, the widest rung's
/// width, and the devices the program uses (the device table's start).
pub async fn ladder_outline(State(app): State<App>) -> Response {
    let Some(view) = app.shared.view() else {
        return error(StatusCode::SERVICE_UNAVAILABLE, "no program runs yet");
    };
    Json(json!({
        "program": app.shared.swaps(),
        "style": ladder_diagram::svg::STYLE,
        "heights": view.heights,
        "width": view.width,
        "devices": view.devices,
    }))
    .into_response()
}

#[derive(serde::Deserialize)]
pub struct Window {
    /// The first rung.
    from: Option<usize>,
    /// How many rungs (at most 500).
    count: Option<usize>,
}

/// The drawings of a window of rungs: `{program, from, drawings: [svg...]}`.
pub async fn ladder_rungs(
    State(app): State<App>,
    query: Result<Query<Window>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(window)) = query else {
        return error(StatusCode::BAD_REQUEST, "the query is not `from=N&count=N`");
    };
    let Some(view) = app.shared.view() else {
        return error(StatusCode::SERVICE_UNAVAILABLE, "no program runs yet");
    };
    let from = window.from.unwrap_or(0);
    let count = window.count.unwrap_or(50);
    if count > MOST_DRAWINGS {
        return error(
            StatusCode::BAD_REQUEST,
            format!("at most {MOST_DRAWINGS} rungs at a time"),
        );
    }
    let end = from.saturating_add(count).min(view.drawings.len());
    let drawings = view.drawings.get(from..end).unwrap_or(&[]);
    Json(json!({ "program": app.shared.swaps(), "from": from, "drawings": drawings })).into_response()
}

#[derive(serde::Deserialize)]
pub struct Rungs {
    /// Rung numbers, comma-separated (the ones on screen).
    rungs: Option<String>,
}

/// The elements of some rungs as the latest scan left them: `elements`:
/// `[instruction, on, forced, [values]]`, and which program they are of.
pub async fn ladder_state(
    State(app): State<App>,
    query: Result<Query<Rungs>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(query)) = query else {
        return error(StatusCode::BAD_REQUEST, "the query is not `rungs=N,N,...`");
    };
    let Some(view) = app.shared.view() else {
        return error(StatusCode::SERVICE_UNAVAILABLE, "no program runs yet");
    };
    let mut rungs = Vec::new();
    for word in query
        .rungs
        .as_deref()
        .unwrap_or("")
        .split(',')
        .filter(|w| !w.trim().is_empty())
    {
        match word.trim().parse::<usize>() {
            Ok(rung) if rung < view.rungs.len() => rungs.push(rung),
            Ok(_) | Err(_) => {
                return error(
                    StatusCode::BAD_REQUEST,
                    format!("`{word}` is not a rung (0-{})", view.rungs.len().saturating_sub(1)),
                )
            }
        }
    }
    let (elements, scan) = {
        let image = app.shared.image();
        (view.states(&rungs, &image), image.scan_count)
    };
    Json(json!({ "program": app.shared.swaps(), "scan": scan, "elements": elements })).into_response()
}

pub async fn control(State(app): State<App>) -> Json<Value> {
    Json(control_json(&app.shared))
}

#[derive(serde::Deserialize)]
pub struct Action {
    /// `run`, `stop`, `pause`, `resume` or `step`.
    action: String,
    /// Scans for `step` (default 1).
    scans: Option<u32>,
}

/// Changes the switch: RUN/STOP, pause/resume, step N scans.
pub async fn set_control(
    State(app): State<App>,
    body: Result<Json<Action>, axum::extract::rejection::JsonRejection>,
) -> Response {
    let Json(body) = match body {
        Ok(body) => body,
        Err(rejection) => return error(rejection.status(), rejection.body_text()),
    };
    {
        let mut control = app.shared.control();
        match body.action.to_ascii_lowercase().as_str() {
            "run" => control.run(),
            "stop" => control.stopped = true,
            "pause" => control.paused = true,
            "resume" => {
                control.paused = false;
                control.steps = 0;
                control.hit = None;
            }
            "step" => {
                let scans = body.scans.unwrap_or(1);
                if !(1..=MOST_STEPS).contains(&scans) {
                    return error(StatusCode::BAD_REQUEST, format!("a step is 1 to {MOST_STEPS} scans"));
                }
                control.paused = true;
                control.hit = None;
                control.steps = control.steps.saturating_add(scans).min(MOST_STEPS);
            }
            other => {
                return error(
                    StatusCode::BAD_REQUEST,
                    format!("`{other}` is not an action: run, stop, pause, resume or step"),
                )
            }
        }
    }
    // A step or a resume is taken at once, not at the next period.
    app.shared.wake();
    Json(control_json(&app.shared)).into_response()
}

pub async fn breakpoints(State(app): State<App>) -> Json<Value> {
    Json(control_json(&app.shared))
}

#[derive(serde::Deserialize)]
pub struct NewBreakpoint {
    condition: String,
}

/// Adds a breakpoint: `{"condition": "D0 > 100"}`.
pub async fn add_breakpoint(
    State(app): State<App>,
    body: Result<Json<NewBreakpoint>, axum::extract::rejection::JsonRejection>,
) -> Response {
    let Json(body) = match body {
        Ok(body) => body,
        Err(rejection) => return error(rejection.status(), rejection.body_text()),
    };
    let added = app.shared.control().add_breakpoint(&body.condition);
    match added {
        Ok(id) => Json(json!({ "id": id, "condition": body.condition.trim() })).into_response(),
        Err(message) => error(StatusCode::BAD_REQUEST, message),
    }
}

#[derive(serde::Deserialize)]
pub struct Which {
    id: Option<u32>,
}

/// Removes breakpoint `?id=N`, or every breakpoint without an id.
pub async fn remove_breakpoints(
    State(app): State<App>,
    query: Result<Query<Which>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(which)) = query else {
        return error(StatusCode::BAD_REQUEST, "the query is not `id=N`");
    };
    if app.shared.control().remove_breakpoints(which.id) {
        Json(control_json(&app.shared)).into_response()
    } else {
        error(StatusCode::NOT_FOUND, "no such breakpoint")
    }
}
