//! The framing GX Developer's binary files share, and the operand records
//! of a program: a 64-byte file header (its length, a 32-byte title, the
//! CPU type and series), and in a program a run of records, each its length
//! byte, its payload and its length byte again. An operand is one record per
//! device, with the records that modify it (digit count, bit, unit, index
//! register) before it.

use super::DecodeError;
use crate::syntax::{Constant, DeviceSyntax, OffsetKind, OffsetSyntax, OperandSyntax, Prefix};

/// Every file starts with a header of this many bytes; its first two bytes
/// say so (little-endian).
pub const HEADER_LEN: usize = 64;
/// Where the header holds the CPU type code and the series (2: FX).
pub const CPU_TYPE_AT: usize = 0x26;
pub const CPU_SERIES_AT: usize = 0x27;
/// The FX series code.
pub const FX_SERIES: u8 = 2;

/// Checks a file's header: its length field and the FX series. Returns the
/// CPU type code.
pub fn check_header(bytes: &[u8]) -> Result<u8, DecodeError> {
    if bytes.len() < HEADER_LEN {
        return Err(DecodeError::new(
            bytes.len(),
            format!("a {HEADER_LEN}-byte header (the file has {} bytes)", bytes.len()),
        ));
    }
    if bytes[..4] != [HEADER_LEN as u8, 0x00, 0x22, 0x01] {
        return Err(DecodeError::new(0, "the header mark 40 00 22 01"));
    }
    if bytes[CPU_SERIES_AT] != FX_SERIES {
        return Err(DecodeError::new(
            CPU_SERIES_AT,
            format!(
                "the FX series code 02 (found {:02X}: a project of another MELSEC family)",
                bytes[CPU_SERIES_AT]
            ),
        ));
    }
    Ok(bytes[CPU_TYPE_AT])
}

/// A header for a file of a project for CPU type `cpu`, with the bytes GX
/// Developer writes after the CPU (`tail`, up to offset 0x40).
pub fn header(cpu: u8, tail: &[u8]) -> Vec<u8> {
    let mut bytes = vec![HEADER_LEN as u8, 0x00, 0x22, 0x01];
    bytes.resize(0x24, b' ');
    bytes.extend_from_slice(&[0x04, 0x02, cpu, FX_SERIES]);
    bytes.extend_from_slice(tail);
    bytes.resize(HEADER_LEN, 0xFF);
    bytes
}

/// One record of a program: where it starts and its payload.
#[derive(Clone, Copy, Debug)]
pub struct Record<'a> {
    pub at: usize,
    pub payload: &'a [u8],
}

/// Splits `bytes` (from `base` in the file) into records.
pub fn split(bytes: &[u8], base: usize) -> Result<Vec<Record<'_>>, DecodeError> {
    records(bytes, base).collect()
}

/// The records of `bytes` (from `base` in the file), one at a time: a
/// reader can stop at a limit before the rest is looked at.
pub fn records(bytes: &[u8], base: usize) -> Records<'_> {
    Records { bytes, base, at: 0 }
}

/// The iterator `records` returns; it ends after the first error.
pub struct Records<'a> {
    bytes: &'a [u8],
    base: usize,
    at: usize,
}

impl<'a> Iterator for Records<'a> {
    type Item = Result<Record<'a>, DecodeError>;

    fn next(&mut self) -> Option<Self::Item> {
        let (bytes, base, at) = (self.bytes, self.base, self.at);
        let length = usize::from(*bytes.get(at)?);
        // After an error there is nothing more to read.
        self.at = bytes.len();
        if length < 2 {
            return Some(Err(DecodeError::new(
                base + at,
                format!("a record length of at least 2 (found {length})"),
            )));
        }
        let Some(&closing) = bytes.get(at + length - 1) else {
            return Some(Err(DecodeError::new(
                base + at,
                format!("a record of {length} bytes (the file ends after {})", bytes.len() - at),
            )));
        };
        if usize::from(closing) != length {
            return Some(Err(DecodeError::new(
                base + at + length - 1,
                format!("the record's closing length byte {length:02X} (found {closing:02X})"),
            )));
        }
        self.at = at + length;
        Some(Ok(Record {
            at: base + at,
            payload: &bytes[at + 1..at + length - 1],
        }))
    }
}

/// Appends a record with `payload`.
pub fn push(out: &mut Vec<u8>, payload: &[u8]) {
    let length = payload.len() as u8 + 2;
    out.push(length);
    out.extend_from_slice(payload);
    out.push(length);
}

/// Device codes of operand records (the MC protocol's codes where it has
/// one).
pub mod code {
    pub const M: u8 = 0x90;
    pub const S: u8 = 0x98;
    pub const X: u8 = 0x9C;
    pub const Y: u8 = 0x9D;
    pub const D: u8 = 0xA8;
    pub const G: u8 = 0xAB;
    pub const R: u8 = 0xAF;
    pub const T: u8 = 0xC2;
    pub const C: u8 = 0xC5;
    pub const Z: u8 = 0xCC;
    pub const V: u8 = 0xCD;
    pub const P: u8 = 0xD0;
    pub const I: u8 = 0xD1;
    pub const N: u8 = 0xD2;
    pub const K: u8 = 0xE8;
    pub const K32: u8 = 0xE9;
    pub const H: u8 = 0xEA;
    pub const H32: u8 = 0xEB;
    pub const E: u8 = 0xEC;
    /// Modifiers: they come before the device they modify.
    pub const INDEX_Z: u8 = 0xF0;
    pub const DIGITS: u8 = 0xF1;
    pub const BIT: u8 = 0xF2;
    pub const INDEX_V: u8 = 0xF4;
    pub const UNIT: u8 = 0xF8;
    /// The first code that is an operand record (instructions, statements
    /// and labels are below).
    pub const FIRST_OPERAND: u8 = 0x90;
}

/// The little-endian number of a record's value bytes.
fn value(bytes: &[u8]) -> u32 {
    bytes.iter().rev().fold(0, |acc, &b| (acc << 8) | u32::from(b))
}

/// The fewest little-endian bytes that hold `number` (at least one).
fn value_bytes(number: u32) -> Vec<u8> {
    let bytes = number.to_le_bytes();
    let used = 4 - (number.leading_zeros() as usize / 8).min(3);
    bytes[..used].to_vec()
}

/// An operand as it is written in IL.
pub fn operand_text(records: &[Record], wide: bool) -> Result<String, DecodeError> {
    let mut digits = None;
    let mut bit = None;
    let mut unit = None;
    let mut index = None;
    for record in records {
        let [code, bytes @ ..] = record.payload else {
            return Err(DecodeError::new(record.at, "an operand"));
        };
        if bytes.is_empty() || bytes.len() > 4 {
            return Err(DecodeError::new(record.at, "an operand value of 1 to 4 bytes"));
        }
        let number = value(bytes);
        let plain = |letter: &str| format!("{letter}{number}");
        let text = match *code {
            code::DIGITS => {
                digits = Some(number);
                continue;
            }
            code::BIT => {
                bit = Some(number);
                continue;
            }
            code::UNIT => {
                unit = Some(number);
                continue;
            }
            code::INDEX_Z => {
                index = Some(format!("Z{number}"));
                continue;
            }
            code::INDEX_V => {
                index = Some(format!("V{number}"));
                continue;
            }
            code::X => format!("X{number:03o}"),
            code::Y => format!("Y{number:03o}"),
            code::M => plain("M"),
            code::S => plain("S"),
            code::T => plain("T"),
            code::C => plain("C"),
            code::D => plain("D"),
            code::R => plain("R"),
            code::Z => plain("Z"),
            code::V => plain("V"),
            code::P => plain("P"),
            code::N => plain("N"),
            code::G => match unit.take() {
                Some(unit) => format!("U{unit}\\G{number}"),
                None => return Err(DecodeError::new(record.at, "a unit number before a buffer word")),
            },
            code::K | code::K32 => format!("K{}", constant(number, bytes.len(), *code == code::K32 || wide)),
            code::H | code::H32 => format!("H{number:X}"),
            code::E if bytes.len() == 4 => format!("E{}", f32::from_bits(number)),
            other => {
                return Err(DecodeError::new(
                    record.at,
                    format!("a device or constant code (found {other:02X}, which ladderc does not know)"),
                ))
            }
        };
        let mut text = match digits.take() {
            Some(n) => format!("K{n}{text}"),
            None => text,
        };
        if let Some(bit) = bit.take() {
            text.push_str(&format!(".{bit:X}"));
        }
        if let Some(index) = index.take() {
            text.push_str(&index);
        }
        return Ok(text);
    }
    let at = records.last().map_or(0, |r| r.at);
    Err(DecodeError::new(at, "a device after its modifiers"))
}

/// A K constant's value: as many bytes as it needs when it is not negative;
/// a negative one fills its word (two bytes) or its double word (four).
fn constant(number: u32, bytes: usize, wide: bool) -> i64 {
    match (bytes, wide) {
        (2, false) => i64::from(number as u16 as i16),
        (4, _) => i64::from(number as i32),
        _ => i64::from(number),
    }
}

/// Why an operand cannot be written to a program file.
pub type EncodeError = String;

/// The operand records of `operand` (`wide`: of a 32-bit instruction;
/// `wide_value`: a 32-bit value, as a 32-bit counter's preset is).
pub fn encode_operand(
    out: &mut Vec<u8>,
    operand: &OperandSyntax,
    wide: bool,
    wide_value: bool,
) -> Result<(), EncodeError> {
    let record = |out: &mut Vec<u8>, code: u8, number: u32| {
        let mut payload = vec![code];
        payload.extend(value_bytes(number));
        push(out, &payload);
    };
    match *operand {
        OperandSyntax::Constant(Constant { value, hex }) => {
            let code = match (hex, wide) {
                (false, false) => code::K,
                (false, true) => code::K32,
                (true, false) => code::H,
                (true, true) => code::H32,
            };
            // A negative value fills its word, or its double word when it
            // is 32-bit or does not fit a word.
            let bits = value as u32;
            let mut payload = vec![code];
            if value < 0 && (wide || wide_value || value < i64::from(i16::MIN)) {
                payload.extend(bits.to_le_bytes());
            } else if value < 0 {
                payload.extend(&bits.to_le_bytes()[..2]);
            } else {
                payload.extend(value_bytes(bits));
            }
            push(out, &payload);
        }
        OperandSyntax::Real(real) => {
            let mut payload = vec![code::E];
            payload.extend(real.value.to_bits().to_le_bytes());
            push(out, &payload);
        }
        OperandSyntax::Device(DeviceSyntax {
            prefix,
            number,
            digits,
            bit,
            offset,
        }) => {
            if let Some(n) = digits {
                record(out, code::DIGITS, u32::from(n));
            }
            if let Some(b) = bit {
                record(out, code::BIT, u32::from(b));
            }
            let (device_code, number) = match prefix {
                Prefix::X => (code::X, number),
                Prefix::Y => (code::Y, number),
                Prefix::M => (code::M, number),
                Prefix::S => (code::S, number),
                Prefix::T | Prefix::Ts | Prefix::Tn => (code::T, number),
                Prefix::C | Prefix::Cs | Prefix::Cn => (code::C, number),
                Prefix::D => (code::D, number),
                Prefix::R => (code::R, number),
                Prefix::P => (code::P, number),
                Prefix::N => (code::N, number),
                Prefix::V => (code::V, number),
                Prefix::Z => (code::Z, number),
                Prefix::U => {
                    use ladder_runtime::device::BUFFER_WORDS_PER_UNIT;
                    record(out, code::UNIT, number / BUFFER_WORDS_PER_UNIT);
                    (code::G, number % BUFFER_WORDS_PER_UNIT)
                }
                Prefix::Sm | Prefix::Sd => {
                    return Err(format!(
                        "{} devices are not FX devices (write M8000 or D8000 numbers)",
                        prefix.as_str()
                    ))
                }
            };
            match offset {
                None => {}
                Some(OffsetSyntax {
                    kind: OffsetKind::Z,
                    register,
                    ..
                }) => record(out, code::INDEX_Z, register),
                Some(OffsetSyntax {
                    kind: OffsetKind::V,
                    register,
                    ..
                }) => record(out, code::INDEX_V, register),
                Some(OffsetSyntax {
                    kind: OffsetKind::D, ..
                }) => return Err("an index by a data register (`[Dn]`) has no form in a GX Developer program".into()),
            }
            record(out, device_code, number);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_frame_and_unframe() {
        let mut bytes = Vec::new();
        push(&mut bytes, &[0x00]);
        push(&mut bytes, &[code::X, 0x09]);
        push(&mut bytes, &[]);
        assert_eq!(bytes, [3, 0, 3, 4, 0x9C, 9, 4, 2, 2]);
        let records = split(&bytes, 0x44).unwrap();
        assert_eq!(records.len(), 3);
        assert_eq!(records[1].at, 0x47);
        assert_eq!(operand_text(&records[1..2], false).unwrap(), "X011");
    }

    #[test]
    fn broken_records_name_their_offset() {
        let error = split(&[4, 0x9C, 9, 5], 0x40).unwrap_err();
        assert_eq!(error.offset, 0x43);
        let error = split(&[6, 0x9C], 0x40).unwrap_err();
        assert_eq!(error.offset, 0x40);
        let error = split(&[0], 0x40).unwrap_err();
        assert!(error.expected.contains("at least 2"));
    }

    #[test]
    fn constants_take_the_bytes_they_need() {
        let encode = |text: &str, wide: bool| {
            let operand = crate::syntax::operand::parse_operand(text, 0).unwrap();
            let mut out = Vec::new();
            encode_operand(&mut out, &operand.syntax, wide, wide).unwrap();
            let records = split(&out, 0).unwrap();
            (out.clone(), operand_text(&records, wide).unwrap())
        };
        assert_eq!(encode("K30", false), (vec![4, 0xE8, 30, 4], "K30".into()));
        assert_eq!(encode("K300", false).1, "K300");
        assert_eq!(encode("K-1", false), (vec![5, 0xE8, 0xFF, 0xFF, 5], "K-1".into()));
        assert_eq!(encode("K-100000", true).1, "K-100000");
        assert_eq!(encode("H1F", false).1, "H1F");
        assert_eq!(encode("K4M0", false).1, "K4M0");
        assert_eq!(encode("D0Z1", false).1, "D0Z1");
        assert_eq!(encode("D10.F", false).1, "D10.F");
        assert_eq!(encode("E1.5", true).1, "E1.5");
        assert_eq!(encode("M321", false).0, vec![5, 0x90, 0x41, 0x01, 5]);
    }
}
