//! The Modbus RTU slave of `serve` (`--modbus-rtu TTY[:BAUD,FORMAT]`): the
//! Modbus TCP map on a serial line (an RS-485 adapter, as an FX3U-485-BD
//! is wired), through the `serialport` crate. A thread reads the line; a
//! frame ends where it has been silent for 3.5 characters. A frame with a
//! bad CRC, or addressed to another unit, is not answered (the next frame
//! is); a broadcast (unit 0) is carried out and answered by nobody.
//! Writes follow `--read-only` (whoever wired the line may write).

use crate::modbus::Service;
use crate::modbus_tcp::respond;
use ladder_modbus::rtu::{self, Format, Frame, Parity, BROADCAST};
use std::io::{Read, Write};
use std::time::Duration;

/// The serial line and who the server is on it.
#[derive(Clone, Debug)]
pub struct Line {
    pub path: String,
    pub format: Format,
    /// The address the server answers (1-247).
    pub unit: u8,
}

/// Opens the line as its format says; `Err` is a message for the user.
pub fn open(line: &Line) -> Result<Box<dyn serialport::SerialPort>, String> {
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
    serialport::new(&line.path, line.format.baud)
        .data_bits(data_bits)
        .parity(parity)
        .stop_bits(stop_bits)
        .flow_control(serialport::FlowControl::None)
        .timeout(line.format.silence())
        .open()
        .map_err(|e| format!("cannot open the serial line {}: {e}", line.path))
}

/// What the server does with one frame: the bytes to send back, if any.
pub fn answer(service: &Service, unit: u8, bytes: &[u8]) -> Option<Vec<u8>> {
    match rtu::frame(bytes) {
        Frame::Request { unit: to, pdu } if to == unit => Some(rtu::encode(unit, &respond(service, pdu))),
        Frame::Request { unit: BROADCAST, pdu } => {
            // Carried out (writes are what a broadcast may carry), not
            // answered.
            let _ = respond(service, pdu);
            None
        }
        Frame::Request { .. } | Frame::BadCrc | Frame::Malformed => None,
    }
}

/// Serves the line until the process ends (or the line goes away: said on
/// stderr, and the rest of the server goes on).
pub fn serve(mut port: Box<dyn serialport::SerialPort>, line: &Line, service: &Service) {
    let mut frame: Vec<u8> = Vec::with_capacity(rtu::MAX_FRAME);
    let mut chunk = [0u8; rtu::MAX_FRAME];
    loop {
        match port.read(&mut chunk) {
            Ok(0) => std::thread::sleep(line.format.silence()),
            Ok(n) => {
                // A frame longer than any frame is noise: it is dropped once
                // the line falls silent.
                if frame.len() + n <= rtu::MAX_FRAME + 1 {
                    frame.extend_from_slice(&chunk[..n]);
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {
                if frame.is_empty() {
                    continue;
                }
                if let Some(reply) = answer(service, line.unit, &frame) {
                    let _ = port.write_all(&reply);
                    let _ = port.flush();
                }
                frame.clear();
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => {
                use std::io::Write as _;
                let _ = writeln!(
                    std::io::stderr(),
                    "modbus-rtu: {}: {e}; the serial line is no longer served",
                    line.path
                );
                // Do not spin on a line that is gone.
                std::thread::sleep(Duration::from_millis(100));
                return;
            }
        }
    }
}
