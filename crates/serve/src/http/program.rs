//! The running program in the JSON API, and online change: a new program
//! uploaded, compiled off the scan thread (`change::accept`) and swapped in
//! between two scans.

use super::{error, App};
use crate::change::{self, Refusal};
use axum::extract::{Query, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;
use std::time::Duration;

/// The running program: its name, SHA-256, when it was loaded, its text.
pub async fn running(State(app): State<App>) -> Response {
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
pub struct Upload {
    /// `allow_empty=1`: a program that drives nothing is meant.
    allow_empty: Option<String>,
}

/// Content types a browser page may send without asking the server first
/// (a CORS "simple" request): a program upload never has one of them (nor
/// none), so no page of another origin can make one unasked.
const SIMPLE_CONTENT_TYPES: [&str; 3] = ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data"];

/// Online change: the body is the new program's text. It is compiled here
/// (not in the scan thread); one that does not compile, or drives nothing
/// unless `?allow_empty=1`, is refused (422, with its diagnostics) and the
/// running program goes on. Otherwise it replaces the running one between
/// two scans, and the answer comes once it runs.
pub async fn upload(
    State(app): State<App>,
    headers: axum::http::HeaderMap,
    query: Result<Query<Upload>, axum::extract::rejection::QueryRejection>,
    body: Result<axum::body::Bytes, axum::extract::rejection::BytesRejection>,
) -> Response {
    if let Some(refused) = refuse_simple_content_type(&headers) {
        return refused;
    }
    let allow_empty = matches!(query, Ok(Query(Upload { allow_empty: Some(ref v) })) if v == "1" || v == "true");
    let bytes = match body {
        Ok(bytes) => bytes,
        Err(rejection) => return error(rejection.status(), rejection.body_text()),
    };
    let native = app.native;
    let compiled = tokio::task::spawn_blocking(move || change::accept("<upload>", &bytes, allow_empty, native)).await;
    let (message, diagnostics) = match compiled {
        Ok(Ok(loaded)) => return swap_in(&app, loaded).await,
        Ok(Err(Refusal::DrivesNothing(shown))) => (
            "the program drives nothing (W0004); the running one goes on (`?allow_empty=1` if it is meant)",
            shown,
        ),
        Ok(Err(Refusal::Native(why))) => ("the program cannot be compiled to native code", why),
        Ok(Err(Refusal::DoesNotCompile(shown))) => ("the program does not compile; the running one goes on", shown),
        Err(_) => return error(StatusCode::INTERNAL_SERVER_ERROR, "compiling failed"),
    };
    (
        StatusCode::UNPROCESSABLE_ENTITY,
        Json(json!({ "error": message, "diagnostics": diagnostics })),
    )
        .into_response()
}

/// 415 for an upload without a content type or with one a browser page may
/// send unasked.
fn refuse_simple_content_type(headers: &axum::http::HeaderMap) -> Option<Response> {
    let content_type = headers
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|value| value.to_str().ok())
        .map(|value| value.split(';').next().unwrap_or("").trim().to_ascii_lowercase());
    content_type
        .as_deref()
        .is_none_or(|kind| kind.is_empty() || SIMPLE_CONTENT_TYPES.contains(&kind))
        .then(|| {
            error(
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                "send the program with `Content-Type: application/octet-stream` (e.g. curl -H \
                 'Content-Type: application/octet-stream' --data-binary @prog.il URL/api/program); a type a browser \
                 page may send unasked is refused",
            )
        })
}

/// Offers the accepted program to the scan thread; the answer comes once
/// the new program has run a scan.
async fn swap_in(app: &App, loaded: change::Loaded) -> Response {
    let before = app.shared.swaps();
    if !app.shared.offer(loaded) {
        return error(StatusCode::CONFLICT, "another program is being swapped in; try again");
    }
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
