//! The commands the frames carry, once decoded, and how they are carried
//! out against a [`Plc`]: range checks, point limits, the one image every
//! read of a request sees, and writes given to the PLC all at once. The
//! frame modules decode their bytes into a [`Request`] and encode the
//! [`Reply`] or the [`Error`] as their own end codes.

use crate::wire::Fault;
use crate::{Device, Family, Plc};

/// A write a request asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Write {
    Bit(Device, bool),
    Word(Device, u16),
    Dword(Device, u32),
}

/// What the RUN/STOP switch is asked to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Remote {
    Run,
    Stop,
    Pause,
}

/// Why the PLC refused a write or a remote operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// Writes are not allowed (read-only server, or a peer not allowed to
    /// write).
    NotAllowed,
    /// Too many writes wait for the next scan.
    Busy,
}

/// A decoded command.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Request {
    /// Bit devices in bit units.
    ReadBits {
        first: Device,
        count: u32,
    },
    /// Word devices, or bit devices 16 points a word.
    ReadWords {
        first: Device,
        count: u32,
    },
    WriteBits {
        first: Device,
        values: Vec<bool>,
    },
    /// Word values in order: for a 32-bit device, low word then high.
    WriteWords {
        first: Device,
        values: Vec<u16>,
    },
    RandomRead {
        words: Vec<Device>,
        dwords: Vec<Device>,
    },
    RandomWriteBits(Vec<(Device, bool)>),
    /// 16-bit writes (a bit device's: 16 points) and 32-bit writes.
    RandomWriteWords {
        words: Vec<(Device, u16)>,
        dwords: Vec<(Device, u32)>,
    },
    Remote(Remote),
    Model,
    Loopback(Vec<u8>),
}

/// Why a request was not carried out; each frame kind has its end code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    UnknownCommand,
    /// ASCII text that is not a number.
    NotDigit,
    /// The frame is shorter or longer than its command and points need.
    Length,
    /// A device code the PLC does not have.
    UnknownDevice,
    /// A head device beyond the family's last (or a 16-bit access to a
    /// 32-bit device).
    OutOfRange,
    /// A run whose head exists but whose last point is beyond the family's.
    RunPastEnd,
    /// No points, or more than the command takes.
    Points,
    /// Bit units asked of a word device.
    WordDeviceInBitUnits,
    /// Word units of a bit device not starting at a multiple of 16 (1E).
    BitHeadNotMultipleOf16,
    /// A device that cannot be written (a coil).
    ReadOnlyDevice,
    Refused(Refusal),
}

/// What a carried-out request answers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reply {
    Done,
    Bits(Vec<bool>),
    /// Fields of 2 or 4 bytes: (value, bytes).
    Values(Vec<(u32, usize)>),
    Model,
    Loopback(Vec<u8>),
}

/// Checks that `count` devices from `first` exist.
pub fn check_run(plc: &dyn Plc, first: Device, count: u32) -> Result<(), Error> {
    let points = plc.points(first.family);
    if points == 0 {
        return Err(Error::UnknownDevice);
    }
    if first.number >= points {
        return Err(Error::OutOfRange);
    }
    match first.number.checked_add(count) {
        Some(end) if end <= points => Ok(()),
        Some(_) | None => Err(Error::RunPastEnd),
    }
}

/// Checks that `count` 16-bit devices from `first` exist: none of them a
/// 32-bit device, which a 16-bit access would cut.
fn check_narrow(plc: &dyn Plc, first: Device, count: u32) -> Result<(), Error> {
    check_run(plc, first, count)?;
    if (0..count).any(|n| plc.wide(device(first.family, first.number + n))) {
        return Err(Error::OutOfRange);
    }
    Ok(())
}

fn device(family: Family, number: u32) -> Device {
    Device { family, number }
}

/// Points `first..first+count` of a bit family as words, 16 a word, the
/// first point in bit 0.
fn bit_words(plc: &dyn Plc, first: Device, words: u32) -> Vec<(u32, usize)> {
    (0..words)
        .map(|w| {
            let value = (0..16).fold(0u32, |value, bit| {
                let on = plc.bit(device(first.family, first.number + 16 * w + bit));
                value | u32::from(on) << bit
            });
            (value, 2)
        })
        .collect()
}

/// A word device's value as the frame carries it: 4 bytes if it is 32-bit.
fn value(plc: &dyn Plc, device: Device) -> (u32, usize) {
    if plc.wide(device) {
        (plc.dword(device), 4)
    } else {
        (u32::from(plc.word(device)), 2)
    }
}

/// Coils are read, never written.
fn writable(family: Family) -> Result<(), Error> {
    if matches!(family, Family::TimerCoil | Family::CounterCoil) {
        Err(Error::ReadOnlyDevice)
    } else {
        Ok(())
    }
}

/// A frame that could not be read, as the error it answers.
pub fn fault(fault: Fault) -> Error {
    match fault {
        Fault::Short => Error::Length,
        Fault::NotDigit => Error::NotDigit,
    }
}

/// `points` within `1..=most`.
pub fn limit(points: u32, most: u32) -> Result<u32, Error> {
    if (1..=most).contains(&points) {
        Ok(points)
    } else {
        Err(Error::Points)
    }
}

/// Carries out a request whose point counts the frame module has checked
/// against its own limits.
pub fn execute(request: Request, plc: &mut dyn Plc) -> Result<Reply, Error> {
    match request {
        Request::ReadBits { first, count } => {
            if !first.family.is_bit() {
                return Err(Error::WordDeviceInBitUnits);
            }
            check_run(plc, first, count)?;
            Ok(Reply::Bits(
                (0..count)
                    .map(|n| plc.bit(device(first.family, first.number + n)))
                    .collect(),
            ))
        }
        Request::ReadWords { first, count } => {
            if first.family.is_bit() {
                check_run(plc, first, count.saturating_mul(16))?;
                return Ok(Reply::Values(bit_words(plc, first, count)));
            }
            check_run(plc, first, count)?;
            Ok(Reply::Values(
                (0..count)
                    .map(|n| value(plc, device(first.family, first.number + n)))
                    .collect(),
            ))
        }
        Request::WriteBits { first, values } => {
            if !first.family.is_bit() {
                return Err(Error::WordDeviceInBitUnits);
            }
            writable(first.family)?;
            check_run(plc, first, values.len() as u32)?;
            let writes = (first.number..)
                .zip(values)
                .map(|(n, on)| Write::Bit(device(first.family, n), on))
                .collect();
            plc.write(writes).map_err(Error::Refused)?;
            Ok(Reply::Done)
        }
        Request::WriteWords { first, values } => {
            writable(first.family)?;
            let writes = if first.family.is_bit() {
                check_run(plc, first, 16 * values.len() as u32)?;
                values
                    .iter()
                    .enumerate()
                    .flat_map(|(w, &word)| {
                        (0..16).map(move |bit| {
                            let number = first.number + 16 * w as u32 + bit;
                            Write::Bit(device(first.family, number), word >> bit & 1 != 0)
                        })
                    })
                    .collect()
            } else {
                let mut writes = Vec::new();
                let mut words = values.iter();
                let mut number = first.number;
                while let Some(&low) = words.next() {
                    let at = device(first.family, number);
                    check_run(plc, at, 1)?;
                    if plc.wide(at) {
                        let high = *words.next().ok_or(Error::Length)?;
                        writes.push(Write::Dword(at, u32::from(high) << 16 | u32::from(low)));
                    } else {
                        writes.push(Write::Word(at, low));
                    }
                    number += 1;
                }
                writes
            };
            plc.write(writes).map_err(Error::Refused)?;
            Ok(Reply::Done)
        }
        Request::RandomRead { words, dwords } => {
            // A word point is 16 bits (16 points of a bit device), a double
            // word 32 (two words, or one 32-bit device).
            for &at in &words {
                if at.family.is_bit() {
                    check_run(plc, at, 16)?;
                } else {
                    check_narrow(plc, at, 1)?;
                }
            }
            for &at in &dwords {
                if at.family.is_bit() {
                    check_run(plc, at, 32)?;
                } else if plc.wide(at) {
                    check_run(plc, at, 1)?;
                } else {
                    check_narrow(plc, at, 2)?;
                }
            }
            let word = |at: Device| -> (u32, usize) {
                if at.family.is_bit() {
                    bit_words(plc, at, 1)[0]
                } else {
                    (u32::from(plc.word(at)), 2)
                }
            };
            let dword = |at: Device| -> (u32, usize) {
                if at.family.is_bit() {
                    let low = bit_words(plc, at, 1)[0].0;
                    let high = bit_words(plc, device(at.family, at.number + 16), 1)[0].0;
                    (high << 16 | low, 4)
                } else if plc.wide(at) {
                    (plc.dword(at), 4)
                } else {
                    let high = plc.word(device(at.family, at.number + 1));
                    (u32::from(high) << 16 | u32::from(plc.word(at)), 4)
                }
            };
            let mut values: Vec<(u32, usize)> = words.iter().map(|&at| word(at)).collect();
            values.extend(dwords.iter().map(|&at| dword(at)));
            Ok(Reply::Values(values))
        }
        Request::RandomWriteBits(points) => {
            for &(at, _) in &points {
                if !at.family.is_bit() {
                    return Err(Error::WordDeviceInBitUnits);
                }
                writable(at.family)?;
                check_run(plc, at, 1)?;
            }
            let writes = points.into_iter().map(|(at, on)| Write::Bit(at, on)).collect();
            plc.write(writes).map_err(Error::Refused)?;
            Ok(Reply::Done)
        }
        Request::RandomWriteWords { words, dwords } => {
            let mut writes = Vec::new();
            for (at, word) in words {
                writable(at.family)?;
                if at.family.is_bit() {
                    check_run(plc, at, 16)?;
                    writes.extend(
                        (0..16).map(|bit| Write::Bit(device(at.family, at.number + bit), word >> bit & 1 != 0)),
                    );
                } else {
                    check_narrow(plc, at, 1)?;
                    writes.push(Write::Word(at, word));
                }
            }
            for (at, dword) in dwords {
                writable(at.family)?;
                if at.family.is_bit() {
                    check_run(plc, at, 32)?;
                    writes.extend(
                        (0..32).map(|bit| Write::Bit(device(at.family, at.number + bit), dword >> bit & 1 != 0)),
                    );
                } else if plc.wide(at) {
                    check_run(plc, at, 1)?;
                    writes.push(Write::Dword(at, dword));
                } else {
                    check_narrow(plc, at, 2)?;
                    writes.push(Write::Word(at, dword as u16));
                    writes.push(Write::Word(device(at.family, at.number + 1), (dword >> 16) as u16));
                }
            }
            plc.write(writes).map_err(Error::Refused)?;
            Ok(Reply::Done)
        }
        Request::Remote(operation) => {
            plc.remote(operation).map_err(Error::Refused)?;
            Ok(Reply::Done)
        }
        Request::Model => Ok(Reply::Model),
        Request::Loopback(data) => Ok(Reply::Loopback(data)),
    }
}
