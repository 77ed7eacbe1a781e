//! The Modbus TCP server of `serve`: frames (the MBAP header and PDUs of
//! the `ladder-modbus` crate) answered by the map (`modbus::Service`). An
//! MBAP header that cannot be right closes the connection (a TCP stream
//! cannot find the next frame after a length it cannot trust), as does a
//! frame that does not arrive whole within `FRAME_TIMEOUT`; a request the
//! specification answers with an exception gets it and the connection
//! stays. A write is answered once it is applied (`Reply`).
//!
//! Connections are bounded as `connections` bounds them.

use super::acks::{NotApplied, Ticket};
use super::modbus::Service;
use super::shared::Shared;
pub use crate::connections::ConnectionLimits;
use crate::connections::{accept, Open};
pub use ladder_modbus::{decode, encode, header, Header, HEADER_LEN};
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_modbus::prelude::ExceptionCode;

/// A frame that has started must be complete within this time.
const FRAME_TIMEOUT: Duration = Duration::from_secs(5);

/// A response PDU, and the write it acknowledges: sent once the write is
/// applied (a read after it sees the write), else exception 04.
pub struct Reply {
    pub pdu: Vec<u8>,
    function: u8,
    pub ticket: Option<Ticket>,
}

impl Reply {
    /// The PDU once its write is applied, waiting on this thread.
    pub fn settle(self, shared: &Shared) -> Vec<u8> {
        match self.ticket.map(|ticket| shared.wait_applied(ticket)) {
            None | Some(Ok(())) => self.pdu,
            Some(Err(NotApplied::TimedOut | NotApplied::Stopping)) => not_applied(self.function),
        }
    }

    /// The PDU once its write is applied, waiting as a task.
    pub async fn settled(self, shared: &Shared) -> Vec<u8> {
        let applied = match self.ticket {
            Some(ticket) => shared.applied(ticket).await,
            None => Ok(()),
        };
        match applied {
            Ok(()) => self.pdu,
            Err(NotApplied::TimedOut | NotApplied::Stopping) => not_applied(self.function),
        }
    }
}

/// A write queued but not applied in time (or the server stopping):
/// exception 04, server device failure (the write may still take effect).
fn not_applied(function: u8) -> Vec<u8> {
    encode(function, Err(ExceptionCode::ServerDeviceFailure))
}

/// The response PDU to a request PDU, whatever carries them (TCP or RTU).
pub fn respond(service: &Service, pdu: &[u8]) -> Reply {
    let function = pdu.first().copied().unwrap_or(0);
    // A write where writes are refused is an unsupported function (01),
    // checked first as the specification orders the checks: before its
    // values (03) and its address (02).
    let response = if matches!(function, 0x05 | 0x06 | 0x0F | 0x10) && !service.may_write {
        Err(ExceptionCode::IllegalFunction)
    } else {
        decode(pdu).and_then(|request| service.respond(request))
    };
    let (response, ticket) = match response {
        Ok((response, ticket)) => (Ok(response), ticket),
        Err(code) => (Err(code), None),
    };
    Reply {
        pdu: encode(function, response),
        function,
        ticket,
    }
}

/// The whole answer to one frame (header and PDU), as it goes on the
/// wire, without waiting for its write to be applied (the fuzzing harness
/// has no scan thread; a connection waits: `Reply::settled`).
pub fn answer(service: &Service, header: &[u8; HEADER_LEN], pdu: &[u8]) -> Vec<u8> {
    frame(header, &respond(service, pdu).pdu)
}

/// A PDU framed with the request's header.
pub fn frame(header: &[u8; HEADER_LEN], body: &[u8]) -> Vec<u8> {
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
        let body = respond(&service, &pdu).settled(&service.shared).await;
        let reply = frame(&header_bytes, &body);
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn a_write_is_answered_once_applied_and_exception_04_when_it_cannot_be() {
        let shared = Arc::new(Shared::default());
        let service = Service {
            shared: Arc::clone(&shared),
            may_write: true,
        };
        let read = respond(&service, &[0x03, 0, 1, 0, 1]);
        assert!(read.ticket.is_none(), "a read waits for nothing");
        let write = respond(&service, &[0x06, 0, 1, 0, 5]);
        assert!(write.ticket.is_some());
        // The scan thread's END processing: taken, applied, published.
        let _ = shared.take_writes();
        shared.acknowledge();
        assert_eq!(write.settle(&shared), [0x06, 0, 1, 0, 5]);
        let write = respond(&service, &[0x06, 0, 1, 0, 6]);
        shared.stop();
        assert_eq!(write.settle(&shared), [0x86, 0x04], "the server stopped first");
    }
}
