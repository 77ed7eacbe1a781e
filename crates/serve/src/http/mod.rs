//! The HTTP side of `ladderc serve` (axum): a live monitor page served by
//! the binary itself, a JSON API for scripts, and server-sent events that
//! push device values to the page. Like Modbus, it reads the image the
//! latest scan published and queues writes, answered once applied. This file
//! is the router; the handlers are `devices.rs` (watched devices, events,
//! statistics), `writes.rs` (writes and forces), `program.rs` (the running
//! program, online change) and `debug.rs` (the ladder, the switch, the
//! debugger).

mod debug;
mod devices;
mod program;
mod writes;

use super::shared::Shared;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde_json::json;
use std::sync::Arc;

/// Request bodies larger than this are refused (413).
const BODY_LIMIT: usize = 64 * 1024;
/// Uploaded programs larger than this are refused (413).
const PROGRAM_LIMIT: usize = 8 * 1024 * 1024;

#[derive(Clone)]
pub struct App {
    pub shared: Arc<Shared>,
    /// Programs run as native code: online change compiles them here.
    native: bool,
}

pub fn router(shared: Arc<Shared>, native: bool) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/api/devices", get(devices::devices))
        .route("/api/events", get(devices::events))
        .route("/api/stats", get(devices::stats))
        .route("/api/set", post(writes::set))
        .route("/api/force", post(writes::force))
        .route("/api/unforce", post(writes::unforce))
        .route("/api/forces", get(writes::forces))
        .route("/api/unforce-all", post(writes::unforce_all))
        .route("/api/stats/reset", post(devices::reset_stats))
        .route("/api/io", get(devices::remote_io))
        .route("/api/ladder", get(debug::ladder))
        .route("/api/ladder/state", get(debug::ladder_state))
        .route("/api/ladder/outline", get(debug::ladder_outline))
        .route("/api/ladder/rungs", get(debug::ladder_rungs))
        .route("/api/control", get(debug::control).post(debug::set_control))
        .route(
            "/api/breakpoints",
            get(debug::breakpoints)
                .post(debug::add_breakpoint)
                .delete(debug::remove_breakpoints),
        )
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .route(
            "/api/program",
            post(program::upload)
                .get(program::running)
                .layer(DefaultBodyLimit::max(PROGRAM_LIMIT)),
        )
        .with_state(App { shared, native })
}

/// The answer to a write queued but not applied in time (a scan that does
/// not end, or the server stopping): 503, never an acknowledgement.
pub fn not_applied() -> Response {
    error(
        StatusCode::SERVICE_UNAVAILABLE,
        "the write was not applied in time (the scan did not end, or the server is stopping)",
    )
}

/// The answer to a write when the queue of writes is full (clients write
/// faster than the scan thread applies them).
pub fn busy() -> Response {
    let mut response = error(
        StatusCode::SERVICE_UNAVAILABLE,
        "too many writes are waiting to be applied; try again",
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

async fn page() -> Html<&'static str> {
    Html(include_str!("monitor.html"))
}
