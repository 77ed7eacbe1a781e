//! What `ladderc run` watches and how it shows values: device lists with
//! ranges (`Y0..Y7`, `D100..D109`), 32-bit values (`D10:32`) and real
//! numbers (`D20:float`), in decimal or hex.

use crate::waveform::{device_name, Signal};
use ladder_front::host_device::{parse_device, HostDevice};
use ladder_runtime::Device;

/// The most devices one range may name.
const MOST_IN_RANGE: u32 = 1024;

/// One `--watch` entry: a device, `FIRST..LAST` of one kind, `DEV:32`, or
/// `DEV:float` (the pair read as a real number).
pub fn parse_watch(entry: &str) -> Result<Vec<Signal>, String> {
    let entry = entry.trim();
    let lower = entry.to_ascii_lowercase();
    let (entry, double, real) = if lower.ends_with(":float") || lower.ends_with(":real") {
        let colon = entry.rfind(':').unwrap_or(entry.len());
        (&entry[..colon], true, true)
    } else {
        match entry.strip_suffix(":32") {
            Some(bare) => (bare, true, false),
            None => (entry, false, false),
        }
    };
    let named = |device: HostDevice| {
        let name = device_name(device);
        Signal {
            name: if real { name.replace(":32", ":float") } else { name },
            device,
            real,
        }
    };
    if real {
        let words = |device: HostDevice| matches!(device.device, Device::Word(area, _) if area != ladder_runtime::WordArea::TimerValue && area != ladder_runtime::WordArea::CounterValue && area != ladder_runtime::WordArea::Index);
        let ends = entry
            .split("..")
            .map(|end| parse_device(end.trim(), true))
            .collect::<Result<Vec<_>, _>>()?;
        if !ends.into_iter().all(words) {
            return Err(format!(
                "`{entry}`: real numbers are word pairs of D, R, SD or U\\G (D0:float)"
            ));
        }
    }
    let Some((first, last)) = entry.split_once("..") else {
        let device = parse_device(entry, double)?;
        return Ok(vec![if double {
            named(device)
        } else {
            Signal {
                name: entry.to_ascii_uppercase(),
                device,
                real: false,
            }
        }]);
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
            named(device)
        })
        .collect())
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
                .map(|signal| signal.name)
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
        assert_eq!(names("D20:float"), ["D20:float"]);
        assert_eq!(names("R0..R2:float"), ["R0:float", "R2:float"]);
        assert!(parse_watch("D0:float").unwrap()[0].real);
        assert!(parse_watch("M0:float").is_err());
        assert_eq!(names("C235:32"), ["CN235"]);
    }
}
