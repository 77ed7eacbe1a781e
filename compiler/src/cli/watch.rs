//! What `ladderc run` watches and how it shows values: device lists with
//! ranges (`Y0..Y7`, `D100..D109`) and 32-bit values (`D10:32`), in decimal
//! or hex.

use crate::host_device::{parse_device, HostDevice};
use crate::waveform::device_name;
use clap::ValueEnum;
use ladder_runtime::Device;

/// The most devices one range may name.
const MOST_IN_RANGE: u32 = 1024;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Radix {
    #[default]
    Dec,
    Hex,
}

/// One `--watch` entry: a device, `FIRST..LAST` of one kind, or `DEV:32`.
pub fn parse_watch(entry: &str) -> Result<Vec<(String, HostDevice)>, String> {
    let entry = entry.trim();
    let (entry, double) = match entry.strip_suffix(":32") {
        Some(bare) => (bare, true),
        None => (entry, false),
    };
    let Some((first, last)) = entry.split_once("..") else {
        let device = parse_device(entry, double)?;
        let name = if double {
            device_name(device)
        } else {
            entry.to_ascii_uppercase()
        };
        return Ok(vec![(name, device)]);
    };
    let (first, last) = (parse_device(first.trim(), double)?, parse_device(last.trim(), double)?);
    // (the device with number 0, the number): both ends must agree on the first.
    let numbers = |device: HostDevice| match device.device {
        Device::Bit(area, n) => Some((Device::Bit(area, 0), n)),
        Device::Word(area, n) => Some((Device::Word(area, 0), n)),
        Device::WideCounter(n) => Some((Device::WideCounter(0), n)),
        Device::WordBit(..) | Device::Digits(..) => None,
    };
    let (Some((kind, from)), Some((last_kind, to))) = (numbers(first), numbers(last)) else {
        return Err(format!("`{entry}`: ranges are of bits or words (Y0..Y7, D100..D109)"));
    };
    if kind != last_kind {
        return Err(format!(
            "`{entry}`: both ends of a range must be the same kind of device"
        ));
    }
    if to < from {
        return Err(format!("`{entry}`: the range ends before it starts"));
    }
    // Index registers interleave Z0, V0, Z1, ...: a range of Zn or of Vn
    // steps over the other kind.
    let index_registers = matches!(first.device, Device::Word(ladder_runtime::WordArea::Index, _));
    if index_registers && from % 2 != to % 2 {
        return Err(format!(
            "`{entry}`: both ends of a range must be the same kind of device"
        ));
    }
    let step = if double || index_registers { 2 } else { 1 };
    if (to - from) / step >= MOST_IN_RANGE {
        return Err(format!("`{entry}`: a range holds at most {MOST_IN_RANGE} devices"));
    }
    Ok((from..=to)
        .step_by(step as usize)
        .map(|n| {
            let device = HostDevice {
                device: match first.device {
                    Device::Bit(area, _) => Device::Bit(area, n),
                    Device::Word(area, _) => Device::Word(area, n),
                    Device::WideCounter(_) => Device::WideCounter(n),
                    other @ (Device::WordBit(..) | Device::Digits(..)) => other,
                },
                width: first.width,
            };
            (device_name(device), device)
        })
        .collect())
}

/// A value as `run` shows it: bits 0/1; words signed in decimal, or
/// unsigned `H..` in hex.
pub fn show(value: i32, device: HostDevice, radix: Radix) -> String {
    match (device.bits(), radix) {
        (1, _) | (_, Radix::Dec) => value.to_string(),
        (16, Radix::Hex) => format!("H{:04X}", value as u16),
        (_, Radix::Hex) => format!("H{:08X}", value as u32),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_wide_values() {
        let names = |entry| {
            parse_watch(entry)
                .unwrap()
                .into_iter()
                .map(|(n, _)| n)
                .collect::<Vec<_>>()
        };
        assert_eq!(names("Y6..Y11"), ["Y6", "Y7", "Y10", "Y11"]);
        assert_eq!(names("d100..D102"), ["D100", "D101", "D102"]);
        assert_eq!(names("D10:32"), ["D10:32"]);
        assert_eq!(names("D10..D13:32"), ["D10:32", "D12:32"]);
        assert_eq!(names("X0"), ["X0"]);
        assert_eq!(names("V0..V2"), ["V0", "V1", "V2"]);
        assert!(parse_watch("Z0..V3").is_err());
        assert!(parse_watch("Y7..Y0").is_err());
        assert!(parse_watch("Y0..D3").is_err());
        assert!(parse_watch("M0..M8000").is_err());
    }
}
