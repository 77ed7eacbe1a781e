//! Modbus RTU frames (Modbus over Serial Line v1.02, 2.5): the server's
//! address (the unit), the PDU, and a CRC-16 sent low byte first. A frame
//! ends where the line has been silent for 3.5 characters (`Format::
//! silence`); a frame whose CRC does not match is not answered, nor is one
//! addressed to another unit; a broadcast (address 0) is carried out and
//! answered by nobody.

use std::time::Duration;

/// The longest RTU frame: address, 253-byte PDU, CRC.
pub const MAX_FRAME: usize = 256;
/// The address every server takes and none answers.
pub const BROADCAST: u8 = 0;

const CRC: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_MODBUS);

/// What the bytes between two silences are.
#[derive(Debug, PartialEq, Eq)]
pub enum Frame<'a> {
    Request {
        unit: u8,
        pdu: &'a [u8],
    },
    /// Fewer than an address, a function code and a CRC, or more than a
    /// frame can hold.
    Malformed,
    /// The CRC does not match (noise, or two frames run together).
    BadCrc,
}

/// Reads the bytes of one frame.
pub fn frame(bytes: &[u8]) -> Frame<'_> {
    if bytes.len() < 4 || bytes.len() > MAX_FRAME {
        return Frame::Malformed;
    }
    let (body, crc) = bytes.split_at(bytes.len() - 2);
    if CRC.checksum(body) != u16::from_le_bytes([crc[0], crc[1]]) {
        return Frame::BadCrc;
    }
    Frame::Request {
        unit: body[0],
        pdu: &body[1..],
    }
}

/// How long a request frame that starts with `bytes` is, as its function
/// says (address, PDU, CRC): `None` for a function whose length it cannot
/// tell, or when too little has come to tell.
pub fn request_len(bytes: &[u8]) -> Option<usize> {
    match *bytes.get(1)? {
        // Address and quantity (or value): 4 bytes of data.
        0x01..=0x06 => Some(8),
        // Address, quantity, byte count, then the bytes.
        0x0F | 0x10 => Some(9 + usize::from(*bytes.get(6)?)),
        _ => None,
    }
}

/// A response frame from `unit` carrying `pdu`.
pub fn encode(unit: u8, pdu: &[u8]) -> Vec<u8> {
    let mut frame = Vec::with_capacity(pdu.len() + 3);
    frame.push(unit);
    frame.extend_from_slice(pdu);
    frame.extend_from_slice(&CRC.checksum(&frame).to_le_bytes());
    frame
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parity {
    None,
    Even,
    Odd,
}

/// A serial line's settings: `19200,8E1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Format {
    pub baud: u32,
    pub data_bits: u8,
    pub parity: Parity,
    pub stop_bits: u8,
}

impl Default for Format {
    /// The specification's default: 19200 baud, even parity.
    fn default() -> Self {
        Format {
            baud: 19200,
            data_bits: 8,
            parity: Parity::Even,
            stop_bits: 1,
        }
    }
}

impl Format {
    /// `BAUD` or `BAUD,8E1` (data bits 7 or 8; parity N, E or O; stop bits
    /// 1 or 2).
    pub fn parse(text: &str) -> Result<Format, String> {
        let (baud, rest) = text.split_once(',').unwrap_or((text, "8E1"));
        let baud: u32 = baud
            .parse()
            .ok()
            .filter(|baud| (300..=4_000_000).contains(baud))
            .ok_or_else(|| format!("`{baud}` is not a baud rate (300 to 4000000)"))?;
        let wrong = || format!("`{rest}` is not a character format like 8E1, 8N2 or 7O1");
        let &[data, parity, stop] = rest.as_bytes() else {
            return Err(wrong());
        };
        let parity = match parity.to_ascii_uppercase() {
            b'N' => Parity::None,
            b'E' => Parity::Even,
            b'O' => Parity::Odd,
            _ => return Err(wrong()),
        };
        match (data, stop) {
            (b'7' | b'8', b'1' | b'2') => Ok(Format {
                baud,
                data_bits: data - b'0',
                parity,
                stop_bits: stop - b'0',
            }),
            _ => Err(wrong()),
        }
    }

    /// Bits on the line for one character: start, data, parity, stop.
    pub fn bits_per_character(&self) -> u32 {
        let parity = match self.parity {
            Parity::None => 0,
            Parity::Even | Parity::Odd => 1,
        };
        1 + u32::from(self.data_bits) + parity + u32::from(self.stop_bits)
    }

    /// The silence that ends a frame: 3.5 characters, and 1.75 ms above
    /// 19200 baud (as the specification fixes it there).
    pub fn silence(&self) -> Duration {
        if self.baud > 19200 {
            return Duration::from_micros(1750);
        }
        Duration::from_micros(u64::from(self.bits_per_character()) * 3_500_000 / u64::from(self.baud))
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parity = match self.parity {
            Parity::None => 'N',
            Parity::Even => 'E',
            Parity::Odd => 'O',
        };
        write!(f, "{} {}{parity}{}", self.baud, self.data_bits, self.stop_bits)
    }
}

/// `TTY[:BAUD[,FORMAT]]`: the device and its format (19200 8E1 unless
/// given). A device that exists under the whole text is that device (the
/// names under /dev/serial/by-path hold colons).
pub fn parse_port(text: &str) -> Result<(String, Format), String> {
    if std::path::Path::new(text).exists() {
        return Ok((text.to_string(), Format::default()));
    }
    match text.rsplit_once(':') {
        Some((path, format)) if format.starts_with(|c: char| c.is_ascii_digit()) => {
            Ok((path.to_string(), Format::parse(format)?))
        }
        Some(_) | None => Ok((text.to_string(), Format::default())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_carry_a_crc_low_byte_first() {
        // Read holding register 0, one register, from unit 1.
        let request = [0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A];
        assert_eq!(
            frame(&request),
            Frame::Request {
                unit: 1,
                pdu: &[0x03, 0x00, 0x00, 0x00, 0x01]
            }
        );
        assert_eq!(encode(1, &[0x03, 0x00, 0x00, 0x00, 0x01]), request);
        let mut noisy = request;
        noisy[3] ^= 0x10;
        assert_eq!(frame(&noisy), Frame::BadCrc);
        assert_eq!(frame(&request[..3]), Frame::Malformed);
        assert_eq!(request_len(&request[..2]), Some(8));
        assert_eq!(request_len(&[1, 0x10, 0, 0, 0, 2, 4]), Some(13));
        assert_eq!(request_len(&[1, 0x10, 0, 0]), None);
        assert_eq!(request_len(&[1, 0x2B]), None);
        assert_eq!(frame(&[0u8; MAX_FRAME + 1]), Frame::Malformed);
    }

    #[test]
    fn formats_and_ports_are_read_as_written() {
        assert_eq!(Format::parse("9600,8N2").unwrap().to_string(), "9600 8N2");
        assert_eq!(Format::parse("19200").unwrap(), Format::default());
        assert_eq!(Format::parse("19200,7o1").unwrap().parity, Parity::Odd);
        for wrong in ["fast", "9600,8X1", "9600,9N1", "9600,8N3", "9600,8N", "100"] {
            assert!(Format::parse(wrong).is_err(), "{wrong}");
        }
        assert_eq!(
            parse_port("/dev/ttyUSB0:9600,8N1").unwrap(),
            ("/dev/ttyUSB0".to_string(), Format::parse("9600,8N1").unwrap())
        );
        assert_eq!(
            parse_port("/dev/ttyS1").unwrap(),
            ("/dev/ttyS1".to_string(), Format::default())
        );
        // 11 bits a character at 9600 baud: 3.5 characters are 4.01 ms.
        assert_eq!(Format::parse("9600").unwrap().silence(), Duration::from_micros(4010));
        assert_eq!(Format::parse("115200").unwrap().silence(), Duration::from_micros(1750));
    }
}
