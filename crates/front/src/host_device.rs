//! Devices and values as a host names them: `X0`, `D0.F`, `K4M0`, `TN0`,
//! `CN200` and `K123`, `H1F2A`, `-5`, `on`. Used by `ladderc run` and by
//! scenario files.

use crate::syntax::operand::parse_operand;
use crate::syntax::{OperandSyntax, Prefix};
use ladder_runtime::device::{index_register_word, COUNTER_COUNT, FIRST_WIDE_COUNTER, INDEX_REGISTER_COUNT};
use ladder_runtime::{BitArea, Device, Width, WordArea};

/// A device named by a host, with the width its value has.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct HostDevice {
    pub device: Device,
    pub width: Width,
}

impl HostDevice {
    pub fn is_bit(self) -> bool {
        self.device.is_bit()
    }

    /// Bits in the device's value.
    pub fn bits(self) -> u32 {
        match (self.device, self.width) {
            (Device::Bit(..) | Device::WordBit(..), _) => 1,
            (Device::WideCounter(_), _) | (_, Width::Double) => 32,
            (_, Width::Single) => 16,
        }
    }
}

/// Parses a device name. `double` asks for the 32-bit pair (set32/expect32).
pub fn parse_device(text: &str, double: bool) -> Result<HostDevice, String> {
    let operand = parse_operand(text, 0).map_err(|d| d.message)?;
    let OperandSyntax::Device(d) = operand.syntax else {
        return Err(format!("`{text}` is a constant, not a device"));
    };
    if d.offset.is_some() {
        return Err(format!("`{text}`: offsets are not allowed here"));
    }
    let n = d.number;
    let width = if double { Width::Double } else { Width::Single };
    let bit_area = |area: BitArea| -> Result<Device, String> {
        if n >= area.count() {
            return Err(format!("`{text}` is out of range"));
        }
        Ok(match d.digits {
            Some(digits) => {
                if u64::from(n) + 4 * u64::from(digits) > u64::from(area.count()) {
                    return Err(format!("`{text}` runs past the end of {}", area.prefix()));
                }
                if !double && digits > 4 {
                    return Err(format!("`{text}` has {} bits; use set32/expect32", 4 * digits));
                }
                Device::Digits(area, n, digits)
            }
            None => Device::Bit(area, n),
        })
    };
    let word = |area: WordArea| -> Result<Device, String> {
        let words = if double { 2 } else { 1 };
        if n >= area.count() || u64::from(n) + words > u64::from(area.reach(n).1) {
            // A buffer memory's pair stays within its unit.
            return Err(format!("`{text}` is out of range"));
        }
        Ok(match d.bit {
            Some(bit) => Device::WordBit(area, n, bit),
            None => Device::Word(area, n),
        })
    };
    let device = match d.prefix {
        Prefix::X => bit_area(BitArea::X)?,
        Prefix::Y => bit_area(BitArea::Y)?,
        Prefix::M => bit_area(BitArea::M)?,
        Prefix::S => bit_area(BitArea::S)?,
        Prefix::Sm => bit_area(BitArea::Sm)?,
        Prefix::T | Prefix::Ts => bit_area(BitArea::TimerContact)?,
        // `C235:32` is the 32-bit counter's value, as `CN235` is.
        Prefix::C if double && (FIRST_WIDE_COUNTER..COUNTER_COUNT).contains(&n) => Device::WideCounter(n),
        Prefix::C | Prefix::Cs => bit_area(BitArea::CounterContact)?,
        Prefix::D => word(WordArea::D)?,
        Prefix::Sd => word(WordArea::Sd)?,
        Prefix::R => word(WordArea::R)?,
        Prefix::U => word(WordArea::Buffer)?,
        Prefix::Tn if !double => word(WordArea::TimerValue)?,
        Prefix::Cn if (FIRST_WIDE_COUNTER..COUNTER_COUNT).contains(&n) => Device::WideCounter(n),
        Prefix::Cn if !double && n < FIRST_WIDE_COUNTER => word(WordArea::CounterValue)?,
        Prefix::Tn | Prefix::Cn => return Err(format!("`{text}` is a 16-bit value; use set/expect")),
        Prefix::P | Prefix::N => return Err(format!("`{text}` is not a device")),
        Prefix::V if double => return Err(format!("`{text}` is 16-bit; the 32-bit index register is Z{n}")),
        Prefix::V | Prefix::Z if n >= INDEX_REGISTER_COUNT => return Err(format!("`{text}` is out of range")),
        Prefix::V | Prefix::Z => Device::Word(WordArea::Index, index_register_word(n, d.prefix == Prefix::V)),
    };
    if double && device.is_bit() {
        return Err(format!("`{text}` is a bit; set32/expect32 take words"));
    }
    let width = if matches!(device, Device::WideCounter(_)) {
        Width::Double
    } else {
        width
    };
    Ok(HostDevice { device, width })
}

/// Parses a value for `device`: decimal, `K123`, `H1F2A`, and for bits also
/// `on`/`off`. Words may be given signed or unsigned (`-1` = `HFFFF`).
pub fn parse_value(text: &str, device: HostDevice) -> Result<i32, String> {
    let lower = text.to_ascii_lowercase();
    if device.is_bit() {
        return match lower.as_str() {
            "1" | "on" | "k1" | "h1" => Ok(1),
            "0" | "off" | "k0" | "h0" => Ok(0),
            _ => Err(format!("`{text}` is not a bit value (0, 1, on, off)")),
        };
    }
    let value = parse_number(text)?;
    let bits = device.bits();
    let (min, max) = (-(1i64 << (bits - 1)), (1i64 << bits) - 1);
    if !(min..=max).contains(&value) {
        return Err(format!("`{text}` does not fit in {bits} bits"));
    }
    Ok(value as i32)
}

/// `123`, `-5`, `K123`, `H1F` or `1FH` as an integer.
pub fn parse_number(text: &str) -> Result<i64, String> {
    let invalid = || format!("`{text}` is not a number (decimal, K123 or H1F2A)");
    let (digits, radix) = match text.as_bytes().first() {
        Some(b'K' | b'k') => (&text[1..], 10),
        Some(b'H' | b'h') => (&text[1..], 16),
        _ => match text.strip_suffix(['H', 'h']) {
            Some(hex) => (hex, 16),
            None => (text, 10),
        },
    };
    let (negative, magnitude) = match digits.strip_prefix('-') {
        Some(rest) if radix == 10 => (true, rest),
        _ => (false, digits),
    };
    if magnitude.is_empty() || magnitude.len() > 20 || !magnitude.chars().all(|c| c.is_digit(radix)) {
        return Err(invalid());
    }
    let value = i64::from_str_radix(magnitude, radix).map_err(|_| invalid())?;
    Ok(if negative { -value } else { value })
}

/// Whether two values are the same bits of a device of `bits` width.
pub fn same_bits(a: i32, b: i32, bits: u32) -> bool {
    let mask = if bits >= 32 { u32::MAX } else { (1u32 << bits) - 1 };
    (a as u32 & mask) == (b as u32 & mask)
}

/// A device's value for people: bits as 0/1, words signed with their hex.
pub fn format_value(value: i32, device: HostDevice) -> String {
    match device.bits() {
        1 => value.to_string(),
        16 => format!("{} (H{:04X})", value as i16, value as u16),
        _ => format!("{value} (H{:08X})", value as u32),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(parse_device("X17", false).unwrap().device, Device::Bit(BitArea::X, 15));
        assert_eq!(
            parse_device("TS0", false).unwrap().device,
            Device::Bit(BitArea::TimerContact, 0)
        );
        assert_eq!(
            parse_device("TN0", false).unwrap().device,
            Device::Word(WordArea::TimerValue, 0)
        );
        assert_eq!(
            parse_device("CN3", false).unwrap().device,
            Device::Word(WordArea::CounterValue, 3)
        );
        let wide = parse_device("CN200", false).unwrap();
        assert_eq!((wide.device, wide.width), (Device::WideCounter(200), Width::Double));
        assert_eq!(
            parse_device("D0.F", false).unwrap().device,
            Device::WordBit(WordArea::D, 0, 15)
        );
        assert_eq!(
            parse_device("K4M0", false).unwrap().device,
            Device::Digits(BitArea::M, 0, 4)
        );
        assert!(parse_device("K8M0", false).is_err());
        assert!(parse_device("K8M0", true).is_ok());
        assert!(parse_device("D8511", true).is_err());
        assert!(parse_device("K5", false).is_err());
        assert!(parse_device("M0[D0]", false).is_err());
    }

    #[test]
    fn values() {
        let word = parse_device("D0", false).unwrap();
        assert_eq!(parse_value("H8F2A", word), Ok(0x8F2A));
        assert!(same_bits(
            parse_value("H8F2A", word).unwrap(),
            parse_value("-28886", word).unwrap(),
            16
        ));
        assert!(parse_value("65536", word).is_err());
        assert!(parse_value("-32769", word).is_err());
        let pair = parse_device("D0", true).unwrap();
        assert!(same_bits(
            parse_value("H80000000", pair).unwrap(),
            parse_value("-2147483648", pair).unwrap(),
            32
        ));
        let bit = parse_device("Y0", false).unwrap();
        assert_eq!(parse_value("on", bit), Ok(1));
        assert!(parse_value("2", bit).is_err());
        assert_eq!(parse_number("4085H"), Ok(0x4085));
        assert_eq!(parse_number("K-5"), Ok(-5));
        assert!(parse_number("H-5").is_err());
    }
}
