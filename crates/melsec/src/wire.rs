//! Reading and writing the fields of a frame in either data code: in
//! binary a field of n bytes is little-endian; in ASCII it is 2n
//! hexadecimal digits, most significant first (upper-case when written,
//! either case when read).

/// The data code of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Code {
    Binary,
    Ascii,
}

impl Code {
    /// Characters (bytes on the wire) of a field of `width` binary bytes.
    pub fn chars(self, width: usize) -> usize {
        match self {
            Code::Binary => width,
            Code::Ascii => 2 * width,
        }
    }
}

/// Why a frame could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// It ended before a field it must have (or its length says less).
    Short,
    /// An ASCII field holds a character that is not a digit of its radix.
    NotDigit,
}

pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    pub code: Code,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8], code: Code) -> Reader<'a> {
        Reader { bytes, at: 0, code }
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    pub fn raw(&mut self, count: usize) -> Result<&'a [u8], Fault> {
        let end = self.at.checked_add(count).ok_or(Fault::Short)?;
        let taken = self.bytes.get(self.at..end).ok_or(Fault::Short)?;
        self.at = end;
        Ok(taken)
    }

    /// An unsigned field of `width` binary bytes (at most 4).
    pub fn field(&mut self, width: usize) -> Result<u32, Fault> {
        match self.code {
            Code::Binary => Ok(self
                .raw(width)?
                .iter()
                .rev()
                .fold(0, |value, &byte| value << 8 | u32::from(byte))),
            Code::Ascii => self.digits(2 * width, 16),
        }
    }

    /// `count` ASCII characters as a number in `radix`.
    pub fn digits(&mut self, count: usize, radix: u32) -> Result<u32, Fault> {
        let text = self.raw(count)?;
        text.iter().try_fold(0u32, |value, &c| {
            let digit = char::from(c).to_digit(radix).ok_or(Fault::NotDigit)?;
            Ok(value.wrapping_mul(radix).wrapping_add(digit))
        })
    }

    /// `count` bit-unit points: in binary two a byte, the first in the high
    /// four bits; in ASCII one character (`0`/`1`) a point. With `padded`,
    /// an odd count is followed by a dummy point (as 1E frames send it).
    pub fn points(&mut self, count: usize, padded: bool) -> Result<Vec<bool>, Fault> {
        let point = |nibble: u32| match nibble {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(Fault::NotDigit),
        };
        match self.code {
            Code::Binary => {
                let bytes = self.raw(count.div_ceil(2))?;
                let mut points = Vec::with_capacity(count);
                for (n, byte) in bytes.iter().enumerate() {
                    points.push(point(u32::from(byte >> 4))?);
                    if 2 * n + 1 < count {
                        points.push(point(u32::from(byte & 0x0F))?);
                    }
                }
                Ok(points)
            }
            Code::Ascii => {
                let chars = if padded { count.div_ceil(2) * 2 } else { count };
                let text = self.raw(chars)?;
                let values: Result<Vec<bool>, Fault> = text
                    .iter()
                    .map(|&c| point(char::from(c).to_digit(16).ok_or(Fault::NotDigit)?))
                    .collect();
                let mut values = values?;
                values.truncate(count);
                Ok(values)
            }
        }
    }
}

#[derive(Default)]
pub struct Writer {
    pub bytes: Vec<u8>,
    ascii: bool,
}

impl Writer {
    pub fn new(code: Code) -> Writer {
        Writer {
            bytes: Vec::new(),
            ascii: code == Code::Ascii,
        }
    }

    pub fn raw(&mut self, bytes: &[u8]) {
        self.bytes.extend_from_slice(bytes);
    }

    /// The unsigned `value` as a field of `width` binary bytes.
    pub fn field(&mut self, value: u32, width: usize) {
        if self.ascii {
            for n in (0..width).rev() {
                let byte = value >> (8 * n) & 0xFF;
                self.bytes.extend_from_slice(format!("{byte:02X}").as_bytes());
            }
        } else {
            self.bytes.extend(value.to_le_bytes().iter().take(width));
        }
    }

    /// Bit-unit points, as `Reader::points` reads them.
    pub fn points(&mut self, points: &[bool], padded: bool) {
        if self.ascii {
            self.bytes.extend(points.iter().map(|&on| if on { b'1' } else { b'0' }));
            if padded && points.len() % 2 == 1 {
                self.bytes.push(b'0');
            }
        } else {
            for pair in points.chunks(2) {
                let high = u8::from(pair[0]) << 4;
                let low = pair.get(1).map_or(0, |&on| u8::from(on));
                self.bytes.push(high | low);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_little_endian_in_binary_and_hex_text_in_ascii() {
        let mut binary = Writer::new(Code::Binary);
        binary.field(0x1234, 2);
        binary.field(0x64, 4);
        assert_eq!(binary.bytes, [0x34, 0x12, 0x64, 0, 0, 0]);
        let mut ascii = Writer::new(Code::Ascii);
        ascii.field(0x1234, 2);
        ascii.field(0xAB, 1);
        assert_eq!(ascii.bytes, b"1234AB");
        let mut reader = Reader::new(b"00ffzz", Code::Ascii);
        assert_eq!(reader.field(2), Ok(0xFF));
        assert_eq!(reader.field(1), Err(Fault::NotDigit));
        let mut reader = Reader::new(&[0x34, 0x12, 0x01], Code::Binary);
        assert_eq!(reader.field(2), Ok(0x1234));
        assert_eq!(reader.field(2), Err(Fault::Short));
    }

    #[test]
    fn points_pack_two_a_byte_high_nibble_first() {
        let points = [true, false, true, true, false];
        let mut binary = Writer::new(Code::Binary);
        binary.points(&points, true);
        assert_eq!(binary.bytes, [0x10, 0x11, 0x00]);
        assert_eq!(
            Reader::new(&binary.bytes, Code::Binary).points(5, true),
            Ok(points.to_vec())
        );
        let mut ascii = Writer::new(Code::Ascii);
        ascii.points(&points, true);
        assert_eq!(ascii.bytes, b"101100");
        assert_eq!(Reader::new(b"101100", Code::Ascii).points(5, true), Ok(points.to_vec()));
        assert_eq!(Reader::new(b"10110", Code::Ascii).points(5, false), Ok(points.to_vec()));
        assert_eq!(Reader::new(&[0x12], Code::Binary).points(2, true), Err(Fault::NotDigit));
    }
}
