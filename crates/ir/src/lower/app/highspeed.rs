//! High-speed counters and pulse outputs in the lowering: operands are
//! resolved and checked here; the machine (counting, moving outputs) is the
//! runtime's, reached through its helpers.

use super::{Execution, Step};
use crate::lower::operand::{Operand, Units};
use crate::CompareOp;
use crate::{Index, Type, Value};
use ladder_front::program::PulseOperands;
use ladder_front::program::{BitRef, CounterRef, WordRef};
use ladder_runtime::helpers::{width_arg, Helper};
use ladder_runtime::hsc::{HscCompare, FIRST_HSC, LAST_HSC};
use ladder_runtime::pulse::NO_PLACE;
use ladder_runtime::{OperationError, Width};

impl Step<'_, '_> {
    /// The number of a bit operand as an I32.
    fn bit_number(&mut self, operand: &Operand) -> Value {
        let index = match *operand {
            Operand::Bit(_, index) | Operand::WordBit(_, index) => index,
            Operand::Constant(_) | Operand::Word(..) | Operand::WideCounter(_) | Operand::Digits(..) => Index::Fixed(0),
        };
        match index {
            Index::Fixed(n) => self.b().constant(Type::I32, i64::from(n)),
            Index::Dynamic(value) => value,
        }
    }

    /// Requires a bit operand's number to be at most `last` (4084H).
    fn require_number_at_most(&mut self, operand: &Operand, last: i64) -> Value {
        let number = self.bit_number(operand);
        let last = self.b().constant(Type::I32, last);
        let fits = self.b().compare(CompareOp::Le, number, last);
        self.require(fits, OperationError::DataOutOfRange);
        number
    }

    fn value_i32(&mut self, operand: &Operand, width: Width) -> Value {
        let value = self.read_at(operand, width);
        self.b().truncate(value, Type::I32)
    }
}

/// DHSCS, DHSCR (one value) and DHSZ (two) every scan.
pub fn compare(
    step: &mut Step,
    run: &Execution,
    kind: HscCompare,
    values: &[&WordRef],
    counter: &CounterRef,
    d: &BitRef,
) {
    let operands: Vec<Operand> = values
        .iter()
        .map(|v| step.resolve(v, Width::Double, Units::Checked(1), true))
        .collect();
    let counter = step.address_number(counter.0, FIRST_HSC, LAST_HSC + 1);
    let outputs = if kind == HscCompare::Zone { 3 } else { 1 };
    let d = step.bits(d, Units::Checked(outputs), false);
    step.commit();
    let mut read: Vec<Value> = operands.iter().map(|o| step.value_i32(o, Width::Double)).collect();
    while read.len() < 2 {
        read.push(step.b().constant(Type::I32, 0));
    }
    let code = kind.code();
    let b = step.b();
    let instance = b.number(run.job);
    let code = b.number(code);
    let power = b.extend(run.power, Type::I32, false);
    let d = step.l.place(&d);
    step.b().call(
        Helper::HighSpeedCompare,
        vec![instance, code, power, counter, read[0], read[1], d],
    );
}

/// SPD S1 S2 D.
pub fn speed(step: &mut Step, s1: &BitRef, s2: &WordRef, d: &WordRef) {
    let width = step.width;
    let input = step.bits(s1, Units::Checked(1), true);
    let period = step.source(s2);
    let three = step.run_of(3);
    let d = step.resolve(d, width, three, false);
    step.commit();
    let input = step.require_number_at_most(&input, 5);
    let period = step.read(&period);
    let one = step.b().constant(Type::I64, 1);
    let positive = step.b().compare(CompareOp::Ge, period, one);
    step.require(positive, OperationError::DataOutOfRange);
    let period = step.b().truncate(period, Type::I32);
    let d = step.l.place(&d);
    let width = step.b().number(width_arg(width));
    step.b().call(Helper::Speed, vec![input, period, d, width]);
}

/// PLSY, PLSR, PLSV, DRVI, DRVA, ZRN, DSZR every scan.
pub fn pulse(step: &mut Step, run: &Execution, operands: &PulseOperands) {
    let off = step.b().not(run.power);
    step.when(off, |step| {
        let instance = step.b().number(run.job);
        step.b().call(Helper::PulseStop, vec![instance]);
    });
    step.skip_unless(run.power);
    let width = step.width;
    let words: Vec<Option<Operand>> = [operands.frequency, operands.amount, operands.ramp, operands.creep]
        .into_iter()
        .map(|word| word.map(|w| step.resolve(w, width, Units::Checked(1), true)))
        .collect();
    let near_point = operands.near_point.map(|b| step.bits(b, Units::Checked(1), true));
    if let Some(zero_signal) = operands.zero_signal {
        step.bits(zero_signal, Units::Checked(1), true);
    }
    let output = step.bits(operands.output, Units::Checked(1), false);
    let direction = operands.direction.map(|b| step.bits(b, Units::Checked(1), false));
    step.commit();
    let output = step.require_number_at_most(&output, 3);
    let mut args = vec![step.b().number(run.job), step.b().number(operands.kind as u32), output];
    for word in &words {
        let value = match word {
            Some(operand) => step.value_i32(operand, width),
            None => step.b().constant(Type::I32, 0),
        };
        args.push(value);
    }
    let near = match near_point {
        Some(operand) => {
            let on = step.read_at(&operand, Width::Single);
            step.b().truncate(on, Type::I32)
        }
        None => step.b().constant(Type::I32, 0),
    };
    args.push(near);
    args.push(match direction {
        Some(operand) => step.l.place(&operand),
        None => step.b().constant(Type::I32, i64::from(NO_PLACE)),
    });
    let started = step.helper(Helper::PulseOutput, args);
    step.require_ok(started);
}

/// PWM S1 S2 D every scan.
pub fn pulse_width(step: &mut Step, run: &Execution, s1: &WordRef, s2: &WordRef, d: &BitRef) {
    let on_time = step.source(s1);
    let period = step.source(s2);
    let d = step.bits(d, Units::Checked(1), false);
    step.commit();
    step.require_number_at_most(&d, 3);
    let on_time = step.read(&on_time);
    let period = step.read(&period);
    let b = step.b();
    let (zero, one) = (b.constant(Type::I64, 0), b.constant(Type::I64, 1));
    let period_ok = b.compare(CompareOp::Ge, period, one);
    let from_zero = b.compare(CompareOp::Ge, on_time, zero);
    let within = b.compare(CompareOp::Le, on_time, period);
    let valid = b.and(period_ok, from_zero);
    let valid = b.and(valid, within);
    let off = b.not(run.power);
    let fine = b.or(valid, off);
    step.require(fine, OperationError::DataOutOfRange);
    let b = step.b();
    let negative_on = b.compare(CompareOp::Lt, on_time, zero);
    let on_time = b.select(negative_on, zero, on_time);
    let negative_period = b.compare(CompareOp::Lt, period, zero);
    let period = b.select(negative_period, zero, period);
    let on_time = b.truncate(on_time, Type::I32);
    let period = b.truncate(period, Type::I32);
    let instance = b.number(run.job);
    let power = b.extend(run.power, Type::I32, false);
    let d = step.l.place(&d);
    step.b()
        .call(Helper::PulseWidth, vec![instance, power, on_time, period, d]);
}
