//! Floating point: DEMOV, DEADD, DESUB, DEMUL, DEDIV, DECMP, DEZCP, DESQR,
//! DENEG, FLT, INT, DEBCD, DEBIN, the trigonometric functions, DRAD, DDEG,
//! DEXP, DLOGE, DLOG10 (docs/language.md, "Machine programs").
//!
//! A real number is IEEE-754 binary32 in a word pair, whatever the
//! instruction's width. A NaN or infinity as a source is 4084H and nothing
//! is written. Arithmetic is exact in double precision, then rounded to
//! single: a result below the smallest normal magnitude is 0 with M8021
//! (borrow), one beyond the largest is the largest with its sign and M8022
//! (carry); M8020 (zero) when what is written is 0.

use super::{Outcome, Step};
use ladder_front::program::{BitRef, WordRef};
use ladder_runtime::real::RealFunction;
use ladder_runtime::special::SpecialBit;
use ladder_runtime::{OperationError, Place, Width};

fn real(bits: i64) -> f32 {
    f32::from_bits(bits as u32)
}

fn bits(value: f32) -> i64 {
    i64::from(value.to_bits() as i32)
}

/// A real source, checked: a NaN or infinity is 4084H.
fn finite(value: f32) -> Result<f32, OperationError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(OperationError::DataOutOfRange)
    }
}

/// What is written for an exact result, with the flags zero, borrow, carry.
pub fn rounded(exact: f64) -> (f32, [bool; 3]) {
    let single = exact as f32;
    if exact == 0.0 {
        (0.0, [true, false, false])
    } else if exact.abs() < f64::from(f32::MIN_POSITIVE) {
        (0.0, [true, true, false])
    } else if single.is_infinite() {
        (f32::MAX.copysign(single), [false, false, true])
    } else {
        (single, [false, false, false])
    }
}

impl Step<'_> {
    /// A real source operand (always a pair).
    fn real_place(&mut self, word: &WordRef, read: bool) -> Option<Place> {
        self.resolve(word, Width::Double, 1, read)
    }

    fn real_value(&self, place: Option<Place>) -> Result<f32, OperationError> {
        finite(place.map_or(0.0, |p| real(self.read_at(p, Width::Double))))
    }

    fn write_real(&mut self, place: Option<Place>, value: f32) {
        if let Some(place) = place {
            self.write_at(place, Width::Double, bits(value));
        }
    }
}

/// D = kernel(S1, ..., Sn) on real numbers, with the instruction's flags
/// (declaration order) from the kernel.
pub fn map<const N: usize, const F: usize>(
    step: &mut Step,
    sources: [&WordRef; N],
    d: &WordRef,
    flags: &[SpecialBit],
    kernel: impl FnOnce([f32; N]) -> Result<(f32, [bool; F]), OperationError>,
) -> Outcome {
    let places = sources.map(|s| step.real_place(s, true));
    let d = step.real_place(d, false);
    step.commit()?;
    let mut values = [0.0f32; N];
    for (value, place) in values.iter_mut().zip(places) {
        *value = step.real_value(place)?;
    }
    let (result, on) = kernel(values)?;
    step.write_real(d, result);
    step.write_flags(flags, &on);
    Ok(())
}

pub fn mov([s]: [f32; 1]) -> Result<(f32, [bool; 0]), OperationError> {
    Ok((s, []))
}

pub fn add([a, b]: [f32; 2]) -> Result<(f32, [bool; 3]), OperationError> {
    Ok(rounded(f64::from(a) + f64::from(b)))
}

pub fn sub([a, b]: [f32; 2]) -> Result<(f32, [bool; 3]), OperationError> {
    Ok(rounded(f64::from(a) - f64::from(b)))
}

pub fn mul([a, b]: [f32; 2]) -> Result<(f32, [bool; 3]), OperationError> {
    Ok(rounded(f64::from(a) * f64::from(b)))
}

/// A zero divisor (+0 or -0) is 4084H.
pub fn div([a, b]: [f32; 2]) -> Result<(f32, [bool; 3]), OperationError> {
    if b == 0.0 {
        return Err(OperationError::DataOutOfRange);
    }
    Ok(rounded(f64::from(a) / f64::from(b)))
}

/// The root of a number that is not negative, and M8020 when it is 0.
pub fn sqr([s]: [f32; 1]) -> Result<(f32, [bool; 1]), OperationError> {
    if s < 0.0 {
        return Err(OperationError::DataOutOfRange);
    }
    let root = f64::from(s).sqrt() as f32;
    Ok((root, [root == 0.0]))
}

/// A mathematical function, rounded to single precision; `valid` says
/// which arguments it takes, and a result out of range is 4084H.
fn function(f: RealFunction, x: f32, valid: impl FnOnce(f32) -> bool) -> Result<(f32, [bool; 0]), OperationError> {
    if !valid(x) {
        return Err(OperationError::DataOutOfRange);
    }
    let y = f.apply(f64::from(x));
    let single = y as f32;
    // e^x is never 0: an exact 0 from DEXP is an underflow of the double.
    let underflow = y.abs() < f64::from(f32::MIN_POSITIVE) && (y != 0.0 || f == RealFunction::Exp);
    if !single.is_finite() || underflow {
        return Err(OperationError::DataOutOfRange);
    }
    Ok((single, []))
}

/// DSIN, DCOS, DTAN, DASIN, DACOS, DATAN, DEXP, DLOGE, DLOG10: the inverse
/// sine and cosine take -1..1, the logarithms numbers above 0.
pub fn apply(f: RealFunction) -> impl FnOnce([f32; 1]) -> Result<(f32, [bool; 0]), OperationError> {
    move |[x]| {
        function(f, x, |x| match f {
            RealFunction::Asin | RealFunction::Acos => (-1.0..=1.0).contains(&x),
            RealFunction::Ln | RealFunction::Log10 => x > 0.0,
            RealFunction::Sin | RealFunction::Cos | RealFunction::Tan | RealFunction::Atan | RealFunction::Exp => true,
        })
    }
}

/// DRAD (`to_radians`) and DDEG: degrees and radians.
pub fn angle(to_radians: bool) -> impl FnOnce([f32; 1]) -> Result<(f32, [bool; 0]), OperationError> {
    move |[x]| {
        let factor = if to_radians {
            core::f64::consts::PI / 180.0
        } else {
            180.0 / core::f64::consts::PI
        };
        let y = (f64::from(x) * factor) as f32;
        if y.is_finite() {
            Ok((y, []))
        } else {
            Err(OperationError::DataOutOfRange)
        }
    }
}

/// DENEG D: the sign of D changes.
pub fn neg(step: &mut Step, d: &WordRef) -> Outcome {
    let place = step.real_place(d, true);
    step.commit()?;
    let value = step.real_value(place)?;
    step.write_real(place, -value);
    Ok(())
}

/// DECMP (`zone` false: S1, S2) and DEZCP (S1, S2, S): three result bits.
pub fn compare(step: &mut Step, sources: &[&WordRef], d: &BitRef) -> Outcome {
    let places: Vec<Option<Place>> = sources.iter().map(|s| step.real_place(s, true)).collect();
    let d = step.bits(d, 3, false);
    step.commit()?;
    let values = places
        .into_iter()
        .map(|p| step.real_value(p))
        .collect::<Result<Vec<f32>, _>>()?;
    let results = match values[..] {
        [a, b] => [a > b, a == b, a < b],
        // A reversed zone counts as the single value S1, as in ZCP.
        [low, high, s] => {
            let high = if low > high { low } else { high };
            [s < low, low <= s && s <= high, s > high]
        }
        _ => return Ok(()),
    };
    if let Some(d) = d {
        for (unit, on) in (0..).zip(results) {
            step.write_at(d.nth(unit, Width::Single), Width::Single, i64::from(on));
        }
    }
    Ok(())
}

/// FLT/DFLT: the integer S (16 or 32 bits) as a real number.
pub fn flt(step: &mut Step, s: &WordRef, d: &WordRef) -> Outcome {
    let source = step.source(s);
    let d = step.real_place(d, false);
    step.commit()?;
    let value = source.map_or(0, |p| step.read(p));
    step.write_real(d, value as f32);
    Ok(())
}

/// INT/DINT: the real S toward zero, as an integer of the instruction's
/// width (4084H if it does not fit); M8020 when 0, M8021 when a fraction
/// was dropped, M8022 never (a result that does not fit is an error).
pub fn int(step: &mut Step, s: &WordRef, d: &WordRef, flags: &[SpecialBit]) -> Outcome {
    let source = step.real_place(s, true);
    let d = step.destination(d);
    step.commit()?;
    let value = step.real_value(source)?;
    let whole = value.trunc();
    let fits = match step.width {
        Width::Single => (-32768.0..=32767.0).contains(&whole),
        // 2^31 is the first real number past i32::MAX.
        Width::Double => (-2_147_483_648.0..2_147_483_648.0).contains(&whole),
    };
    if !fits {
        return Err(OperationError::DataOutOfRange);
    }
    let integer = whole as i64;
    if let Some(d) = d {
        step.write(d, integer);
    }
    step.write_flags(flags, &[integer == 0, whole != value, false]);
    Ok(())
}

/// DEBCD: the real S in scientific notation: D = a 4-digit mantissa
/// (1000-9999 with its sign, the further digits dropped), D+1 = the
/// decimal exponent; 0 is 0 × 10^0. The digits are those of the shortest
/// decimal that reads back as S.
pub fn to_decimal(step: &mut Step, s: &WordRef, d: &WordRef) -> Outcome {
    let source = step.real_place(s, true);
    let d = step.real_place(d, false);
    step.commit()?;
    let value = step.real_value(source)?;
    let (mantissa, exponent) = decimal_of(value);
    if let Some(d) = d {
        step.write_at(d, Width::Single, i64::from(mantissa));
        step.write_at(d.nth(1, Width::Single), Width::Single, i64::from(exponent));
    }
    Ok(())
}

fn decimal_of(value: f32) -> (i16, i16) {
    if value == 0.0 {
        return (0, 0);
    }
    let text = format!("{:e}", value.abs());
    let (digits, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let mut mantissa: i32 = 0;
    let mut taken = 0;
    for digit in digits.chars().filter_map(|c| c.to_digit(10)) {
        if taken == 4 {
            break;
        }
        mantissa = mantissa * 10 + digit as i32;
        taken += 1;
    }
    while taken < 4 {
        mantissa *= 10;
        taken += 1;
    }
    let signed = if value < 0.0 { -mantissa } else { mantissa };
    (signed as i16, (exponent - 3) as i16)
}

/// DEBIN: the mantissa S and exponent S+1 (scientific notation) as a real
/// number: |mantissa| at most 9999, exponent -41..35, a result in range.
pub fn from_decimal(step: &mut Step, s: &WordRef, d: &WordRef) -> Outcome {
    let source = step.real_place(s, true);
    let d = step.real_place(d, false);
    step.commit()?;
    let Some(source) = source else { return Ok(()) };
    let mantissa = step.read_at(source, Width::Single);
    let exponent = step.read_at(source.nth(1, Width::Single), Width::Single);
    if mantissa.abs() > 9999 || !(-41..=35).contains(&exponent) {
        return Err(OperationError::DataOutOfRange);
    }
    let value: f32 = format!("{mantissa}e{exponent}").parse().unwrap_or(f32::NAN);
    if !value.is_finite() || (value != 0.0 && value.abs() < f32::MIN_POSITIVE) {
        return Err(OperationError::DataOutOfRange);
    }
    step.write_real(d, value);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_and_flags() {
        assert_eq!(rounded(1.5), (1.5, [false, false, false]));
        assert_eq!(rounded(1e-60), (0.0, [true, true, false]));
        assert_eq!(rounded(-1e39), (-f32::MAX, [false, false, true]));
        assert_eq!(rounded(0.0), (0.0, [true, false, false]));
    }

    #[test]
    fn scientific_notation() {
        assert_eq!(decimal_of(2345.67), (2345, 0));
        assert_eq!(decimal_of(-0.1), (-1000, -4));
        assert_eq!(decimal_of(core::f32::consts::PI), (3141, -3));
        assert_eq!(decimal_of(f32::MAX), (3402, 35));
        assert_eq!(decimal_of(f32::MIN_POSITIVE), (1175, -41));
        assert_eq!(decimal_of(3.4567e-5), (3456, -8));
    }
}
