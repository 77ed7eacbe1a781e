//! The MELSEC side of `ladderc serve` (`--melsec`): 1E, 3E and 4E frames,
//! binary and ASCII, on one TCP port (and with `--melsec-udp` the same UDP
//! port), answered by
//! the `ladder-melsec` crate over the soft PLC's image. Reads see the
//! image the latest scan published; writes go to the same queue of host
//! writes as Modbus and HTTP, applied at the end of the scan in progress
//! and answered once applied (a write not applied in time is answered
//! with the busy end code, as a full queue is); remote
//! RUN/STOP/PAUSE move the same switch as the monitor's buttons (and SD203
//! reports it, as on an iQ-F: 0 RUN, 2 STOP, 3 PAUSE). Writes
//! and remote operations follow the Modbus rules: refused with
//! `--read-only`, and from peers beyond loopback unless they are in a
//! `--modbus-write-from` network.
//!
//! A connection is bounded as Modbus connections are (`connections`); a
//! frame must arrive whole within `FRAME_TIMEOUT`; bytes that cannot
//! start a frame, or a header whose length cannot be right, close the
//! connection (a stream cannot find the next frame after them).

use crate::acks::{NotApplied, Ticket};
use crate::connections::{accept, ConnectionLimits, Open, Permission};
use crate::shared::{HostWrite, Shared};
use ladder_front::host_device::HostDevice;
use ladder_melsec::{Device, Family, Length, Plc, Refusal, Remote, Write};
use ladder_runtime::device::FIRST_WIDE_COUNTER;
use ladder_runtime::{BitArea, Memory, Width, WordArea};
use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};

/// SD203, the operating status: 0 RUN, 2 STOP, 3 PAUSE in its low four
/// bits.
const OPERATING_STATUS: u32 = 203;

/// A frame that has started must be complete within this time.
const FRAME_TIMEOUT: Duration = Duration::from_secs(5);

/// The PLC as one request sees it: one image for all its reads.
pub struct Station {
    pub shared: Arc<Shared>,
    pub image: Arc<Memory>,
    pub may_write: bool,
    /// The writes of this request, queued: the answer waits for them.
    pub ticket: Option<Ticket>,
    /// Its writes were queued once and not applied in time: answering
    /// again, every write is refused as busy.
    pub not_applied: bool,
}

/// Where a family's devices are in the image.
#[derive(Clone, Copy)]
enum Storage {
    Bits(BitArea),
    /// Words; the counters' (CN, LCN) are 16-bit for C0-C199, 32-bit from
    /// C200 (`Station::wide`).
    Words(WordArea),
    /// Whether each timer's coil was ON at its last execution.
    TimerCoils,
    CounterCoils,
}

fn storage(family: Family) -> Storage {
    match family {
        Family::X => Storage::Bits(BitArea::X),
        Family::Y => Storage::Bits(BitArea::Y),
        Family::M => Storage::Bits(BitArea::M),
        Family::S => Storage::Bits(BitArea::S),
        Family::Sm => Storage::Bits(BitArea::Sm),
        Family::TimerContact => Storage::Bits(BitArea::TimerContact),
        Family::CounterContact => Storage::Bits(BitArea::CounterContact),
        Family::Sd => Storage::Words(WordArea::Sd),
        Family::D => Storage::Words(WordArea::D),
        Family::R => Storage::Words(WordArea::R),
        Family::TimerValue => Storage::Words(WordArea::TimerValue),
        Family::CounterValue | Family::LongCounterValue => Storage::Words(WordArea::CounterValue),
        Family::TimerCoil => Storage::TimerCoils,
        Family::CounterCoil => Storage::CounterCoils,
    }
}

/// The host device a MELSEC device is (none for a coil).
fn host_device(device: Device, wide: bool) -> Option<HostDevice> {
    let (device, width) = match (storage(device.family), wide) {
        (Storage::Words(_), true) => (ladder_runtime::Device::WideCounter(device.number), Width::Double),
        (Storage::Bits(area), false | true) => (ladder_runtime::Device::Bit(area, device.number), Width::Single),
        (Storage::Words(area), false) => (ladder_runtime::Device::Word(area, device.number), Width::Single),
        (Storage::TimerCoils | Storage::CounterCoils, false | true) => return None,
    };
    Some(HostDevice { device, width })
}

impl Plc for Station {
    fn points(&self, family: Family) -> u32 {
        match storage(family) {
            // C0-C199 are 16-bit, C200-C255 32-bit: CN and LCN number them
            // all (the protocol crate refuses each where it does not fit).
            Storage::Words(WordArea::CounterValue) | Storage::CounterCoils => BitArea::CounterContact.count(),
            Storage::Words(area) => area.count(),
            Storage::Bits(area) => area.count(),
            Storage::TimerCoils => BitArea::TimerContact.count(),
        }
    }

    fn wide(&self, device: Device) -> bool {
        device.family == Family::CounterValue && device.number >= FIRST_WIDE_COUNTER
    }

    fn bit(&self, device: Device) -> bool {
        let index = device.number as usize;
        match storage(device.family) {
            Storage::TimerCoils => self.image.timer_coil_was_on.get(index).is_some_and(|&on| on != 0),
            Storage::CounterCoils => self.image.counter_coil_was_on.get(index).is_some_and(|&on| on != 0),
            Storage::Bits(_) | Storage::Words(_) => host_device(device, false)
                .and_then(|host| self.image.read_device(host.device, host.width))
                .is_some_and(|value| value != 0),
        }
    }

    fn word(&self, device: Device) -> u16 {
        let value = host_device(device, false)
            .and_then(|host| self.image.read_device(host.device, host.width))
            .unwrap_or(0) as u16;
        if device.family == Family::Sd && device.number == OPERATING_STATUS {
            // Its low four bits are the switch, as an iQ-F reports it (SLMP
            // clients read the CPU's state there).
            let control = self.shared.control();
            let status = match (control.stopped, control.paused) {
                (true, _) => 2,
                (false, true) => 3,
                (false, false) => 0,
            };
            return value & !0xF | status;
        }
        value
    }

    fn dword(&self, device: Device) -> u32 {
        host_device(device, self.wide(device))
            .and_then(|host| self.image.read_device(host.device, host.width))
            .unwrap_or(0) as u32
    }

    fn write(&mut self, writes: Vec<Write>) -> Result<(), Refusal> {
        if !self.may_write {
            return Err(Refusal::NotAllowed);
        }
        if self.not_applied {
            return Err(Refusal::Busy);
        }
        let mut queued = Vec::with_capacity(writes.len());
        for write in writes {
            let (device, value) = match write {
                Write::Bit(device, on) => (host_device(device, false), i32::from(on)),
                Write::Word(device, value) => (host_device(device, false), i32::from(value as i16)),
                Write::Dword(device, value) => (host_device(device, self.wide(device)), value as i32),
            };
            // The protocol crate has checked every device against `points`;
            // one without a host device (a coil) never reaches here.
            let Some(device) = device else {
                return Err(Refusal::NotAllowed);
            };
            queued.push(HostWrite::Set(device, value));
        }
        // A device the remote I/O writes before every scan (`--io`).
        if crate::remote_io::refused(&self.shared, &queued).is_some() {
            return Err(Refusal::NotAllowed);
        }
        let ticket = self.shared.queue(queued).ok_or(Refusal::Busy)?;
        self.ticket = Some(ticket);
        Ok(())
    }

    fn remote(&mut self, operation: Remote) -> Result<(), Refusal> {
        if !self.may_write {
            return Err(Refusal::NotAllowed);
        }
        {
            let mut control = self.shared.control();
            match operation {
                Remote::Run => control.run(),
                Remote::Stop => control.stopped = true,
                Remote::Pause => control.paused = true,
            }
        }
        self.shared.wake();
        Ok(())
    }
}

/// The answer to one frame, from the latest image, without waiting for
/// its writes to be applied (the fuzzing harness has no scan thread).
#[cfg(feature = "fuzzing")]
pub fn answer(shared: &Arc<Shared>, may_write: bool, frame: &[u8]) -> Option<Vec<u8>> {
    answer_queued(shared, may_write, frame).0
}

/// The answer to one frame and the ticket of the writes it queued.
fn answer_queued(shared: &Arc<Shared>, may_write: bool, frame: &[u8]) -> (Option<Vec<u8>>, Option<Ticket>) {
    let mut station = Station {
        shared: Arc::clone(shared),
        image: shared.image(),
        may_write,
        ticket: None,
        not_applied: false,
    };
    let reply = ladder_melsec::answer(frame, &mut station);
    (reply, station.ticket)
}

/// The answer to one frame, sent once its writes are applied (a read
/// after it sees them); the busy end code when they were not in time.
async fn answer_applied(shared: &Arc<Shared>, may_write: bool, frame: &[u8]) -> Option<Vec<u8>> {
    let (reply, ticket) = answer_queued(shared, may_write, frame);
    let Some(ticket) = ticket else {
        return reply;
    };
    match shared.applied(ticket).await {
        Ok(()) => return reply,
        Err(NotApplied::TimedOut | NotApplied::Stopping) => {}
    }
    let mut refusing = Station {
        shared: Arc::clone(shared),
        image: shared.image(),
        may_write,
        ticket: None,
        not_applied: true,
    };
    ladder_melsec::answer(frame, &mut refusing)
}

async fn serve_connection(
    mut stream: tokio::net::TcpStream,
    shared: Arc<Shared>,
    may_write: bool,
    open: &Open,
    idle: Duration,
) {
    let _ = stream.set_nodelay(true);
    let mut buffer: Vec<u8> = Vec::new();
    let mut chunk = vec![0u8; 4096];
    // When the frame now in `buffer` started arriving.
    let mut started = tokio::time::Instant::now();
    loop {
        match ladder_melsec::frame_length(&buffer) {
            Length::Frame(length) if length <= buffer.len() => {
                let frame: Vec<u8> = buffer.drain(..length).collect();
                // What arrived after the frame starts the next one now.
                started = tokio::time::Instant::now();
                open.touch();
                if let Some(reply) = answer_applied(&shared, may_write, &frame).await {
                    if tokio::time::timeout(FRAME_TIMEOUT, stream.write_all(&reply))
                        .await
                        .is_err()
                    {
                        return;
                    }
                }
                continue;
            }
            Length::Invalid => return,
            Length::Frame(_) | Length::Need(_) => {}
        }
        // Waiting for a request may take up to the idle time; a started one
        // must be whole within the frame time, however it trickles in.
        let deadline = if buffer.is_empty() {
            tokio::time::Instant::now() + idle
        } else {
            started + FRAME_TIMEOUT
        };
        tokio::select! {
            read = tokio::time::timeout_at(deadline, stream.read(&mut chunk)) => match read {
                Ok(Ok(n)) if n > 0 => {
                    if buffer.is_empty() {
                        started = tokio::time::Instant::now();
                    }
                    buffer.extend_from_slice(&chunk[..n]);
                }
                Ok(Ok(_) | Err(_)) | Err(_) => return,
            },
            () = open.close.notified() => return,
        }
    }
}

/// Serves one frame a datagram. Each datagram is answered on a task of its
/// own, so that a write waiting for the end of a scan holds up no other
/// peer; a peer's datagrams are answered in the order they came (a read
/// sent after a write sees it, as the CPU answers them), each waiting for
/// the one before. At most `most` datagrams are in hand at once (the bound
/// of MELSEC connections): beyond, none is read until one is answered.
async fn serve_datagrams(socket: Arc<tokio::net::UdpSocket>, most: usize, permission: Permission, shared: Arc<Shared>) {
    let places = Arc::new(tokio::sync::Semaphore::new(most.max(1)));
    // Each peer's latest datagram in hand: its next one waits for it.
    let mut latest: HashMap<SocketAddr, tokio::task::JoinHandle<()>> = HashMap::new();
    let mut datagram = vec![0u8; ladder_melsec::MAX_FRAME];
    loop {
        let Ok(place) = Arc::clone(&places).acquire_owned().await else {
            return;
        };
        let Ok((n, peer)) = socket.recv_from(&mut datagram).await else {
            continue;
        };
        let Some(frame) = datagram.get(..n).map(<[u8]>::to_vec) else {
            continue;
        };
        if ladder_melsec::frame_length(&frame) != Length::Frame(n) {
            continue;
        }
        let before = latest.remove(&peer);
        let (socket, shared) = (Arc::clone(&socket), Arc::clone(&shared));
        let may_write = permission.may_write(peer);
        let answering = tokio::spawn(async move {
            let _place = place;
            if let Some(before) = before {
                let _ = before.await;
            }
            if let Some(reply) = answer_applied(&shared, may_write, &frame).await {
                let _ = socket.send_to(&reply, peer).await;
            }
        });
        latest.insert(peer, answering);
        if latest.len() > most {
            // At most `most` are unanswered: the rest are done.
            latest.retain(|_, answering| !answering.is_finished());
        }
    }
}

/// Serves MELSEC frames on `listener` (TCP) and `datagrams` (UDP, one
/// frame a datagram) until the process ends.
pub async fn serve(
    listener: tokio::net::TcpListener,
    datagrams: Option<tokio::net::UdpSocket>,
    limits: ConnectionLimits,
    permission: Permission,
    shared: Arc<Shared>,
) {
    if let Some(socket) = datagrams {
        tokio::spawn(serve_datagrams(
            Arc::new(socket),
            limits.connections,
            permission.clone(),
            Arc::clone(&shared),
        ));
    }
    let idle = limits.idle;
    accept(listener, limits, move |stream, peer, open| {
        let shared = Arc::clone(&shared);
        let may_write = permission.may_write(peer);
        async move { serve_connection(stream, shared, may_write, &open, idle).await }
    })
    .await;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A binary 3E batch write of D100 = 1234, as the manuals lay it out.
    const WRITE_D100: [u8; 23] = [
        0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0E, 0x00, 0x10, 0x00, 0x01, 0x14, 0x00, 0x00, 0x64, 0x00, 0x00,
        0xA8, 0x01, 0x00, 0xD2, 0x04,
    ];

    fn end_code(reply: &[u8]) -> u16 {
        u16::from_le_bytes([reply[9], reply[10]])
    }

    #[test]
    fn a_write_is_answered_once_applied_and_busy_when_it_cannot_be() {
        let shared = Arc::new(Shared::default());
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let end_processing = {
            let shared = Arc::clone(&shared);
            std::thread::spawn(move || {
                while !shared.writes_waiting() {
                    std::thread::sleep(Duration::from_millis(1));
                }
                let writes = shared.take_writes();
                shared.acknowledge();
                writes
            })
        };
        let reply = runtime.block_on(answer_applied(&shared, true, &WRITE_D100));
        assert_eq!(reply.as_deref().map(end_code), Some(0));
        assert_eq!(end_processing.join().ok().map(|writes| writes.len()), Some(1));
        shared.stop();
        let reply = runtime.block_on(answer_applied(&shared, true, &WRITE_D100));
        assert_eq!(reply.as_deref().map(end_code), Some(0xCEE0), "not applied: busy");
    }
}
