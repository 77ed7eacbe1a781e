//! Floating point in the lowering: real numbers are loaded as the bits of
//! a word pair, cast to F32 and widened to F64, so that every result is
//! exact before it is rounded to single precision, as the interpreter
//! computes it. The mathematical functions and the scientific notation
//! call the runtime's helpers.

use super::Step;
use crate::lower::operand::{Operand, Units};
use crate::CompareOp;
use crate::{BinOp, Conversion, FloatOp, FloatUnaryOp, Type, Value};
use ladder_front::program::{BitRef, WordRef};
use ladder_runtime::helpers::Helper;
use ladder_runtime::real::RealFunction;
use ladder_runtime::special::SpecialBit;
use ladder_runtime::{OperationError, Width};

/// The exponent bits of binary32: all ON for a NaN or an infinity.
const EXPONENT: i64 = 0x7F80_0000;

impl Step<'_, '_> {
    fn real_operand(&mut self, word: &WordRef, read: bool) -> Operand {
        self.resolve(word, Width::Double, Units::Checked(1), read)
    }

    /// The I32 bits of a real operand.
    fn real_bits(&mut self, operand: &Operand) -> Value {
        let value = self.read_at(operand, Width::Double);
        self.b().truncate(value, Type::I32)
    }

    /// Leaves with 4084H unless the bits are a finite number.
    fn require_finite(&mut self, bits: Value) {
        let b = self.b();
        let mask = b.constant(Type::I32, EXPONENT);
        let exponent = b.binary(BinOp::And, bits, mask);
        let finite = b.compare(CompareOp::Ne, exponent, mask);
        self.require(finite, OperationError::DataOutOfRange);
    }

    /// The F64 of real bits (exact).
    fn widen(&mut self, bits: Value) -> Value {
        let b = self.b();
        let single = b.bitcast(bits, Type::F32);
        b.convert(single, Type::F64, Conversion::FloatToFloat)
    }

    /// Writes an F32 to a real operand.
    fn write_real(&mut self, operand: &Operand, value: Value) {
        let b = self.b();
        let bits = b.bitcast(value, Type::I32);
        let wide = b.extend(bits, Type::I64, true);
        self.l.write(operand, Width::Double, wide);
    }

    fn write_flags(&mut self, flags: &[SpecialBit], on: &[Value]) {
        for (flag, &on) in flags.iter().zip(on) {
            self.b().store_bit(flag.area, crate::Index::Fixed(flag.number), on);
        }
    }
}

/// What is written for an exact F64 result (an F32) and the flags zero,
/// borrow, carry: 0 below the smallest normal magnitude, the largest with
/// its sign beyond the largest.
fn rounded(step: &mut Step, exact: Value) -> (Value, [Value; 3]) {
    let b = step.b();
    let zero64 = b.real64(0.0);
    let smallest = b.real64(f64::from(f32::MIN_POSITIVE));
    let magnitude = b.float_unary(FloatUnaryOp::Abs, exact);
    let is_zero = b.float_compare(CompareOp::Eq, exact, zero64);
    let tiny = b.float_compare(CompareOp::Lt, magnitude, smallest);
    let single = b.convert(exact, Type::F32, Conversion::FloatToFloat);
    let bits = b.bitcast(single, Type::I32);
    let no_sign = b.constant(Type::I32, 0x7FFF_FFFF);
    let magnitude_bits = b.binary(BinOp::And, bits, no_sign);
    let infinity = b.constant(Type::I32, EXPONENT);
    let overflow = b.compare(CompareOp::Eq, magnitude_bits, infinity);
    let negative = b.float_compare(CompareOp::Lt, exact, zero64);
    let largest = b.real(f32::MAX);
    let lowest = b.real(-f32::MAX);
    let limit = b.select(negative, lowest, largest);
    let zero32 = b.real(0.0);
    let kept = b.select(overflow, limit, single);
    let result = b.select(tiny, zero32, kept);
    let not_zero = b.not(is_zero);
    let borrow = b.and(tiny, not_zero);
    let not_tiny = b.not(tiny);
    let carry = b.and(overflow, not_tiny);
    (result, [tiny, borrow, carry])
}

/// D = kernel(S1, ..., Sn) on real numbers (F64 in, F32 and flags out).
pub fn map<const N: usize, const F: usize>(
    step: &mut Step,
    sources: [&WordRef; N],
    d: &WordRef,
    flags: &[SpecialBit],
    kernel: impl FnOnce(&mut Step, [Value; N]) -> (Value, [Value; F]),
) {
    let sources = sources.map(|s| step.real_operand(s, true));
    let d = step.real_operand(d, false);
    step.commit();
    let bits = sources.map(|s| step.real_bits(&s));
    for &value in &bits {
        step.require_finite(value);
    }
    let values = bits.map(|v| step.widen(v));
    let (result, on) = kernel(step, values);
    step.write_real(&d, result);
    step.write_flags(flags, &on);
}

pub fn mov(step: &mut Step, [s]: [Value; 1]) -> (Value, [Value; 0]) {
    (step.b().convert(s, Type::F32, Conversion::FloatToFloat), [])
}

fn arithmetic(step: &mut Step, op: FloatOp, a: Value, b: Value) -> (Value, [Value; 3]) {
    let exact = step.b().float(op, a, b);
    rounded(step, exact)
}

pub fn add(step: &mut Step, [a, b]: [Value; 2]) -> (Value, [Value; 3]) {
    arithmetic(step, FloatOp::Add, a, b)
}

pub fn sub(step: &mut Step, [a, b]: [Value; 2]) -> (Value, [Value; 3]) {
    arithmetic(step, FloatOp::Sub, a, b)
}

pub fn mul(step: &mut Step, [a, b]: [Value; 2]) -> (Value, [Value; 3]) {
    arithmetic(step, FloatOp::Mul, a, b)
}

/// A zero divisor is 4084H.
pub fn div(step: &mut Step, [a, b]: [Value; 2]) -> (Value, [Value; 3]) {
    let zero = step.b().real64(0.0);
    let nonzero = step.b().float_compare(CompareOp::Ne, b, zero);
    step.require(nonzero, OperationError::DataOutOfRange);
    arithmetic(step, FloatOp::Div, a, b)
}

/// The root of a number that is not negative; M8020 when it is 0.
pub fn sqr(step: &mut Step, [s]: [Value; 1]) -> (Value, [Value; 1]) {
    let zero = step.b().real64(0.0);
    let valid = step.b().float_compare(CompareOp::Ge, s, zero);
    step.require(valid, OperationError::DataOutOfRange);
    let b = step.b();
    let root = b.float_unary(FloatUnaryOp::SquareRoot, s);
    let single = b.convert(root, Type::F32, Conversion::FloatToFloat);
    let zero32 = b.real(0.0);
    let is_zero = b.float_compare(CompareOp::Eq, single, zero32);
    (single, [is_zero])
}

/// The helper's result: the F32 of a function, or a NaN for an argument
/// or a result out of range (then 4084H).
pub fn apply(function: RealFunction) -> impl FnOnce(&mut Step, [Value; 1]) -> (Value, [Value; 0]) {
    move |step, [x]| {
        let b = step.b();
        let single = b.convert(x, Type::F32, Conversion::FloatToFloat);
        let bits = b.bitcast(single, Type::I32);
        let code = b.number(function as u32);
        let result = b
            .call(Helper::RealFunction, vec![code, bits])
            .unwrap_or_else(|| step.l.b.constant(Type::I32, 0));
        step.require_finite(result);
        (step.b().bitcast(result, Type::F32), [])
    }
}

/// DRAD (`to_radians`) and DDEG; a result out of range is 4084H.
pub fn angle(to_radians: bool) -> impl FnOnce(&mut Step, [Value; 1]) -> (Value, [Value; 0]) {
    move |step, [x]| {
        let factor = if to_radians {
            core::f64::consts::PI / 180.0
        } else {
            180.0 / core::f64::consts::PI
        };
        let b = step.b();
        let factor = b.real64(factor);
        let product = b.float(FloatOp::Mul, x, factor);
        let single = b.convert(product, Type::F32, Conversion::FloatToFloat);
        let bits = b.bitcast(single, Type::I32);
        step.require_finite(bits);
        (single, [])
    }
}

/// DENEG D: the sign bit of D changes.
pub fn neg(step: &mut Step, d: &WordRef) {
    let d = step.real_operand(d, true);
    step.commit();
    let bits = step.real_bits(&d);
    step.require_finite(bits);
    let b = step.b();
    let sign = b.constant(Type::I32, i64::from(i32::MIN));
    let flipped = b.binary(BinOp::Xor, bits, sign);
    let wide = b.extend(flipped, Type::I64, true);
    step.l.write(&d, Width::Double, wide);
}

/// DECMP (two sources) and DEZCP (S1, S2, S): three result bits.
pub fn compare(step: &mut Step, sources: &[&WordRef], d: &BitRef) {
    let operands: Vec<Operand> = sources.iter().map(|s| step.real_operand(s, true)).collect();
    let d = step.bits(d, Units::Checked(3), false);
    step.commit();
    let bits: Vec<Value> = operands.iter().map(|o| step.real_bits(o)).collect();
    for &value in &bits {
        step.require_finite(value);
    }
    let values: Vec<Value> = bits.into_iter().map(|v| step.widen(v)).collect();
    let b = step.b();
    let results = match values[..] {
        [a, c] => [
            b.float_compare(CompareOp::Gt, a, c),
            b.float_compare(CompareOp::Eq, a, c),
            b.float_compare(CompareOp::Lt, a, c),
        ],
        [low, high, s] => {
            // A reversed zone counts as the single value S1, as in ZCP.
            let reversed = b.float_compare(CompareOp::Gt, low, high);
            let high = b.select(reversed, low, high);
            let below = b.float_compare(CompareOp::Lt, s, low);
            let from_low = b.float_compare(CompareOp::Le, low, s);
            let to_high = b.float_compare(CompareOp::Le, s, high);
            let inside = b.and(from_low, to_high);
            let above = b.float_compare(CompareOp::Gt, s, high);
            [below, inside, above]
        }
        _ => return,
    };
    for (unit, on) in (0..).zip(results) {
        let target = step.l.nth(&d, unit, Width::Single);
        step.write_bit(&target, on);
    }
}

/// FLT/DFLT: the integer S as the nearest real number.
pub fn flt(step: &mut Step, s: &WordRef, d: &WordRef) {
    let s = step.source(s);
    let d = step.real_operand(d, false);
    step.commit();
    let value = step.read(&s);
    let single = step.b().convert(value, Type::F32, Conversion::IntToFloat);
    step.write_real(&d, single);
}

/// INT/DINT: toward zero; 4084H when it does not fit the width; M8020
/// when 0, M8021 when a fraction was dropped, M8022 OFF.
pub fn int(step: &mut Step, s: &WordRef, d: &WordRef, flags: &[SpecialBit]) {
    let s = step.real_operand(s, true);
    let d = step.destination(d);
    step.commit();
    let bits = step.real_bits(&s);
    step.require_finite(bits);
    let value = step.widen(bits);
    let (min, max) = match step.width {
        Width::Single => (i64::from(i16::MIN), i64::from(i16::MAX)),
        Width::Double => (i64::from(i32::MIN), i64::from(i32::MAX)),
    };
    let whole = step.b().convert(value, Type::I64, Conversion::FloatToInt);
    step.require_within(whole, min, max);
    let b = step.b();
    let back = b.convert(whole, Type::F64, Conversion::IntToFloat);
    let dropped = b.float_compare(CompareOp::Ne, back, value);
    let zero = b.constant(Type::I64, 0);
    let is_zero = b.compare(CompareOp::Eq, whole, zero);
    let never = b.bit(false);
    step.write(&d, whole);
    step.write_flags(flags, &[is_zero, dropped, never]);
}

/// DEBCD: the helper packs the mantissa (low word) and exponent (high word).
pub fn to_decimal(step: &mut Step, s: &WordRef, d: &WordRef) {
    let s = step.real_operand(s, true);
    let d = step.real_operand(d, false);
    step.commit();
    let bits = step.real_bits(&s);
    step.require_finite(bits);
    let packed = step
        .b()
        .call(Helper::RealToDecimal, vec![bits])
        .unwrap_or_else(|| step.l.b.constant(Type::I32, 0));
    let wide = step.b().extend(packed, Type::I64, true);
    step.l.write(&d, Width::Double, wide);
}

/// DEBIN: the helper gives the real number's bits, or a NaN when the
/// notation or the result is out of range (4084H).
pub fn from_decimal(step: &mut Step, s: &WordRef, d: &WordRef) {
    let s = step.real_operand(s, true);
    let d = step.real_operand(d, false);
    step.commit();
    let packed = step.real_bits(&s);
    let bits = step
        .b()
        .call(Helper::DecimalToReal, vec![packed])
        .unwrap_or_else(|| step.l.b.constant(Type::I32, 0));
    step.require_finite(bits);
    let wide = step.b().extend(bits, Type::I64, true);
    step.l.write(&d, Width::Double, wide);
}
