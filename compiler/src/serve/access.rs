//! Who may do what over HTTP. With `--token-file`, every write (any method
//! but GET and HEAD: set, force, control, upload) needs the token as
//! `Authorization: Bearer TOKEN`, from every peer — a process on the same
//! machine is not trusted for being there; with `--token-reads` the JSON
//! API and the event stream need it too (the page itself holds no data and
//! stays open, so a browser can load it and ask for the token). Event
//! streams may carry it as `?access_token=` (RFC 6750), since a browser's
//! EventSource cannot set headers. Without a token file, writes come only
//! from loopback peers; with `--read-only`, from nobody. Refusals are JSON:
//! 401 (no or wrong token, with `WWW-Authenticate: Bearer`) or 403
//! (read-only, or no token file and a peer beyond loopback).

use axum::extract::{ConnectInfo, Request, State};
use axum::http::{header, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::net::SocketAddr;
use std::sync::Arc;

/// Shortest token a token file may hold.
pub const SHORTEST_TOKEN: usize = 16;

#[derive(Clone, Debug, Default)]
pub struct Access {
    /// The token, when `--token-file` gave one.
    pub token: Option<String>,
    /// Reads need the token too.
    pub token_reads: bool,
    /// `--read-only`: every write is refused (403), whoever asks.
    pub read_only: bool,
}

/// Reads a token file: its first line, trimmed, of at least
/// `SHORTEST_TOKEN` characters.
pub fn read_token_file(path: &std::path::Path) -> Result<String, String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("cannot read the token file {}: {e}", path.display()))?;
    let token = text.lines().next().unwrap_or("").trim().to_string();
    if token.chars().count() < SHORTEST_TOKEN {
        return Err(format!(
            "the token file {} holds a token of {} characters; use at least {SHORTEST_TOKEN} (e.g. `openssl rand -hex 16`)",
            path.display(),
            token.chars().count()
        ));
    }
    Ok(token)
}

/// Equal without telling, by its duration, how much of a guess was right.
fn same(given: &[u8], token: &[u8]) -> bool {
    given.len() == token.len() && given.iter().zip(token).fold(0u8, |diff, (a, b)| diff | (a ^ b)) == 0
}

/// The token a request carries: the bearer header, or `access_token` in
/// the query.
fn token_of(request: &Request) -> Option<String> {
    let bearer = request
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|value| value.to_str().ok())
        .and_then(|value| value.strip_prefix("Bearer "))
        .map(|token| token.trim().to_string());
    bearer.or_else(|| {
        request.uri().query().and_then(|query| {
            query
                .split('&')
                .find_map(|pair| pair.strip_prefix("access_token="))
                .map(percent_decode)
        })
    })
}

/// `%2B` and `+` as a browser's `encodeURIComponent` and forms write them.
fn percent_decode(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => match (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                (Some(high), Some(low)) => {
                    out.push((high * 16 + low) as u8);
                    i += 3;
                    continue;
                }
                _ => out.push(b'%'),
            },
            b'+' => out.push(b' '),
            other => out.push(other),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn refuse(status: StatusCode, message: &str) -> Response {
    let mut response = super::http::error(status, message);
    if status == StatusCode::UNAUTHORIZED {
        response
            .headers_mut()
            .insert(header::WWW_AUTHENTICATE, header::HeaderValue::from_static("Bearer"));
    }
    response
}

/// The middleware: passes the request on, or refuses it.
pub async fn check(
    State(access): State<Arc<Access>>,
    ConnectInfo(peer): ConnectInfo<SocketAddr>,
    request: Request,
    next: Next,
) -> Response {
    let writes = !matches!(*request.method(), Method::GET | Method::HEAD);
    let page = request.uri().path() == "/";
    if writes && access.read_only {
        return refuse(StatusCode::FORBIDDEN, "the server is read-only");
    }
    match &access.token {
        Some(token) if writes || (access.token_reads && !page) => match token_of(&request) {
            Some(given) if same(given.as_bytes(), token.as_bytes()) => next.run(request).await,
            Some(_) => refuse(StatusCode::UNAUTHORIZED, "wrong access token"),
            None => refuse(
                StatusCode::UNAUTHORIZED,
                "this server needs its access token (Authorization: Bearer TOKEN)",
            ),
        },
        None if writes && !peer.ip().to_canonical().is_loopback() => refuse(
            StatusCode::FORBIDDEN,
            "writes from beyond loopback need a token: start the server with --token-file",
        ),
        Some(_) | None => next.run(request).await,
    }
    .into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_compare_whole() {
        assert!(same(b"0123456789abcdef", b"0123456789abcdef"));
        assert!(!same(b"0123456789abcdeF", b"0123456789abcdef"));
        assert!(!same(b"0123456789abcde", b"0123456789abcdef"));
        assert!(!same(b"", b"0123456789abcdef"));
    }

    #[test]
    fn query_tokens_are_percent_decoded() {
        assert_eq!(percent_decode("a%2Bb%3d+c"), "a+b= c");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz%4"), "%zz%4");
    }
}
