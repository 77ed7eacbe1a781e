//! 3E and 4E frames (QnA-compatible; SLMP), binary and ASCII.
//!
//! A request: subheader (5000H; 4E: 5400H, a serial number, 0000H), the
//! route (network, PC, module I/O, station), the request data length, then
//! the monitoring timer, command, subcommand and the command's data. The
//! response: D000H (D400H with the request's serial), the request's
//! route, the response data length, the end code, and the data — or, on
//! an error, the route, command and subcommand the error answers.
//!
//! Subcommands 0000H/0001H (word/bit units) name devices as a Q/L/iQ-F
//! does (a 3-byte number and 1-byte code; ASCII: 2 characters and 6
//! digits), 0002H/0003H as an iQ-R does (4-byte number, 2-byte code; 4
//! characters and 8 digits). ASCII numbers are decimal, X and Y octal.
//!
//! Commands: 0401H/1401H batch read/write, 0403H/1402H random read/write,
//! 1001H/1002H/1003H remote RUN/STOP/PAUSE, 0101H model read, 0619H
//! loopback. End codes: C059H unknown command or subcommand, C050H ASCII
//! that is not a number, C061H a request whose length does not match its
//! points, C051H too many (or no) points, C056H devices beyond the last,
//! C05BH a device the PLC does not have or that cannot be written, C05CH
//! bit units of a word device, C05FH writes refused (read-only server or
//! peer), CEE0H host writes waiting beyond the server's bound.

use crate::exec::{execute, fault, limit, Error, Refusal, Reply, Request};
use crate::wire::{Code, Fault, Reader, Writer};
use crate::{Device, Family, Length, Plc, Remote, MAX_FRAME};

/// The model `0101H` reads: 16 characters, and a code.
pub const MODEL_NAME: &[u8; 16] = b"FX3U-LADDERC    ";
pub const MODEL_CODE: u16 = 0x00F3;

const MOST_BATCH_BITS: u32 = 7168;
const MOST_BATCH_WORDS: u32 = 960;
const MOST_RANDOM_READ: u32 = 192;
const MOST_RANDOM_BITS: u32 = 188;
/// Random word writes: 12 per word point and 14 per double-word point.
const RANDOM_WRITE_BUDGET: u32 = 960;

/// Bytes (characters) before the request data: subheader to length.
fn header_len(code: Code, four: bool) -> usize {
    code.chars(if four { 13 } else { 9 })
}

pub fn frame_length(bytes: &[u8], code: Code, four: bool) -> Length {
    let header = header_len(code, four);
    if bytes.len() < header {
        return Length::Need(header);
    }
    let mut reader = Reader::new(&bytes[header - code.chars(2)..header], code);
    let Ok(length) = reader.field(2) else {
        return Length::Invalid;
    };
    let length = length as usize;
    if length < code.chars(6) || header + length > MAX_FRAME {
        return Length::Invalid;
    }
    Length::Frame(header + length)
}

/// How devices are named: the subcommand's device form.
#[derive(Clone, Copy)]
struct Form {
    /// iQ-R: 4-byte numbers and 2-byte codes.
    long: bool,
}

fn device(reader: &mut Reader<'_>, form: Form) -> Result<Device, Error> {
    let (number_width, code_width) = if form.long { (4, 2) } else { (3, 1) };
    let (family, number) = match reader.code {
        Code::Binary => {
            let number = reader.field(number_width).map_err(fault)?;
            let code = reader.field(code_width).map_err(fault)?;
            (Family::from_code_3e(code as u16), number)
        }
        Code::Ascii => {
            let name = reader.raw(2 * code_width).map_err(fault)?;
            let family = Family::from_name_3e(name);
            let radix = if family.is_some_and(Family::octal) { 8 } else { 10 };
            (family, reader.digits(2 * number_width, radix).map_err(fault)?)
        }
    };
    let family = family.ok_or(Error::UnknownDevice)?;
    Ok(Device { family, number })
}

/// The FX3's 32-bit counters are LCN here; CN names the 16-bit ones only.
/// Checks a run of counter values and gives LCN as the counters it names.
fn counters(first: Device, count: u32, plc: &dyn Plc) -> Result<Device, Error> {
    let wide = |n: u32| {
        plc.wide(Device {
            family: Family::CounterValue,
            number: first.number.saturating_add(n),
        })
    };
    if first.family == Family::CounterValue && (0..count).any(wide) {
        return Err(Error::OutOfRange);
    }
    if first.family != Family::LongCounterValue {
        return Ok(first);
    }
    if !(0..count).all(wide) {
        return Err(Error::OutOfRange);
    }
    Ok(Device {
        family: Family::CounterValue,
        number: first.number,
    })
}

fn words(reader: &mut Reader<'_>, count: u32) -> Result<Vec<u16>, Error> {
    (0..count)
        .map(|_| reader.field(2).map(|w| w as u16).map_err(fault))
        .collect()
}

/// The request a body carries, from its command and subcommand on.
fn decode(reader: &mut Reader<'_>, command: u32, subcommand: u32, plc: &dyn Plc) -> Result<Request, Error> {
    let form = |bits: bool| -> Result<Form, Error> {
        match (subcommand, bits) {
            (0x0000, false) | (0x0001, true) => Ok(Form { long: false }),
            (0x0002, false) | (0x0003, true) => Ok(Form { long: true }),
            _ => Err(Error::UnknownCommand),
        }
    };
    let units_are_bits = matches!(subcommand, 0x0001 | 0x0003);
    let request = match command {
        0x0401 | 0x1401 => {
            let form = form(units_are_bits)?;
            let first = device(reader, form)?;
            let points = reader.field(2).map_err(fault)?;
            let most = if units_are_bits {
                MOST_BATCH_BITS
            } else {
                MOST_BATCH_WORDS
            };
            let points = limit(points, most)?;
            let first = counters(first, points, plc)?;
            let wide = first.family == Family::CounterValue && plc.wide(first);
            match (command == 0x0401, units_are_bits) {
                (true, true) => Request::ReadBits { first, count: points },
                (true, false) => Request::ReadWords { first, count: points },
                (false, true) => Request::WriteBits {
                    first,
                    values: reader.points(points as usize, false).map_err(fault)?,
                },
                (false, false) => Request::WriteWords {
                    first,
                    values: words(reader, if wide { 2 * points } else { points })?,
                },
            }
        }
        0x0403 => {
            let form = form(false)?;
            let word_points = reader.field(1).map_err(fault)?;
            let dword_points = reader.field(1).map_err(fault)?;
            limit(word_points + dword_points, MOST_RANDOM_READ)?;
            let mut read = |count: u32| -> Result<Vec<Device>, Error> {
                (0..count)
                    .map(|_| {
                        let at = device(reader, form)?;
                        counters(at, 1, plc)
                    })
                    .collect()
            };
            let words = read(word_points)?;
            let dwords = read(dword_points)?;
            Request::RandomRead { words, dwords }
        }
        0x1402 if units_are_bits => {
            let form = form(true)?;
            let points = limit(reader.field(1).map_err(fault)?, MOST_RANDOM_BITS)?;
            let value_width = if form.long { 2 } else { 1 };
            let mut writes = Vec::new();
            for _ in 0..points {
                let at = device(reader, form)?;
                writes.push((at, reader.field(value_width).map_err(fault)? != 0));
            }
            Request::RandomWriteBits(writes)
        }
        0x1402 => {
            let form = form(false)?;
            let word_points = reader.field(1).map_err(fault)?;
            let dword_points = reader.field(1).map_err(fault)?;
            if word_points + dword_points == 0 || 12 * word_points + 14 * dword_points > RANDOM_WRITE_BUDGET {
                return Err(Error::Points);
            }
            let mut words = Vec::new();
            for _ in 0..word_points {
                let at = counters(device(reader, form)?, 1, plc)?;
                words.push((at, reader.field(2).map_err(fault)? as u16));
            }
            let mut dwords = Vec::new();
            for _ in 0..dword_points {
                let at = counters(device(reader, form)?, 1, plc)?;
                dwords.push((at, reader.field(4).map_err(fault)?));
            }
            Request::RandomWriteWords { words, dwords }
        }
        0x1001..=0x1003 if subcommand == 0 => {
            // Mode (and for RUN the clear mode and a fixed byte): the soft PLC
            // clears as its RUN/STOP switch does, whatever is asked.
            reader.field(2).map_err(fault)?;
            if command == 0x1001 {
                reader.field(2).map_err(fault)?;
            }
            Request::Remote(match command {
                0x1001 => Remote::Run,
                0x1002 => Remote::Stop,
                _ => Remote::Pause,
            })
        }
        0x0101 if subcommand == 0 => Request::Model,
        0x0619 if subcommand == 0 => {
            let length = reader.field(2).map_err(fault)? as usize;
            if !(1..=960).contains(&length) {
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

fn end_code(error: Error) -> u32 {
    match error {
        Error::UnknownCommand => 0xC059,
        Error::NotDigit => 0xC050,
        Error::Length => 0xC061,
        Error::Points => 0xC051,
        Error::OutOfRange | Error::RunPastEnd => 0xC056,
        Error::UnknownDevice | Error::ReadOnlyDevice => 0xC05B,
        Error::WordDeviceInBitUnits | Error::BitHeadNotMultipleOf16 => 0xC05C,
        Error::Refused(Refusal::NotAllowed) => 0xC05F,
        Error::Refused(Refusal::Busy) => 0xCEE0,
    }
}

/// The response to a whole frame; `None` for one whose header cannot be
/// read (`frame_length` has refused it before).
pub fn answer(frame: &[u8], code: Code, four: bool, plc: &mut dyn Plc) -> Option<Vec<u8>> {
    let header = header_len(code, four);
    let serial = frame.get(code.chars(2)..code.chars(4))?;
    let route_at = if four { code.chars(6) } else { code.chars(2) };
    let route = frame.get(route_at..route_at + code.chars(5))?;
    let body = frame.get(header..)?;
    let mut reader = Reader::new(body, code);
    let command_and_sub = (|| -> Result<(u32, u32), Fault> {
        reader.field(2)?; // monitoring timer: answers never wait
        Ok((reader.field(2)?, reader.field(2)?))
    })();
    let (result, command, subcommand) = match command_and_sub {
        Ok((command, subcommand)) => {
            let result = decode(&mut reader, command, subcommand, plc).and_then(|request| {
                let batch = matches!(request, Request::ReadWords { .. });
                execute(request, plc).map(|reply| (reply, batch))
            });
            (result, command, subcommand)
        }
        Err(error) => (Err(fault(error)), 0, 0),
    };
    let mut data = Writer::new(code);
    let end = match result {
        Ok((reply, batch)) => {
            match reply {
                Reply::Done => {}
                Reply::Bits(points) => data.points(&points, false),
                Reply::Values(values) => {
                    for (value, bytes) in values {
                        if batch && bytes == 4 {
                            // A 32-bit counter in a batch: two words, low first.
                            data.field(value & 0xFFFF, 2);
                            data.field(value >> 16, 2);
                        } else {
                            data.field(value, bytes);
                        }
                    }
                }
                Reply::Model => {
                    data.raw(MODEL_NAME);
                    data.field(u32::from(MODEL_CODE), 2);
                }
                Reply::Loopback(echo) => {
                    data.field(echo.len() as u32, 2);
                    data.raw(&echo);
                }
            }
            0
        }
        Err(error) => {
            data.raw(route);
            data.field(command, 2);
            data.field(subcommand, 2);
            end_code(error)
        }
    };
    let mut out = Writer::new(code);
    match (code, four) {
        (Code::Binary, false) => out.raw(&[0xD0, 0x00]),
        (Code::Binary, true) => out.raw(&[0xD4, 0x00]),
        (Code::Ascii, false) => out.raw(b"D000"),
        (Code::Ascii, true) => out.raw(b"D400"),
    }
    if four {
        out.raw(serial);
        out.field(0, 2);
    }
    out.raw(route);
    out.field((code.chars(2) + data.bytes.len()) as u32, 2);
    out.field(end, 2);
    out.raw(&data.bytes);
    Some(out.bytes)
}
