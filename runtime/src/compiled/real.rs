//! Real-number work of compiled code (DSIN ..., DEBCD, DEBIN): the same
//! rules as the interpreter's float kernels, written apart from them so that
//! the differential test compares the two.

use crate::real::RealFunction;
use core::fmt::Write as _;

/// The bits compiled code takes for "out of range": a quiet NaN.
const OUT_OF_RANGE: i32 = 0x7FC0_0000;

/// A result is written only when it is finite and 0 or at least the
/// smallest normal magnitude.
fn checked(exact: f64) -> i32 {
    let single = exact as f32;
    if !single.is_finite() || (exact != 0.0 && exact.abs() < f64::from(f32::MIN_POSITIVE)) {
        OUT_OF_RANGE
    } else {
        single.to_bits() as i32
    }
}

/// `function` of the real number with bits `x`: the arcsine and arccosine
/// take -1..1, the logarithms numbers above 0.
pub fn real_function(function: u32, x: u32) -> i32 {
    let x = f32::from_bits(x);
    let Some(function) = RealFunction::from_code(function) else {
        return OUT_OF_RANGE;
    };
    let in_domain = x.is_finite()
        && match function {
            RealFunction::Asin | RealFunction::Acos => (-1.0..=1.0).contains(&x),
            RealFunction::Ln | RealFunction::Log10 => x > 0.0,
            RealFunction::Sin | RealFunction::Cos | RealFunction::Tan | RealFunction::Atan | RealFunction::Exp => true,
        };
    if !in_domain {
        return OUT_OF_RANGE;
    }
    let exact = function.apply(f64::from(x));
    if function == RealFunction::Exp && exact == 0.0 {
        // e^x is never 0: below about e^-745 double precision underflows too.
        return OUT_OF_RANGE;
    }
    checked(exact)
}

/// Text of a few dozen bytes on the stack (no allocation on firmware).
struct Buffer {
    bytes: [u8; 48],
    len: usize,
}

impl core::fmt::Write for Buffer {
    fn write_str(&mut self, text: &str) -> core::fmt::Result {
        let end = self.len + text.len();
        let room = self.bytes.get_mut(self.len..end).ok_or(core::fmt::Error)?;
        room.copy_from_slice(text.as_bytes());
        self.len = end;
        Ok(())
    }
}

impl Buffer {
    fn new() -> Buffer {
        Buffer { bytes: [0; 48], len: 0 }
    }

    fn text(&self) -> &str {
        core::str::from_utf8(&self.bytes[..self.len]).unwrap_or("")
    }
}

/// DEBCD: the 4-digit mantissa (the digits of the shortest decimal that
/// reads back as the number, the fifth and further dropped) in the low
/// word, the decimal exponent in the high word; 0 is 0 × 10^0.
pub fn real_to_decimal(x: u32) -> i32 {
    let value = f32::from_bits(x);
    if value == 0.0 || !value.is_finite() {
        return 0;
    }
    let mut buffer = Buffer::new();
    if write!(buffer, "{:e}", value.abs()).is_err() {
        return 0;
    }
    let text = buffer.text();
    let (digits, exponent) = text.split_once('e').unwrap_or((text, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let mut mantissa: i32 = 0;
    let significant = digits.bytes().filter(u8::is_ascii_digit).map(|d| i32::from(d - b'0'));
    for digit in significant.chain(core::iter::repeat(0)).take(4) {
        mantissa = mantissa * 10 + digit;
    }
    if value < 0.0 {
        mantissa = -mantissa;
    }
    (i32::from(mantissa as i16) & 0xFFFF) | ((exponent - 3) << 16)
}

/// DEBIN: mantissa (low word, at most 9999 in magnitude) × 10^exponent
/// (high word, -41..35), when the result is a real number in range.
pub fn decimal_to_real(decimal: u32) -> i32 {
    let mantissa = i32::from(decimal as u16 as i16);
    let exponent = i32::from((decimal >> 16) as u16 as i16);
    if mantissa.abs() > 9999 || !(-41..=35).contains(&exponent) {
        return OUT_OF_RANGE;
    }
    let mut buffer = Buffer::new();
    if write!(buffer, "{mantissa}e{exponent}").is_err() {
        return OUT_OF_RANGE;
    }
    match buffer.text().parse::<f32>() {
        Ok(value) => checked(f64::from(value)),
        Err(_) => OUT_OF_RANGE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decimal(x: f32) -> (i16, i16) {
        let packed = real_to_decimal(x.to_bits());
        (packed as i16, (packed >> 16) as i16)
    }

    #[test]
    fn scientific_notation_both_ways() {
        assert_eq!(decimal(2345.67), (2345, 0));
        assert_eq!(decimal(-0.1), (-1000, -4));
        assert_eq!(decimal(f32::MAX), (3402, 35));
        assert_eq!(decimal(0.0), (0, 0));
        let pack = |m: i16, e: i16| (m as u16 as u32) | ((e as u16 as u32) << 16);
        assert_eq!(f32::from_bits(decimal_to_real(pack(5432, 12)) as u32), 5.432e15);
        assert_eq!(f32::from_bits(decimal_to_real(pack(-1000, -4)) as u32), -0.1);
        assert_eq!(decimal_to_real(pack(1, 40)), OUT_OF_RANGE);
        assert_eq!(decimal_to_real(pack(9999, 35)), OUT_OF_RANGE, "beyond the largest");
    }

    #[test]
    fn functions_check_their_domains() {
        assert_eq!(real_function(RealFunction::Asin as u32, 2.0f32.to_bits()), OUT_OF_RANGE);
        assert_eq!(real_function(RealFunction::Ln as u32, 0.0f32.to_bits()), OUT_OF_RANGE);
        assert_eq!(real_function(RealFunction::Exp as u32, 89.0f32.to_bits()), OUT_OF_RANGE);
        assert_eq!(
            real_function(RealFunction::Exp as u32, (-88.0f32).to_bits()),
            OUT_OF_RANGE
        );
        assert_eq!(
            f32::from_bits(real_function(RealFunction::Log10 as u32, 100.0f32.to_bits()) as u32),
            2.0
        );
    }
}
