//! A-compatible 1E frames, as an FX3U-ENET-ADP answers them (its manual's
//! chapter 7): subheader (the command), PC number (FFH: this PLC), the
//! monitoring timer, then the command's fields. A response is the command
//! with bit 7 set, the end code, and the data.
//!
//! In binary, multi-byte fields are little-endian and the head device is
//! its number (4 bytes) then its name (2 bytes); in ASCII every field is
//! hex text, most significant digit first, and the head device is its
//! name (4 digits) then its number (8 digits). Bit-unit data is one point
//! a nibble (binary) or a character (ASCII), padded to an even count.
//!
//! End codes (the FX3U-ENET-ADP manual's table): 50H unknown command, 54H
//! ASCII that is not hex, 55H writes refused (read-only server or peer),
//! 56H an unknown device, 57H too many (or no) points, a run past the last
//! device, a frame whose length does not match its points, an odd word
//! count for C200-C255; 58H a head device out of range, a word device in a
//! bit command, a bit device's word access not starting at a multiple of
//! 16, a run that mixes C0-C199 with C200-C255; 5BH with abnormal code 10H
//! for another PC number and 18H when host writes are waiting beyond the
//! server's bound.

use crate::exec::{execute, fault, limit, Error, Refusal, Reply, Request};
use crate::wire::{Code, Fault, Reader, Writer};
use crate::{Device, Family, Length, Plc, Remote};

const BATCH_READ_BITS: u8 = 0x00;
const BATCH_READ_WORDS: u8 = 0x01;
const BATCH_WRITE_BITS: u8 = 0x02;
const BATCH_WRITE_WORDS: u8 = 0x03;
const TEST_BITS: u8 = 0x04;
const TEST_WORDS: u8 = 0x05;
const REMOTE_RUN: u8 = 0x13;
const REMOTE_STOP: u8 = 0x14;
const MODEL_NAME: u8 = 0x15;
const LOOPBACK: u8 = 0x16;

/// The model code of an FX3U/FX3UC, as command 15H reads it.
pub const MODEL_CODE: u8 = 0xF3;

/// The first C of the 32-bit counters, which 1E frames carry as two words.
const FIRST_WIDE_COUNTER: u32 = 200;

/// Whether a first byte starts a binary 1E frame: every command byte up
/// to 1FH, so that the unknown ones get end code 50H (ASCII digits, 3E and
/// 4E subheaders are all above it).
pub fn is_command(byte: u8) -> bool {
    byte <= 0x1F
}

/// The command byte, the fields before the command's own.
struct Header {
    command: u8,
    pc: u8,
}

fn header(reader: &mut Reader<'_>) -> Result<Header, Fault> {
    let command = reader.field(1)? as u8;
    let pc = reader.field(1)? as u8;
    reader.field(2)?; // monitoring timer: answers never wait
    Ok(Header { command, pc })
}

/// Points in a 1-byte count field: 0 is 256.
fn count(reader: &mut Reader<'_>) -> Result<u32, Fault> {
    Ok(match reader.field(1)? {
        0 => 256,
        n => n,
    })
}

/// A device field: number then name in binary, name then number in ASCII.
/// Unknown names decode as `None` (the command is refused once its length
/// is known).
fn device(reader: &mut Reader<'_>) -> Result<Option<Device>, Fault> {
    let (name, number) = match reader.code {
        Code::Binary => {
            let number = reader.field(4)?;
            (reader.field(2)?, number)
        }
        Code::Ascii => {
            let name = reader.field(2)?;
            (name, reader.field(4)?)
        }
    };
    Ok(Family::from_code_1e(name as u16).map(|family| Device { family, number }))
}

fn is_wide(device: Option<Device>) -> bool {
    matches!(device, Some(Device { family: Family::CounterValue, number }) if number >= FIRST_WIDE_COUNTER)
}

/// Bytes a frame needs, from its fields: the length of the frame, or the
/// reader's fault (short: more bytes needed).
fn needed(bytes: &[u8], code: Code) -> Result<usize, Fault> {
    let mut reader = Reader::new(bytes, code);
    let head = header(&mut reader)?;
    let fields = match head.command {
        BATCH_READ_BITS | BATCH_READ_WORDS => 8,
        // The data of a word write is two bytes a point: for C200-C255 the
        // count is in words, so this holds for them too.
        BATCH_WRITE_BITS | BATCH_WRITE_WORDS => {
            device(&mut reader)?;
            let points = count(&mut reader)? as usize;
            8 + if head.command == BATCH_WRITE_BITS {
                points.div_ceil(2)
            } else {
                2 * points
            }
        }
        TEST_BITS => 2 + 7 * count(&mut reader)? as usize,
        TEST_WORDS => 2 + 8 * count(&mut reader)? as usize,
        LOOPBACK => {
            let length = reader.field(1)? as usize;
            // Loopback data is characters in either code.
            return Ok(code.chars(5) + length);
        }
        REMOTE_RUN | REMOTE_STOP | MODEL_NAME => 0,
        // An unknown command cannot be measured: what arrived is answered
        // with 50H as one frame.
        _ => return Ok(bytes.len()),
    };
    Ok(code.chars(4 + fields))
}

pub fn frame_length(bytes: &[u8], code: Code) -> Length {
    match needed(bytes, code) {
        Ok(length) => Length::Frame(length),
        Err(Fault::Short) => Length::Need(bytes.len() + 1),
        // Text that is not hex: the frame cannot be measured; what arrived
        // is answered with 54H as one frame.
        Err(Fault::NotDigit) => Length::Frame(bytes.len()),
    }
}

fn end_code(error: Error) -> (u8, Option<u8>) {
    match error {
        Error::UnknownCommand => (0x50, None),
        Error::NotDigit => (0x54, None),
        Error::Refused(Refusal::NotAllowed) => (0x55, None),
        Error::UnknownDevice => (0x56, None),
        Error::Points | Error::RunPastEnd | Error::Length => (0x57, None),
        Error::OutOfRange | Error::WordDeviceInBitUnits | Error::BitHeadNotMultipleOf16 | Error::ReadOnlyDevice => {
            (0x58, None)
        }
        Error::Refused(Refusal::Busy) => (0x5B, Some(0x18)),
    }
}

/// A word access to bit devices starts at a multiple of 16.
fn word_head(first: Device) -> Result<Device, Error> {
    if first.family.is_bit() && !first.number.is_multiple_of(16) {
        Err(Error::BitHeadNotMultipleOf16)
    } else {
        Ok(first)
    }
}

/// The command's request, its point counts within the FX3U-ENET-ADP's
/// limits.
fn decode(reader: &mut Reader<'_>, command: u8) -> Result<Request, Error> {
    let known = |device: Option<Device>| device.ok_or(Error::UnknownDevice);
    let request = match command {
        BATCH_READ_BITS | BATCH_READ_WORDS | BATCH_WRITE_BITS | BATCH_WRITE_WORDS => {
            let first = device(reader).map_err(fault)?;
            let points = count(reader).map_err(fault)?;
            reader.field(1).map_err(fault)?; // fixed 00H
            let first = known(first)?;
            let wide = is_wide(Some(first));
            // C0-C199 and C200-C255 are not named in one run (the manual's
            // rule): a word run from below C200 stays below it.
            let word_command = matches!(command, BATCH_READ_WORDS | BATCH_WRITE_WORDS);
            if word_command
                && first.family == Family::CounterValue
                && !wide
                && first.number.saturating_add(points) > FIRST_WIDE_COUNTER
            {
                return Err(Error::OutOfRange);
            }
            match command {
                BATCH_READ_BITS => Request::ReadBits {
                    first,
                    count: limit(points, 256)?,
                },
                BATCH_READ_WORDS if wide => Request::ReadWords {
                    first,
                    count: wide_count(points)?,
                },
                BATCH_READ_WORDS => Request::ReadWords {
                    first: word_head(first)?,
                    count: limit(points, if first.family.is_bit() { 32 } else { 64 })?,
                },
                BATCH_WRITE_BITS => Request::WriteBits {
                    first,
                    values: reader.points(limit(points, 160)? as usize, true).map_err(fault)?,
                },
                _ => {
                    let words = if wide {
                        wide_count(points)? * 2
                    } else {
                        limit(points, if first.family.is_bit() { 10 } else { 64 })?
                    };
                    let values = (0..words)
                        .map(|_| reader.field(2).map(|w| w as u16))
                        .collect::<Result<Vec<u16>, Fault>>()
                        .map_err(fault)?;
                    let values = if wide {
                        // Each counter's 4 bytes are one field: low word first
                        // in binary, high digits first in ASCII.
                        values
                            .chunks(2)
                            .flat_map(|pair| match reader.code {
                                Code::Binary => [pair[0], pair[1]],
                                Code::Ascii => [pair[1], pair[0]],
                            })
                            .collect()
                    } else {
                        values
                    };
                    Request::WriteWords {
                        first: word_head(first)?,
                        values,
                    }
                }
            }
        }
        TEST_BITS => {
            let points = limit(count(reader).map_err(fault)?, 80)?;
            reader.field(1).map_err(fault)?;
            let mut writes = Vec::new();
            for _ in 0..points {
                let at = device(reader).map_err(fault)?;
                let value = reader.field(1).map_err(fault)?;
                writes.push((known(at)?, value != 0));
            }
            Request::RandomWriteBits(writes)
        }
        TEST_WORDS => {
            let points = limit(count(reader).map_err(fault)?, 10)?;
            reader.field(1).map_err(fault)?;
            let mut words = Vec::new();
            for _ in 0..points {
                let at = device(reader).map_err(fault)?;
                let value = reader.field(2).map_err(fault)? as u16;
                if is_wide(at) {
                    return Err(Error::OutOfRange);
                }
                words.push((word_head(known(at)?)?, value));
            }
            Request::RandomWriteWords {
                words,
                dwords: Vec::new(),
            }
        }
        REMOTE_RUN => Request::Remote(Remote::Run),
        REMOTE_STOP => Request::Remote(Remote::Stop),
        MODEL_NAME => Request::Model,
        LOOPBACK => {
            let length = reader.field(1).map_err(fault)? as usize;
            if length == 0 {
                return Err(Error::Points);
            }
            Request::Loopback(reader.raw(length).map_err(fault)?.to_vec())
        }
        _ => return Err(Error::UnknownCommand),
    };
    if reader.remaining() != 0 {
        return Err(Error::Length);
    }
    Ok(request)
}

/// C200-C255 in a word command: the count is in words, two a counter.
fn wide_count(words: u32) -> Result<u32, Error> {
    if !words.is_multiple_of(2) {
        return Err(Error::Length);
    }
    limit(words / 2, 32)
}

pub fn answer(frame: &[u8], code: Code, plc: &mut dyn Plc) -> Vec<u8> {
    let mut reader = Reader::new(frame, code);
    let mut out = Writer::new(code);
    let head = match header(&mut reader) {
        Ok(head) => head,
        Err(_) => {
            // Not even a header: answer the command with 54H (ASCII that is
            // not hex) or 57H (cut short).
            let command = match code {
                Code::Binary => frame.first().copied().unwrap_or(0),
                Code::Ascii => Reader::new(frame, code).field(1).map_or(0, |c| c as u8),
            };
            let end = if code == Code::Ascii { 0x54 } else { 0x57 };
            out.field(u32::from(command | 0x80), 1);
            out.field(end, 1);
            return out.bytes;
        }
    };
    out.field(u32::from(head.command | 0x80), 1);
    let result = if head.pc != 0xFF {
        Err((0x5B, Some(0x10)))
    } else {
        decode(&mut reader, head.command)
            .and_then(|request| execute(request, plc))
            .map_err(end_code)
    };
    match result {
        Ok(reply) => {
            out.field(0, 1);
            match reply {
                Reply::Done => {}
                Reply::Bits(points) => out.points(&points, true),
                Reply::Values(values) => {
                    for (value, bytes) in values {
                        out.field(value, bytes);
                    }
                }
                Reply::Model => out.field(u32::from(MODEL_CODE), 1),
                Reply::Loopback(data) => {
                    out.field(data.len() as u32, 1);
                    out.raw(&data);
                }
            }
        }
        Err((end, abnormal)) => {
            out.field(u32::from(end), 1);
            if let Some(abnormal) = abnormal {
                out.field(u32::from(abnormal), 1);
                out.field(0, 1);
            }
        }
    }
    out.bytes
}
