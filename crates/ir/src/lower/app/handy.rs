//! Handy, display and table instructions in the lowering: counts and
//! operands are resolved and checked here (in the interpreter's order), the
//! work is done by the runtime's helpers.

use super::{Execution, Step};
use crate::lower::operand::Units;
use crate::CompareOp;
use crate::{BinOp, Index, Type, Value};
use ladder_front::program::{Address, BitRef, CounterRef, WordRef};
use ladder_runtime::compiled::handy::CharacterOp;
use ladder_runtime::helpers::{width_arg, Helper};
use ladder_runtime::special::M_EIGHT_BIT_MODE_FX;
use ladder_runtime::{BitArea, OperationError, Width};

impl Step<'_, '_> {
    /// A count read on its own, required within `low..=high`, as an I32.
    fn count_within(&mut self, n: &WordRef, low: i64, high: i64) -> Value {
        let n = self.count_value(n);
        self.require_within(n, low, high);
        self.b().truncate(n, Type::I32)
    }

    fn i32_of(&mut self, value: Value) -> Value {
        self.b().truncate(value, Type::I32)
    }

    /// `a` / `b` rounded up, for I32 values and a constant `b`.
    fn ceil_div(&mut self, a: Value, b: i64) -> Value {
        let b_ = self.b();
        let plus = b_.constant(Type::I32, b - 1);
        let sum = b_.binary(BinOp::Add, a, plus);
        let divisor = b_.constant(Type::I32, b);
        b_.binary(BinOp::Div, sum, divisor)
    }

    /// Leaves the instruction unless `power`; before leaving, the
    /// instance starts afresh.
    fn off_resets(&mut self, instance: u32, power: Value) {
        let off = self.b().not(power);
        self.when(off, |step| {
            let instance = step.b().number(instance);
            step.b().call(Helper::InstanceOff, vec![instance]);
        });
        self.skip_unless(power);
    }
}

/// SER / DSER S1 S2 D n.
pub fn search(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &WordRef, n: &WordRef) {
    let width = step.width;
    let n = step.source_value(n);
    let limit = if width == Width::Double { 128 } else { 256 };
    step.require_within(n, 1, limit);
    let n = step.i32_of(n);
    let table = step.resolve(s1, width, Units::Dynamic(n), true);
    let key = step.source(s2);
    let five = step.run_of(5);
    let d = step.resolve(d, width, five, false);
    step.commit();
    let key = step.read(&key);
    let key = step.i32_of(key);
    let (table, d) = (step.l.place(&table), step.l.place(&d));
    let width = step.b().number(width_arg(width));
    step.b().call(Helper::Search, vec![table, n, key, d, width]);
}

/// ABSD / DABSD S1 S2 D n.
pub fn absolute_drum(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &BitRef, n: &WordRef) {
    let width = step.width;
    let n = step.count_within(n, 1, 64);
    let two = step.b().constant(Type::I32, 2);
    let points = step.b().binary(BinOp::Mul, n, two);
    let table = step.resolve(s1, width, Units::Dynamic(points), true);
    let counter = step.source(s2);
    let d = step.bits(d, Units::Dynamic(n), false);
    step.commit();
    let value = step.read(&counter);
    let value = step.i32_of(value);
    let (table, d) = (step.l.place(&table), step.l.place(&d));
    let width = step.b().number(width_arg(width));
    step.b().call(Helper::AbsoluteDrum, vec![table, n, value, d, width]);
}

/// INCD S1 S2 D n (every scan).
pub fn incremental_drum(step: &mut Step, run: &Execution, s1: &WordRef, s2: &CounterRef, d: &BitRef, n: &WordRef) {
    let n = step.count_within(n, 1, 64);
    let table = step.resolve(s1, Width::Single, Units::Dynamic(n), true);
    let counter = step.address_number(s2.0, 0, 199);
    let d = step.bits(d, Units::Dynamic(n), false);
    step.commit();
    let (table, d) = (step.l.place(&table), step.l.place(&d));
    let power = step.b().extend(run.power, Type::I32, false);
    step.b()
        .call(Helper::IncrementalDrum, vec![table, n, counter, d, power]);
}

/// RAMP S1 S2 D n (every scan).
pub fn ramp(step: &mut Step, run: &Execution, s1: &WordRef, s2: &WordRef, d: &WordRef, n: &WordRef) {
    step.off_resets(run.job, run.power);
    let n = step.count_within(n, 1, 32_767);
    let from = step.count(s1);
    let to = step.count(s2);
    let two = step.run_of(2);
    let d = step.resolve(d, Width::Single, two, false);
    step.commit();
    let from = step.read_at(&from, Width::Single);
    let from = step.i32_of(from);
    let to = step.read_at(&to, Width::Single);
    let to = step.i32_of(to);
    let d = step.l.place(&d);
    let instance = step.b().number(run.job);
    step.b().call(Helper::Ramp, vec![instance, from, to, d, n]);
}

/// TTMR D n (every scan).
pub fn teaching_timer(step: &mut Step, run: &Execution, d: &WordRef, n: &WordRef) {
    let n = step.count_within(n, 0, 2);
    let two = step.run_of(2);
    let d = step.resolve(d, Width::Single, two, false);
    step.commit();
    let d = step.l.place(&d);
    let instance = step.b().number(run.job);
    let power = step.b().extend(run.power, Type::I32, false);
    step.b().call(Helper::TeachingTimer, vec![instance, power, d, n]);
}

/// STMR S m D (every scan).
pub fn special_timer(step: &mut Step, run: &Execution, s: &Address, m: &WordRef, d: &BitRef) {
    let m = step.count_within(m, 1, 32_767);
    let timer = step.address_number(*s, 0, 200);
    let d = step.bits(d, Units::Checked(4), false);
    step.commit();
    let d = step.l.place(&d);
    let instance = step.b().number(run.job);
    let power = step.b().extend(run.power, Type::I32, false);
    step.b().call(Helper::SpecialTimer, vec![instance, power, timer, m, d]);
}

/// SEGD S D: the segments of the low digit of S into the low byte of D.
pub fn segment_decode(step: &mut Step, s: &WordRef, d: &WordRef) {
    let s = step.source(s);
    let d = step.destination(d);
    step.commit();
    let value = step.read(&s);
    let digit = step.i32_of(value);
    let segments = match step.b().call(Helper::Segments, vec![digit]) {
        Some(code) => code,
        None => step.b().constant(Type::I32, 0),
    };
    let kept = step.read(&d);
    let b = step.b();
    let high = b.constant(Type::I64, !0xFF);
    let kept = b.binary(BinOp::And, kept, high);
    let segments = b.extend(segments, Type::I64, false);
    let value = b.binary(BinOp::Or, kept, segments);
    step.write(&d, value);
}

/// SEGL S D n (every scan).
pub fn segment_latch(step: &mut Step, run: &Execution, s: &WordRef, d: &BitRef, n: &WordRef) {
    step.off_resets(run.job, run.power);
    let n = step.count_within(n, 0, 7);
    let b = step.b();
    let four = b.constant(Type::I32, 4);
    let two_sets = b.compare(CompareOp::Ge, n, four);
    let (one, two) = (b.constant(Type::I32, 1), b.constant(Type::I32, 2));
    let sets = b.select(two_sets, two, one);
    let (eight, twelve) = (b.constant(Type::I32, 8), b.constant(Type::I32, 12));
    let outputs = b.select(two_sets, twelve, eight);
    let s = step.resolve(s, Width::Single, Units::Dynamic(sets), true);
    let d = step.bits(d, Units::Dynamic(outputs), false);
    step.commit();
    let first = step.read_at(&s, Width::Single);
    let first = step.i32_of(first);
    // The second set's value only counts with two sets (the read of a
    // word past the operand is clamped to the image, and then unused).
    let next = step.l.nth(&s, 1, Width::Single);
    let second = step.read_at(&next, Width::Single);
    let second = step.i32_of(second);
    let zero = step.b().constant(Type::I32, 0);
    let second = step.b().select(two_sets, second, zero);
    let d = step.l.place(&d);
    let instance = step.b().number(run.job);
    let answer = match step
        .b()
        .call(Helper::SegmentLatch, vec![instance, first, second, sets, d, n])
    {
        Some(answer) => answer,
        None => step.b().constant(Type::I32, 0),
    };
    let zero = step.b().constant(Type::I32, 0);
    let ok = step.b().compare(CompareOp::Ne, answer, zero);
    step.require(ok, OperationError::DataOutOfRange);
}

/// ASCI S D n: hex digits to characters.
pub fn ascii(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    characters(step, CharacterOp::Ascii, s, d, n);
}

/// HEX S D n: characters to hex digits.
pub fn hex(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    characters(step, CharacterOp::Hex, s, d, n);
}

/// CCD S D n: the sum and parity of n characters.
pub fn check_code(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    characters(step, CharacterOp::CheckCode, s, d, n);
}

fn characters(step: &mut Step, op: CharacterOp, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = step.count_within(n, 1, 256);
    let eight_bit = step.b().load_bit(BitArea::M, Index::Fixed(M_EIGHT_BIT_MODE_FX));
    let pairs = step.ceil_div(n, 2);
    let character_words = step.b().select(eight_bit, n, pairs);
    let digit_words = step.ceil_div(n, 4);
    let (source_units, destination_units) = match op {
        CharacterOp::Ascii => (Units::Dynamic(digit_words), Units::Dynamic(character_words)),
        CharacterOp::Hex => (Units::Dynamic(character_words), Units::Dynamic(digit_words)),
        CharacterOp::CheckCode => (Units::Dynamic(character_words), step.run_of(2)),
    };
    let s = step.resolve(s, Width::Single, source_units, true);
    let d = step.resolve(d, Width::Single, destination_units, false);
    step.commit();
    let (s, d) = (step.l.place(&s), step.l.place(&d));
    let op = step.b().number(op.code());
    let answer = match step.b().call(Helper::Characters, vec![op, s, d, n]) {
        Some(answer) => answer,
        None => step.b().constant(Type::I32, 0),
    };
    let zero = step.b().constant(Type::I32, 0);
    let ok = step.b().compare(CompareOp::Ne, answer, zero);
    step.require(ok, OperationError::DataOutOfRange);
}
