//! Entry points for the fuzz targets of the servers (`fuzz/`): whatever
//! the bytes, nothing panics, and what comes back is well formed.
//!
//! - `modbus_stream`: bytes as a client's side of a connection, split into
//!   frames as the server splits them; each answer must echo the
//!   transaction and unit, carry a length that matches, and answer the
//!   request's function (or its exception).
//! - `melsec_stream`: bytes as a client's side of a MELSEC connection,
//!   split into frames as the server splits them and answered over the
//!   server's image and write queue; each answer must be of the frame's
//!   kind and code, echo its route (and 4E serial), and carry a length that
//!   matches.
//! - `modbus_rtu_frames`: bytes as frames on a serial line (each preceded
//!   by its length byte), answered as the RTU slave answers them; an answer
//!   comes only to the server's unit, from it, with a CRC that matches.
//! - `http_request`: bytes as a method, a path with its query and a body,
//!   sent to the real router (with the access layer) of a server that has
//!   published an image; no answer may be a 5xx.

use super::modbus::Service;
use super::modbus_tcp::{answer, header, Header, HEADER_LEN};
use super::shared::Shared;
use std::sync::Arc;

/// A server's shared state with a program's drawing and identity, as after
/// start.
fn started() -> Arc<Shared> {
    let shared = Arc::new(Shared::default());
    let source = ladder_front::source::SourceFile::new("fuzz.il", "LD X0\nOUT Y0\nLD M8000\nINC D0\n".to_string());
    if let (Some(program), _) = ladder_front::check::compile_source(&source) {
        let loaded = super::change::Loaded::new(program, &source);
        shared.set_view(Arc::clone(&loaded.view));
        shared.set_identity(Arc::clone(&loaded.identity));
    }
    shared.publish(&ladder_runtime::Memory::new_boxed());
    shared
}

/// Stands in for the scan thread's END processing while it lives: takes
/// every queued write and answers its writer, so that a write request is
/// answered as applied rather than after the wait for a scan runs out.
struct EndProcessing {
    done: Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl EndProcessing {
    fn start(shared: &Arc<Shared>) -> EndProcessing {
        let done = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let thread = {
            let (shared, done) = (Arc::clone(shared), Arc::clone(&done));
            std::thread::spawn(move || {
                while !done.load(std::sync::atomic::Ordering::Relaxed) {
                    if shared.writes_waiting() {
                        let _ = shared.take_writes();
                        shared.acknowledge();
                    }
                    std::thread::sleep(std::time::Duration::from_micros(200));
                }
            })
        };
        EndProcessing {
            done,
            thread: Some(thread),
        }
    }
}

impl Drop for EndProcessing {
    fn drop(&mut self) {
        self.done.store(true, std::sync::atomic::Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The first byte's bit 0 (writes allowed), and the bytes after it.
fn flags(data: &[u8]) -> Option<(bool, &[u8])> {
    data.split_first().map(|(&flags, rest)| (flags & 1 != 0, rest))
}

pub fn modbus_stream(data: &[u8]) {
    let Some((may_write, mut rest)) = flags(data) else {
        return;
    };
    let service = Service {
        shared: started(),
        may_write,
    };
    while rest.len() >= HEADER_LEN {
        let mut head = [0u8; HEADER_LEN];
        head.copy_from_slice(&rest[..HEADER_LEN]);
        let Header::Frame { pdu_len } = header(&head) else {
            return;
        };
        let Some(pdu) = rest.get(HEADER_LEN..HEADER_LEN + pdu_len) else {
            return;
        };
        let reply = answer(&service, &head, pdu);
        assert!(reply.len() >= HEADER_LEN + 2, "a reply has a function and data");
        assert_eq!(reply[..4], head[..4], "transaction and protocol echoed");
        assert_eq!(reply[6], head[6], "unit echoed");
        let length = usize::from(u16::from_be_bytes([reply[4], reply[5]]));
        assert_eq!(length, reply.len() - 6, "the length field counts unit and PDU");
        assert!(reply.len() <= 260, "an ADU is at most 260 bytes");
        assert_eq!(
            reply[7] & 0x7F,
            pdu[0] & 0x7F,
            "the reply answers the request's function"
        );
        rest = &rest[HEADER_LEN + pdu_len..];
    }
}

pub fn melsec_stream(data: &[u8]) {
    use ladder_melsec::{frame_length, kind, Code, Kind, Length};
    let Some((may_write, mut rest)) = flags(data) else {
        return;
    };
    let shared = started();
    loop {
        let length = match frame_length(rest) {
            Length::Frame(length) if length <= rest.len() => length,
            Length::Frame(_) | Length::Need(_) | Length::Invalid => return,
        };
        let frame = &rest[..length];
        let (Some(kind), Some(reply)) = (kind(frame), super::melsec::answer(&shared, may_write, frame)) else {
            panic!("a frame `frame_length` measured got no answer");
        };
        match kind {
            Kind::E1(code) => {
                let command = match code {
                    Code::Binary => frame[0],
                    Code::Ascii => {
                        u8::from_str_radix(std::str::from_utf8(&frame[..2]).unwrap_or("00"), 16).unwrap_or(0)
                    }
                };
                let echoed = match code {
                    Code::Binary => reply.first().copied(),
                    Code::Ascii => reply
                        .get(..2)
                        .and_then(|text| u8::from_str_radix(std::str::from_utf8(text).ok()?, 16).ok()),
                };
                assert_eq!(echoed, Some(command | 0x80), "a 1E answer names its command");
            }
            Kind::E3(code) | Kind::E4(code) => {
                let four = matches!(kind, Kind::E4(_));
                let unit = match code {
                    Code::Binary => 1,
                    Code::Ascii => 2,
                };
                let header = unit * if four { 13 } else { 9 };
                assert!(
                    reply.len() >= header + 2 * unit,
                    "a 3E/4E answer has a header and an end code"
                );
                let route = if four { 6 * unit..11 * unit } else { 2 * unit..7 * unit };
                assert_eq!(reply[route.clone()], frame[route], "the route is echoed");
                if four {
                    assert_eq!(
                        reply[2 * unit..4 * unit],
                        frame[2 * unit..4 * unit],
                        "the serial is echoed"
                    );
                }
                let field = &reply[header - 2 * unit..header];
                let length = match code {
                    Code::Binary => usize::from(u16::from_le_bytes([field[0], field[1]])),
                    Code::Ascii => usize::from_str_radix(std::str::from_utf8(field).unwrap_or(""), 16).unwrap_or(0),
                };
                assert_eq!(length, reply.len() - header, "the length counts the end code and data");
            }
        }
        rest = &rest[length..];
    }
}

pub fn modbus_rtu_frames(data: &[u8]) {
    let Some((may_write, mut rest)) = flags(data) else {
        return;
    };
    let service = Service {
        shared: started(),
        may_write,
    };
    const UNIT: u8 = 1;
    while let Some((&length, tail)) = rest.split_first() {
        let frame = &tail[..usize::from(length).min(tail.len())];
        if let Some(reply) = super::modbus_rtu::answer(&service, UNIT, frame, false) {
            assert_eq!(frame.first(), Some(&UNIT), "only the server's unit is answered");
            assert_eq!(reply[0], UNIT, "the answer is from the server's unit");
            assert!(
                matches!(
                    ladder_modbus::rtu::frame(&reply),
                    ladder_modbus::rtu::Frame::Request { .. }
                ),
                "the answer's CRC matches"
            );
            assert!(
                reply.len() <= ladder_modbus::rtu::MAX_FRAME,
                "an RTU frame is at most 256 bytes"
            );
            assert_eq!(
                reply[1] & 0x7F,
                frame[1] & 0x7F,
                "the reply answers the request's function"
            );
        }
        rest = &tail[frame.len()..];
    }
}

pub fn http_request(data: &[u8]) {
    use axum::body::Body;
    use axum::extract::ConnectInfo;
    use tower::ServiceExt as _;
    let text = String::from_utf8_lossy(data);
    let (head, body) = text.split_once('\n').unwrap_or((&text, ""));
    let mut words = head.splitn(2, ' ');
    let method = match words.next().unwrap_or("") {
        "P" | "POST" => "POST",
        "D" | "DELETE" => "DELETE",
        "H" | "HEAD" => "HEAD",
        "U" | "PUT" => "PUT",
        _ => "GET",
    };
    let path = words.next().unwrap_or("/");
    let path = if path.starts_with('/') {
        path.to_string()
    } else {
        format!("/{path}")
    };
    let Ok(request) = axum::http::Request::builder()
        .method(method)
        .uri(path.as_str())
        .header("content-type", "application/json")
        .body(Body::from(body.to_string()))
    else {
        return;
    };
    let mut request = request;
    let peer: std::net::SocketAddr = if data.first().is_some_and(|b| b & 1 != 0) {
        ([192, 0, 2, 7], 50_000).into()
    } else {
        ([127, 0, 0, 1], 50_000).into()
    };
    request.extensions_mut().insert(ConnectInfo(peer));
    let access = super::access::Access {
        token: data
            .get(1)
            .filter(|b| **b & 1 != 0)
            .map(|_| "0123456789abcdef".to_string()),
        token_reads: data.get(1).is_some_and(|b| b & 2 != 0),
        read_only: data.get(1).is_some_and(|b| b & 4 != 0),
        hosts: super::access::Hosts::of(([127, 0, 0, 1], 8080).into(), false, &[]),
    };
    let shared = started();
    let _end_processing = EndProcessing::start(&shared);
    let router = super::http::router(shared, false).layer(axum::middleware::from_fn_with_state(
        Arc::new(access),
        super::access::check,
    ));
    let Ok(runtime) = tokio::runtime::Builder::new_current_thread().enable_all().build() else {
        return;
    };
    runtime.block_on(async {
        let response = router.oneshot(request).await;
        let Ok(response) = response;
        assert!(
            !response.status().is_server_error(),
            "{method} {path}: {}",
            response.status()
        );
        // Event streams do not end; everything else is read whole.
        if !path.starts_with("/api/events") {
            let _ = tokio::time::timeout(
                std::time::Duration::from_secs(2),
                axum::body::to_bytes(response.into_body(), 16 * 1024 * 1024),
            )
            .await;
        }
    });
}
