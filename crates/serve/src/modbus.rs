//! The Modbus TCP side of `ladderc serve` (tokio-modbus): the documented
//! mapping of Modbus addresses to devices. Reads come from the image as the
//! latest scan left it; writes are queued, applied as host writes at the
//! end of the scan in progress, and answered once applied (`acks`). Bad
//! addresses and unsupported functions get exception responses; a write
//! the queue cannot take gets 06 (server device busy), one not applied in
//! time 04 (server device failure); nothing a client sends stops the scan
//! loop. The framing is
//! in `modbus_tcp`.

use super::acks::Ticket;
use super::shared::{HostWrite, Shared};
use std::sync::Arc;
use tokio_modbus::prelude::{ExceptionCode, Request, Response};

/// Discrete inputs 0-255: X0-X377 (the input image as the program saw it).
pub const INPUTS: (u16, u16) = (0, 256);
/// Coils 0-255: Y0-Y377.
pub const OUTPUTS: (u16, u16) = (0, 256);
/// Coils 1000-9511: M0-M8511.
pub const RELAYS: (u16, u16) = (1000, 8512);
/// Coils 20000-20255: the input image X0-X377, for plant simulators.
pub const INPUT_IMAGE: (u16, u16) = (20000, 256);
/// Holding registers 0-8511: D0-D8511.
pub const DATA: (u16, u16) = (0, 8512);
/// Input registers 0-511: timer current values T0-T511.
pub const TIMERS: (u16, u16) = (0, 512);
/// Input registers 1000-1199: counter current values C0-C199.
pub const COUNTERS: (u16, u16) = (1000, 200);

/// Where a run of `count` addresses from `address` lies in a block
/// `(first, len)`: its offset, if all of it is inside.
fn within(block: (u16, u16), address: u16, count: u16) -> Option<usize> {
    let (first, len) = block;
    let offset = address.checked_sub(first)?;
    (count >= 1 && u32::from(offset) + u32::from(count) <= u32::from(len)).then_some(usize::from(offset))
}

/// The service of one connection.
pub struct Service {
    pub shared: Arc<Shared>,
    /// Writes are allowed: not `--read-only`, and the peer is on loopback
    /// or in a `--modbus-write-from` network.
    pub may_write: bool,
}

impl Service {
    // The match on tokio-modbus's requests: every function this map does
    // not serve (and any it adds) is exception 01.
    #[allow(clippy::wildcard_enum_match_arm)]
    /// The response to a request, and for a write the ticket to wait for
    /// before sending it.
    pub fn respond(&self, request: Request<'_>) -> Result<(Response, Option<Ticket>), ExceptionCode> {
        use ExceptionCode::{IllegalDataAddress, IllegalFunction, ServerDeviceBusy};
        let writes = matches!(
            request,
            Request::WriteSingleCoil(..)
                | Request::WriteMultipleCoils(..)
                | Request::WriteSingleRegister(..)
                | Request::WriteMultipleRegisters(..)
        );
        // A refused write is refused whatever its address or value.
        if writes && !self.may_write {
            return Err(IllegalFunction);
        }
        let image = || self.shared.image();
        let bits = |values: &[u8], offset: usize, count: u16| -> Vec<bool> {
            values[offset..offset + usize::from(count)]
                .iter()
                .map(|&b| b != 0)
                .collect()
        };
        let words = |values: &[i16], offset: usize, count: u16| -> Vec<u16> {
            values[offset..offset + usize::from(count)]
                .iter()
                .map(|&w| w as u16)
                .collect()
        };
        // A full queue of writes (clients writing faster than the scan
        // thread applies them): exception 06, server device busy.
        // A device the remote I/O writes before every scan (`--io`): not
        // writable here (exception 02), rather than answered and lost.
        let write = |writes: Vec<HostWrite>| -> Result<Option<Ticket>, ExceptionCode> {
            if crate::remote_io::refused(&self.shared, &writes).is_some() {
                return Err(IllegalDataAddress);
            }
            self.shared.queue(writes).map(Some).ok_or(ServerDeviceBusy)
        };
        match request {
            Request::ReadDiscreteInputs(address, count) => {
                let offset = within(INPUTS, address, count).ok_or(IllegalDataAddress)?;
                Ok((Response::ReadDiscreteInputs(bits(&image().x, offset, count)), None))
            }
            Request::ReadCoils(address, count) => {
                let image = image();
                if let Some(offset) = within(OUTPUTS, address, count) {
                    Ok((Response::ReadCoils(bits(&image.y, offset, count)), None))
                } else if let Some(offset) = within(RELAYS, address, count) {
                    Ok((Response::ReadCoils(bits(&image.m, offset, count)), None))
                } else if let Some(offset) = within(INPUT_IMAGE, address, count) {
                    Ok((Response::ReadCoils(bits(&image.input_image, offset, count)), None))
                } else {
                    Err(IllegalDataAddress)
                }
            }
            Request::WriteSingleCoil(address, on) => {
                let ticket = write(vec![coil_write(address, 1).ok_or(IllegalDataAddress)?(0, on)])?;
                Ok((Response::WriteSingleCoil(address, on), ticket))
            }
            Request::WriteMultipleCoils(address, values) => {
                let count = u16::try_from(values.len()).map_err(|_| IllegalDataAddress)?;
                let make = coil_write(address, count).ok_or(IllegalDataAddress)?;
                let ticket = write(values.iter().enumerate().map(|(i, &on)| make(i, on)).collect())?;
                Ok((Response::WriteMultipleCoils(address, count), ticket))
            }
            Request::ReadHoldingRegisters(address, count) => {
                let offset = within(DATA, address, count).ok_or(IllegalDataAddress)?;
                Ok((Response::ReadHoldingRegisters(words(&image().d, offset, count)), None))
            }
            Request::ReadInputRegisters(address, count) => {
                let image = image();
                if let Some(offset) = within(TIMERS, address, count) {
                    Ok((
                        Response::ReadInputRegisters(words(&image.timer_value, offset, count)),
                        None,
                    ))
                } else if let Some(offset) = within(COUNTERS, address, count) {
                    Ok((
                        Response::ReadInputRegisters(words(&image.counter_value, offset, count)),
                        None,
                    ))
                } else {
                    Err(IllegalDataAddress)
                }
            }
            Request::WriteSingleRegister(address, value) => {
                let offset = within(DATA, address, 1).ok_or(IllegalDataAddress)?;
                let ticket = write(vec![HostWrite::Data(offset as u32, value as i16)])?;
                Ok((Response::WriteSingleRegister(address, value), ticket))
            }
            Request::WriteMultipleRegisters(address, values) => {
                let count = u16::try_from(values.len()).map_err(|_| IllegalDataAddress)?;
                let offset = within(DATA, address, count).ok_or(IllegalDataAddress)?;
                let ticket = write(
                    values
                        .iter()
                        .enumerate()
                        .map(|(i, &value)| HostWrite::Data((offset + i) as u32, value as i16))
                        .collect(),
                )?;
                Ok((Response::WriteMultipleRegisters(address, count), ticket))
            }
            _ => Err(IllegalFunction),
        }
    }
}

/// The write of coil `address + i` for a run of `count` coils in one block.
fn coil_write(address: u16, count: u16) -> Option<impl Fn(usize, bool) -> HostWrite> {
    let (kind, offset): (fn(u32, bool) -> HostWrite, usize) = if let Some(offset) = within(OUTPUTS, address, count) {
        (HostWrite::Output, offset)
    } else if let Some(offset) = within(RELAYS, address, count) {
        (HostWrite::Relay, offset)
    } else if let Some(offset) = within(INPUT_IMAGE, address, count) {
        (HostWrite::Input, offset)
    } else {
        return None;
    };
    Some(move |i: usize, on: bool| kind((offset + i) as u32, on))
}
