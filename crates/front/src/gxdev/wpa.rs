//! GX Developer's PLC parameters, `param.wpa`: the CPU type, the size of
//! the program memory and the latched (battery-backed) device ranges.
//!
//! After the header come blocks, each its length (two bytes, counting its
//! four head bytes), its code (two bytes) and its data, up to the code FFFF.
//! Block FFE0 holds the program memory in thousands of steps; block 2001 the
//! latched ranges: their number, then per range a device code, a count and
//! the first device (two bytes each). Other blocks (PLC name, comment
//! capacity, I/O assignment, ...) change nothing ladderc models.

use super::records::{self, code};
use super::wcd::device_name;
use super::DecodeError;

const MEMORY: u16 = 0xFFE0;
const LATCH: u16 = 0x2001;
const END: u16 = 0xFFFF;

/// What ladderc takes from the parameters.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Parameters {
    pub cpu: u8,
    /// Steps of program memory.
    pub memory: Option<u32>,
    /// Latched ranges as `serve --latch` spells them (`M500-M1023`).
    pub latched: Vec<String>,
}

/// Decodes a parameter file.
pub fn decode(bytes: &[u8]) -> Result<Parameters, DecodeError> {
    let cpu = records::check_header(bytes)?;
    let mut parameters = Parameters {
        cpu,
        ..Parameters::default()
    };
    let mut at = records::HEADER_LEN;
    loop {
        let u16_at = |i: usize| bytes.get(i..i + 2).map(|b| u16::from_le_bytes([b[0], b[1]]));
        let block_code = u16_at(at + 2);
        if u16_at(at) == Some(END) {
            break;
        }
        let (Some(length), Some(block_code)) = (u16_at(at), block_code) else {
            return Err(DecodeError::new(at, "a parameter block or the end mark FF FF"));
        };
        let length = usize::from(length);
        let data = bytes
            .get(at + 4..at + length.max(4))
            .filter(|_| length >= 4)
            .ok_or_else(|| DecodeError::new(at, format!("a parameter block of {length} bytes")))?;
        match block_code {
            MEMORY => {
                let thousands = u16_at(at + 4).ok_or_else(|| DecodeError::new(at + 4, "the program memory size"))?;
                parameters.memory = Some(u32::from(thousands) * 1000);
            }
            LATCH => {
                let count = u16_at(at + 4).map_or(0, usize::from);
                if data.len() != 2 + count * 6 {
                    return Err(DecodeError::new(at, format!("{count} latched ranges of six bytes")));
                }
                for range in 0..count {
                    let base = at + 6 + range * 6;
                    let (Some(device), Some(count), Some(first)) = (u16_at(base), u16_at(base + 2), u16_at(base + 4))
                    else {
                        return Err(DecodeError::new(base, "a latched range"));
                    };
                    let device = u8::try_from(device).ok().filter(|&d| d != code::X && d != code::Y);
                    let names = device.and_then(|d| {
                        let last = u32::from(first) + u32::from(count).checked_sub(1)?;
                        Some((device_name(d, u32::from(first))?, device_name(d, last)?))
                    });
                    if let Some((first, last)) = names {
                        parameters.latched.push(format!("{first}-{last}"));
                    }
                }
            }
            _ => {}
        }
        at += length;
    }
    Ok(parameters)
}

/// The CPU model of a type code, as GX Developer names it.
pub fn cpu_name(cpu: u8) -> Option<&'static str> {
    Some(match cpu {
        0x01 => "FX0S",
        0x02 => "FX0N",
        0x03 => "FX1",
        0x04 => "FXU",
        0x05 => "FX2N",
        0x06 => "FX1S",
        0x07 => "FX1N",
        0x08 => "FX3U",
        0x09 => "FX3G",
        _ => return None,
    })
}

/// The type code of a CPU model name (FX2NC and FX3UC share their base
/// model's code).
pub fn cpu_code(name: &str) -> Option<u8> {
    let name = name.trim().to_ascii_uppercase();
    let base = name.strip_suffix('C').filter(|b| ["FX2N", "FX3U", "FX1N"].contains(b));
    (1..=9).find(|&code| cpu_name(code) == Some(base.unwrap_or(&name)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_names_round_trip() {
        assert_eq!(cpu_code("FX2N"), Some(5));
        assert_eq!(cpu_code("fx3uc"), Some(8));
        assert_eq!(cpu_name(7), Some("FX1N"));
        assert_eq!(cpu_code("Q06H"), None);
    }

    #[test]
    fn truncated_parameters_are_one_error() {
        let mut bytes = records::header(5, &[0x03, 0x03, 0x01]);
        bytes.extend([6, 0, 0xE0, 0xFF, 8]);
        let error = decode(&bytes).unwrap_err();
        assert_eq!(error.offset, 64);
        bytes.extend([0, 0xFF, 0xFF]);
        assert_eq!(decode(&bytes).unwrap().memory, Some(8000));
    }
}
