//! The Modbus TCP server of `serve`: frames (the MBAP header and PDUs of
//! the `ladder-modbus` crate) answered by the map (`modbus::Service`). An
//! MBAP header that cannot be right closes the connection (a TCP stream
//! cannot find the next frame after a length it cannot trust), as does a
//! frame that does not arrive whole within `FRAME_TIMEOUT`; a request the
//! specification answers with an exception gets it and the connection
//! stays.
//!
//! Connections are bounded as `connections` bounds them.

use super::modbus::Service;
pub use crate::connections::ConnectionLimits;
use crate::connections::{accept, Open};
pub use ladder_modbus::{decode, encode, header, Header, HEADER_LEN};
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_modbus::prelude::ExceptionCode;

/// A frame that has started must be complete within this time.
const FRAME_TIMEOUT: Duration = Duration::from_secs(5);

/// The response PDU to a request PDU, whatever carries them (TCP or RTU).
pub fn respond(service: &Service, pdu: &[u8]) -> Vec<u8> {
    let function = pdu.first().copied().unwrap_or(0);
    // A write where writes are refused is an unsupported function (01),
    // checked first as the specification orders the checks: before its
    // values (03) and its address (02).
    let response = if matches!(function, 0x05 | 0x06 | 0x0F | 0x10) && !service.may_write {
        Err(ExceptionCode::IllegalFunction)
    } else {
        decode(pdu).and_then(|request| service.respond(request))
    };
    encode(function, response)
}

/// The whole answer to one frame (header and PDU), as it goes on the wire.
pub fn answer(service: &Service, header: &[u8; HEADER_LEN], pdu: &[u8]) -> Vec<u8> {
    let body = respond(service, pdu);
    let mut frame = Vec::with_capacity(HEADER_LEN + body.len());
    frame.extend(&header[..4]);
    frame.extend(((body.len() + 1) as u16).to_be_bytes());
    frame.push(header[6]);
    frame.extend(body);
    frame
}

/// Serves one connection until the client closes it, sends what cannot be
/// a frame, stays idle for `idle`, or `open` is told to close.
async fn serve_connection(mut stream: tokio::net::TcpStream, service: Service, open: &Open, idle: Duration) {
    let _ = stream.set_nodelay(true);
    loop {
        let mut header_bytes = [0u8; HEADER_LEN];
        // Waiting for a request may take up to the idle time; a started one
        // no longer than a frame may.
        tokio::select! {
            read = tokio::time::timeout(idle, stream.read_exact(&mut header_bytes[..1])) => match read {
                Ok(Ok(_)) => {}
                Ok(Err(_)) | Err(_) => return,
            },
            () = open.close.notified() => return,
        }
        let whole = async {
            stream.read_exact(&mut header_bytes[1..]).await?;
            let Header::Frame { pdu_len } = header(&header_bytes) else {
                return Ok(None);
            };
            let mut pdu = vec![0u8; pdu_len];
            stream.read_exact(&mut pdu).await?;
            Ok::<_, std::io::Error>(Some(pdu))
        };
        let pdu = match tokio::time::timeout(FRAME_TIMEOUT, whole).await {
            Ok(Ok(Some(pdu))) => pdu,
            _ => return,
        };
        open.touch();
        let reply = answer(&service, &header_bytes, &pdu);
        if tokio::time::timeout(FRAME_TIMEOUT, stream.write_all(&reply))
            .await
            .is_err()
        {
            return;
        }
    }
}

/// Accepts connections until the process ends; each is served on its own
/// task with the write permission its peer address has, within `limits`.
pub async fn serve(
    listener: tokio::net::TcpListener,
    limits: ConnectionLimits,
    make_service: impl Fn(std::net::SocketAddr) -> Service + Send + 'static,
) {
    let idle = limits.idle;
    accept(listener, limits, move |stream, peer, open| {
        let service = make_service(peer);
        async move { serve_connection(stream, service, &open, idle).await }
    })
    .await;
}
