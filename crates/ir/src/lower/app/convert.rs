//! Conversions: SWAP, ENCO, DECO, BTOW, WTOB, DIS, UNI, BCD, BIN.

use super::Step;
use crate::lower::operand::{Operand, Units};
use crate::CompareOp;
use crate::{BinOp, Index, Inst, Type, UnaryOp, Value};
use ladder_front::program::{Element, WordRef};
use ladder_runtime::helpers::Helper;
use ladder_runtime::{OperationError, Width};

fn constant(step: &mut Step, value: i64) -> Value {
    step.b().constant(Type::I64, value)
}

/// Bytes of each 16-bit word exchanged: (v >> 8) & 0x00FF00FF moves the
/// high bytes down, (v & 0x00FF00FF) << 8 the low bytes up.
pub fn swap(step: &mut Step, d: Value) -> Value {
    let low_bytes = constant(step, 0x00FF_00FF);
    let eight = constant(step, 8);
    let b = step.b();
    let down = b.binary(BinOp::Shr, d, eight);
    let down = b.binary(BinOp::And, down, low_bytes);
    let up = b.binary(BinOp::And, d, low_bytes);
    let up = b.binary(BinOp::Shl, up, eight);
    b.binary(BinOp::Or, down, up)
}

/// 1 << `n` as an I64.
fn power_of_two(step: &mut Step, n: Value) -> Value {
    let one = constant(step, 1);
    step.b().binary(BinOp::Shl, one, n)
}

fn as_i32(step: &mut Step, value: Value) -> Value {
    step.b().truncate(value, Type::I32)
}

/// The exponent N of ENCO/DECO, after N = 0 left without processing:
/// 1-8 for bit devices, 1-4 for a word, else 4084H.
fn exponent(step: &mut Step, n: &WordRef, element: &Element) -> Value {
    let n = step.count_value(n);
    let zero = constant(step, 0);
    let nonzero = step.b().compare(CompareOp::Ne, n, zero);
    step.skip_unless(nonzero);
    let limit = match element {
        Element::Bits(_) => 8,
        Element::Word(_) => 4,
    };
    step.require_within(n, 1, limit);
    n
}

/// ENCO S N D: the number of the highest ON bit among 2^N bits from S;
/// none ON records 4084H.
pub fn encode(step: &mut Step, s: &Element, n: &WordRef, d: &WordRef) {
    let n = exponent(step, n, s);
    let count = power_of_two(step, n);
    let highest = match s {
        Element::Bits(bit) => {
            let count = as_i32(step, count);
            let source = step.bits(bit, Units::Dynamic(count), true);
            let destination = step.destination(d);
            step.commit();
            let place = step.l.place(&source);
            let found = step.b().call(Helper::HighestOn, vec![place, count]);
            let found = found.unwrap_or_else(|| step.b().constant(Type::I32, -1));
            let found = step.b().extend(found, Type::I64, true);
            (found, destination)
        }
        Element::Word(word) => {
            let source = step.count(word);
            let destination = step.destination(d);
            step.commit();
            let value = step.read_at(&source, Width::Single);
            let one = constant(step, 1);
            let b = step.b();
            let mask = b.binary(BinOp::Shl, one, count);
            let mask = b.binary(BinOp::Sub, mask, one);
            let bits = b.binary(BinOp::And, value, mask);
            let zeros = b.push(Inst::Unary {
                op: UnaryOp::LeadingZeros,
                value: bits,
            });
            let sixty_three = b.constant(Type::I64, 63);
            // With no bit ON this is -1, which the check below refuses.
            (b.binary(BinOp::Sub, sixty_three, zeros), destination)
        }
    };
    let (highest, destination) = highest;
    let zero = constant(step, 0);
    let found = step.b().compare(CompareOp::Ge, highest, zero);
    step.require(found, OperationError::DataOutOfRange);
    step.write(&destination, highest);
}

/// DECO S N D: of 2^N bits from D (or the 16 bits of a word D), the one
/// numbered by the low N bits of S ON, the rest OFF.
pub fn decode(step: &mut Step, s: &Element, n: &WordRef, d: &Element) {
    let n = exponent(step, n, d);
    let n32 = as_i32(step, n);
    let source = match s {
        Element::Bits(bit) => step.bits(bit, Units::Dynamic(n32), true),
        Element::Word(word) => step.count(word),
    };
    let outputs = power_of_two(step, n);
    let destination = match d {
        Element::Bits(bit) => {
            let count = as_i32(step, outputs);
            step.bits(bit, Units::Dynamic(count), false)
        }
        Element::Word(word) => step.destination(word),
    };
    step.commit();
    // The number: the low N bits of S. Bit devices are read up to the most
    // N allows (8); bits at or past N are masked off.
    let value = match s {
        Element::Bits(_) => {
            let mut value = constant(step, 0);
            for k in 0..8u32 {
                let unit = step.l.nth(&source, k, Width::Single);
                // A bit past its area's end is at or past N here (a run of
                // N bits past the end is error 4085H, caught above): it is
                // masked off, so it is not read.
                let past_the_end = match unit {
                    Operand::Bit(area, Index::Fixed(n)) => n >= area.count(),
                    Operand::WordBit(area, Index::Fixed(n)) => n / 16 >= area.count(),
                    Operand::Bit(_, Index::Dynamic(_))
                    | Operand::WordBit(_, Index::Dynamic(_))
                    | Operand::Constant(_)
                    | Operand::Word(..)
                    | Operand::WideCounter(_)
                    | Operand::Digits(..) => false,
                };
                if past_the_end {
                    continue;
                }
                let bit = step.read_at(&unit, Width::Single);
                let shift = constant(step, i64::from(k));
                let placed = step.b().binary(BinOp::Shl, bit, shift);
                value = step.b().binary(BinOp::Or, value, placed);
            }
            value
        }
        Element::Word(_) => step.read_at(&source, Width::Single),
    };
    let one = constant(step, 1);
    let b = step.b();
    let mask = b.binary(BinOp::Sub, outputs, one);
    let number = b.binary(BinOp::And, value, mask);
    match d {
        Element::Bits(_) => {
            let place = step.l.place(&destination);
            let count = as_i32(step, outputs);
            let width = step.b().number(1);
            let off = step.b().constant(Type::I32, 0);
            step.b().call(Helper::Fill, vec![place, count, width, off]);
            let offset = as_i32(step, number);
            let target = match destination {
                Operand::Bit(area, index) => Operand::Bit(area, step.l.index_plus_value(index, offset)),
                Operand::WordBit(area, index) => Operand::WordBit(area, step.l.index_plus_value(index, offset)),
                Operand::Constant(_) | Operand::Word(..) | Operand::WideCounter(_) | Operand::Digits(..) => destination,
            };
            let on = step.b().bit(true);
            step.write_bit(&target, on);
        }
        Element::Word(_) => {
            let bit = power_of_two(step, number);
            step.write(&destination, bit);
        }
    }
}

/// BTOW (`split` false) and WTOB (`split` true) through the runtime, which
/// orders the work so that overlapping ranges come out as if read first.
pub fn bytes(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef, split: bool) {
    let n = step.count_value(n);
    step.require_within(n, 0, i64::from(i16::MAX));
    let zero = constant(step, 0);
    let nonzero = step.b().compare(CompareOp::Ne, n, zero);
    step.skip_unless(nonzero);
    let n = as_i32(step, n);
    let b = step.b();
    let one = b.constant(Type::I32, 1);
    let rounded = b.binary(BinOp::Add, n, one);
    let words = b.binary(BinOp::Shr, rounded, one);
    let (inputs, outputs) = if split { (words, n) } else { (n, words) };
    let source = step.resolve(s, Width::Single, Units::Dynamic(inputs), true);
    let destination = step.resolve(d, Width::Single, Units::Dynamic(outputs), false);
    step.commit();
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    let split = step.b().number(u32::from(split));
    step.b().call(Helper::Bytes, vec![source, destination, n, split]);
}

/// The count of DIS and UNI: 0-4 (else 4084H), and N = 0 does nothing.
fn nibble_count(step: &mut Step, n: &WordRef) -> Value {
    let n = step.count_value(n);
    step.require_within(n, 0, 4);
    let zero = constant(step, 0);
    let nonzero = step.b().compare(CompareOp::Ne, n, zero);
    step.skip_unless(nonzero);
    n
}

/// `k < n` for an I64 count.
fn below(step: &mut Step, k: u32, n: Value) -> Value {
    let k = constant(step, i64::from(k));
    step.b().compare(CompareOp::Lt, k, n)
}

/// DIS S D N: digit k of S into D+k for k < N (each write only when it is
/// within N, since D+k beyond N was not checked).
pub fn distribute(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = nibble_count(step, n);
    let count = as_i32(step, n);
    let source = step.source(s);
    let destination = step.resolve(d, Width::Single, Units::Dynamic(count), false);
    step.commit();
    let value = step.read(&source);
    for k in 0..4u32 {
        let within = below(step, k, n);
        let shift = constant(step, i64::from(4 * k));
        let fifteen = constant(step, 0xF);
        let b = step.b();
        let shifted = b.binary(BinOp::Shr, value, shift);
        let digit = b.binary(BinOp::And, shifted, fifteen);
        step.l.when(within, |lowering, _| {
            let unit = lowering.nth(&destination, k, Width::Single);
            lowering.write(&unit, Width::Single, digit);
        });
    }
}

/// UNI S D N: the low 4 bits of S+k as digit k of D for k < N, higher digits
/// 0. Words at or past N are read (inside the image) but not used.
pub fn unite(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = nibble_count(step, n);
    let count = as_i32(step, n);
    let source = step.resolve(s, Width::Single, Units::Dynamic(count), true);
    let destination = step.destination(d);
    step.commit();
    let mut value = constant(step, 0);
    for k in 0..4u32 {
        let within = below(step, k, n);
        let unit = step.l.nth(&source, k, Width::Single);
        let word = step.read(&unit);
        let fifteen = constant(step, 0xF);
        let shift = constant(step, i64::from(4 * k));
        let zero = constant(step, 0);
        let b = step.b();
        let digit = b.binary(BinOp::And, word, fifteen);
        let placed = b.binary(BinOp::Shl, digit, shift);
        let placed = b.select(within, placed, zero);
        value = b.binary(BinOp::Or, value, placed);
    }
    step.write(&destination, value);
}

/// BCD S D: S within 0..=9999 (99999999), else 4084H; each decimal digit by
/// division into its 4 bits.
pub fn bcd(step: &mut Step, [s]: [Value; 1]) -> Value {
    let digits = step.width.bits() / 4;
    step.require_within(s, 0, 10i64.pow(digits) - 1);
    let ten = constant(step, 10);
    let mut rest = s;
    let mut bcd = constant(step, 0);
    for position in 0..digits {
        let b = step.b();
        let digit = b.binary(BinOp::Rem, rest, ten);
        rest = b.binary(BinOp::Div, rest, ten);
        let shift = b.constant(Type::I64, i64::from(4 * position));
        let placed = b.binary(BinOp::Shl, digit, shift);
        bcd = b.binary(BinOp::Or, bcd, placed);
    }
    bcd
}

/// BIN S D: every 4-bit digit of S at most 9, else 4084H.
pub fn bin(step: &mut Step, [s]: [Value; 1]) -> Value {
    let bits = step.width.bits();
    let mask = constant(step, (1i64 << bits) - 1);
    let (fifteen, nine, ten) = (constant(step, 15), constant(step, 9), constant(step, 10));
    let b = step.b();
    let unsigned = b.binary(BinOp::And, s, mask);
    let mut valid = b.bit(true);
    let mut value = b.constant(Type::I64, 0);
    for position in (0..bits / 4).rev() {
        let shift = b.constant(Type::I64, i64::from(4 * position));
        let shifted = b.binary(BinOp::UShr, unsigned, shift);
        let digit = b.binary(BinOp::And, shifted, fifteen);
        let decimal = b.compare(CompareOp::Le, digit, nine);
        valid = b.and(valid, decimal);
        let scaled = b.binary(BinOp::Mul, value, ten);
        value = b.binary(BinOp::Add, scaled, digit);
    }
    step.require(valid, OperationError::DataOutOfRange);
    value
}
