//! Who may do what over HTTP.
//!
//! Loopback is not a trust boundary for a browser: any page the browser
//! shows (from the internet, or another local server) can make requests to
//! 127.0.0.1, and a name an attacker controls can be made to resolve to it
//! (DNS rebinding). So before anything else:
//! - a request must name this server in its `Host` (or HTTP/2 authority):
//!   the address it listens on (and `localhost` for a loopback address, any
//!   address of the machine when it listens on all of them), or a name
//!   given with `--allowed-host` (a reverse proxy's); else 403;
//! - a write (any method but GET and HEAD) from a browser page of another
//!   origin is refused (403): its `Origin` must be this server, and its
//!   `Sec-Fetch-Site`, when sent, `same-origin` or `none`. Clients that are
//!   not browsers send neither and are judged by what follows. (A program
//!   upload cannot be a request a browser sends without asking first: its
//!   content type is checked where it is taken, `http::program::upload`.)
//!
//! Then, with `--token-file`, every write needs the token as `Authorization:
//! Bearer TOKEN` (the scheme in any case), from every peer — a process on
//! the same machine is not trusted for being there; with `--token-reads` the
//! JSON API and the event stream need it too (the page itself holds no data
//! and stays open, so a browser can load it and ask for the token). Event
//! streams, and only they, may carry it as `?access_token=` (RFC 6750),
//! since a browser's EventSource cannot set headers. Without a token file,
//! writes come only from loopback peers; with `--read-only`, from nobody.
//! Refusals are JSON: 401 (no or wrong token, with `WWW-Authenticate:
//! Bearer`) or 403. A refused write's body is read (up to the program
//! limit) before the answer, so that an HTTP/2 client sending it sees the
//! answer rather than a reset stream.

use axum::extract::{ConnectInfo, Request, State};
use axum::http::{header, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;

#[derive(Clone, Debug, Default)]
pub struct Access {
    /// The token, when `--token-file` gave one.
    pub token: Option<String>,
    /// Reads need the token too.
    pub token_reads: bool,
    /// `--read-only`: every write is refused (403), whoever asks.
    pub read_only: bool,
    /// Who a request may name as its host.
    pub hosts: Hosts,
}

/// The names and port a request's `Host` may give.
#[derive(Clone, Debug, Default)]
pub struct Hosts {
    /// The port the server listens on (0: any, for tests of the layer alone).
    pub port: u16,
    /// `https` or `http`: what an `Origin` of this server starts with.
    pub scheme: &'static str,
    /// Host names and addresses, in lower case, without brackets.
    pub names: Vec<String>,
    /// `NAME:PORT` entries of `--allowed-host` (a proxy's port).
    pub named_ports: Vec<(String, u16)>,
    /// `NAME` entries of `--allowed-host`: that name on any port (a proxy
    /// forwards the name its clients used, with its own port or none).
    pub any_port: Vec<String>,
    /// The server listens on every address: any IP address is this server.
    pub any_address: bool,
}

impl Hosts {
    /// The hosts of a server listening on `address` (`tls`: HTTPS), with
    /// the names `--allowed-host` adds (`NAME` or `NAME:PORT`).
    pub fn of(address: SocketAddr, tls: bool, allowed: &[String]) -> Hosts {
        let ip = address.ip().to_canonical();
        let mut names = vec![ip.to_string()];
        if ip.is_loopback() {
            names.extend(["localhost".to_string(), "127.0.0.1".to_string(), "::1".to_string()]);
        }
        let (mut named_ports, mut any_port) = (Vec::new(), Vec::new());
        for entry in allowed.iter().flat_map(|entry| entry.split(',')) {
            let entry = entry.trim().to_ascii_lowercase();
            match split_host(&entry) {
                (host, Some(port)) => named_ports.push((host.to_string(), port)),
                (host, None) => any_port.push(host.to_string()),
            }
        }
        Hosts {
            port: address.port(),
            scheme: if tls { "https" } else { "http" },
            names,
            named_ports,
            any_port,
            any_address: ip.is_unspecified(),
        }
    }

    /// Does `authority` (`host[:port]`, as a `Host` header or an origin
    /// without its scheme gives it) name this server?
    pub fn admits(&self, authority: &str) -> bool {
        let authority = authority.trim().to_ascii_lowercase();
        let (host, port) = split_host(&authority);
        let default = if self.scheme == "https" { 443 } else { 80 };
        let port = port.unwrap_or(default);
        let ours = self.port == 0 || port == self.port;
        (ours && (self.names.iter().any(|name| name == host) || (self.any_address && host.parse::<IpAddr>().is_ok())))
            || self.named_ports.iter().any(|(name, p)| name == host && *p == port)
            || self.any_port.iter().any(|name| name == host)
    }

    /// Is `origin` (an `Origin` header) this server?
    fn admits_origin(&self, origin: &str) -> bool {
        origin
            .strip_prefix(self.scheme)
            .and_then(|rest| rest.strip_prefix("://"))
            .is_some_and(|authority| !authority.contains('/') && self.admits(authority))
    }
}

/// `host` and its port of `host[:port]`, `[v6]:port` or a bare IPv6 address.
fn split_host(authority: &str) -> (&str, Option<u16>) {
    if let Some(rest) = authority.strip_prefix('[') {
        return match rest.split_once(']') {
            Some((host, tail)) => (host, tail.strip_prefix(':').and_then(|p| p.parse().ok())),
            None => (rest, None),
        };
    }
    match authority.rsplit_once(':') {
        // A bare IPv6 address has several colons and no port.
        Some((host, port)) if !host.contains(':') => (host, port.parse().ok()),
        Some(_) | None => (authority, None),
    }
}

/// Shortest token a token file may hold.
pub const SHORTEST_TOKEN: usize = 16;

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

/// The token a request carries: the bearer header (the scheme in any
/// case, RFC 7235), or for an event stream `access_token` in the query.
fn token_of(request: &Request) -> Option<String> {
    let bearer = request
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|value| value.to_str().ok())
        .and_then(|value| {
            let (scheme, token) = value.trim().split_once(' ')?;
            scheme.eq_ignore_ascii_case("bearer").then(|| token.trim().to_string())
        });
    let event_stream = request.method() == Method::GET && request.uri().path() == "/api/events";
    bearer.or_else(|| {
        event_stream.then(|| request.uri().query()).flatten().and_then(|query| {
            query
                .split('&')
                .find_map(|pair| pair.strip_prefix("access_token="))
                .map(percent_decode)
        })
    })
}

/// The host a request names: its HTTP/2 authority or its `Host` header.
fn host_of(request: &Request) -> Option<String> {
    request.uri().authority().map(|a| a.to_string()).or_else(|| {
        request
            .headers()
            .get(header::HOST)
            .and_then(|value| value.to_str().ok())
            .map(str::to_string)
    })
}

/// Why a write comes from a browser page of another origin, if it does.
fn foreign_page(request: &Request, hosts: &Hosts) -> Option<String> {
    let headers = request.headers();
    if let Some(site) = headers.get("sec-fetch-site").and_then(|v| v.to_str().ok()) {
        if !matches!(site, "same-origin" | "none") {
            return Some(format!("a {site} page"));
        }
    }
    let origin = headers.get(header::ORIGIN)?;
    let origin = origin.to_str().unwrap_or("");
    (!hosts.admits_origin(origin)).then(|| format!("a page of `{origin}`"))
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

/// The longest body a refused write is read to before it is answered.
const DRAINED: usize = 8 * 1024 * 1024;

/// The middleware: passes the request on, or refuses it.
pub async fn check(State(access): State<Arc<Access>>, request: Request, next: Next) -> Response {
    // The peer as the plain server (guarded) or the TLS one gives it; a
    // request without one (none comes that way) counts as from afar.
    let peer = match request.extensions().get::<ConnectInfo<super::guard::Peer>>() {
        Some(ConnectInfo(super::guard::Peer(peer))) => Some(*peer),
        None => request
            .extensions()
            .get::<ConnectInfo<SocketAddr>>()
            .map(|ConnectInfo(peer)| *peer),
    };
    let loopback = peer.is_some_and(|peer| peer.ip().to_canonical().is_loopback());
    let writes = !matches!(*request.method(), Method::GET | Method::HEAD);
    let page = request.uri().path() == "/";
    let refusal = match host_of(&request) {
        Some(host) if !access.hosts.admits(&host) => Some(refuse(
            StatusCode::FORBIDDEN,
            &format!(
                "this server does not answer to the host `{host}` (a name it is not known by; \
                 behind a reverse proxy, name it with --allowed-host)"
            ),
        )),
        Some(_) | None => None,
    };
    let refusal = refusal.or_else(|| {
        let foreign = writes.then(|| foreign_page(&request, &access.hosts)).flatten()?;
        Some(refuse(
            StatusCode::FORBIDDEN,
            &format!("writes from {foreign} are refused: only this server's own page may write"),
        ))
    });
    let refusal = refusal
        .or_else(|| (writes && access.read_only).then(|| refuse(StatusCode::FORBIDDEN, "the server is read-only")));
    let refusal = refusal.or_else(|| match &access.token {
        Some(token) if writes || (access.token_reads && !page) => match token_of(&request) {
            Some(given) if same(given.as_bytes(), token.as_bytes()) => None,
            Some(_) => Some(refuse(StatusCode::UNAUTHORIZED, "wrong access token")),
            None => Some(refuse(
                StatusCode::UNAUTHORIZED,
                "this server needs its access token (Authorization: Bearer TOKEN)",
            )),
        },
        None if writes && !loopback => Some(refuse(
            StatusCode::FORBIDDEN,
            "writes from beyond loopback need a token: start the server with --token-file",
        )),
        Some(_) | None => None,
    });
    match refusal {
        Some(refusal) => {
            if writes {
                let _ = axum::body::to_bytes(request.into_body(), DRAINED).await;
            }
            refusal
        }
        None => next.run(request).await.into_response(),
    }
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
    fn hosts_are_this_server_by_address_and_name() {
        let local = Hosts::of(
            "127.0.0.1:8090".parse().unwrap(),
            false,
            &["plc.example:443".to_string()],
        );
        for host in ["127.0.0.1:8090", "localhost:8090", "LOCALHOST:8090", "[::1]:8090"] {
            assert!(local.admits(host), "{host}");
        }
        for host in [
            "evil.example:8090",
            "127.0.0.1:8091",
            "localhost",
            "127.0.0.2:8090",
            "plc.example",
        ] {
            assert!(!local.admits(host), "{host}");
        }
        assert!(local.admits("plc.example:443"), "a proxy's name and port");
        assert!(local.admits_origin("http://127.0.0.1:8090"));
        assert!(!local.admits_origin("http://127.0.0.1:9000"));
        assert!(!local.admits_origin("https://127.0.0.1:8090"));
        assert!(!local.admits_origin("null"));
        let all = Hosts::of(
            "0.0.0.0:80".parse().unwrap(),
            false,
            &["machine-7,hmi.local".to_string()],
        );
        assert!(all.admits("192.168.1.20") && all.admits("192.168.1.20:80") && all.admits("machine-7"));
        assert!(all.admits("hmi.local:8443") && !all.admits("192.168.1.20:81"));
        assert!(!all.admits("attacker.example"));
        let tls = Hosts::of("[::1]:443".parse().unwrap(), true, &[]);
        assert!(tls.admits("[::1]") && tls.admits("localhost") && tls.admits_origin("https://localhost"));
    }

    #[test]
    fn query_tokens_are_percent_decoded() {
        assert_eq!(percent_decode("a%2Bb%3d+c"), "a+b= c");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz%4"), "%zz%4");
    }
}
