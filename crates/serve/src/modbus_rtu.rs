//! The Modbus RTU slave of `serve` (`--modbus-rtu TTY[:BAUD,FORMAT]`): the
//! Modbus TCP map on a serial line (an RS-485 adapter, as an FX3U-485-BD
//! is wired), through the `serialport` crate. A thread reads the line; a
//! frame ends where it has been silent for 3.5 characters, unless what has
//! come so far is shorter than its function says a request is (a USB
//! adapter may deliver one frame in two packets with a pause between):
//! then the rest may follow within `LATE_REST`. A frame with a bad CRC, or
//! addressed to another unit, is not answered (the next frame is); a
//! broadcast (unit 0) is carried out and answered by nobody; the server's
//! own answer read back (an adapter that echoes what it sends) is ignored.
//! Writes follow `--read-only` (whoever wired the line may write).

use crate::modbus::Service;
use crate::modbus_tcp::respond;
use ladder_modbus::rtu::{self, Format, Frame, Parity, BROADCAST};
use std::io::{Read, Write};
use std::time::{Duration, Instant};

/// How long the rest of a frame cut short by a pause may take to come.
const LATE_REST: Duration = Duration::from_millis(50);

/// The serial line and who the server is on it.
#[derive(Clone, Debug)]
pub struct Line {
    pub path: String,
    pub format: Format,
    /// The address the server answers (1-247).
    pub unit: u8,
}

/// An open line, ready to serve.
pub struct Serial {
    port: Box<dyn serialport::SerialPort>,
    line: Line,
}

/// Opens the line as its format says and announces it; `Err` is a message
/// for the user.
pub fn open(line: &Line) -> Result<Serial, String> {
    let data_bits = match line.format.data_bits {
        7 => serialport::DataBits::Seven,
        _ => serialport::DataBits::Eight,
    };
    let parity = match line.format.parity {
        Parity::None => serialport::Parity::None,
        Parity::Even => serialport::Parity::Even,
        Parity::Odd => serialport::Parity::Odd,
    };
    let stop_bits = match line.format.stop_bits {
        2 => serialport::StopBits::Two,
        _ => serialport::StopBits::One,
    };
    let port = serialport::new(&line.path, line.format.baud)
        .data_bits(data_bits)
        .parity(parity)
        .stop_bits(stop_bits)
        .flow_control(serialport::FlowControl::None)
        .timeout(line.format.silence())
        .open()
        .map_err(|e| format!("cannot open the serial line {}: {e}", line.path))?;
    crate::announce(&format!(
        "modbus-rtu on {} ({}, unit {})",
        line.path, line.format, line.unit
    ));
    Ok(Serial {
        port,
        line: line.clone(),
    })
}

/// What the server does with one frame: the bytes to send back, if any,
/// once a write it carries is applied (`settle` waits on this thread; the
/// fuzzing harness, without a scan thread, does not).
pub fn answer(service: &Service, unit: u8, bytes: &[u8], settle: bool) -> Option<Vec<u8>> {
    match rtu::frame(bytes) {
        Frame::Request { unit: to, pdu } if to == unit => {
            let reply = respond(service, pdu);
            let pdu = if settle {
                reply.settle(&service.shared)
            } else {
                reply.pdu
            };
            Some(rtu::encode(unit, &pdu))
        }
        Frame::Request { unit: BROADCAST, pdu } => {
            // Carried out (writes are what a broadcast may carry), not
            // answered.
            let _ = respond(service, pdu);
            None
        }
        Frame::Request { .. } | Frame::BadCrc | Frame::Malformed => None,
    }
}

impl Serial {
    /// Serves the line until the process ends (or the line goes away: said
    /// on stderr, and the rest of the server goes on).
    pub fn serve(mut self, service: &Service) {
        let mut frame: Vec<u8> = Vec::with_capacity(rtu::MAX_FRAME);
        let mut chunk = [0u8; rtu::MAX_FRAME];
        let mut last_reply: Vec<u8> = Vec::new();
        let mut last_byte = Instant::now();
        loop {
            match self.port.read(&mut chunk) {
                Ok(0) => std::thread::sleep(self.line.format.silence()),
                Ok(n) => {
                    last_byte = Instant::now();
                    // More than a frame can hold is noise: kept no longer
                    // than one frame's worth, it fails its CRC and goes
                    // unanswered once the line falls silent.
                    let room = (rtu::MAX_FRAME + 1).saturating_sub(frame.len());
                    frame.extend_from_slice(&chunk[..n.min(room)]);
                }
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {
                    if frame.is_empty() {
                        continue;
                    }
                    let short = rtu::request_len(&frame).is_some_and(|whole| frame.len() < whole);
                    if short && last_byte.elapsed() < LATE_REST {
                        continue;
                    }
                    if frame == last_reply {
                        // Our own answer, echoed by the adapter.
                        last_reply.clear();
                    } else if let Some(reply) = answer(service, self.line.unit, &frame, true) {
                        let _ = self.port.write_all(&reply);
                        let _ = self.port.flush();
                        last_reply = reply;
                    }
                    frame.clear();
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    use std::io::Write as _;
                    let _ = writeln!(
                        std::io::stderr(),
                        "modbus-rtu: {}: {e}; the serial line is no longer served",
                        self.line.path
                    );
                    return;
                }
            }
        }
    }
}
