//! Modbus PDUs as a server answers them: the requests of the functions
//! served (01-06, 15, 16) decoded with the exceptions the specification
//! names, and responses encoded; the MBAP header of Modbus TCP. Written
//! here rather than taken from tokio-modbus's server because its decoder
//! drops the whole connection (or serial line) on requests the Modbus
//! specification says to answer with an exception (a coil value other than
//! FF00/0000, a byte count that does not match the quantity) and waits
//! forever on a header whose length cannot be right. Requests and responses
//! are tokio-modbus's types, so a service over them is the same whatever
//! carries it.
//!
//! What a request gets (Modbus Application Protocol v1.1b3, 6.x and 7):
//! - an unknown function code: exception 01;
//! - a known function with a PDU of the wrong length, a quantity out of the
//!   function's range, a byte count that does not match it, or a coil value
//!   other than FF00/0000: exception 03;
//! - an MBAP header with a protocol identifier other than 0 or a length
//!   outside 2-254: `Header::Invalid` (a TCP stream cannot find the next
//!   frame after a length it cannot trust).

use std::borrow::Cow;
use tokio_modbus::prelude::{ExceptionCode, Request, Response};

/// Transaction id, protocol id, length, unit id.
pub const HEADER_LEN: usize = 7;
/// The longest PDU (function code and data) a frame may carry.
pub const MAX_PDU_LEN: usize = 253;

/// What to do with the bytes of a frame.
#[derive(Debug, PartialEq, Eq)]
pub enum Header {
    /// The PDU that follows is this long.
    Frame { pdu_len: usize },
    /// A header that cannot be right: close the connection.
    Invalid,
}

/// Reads an MBAP header.
pub fn header(bytes: &[u8; HEADER_LEN]) -> Header {
    let protocol = u16::from_be_bytes([bytes[2], bytes[3]]);
    let length = usize::from(u16::from_be_bytes([bytes[4], bytes[5]]));
    // The length counts the unit id and the PDU (at least a function code).
    if protocol != 0 || !(2..=MAX_PDU_LEN + 1).contains(&length) {
        return Header::Invalid;
    }
    Header::Frame { pdu_len: length - 1 }
}

/// A request PDU as the map's service takes it, or the exception it gets.
pub fn decode(pdu: &[u8]) -> Result<Request<'static>, ExceptionCode> {
    use ExceptionCode::{IllegalDataValue, IllegalFunction};
    let Some((&function, data)) = pdu.split_first() else {
        return Err(IllegalFunction);
    };
    let word = |at: usize| u16::from_be_bytes([data[at], data[at + 1]]);
    // The fixed-length requests: an address and a quantity or a value.
    let fixed = || -> Result<(u16, u16), ExceptionCode> {
        if data.len() == 4 {
            Ok((word(0), word(2)))
        } else {
            Err(IllegalDataValue)
        }
    };
    let quantity = |count: u16, most: u16| -> Result<u16, ExceptionCode> {
        if (1..=most).contains(&count) {
            Ok(count)
        } else {
            Err(IllegalDataValue)
        }
    };
    // The multiple writes: address, quantity, byte count, then the bytes.
    let multiple = |most: u16, bytes_for: fn(usize) -> usize| -> Result<(u16, u16, &[u8]), ExceptionCode> {
        if data.len() < 5 {
            return Err(IllegalDataValue);
        }
        let count = quantity(word(2), most)?;
        let byte_count = usize::from(data[4]);
        if byte_count != bytes_for(usize::from(count)) || data.len() != 5 + byte_count {
            return Err(IllegalDataValue);
        }
        Ok((word(0), count, &data[5..]))
    };
    match function {
        0x01 => fixed().and_then(|(address, count)| Ok(Request::ReadCoils(address, quantity(count, 2000)?))),
        0x02 => fixed().and_then(|(address, count)| Ok(Request::ReadDiscreteInputs(address, quantity(count, 2000)?))),
        0x03 => fixed().and_then(|(address, count)| Ok(Request::ReadHoldingRegisters(address, quantity(count, 125)?))),
        0x04 => fixed().and_then(|(address, count)| Ok(Request::ReadInputRegisters(address, quantity(count, 125)?))),
        0x05 => fixed().and_then(|(address, value)| match value {
            0xFF00 => Ok(Request::WriteSingleCoil(address, true)),
            0x0000 => Ok(Request::WriteSingleCoil(address, false)),
            _ => Err(IllegalDataValue),
        }),
        0x06 => fixed().map(|(address, value)| Request::WriteSingleRegister(address, value)),
        0x0F => multiple(1968, |count| count.div_ceil(8)).map(|(address, count, bytes)| {
            let coils = (0..usize::from(count))
                .map(|i| bytes[i / 8] & (1 << (i % 8)) != 0)
                .collect();
            Request::WriteMultipleCoils(address, Cow::Owned(coils))
        }),
        0x10 => multiple(123, |count| 2 * count).map(|(address, _, bytes)| {
            let words = bytes
                .chunks_exact(2)
                .map(|w| u16::from_be_bytes([w[0], w[1]]))
                .collect();
            Request::WriteMultipleRegisters(address, Cow::Owned(words))
        }),
        _ => Err(IllegalFunction),
    }
}

/// The response PDU for `function`.
pub fn encode(function: u8, response: Result<Response, ExceptionCode>) -> Vec<u8> {
    let exception = |code: ExceptionCode| vec![function | 0x80, u8::from(code)];
    let response = match response {
        Ok(response) => response,
        Err(code) => return exception(code),
    };
    let bits = |values: &[bool]| {
        let mut out = vec![function, values.len().div_ceil(8) as u8];
        out.extend(values.chunks(8).map(|chunk| {
            chunk
                .iter()
                .enumerate()
                .fold(0u8, |byte, (i, &on)| byte | (u8::from(on) << i))
        }));
        out
    };
    let words = |values: &[u16]| {
        let mut out = vec![function, (values.len() * 2) as u8];
        out.extend(values.iter().flat_map(|w| w.to_be_bytes()));
        out
    };
    let pair = |a: u16, b: u16| {
        let mut out = vec![function];
        out.extend(a.to_be_bytes());
        out.extend(b.to_be_bytes());
        out
    };
    match response {
        Response::ReadCoils(values) | Response::ReadDiscreteInputs(values) => bits(&values),
        Response::ReadHoldingRegisters(values) | Response::ReadInputRegisters(values) => words(&values),
        Response::WriteSingleCoil(address, on) => pair(address, if on { 0xFF00 } else { 0 }),
        Response::WriteSingleRegister(address, value) => pair(address, value),
        Response::WriteMultipleCoils(address, count) | Response::WriteMultipleRegisters(address, count) => {
            pair(address, count)
        }
        // The service answers only the functions `decode` makes.
        Response::ReportServerId(..)
        | Response::MaskWriteRegister(..)
        | Response::ReadWriteMultipleRegisters(_)
        | Response::ReadDeviceIdentification(_)
        | Response::Custom(..) => exception(ExceptionCode::ServerDeviceFailure),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_with_an_impossible_length_or_protocol_are_refused() {
        let frame = |protocol: u16, length: u16| {
            let [p0, p1] = protocol.to_be_bytes();
            let [l0, l1] = length.to_be_bytes();
            [0, 1, p0, p1, l0, l1, 1]
        };
        assert_eq!(header(&frame(0, 6)), Header::Frame { pdu_len: 5 });
        for (protocol, length) in [(0, 0), (0, 1), (0, 255), (0, 0xFFFF), (1, 6)] {
            assert_eq!(header(&frame(protocol, length)), Header::Invalid, "{protocol} {length}");
        }
    }

    #[test]
    fn malformed_requests_get_the_exceptions_the_specification_names() {
        use ExceptionCode::*;
        let cases: [(&[u8], ExceptionCode); 9] = [
            (&[0x05, 0, 0, 0x12, 0x34], IllegalDataValue),
            (&[0x05, 0, 0, 0xFF], IllegalDataValue),
            (&[0x01, 0, 0, 0x07, 0xD1], IllegalDataValue),
            (&[0x03, 0, 0, 0, 0], IllegalDataValue),
            (&[0x10, 0, 0, 0, 2, 3, 0, 1, 0], IllegalDataValue),
            (&[0x10, 0, 0, 0, 2, 4, 0, 1, 0], IllegalDataValue),
            (&[0x0F, 0, 0, 0, 9, 1, 0xFF], IllegalDataValue),
            (&[0x2B, 0x0E, 1, 0], IllegalFunction),
            (&[], IllegalFunction),
        ];
        for (pdu, code) in cases {
            assert_eq!(decode(pdu), Err(code), "{pdu:02x?}");
        }
        assert_eq!(decode(&[0x05, 0, 7, 0xFF, 0]), Ok(Request::WriteSingleCoil(7, true)));
        assert_eq!(
            decode(&[0x0F, 0, 1, 0, 9, 2, 0b1000_0001, 1]),
            Ok(Request::WriteMultipleCoils(
                1,
                Cow::Owned(vec![true, false, false, false, false, false, false, true, true])
            ))
        );
        assert_eq!(
            decode(&[0x10, 0, 2, 0, 2, 4, 0x12, 0x34, 0xFF, 0xFF]),
            Ok(Request::WriteMultipleRegisters(2, Cow::Owned(vec![0x1234, 0xFFFF])))
        );
    }

    #[test]
    fn responses_are_encoded_as_the_specification_lays_them_out() {
        assert_eq!(
            encode(
                0x01,
                Ok(Response::ReadCoils(vec![
                    true, false, true, true, false, false, false, false, true
                ]))
            ),
            [0x01, 2, 0b0000_1101, 0b0000_0001]
        );
        assert_eq!(
            encode(0x03, Ok(Response::ReadHoldingRegisters(vec![0x1234, 1]))),
            [0x03, 4, 0x12, 0x34, 0, 1]
        );
        assert_eq!(
            encode(0x05, Ok(Response::WriteSingleCoil(9, true))),
            [0x05, 0, 9, 0xFF, 0]
        );
        assert_eq!(encode(0x10, Err(ExceptionCode::IllegalDataAddress)), [0x90, 2]);
    }
}
