//! Tables and sorting: MAX, MIN, MEAN, WSUM, SORT, SORT2, DSORT2, through
//! the runtime's table and sort helpers.

use super::{Execution, Step};
use crate::lower::operand::{Operand, Units};
use crate::CompareOp;
use crate::{BinOp, Type, Value};
use ladder_front::program::WordRef;
use ladder_runtime::compiled::TableOp;
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER};
use ladder_runtime::helpers::{self, Helper, SORT_AT_ONCE, SORT_ROW_MAJOR, SORT_WIDE};
use ladder_runtime::{OperationError, Width};

/// An end of a MAX/MIN range: the device it names (an operand at that
/// number) and the number as an I32.
fn end(step: &mut Step, word: &WordRef) -> Option<(Operand, Value)> {
    match *word {
        WordRef::Word(area, address) => {
            let number = step.address_number(address, 0, area.count());
            Some((Operand::Word(area, crate::Index::Dynamic(number)), number))
        }
        WordRef::WideCounter(address) => {
            let number = step.address_number(address, FIRST_WIDE_COUNTER, COUNTER_COUNT);
            Some((Operand::WideCounter(crate::Index::Dynamic(number)), number))
        }
        // Not in the device table.
        WordRef::Constant(_) | WordRef::Digits(..) => None,
    }
}

fn constant(step: &mut Step, value: i64) -> Value {
    step.b().constant(Type::I32, value)
}

/// LIMIT S1 S2 S3 D: S3 kept within S1 (lower) and S2 (upper); 4084H
/// (D unchanged) when S1 is above S2.
pub fn limit(step: &mut Step, [low, high, value]: [Value; 3]) -> Value {
    let ordered = step.b().compare(CompareOp::Le, low, high);
    step.require(ordered, OperationError::DataOutOfRange);
    let b = step.b();
    let below = b.compare(CompareOp::Lt, value, low);
    let raised = b.select(below, low, value);
    let above = b.compare(CompareOp::Gt, raised, high);
    b.select(above, high, raised)
}

/// MAX/MIN S1 S2 D over the devices from S1 to S2 (32-bit words: pairs from
/// S1 in steps of 2): 4093H when the ends are not the same device, 4094H
/// when S1 is after S2, 4085H when the last pair runs past the area.
pub fn extreme(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &WordRef, largest: bool) {
    let (first, last) = (end(step, s1), end(step, s2));
    let destination = step.destination(d);
    step.commit();
    let same_device = match (s1, s2) {
        (WordRef::Word(a, _), WordRef::Word(b, _)) => a == b,
        (WordRef::WideCounter(_), WordRef::WideCounter(_)) => true,
        (WordRef::Word(..), WordRef::Constant(_) | WordRef::WideCounter(_) | WordRef::Digits(..))
        | (WordRef::WideCounter(_), WordRef::Constant(_) | WordRef::Word(..) | WordRef::Digits(..))
        | (WordRef::Constant(_) | WordRef::Digits(..), _) => false,
    };
    let (Some((start, first)), Some((_, last)), true) = (first, last, same_device) else {
        let never = step.b().bit(false);
        step.require(never, OperationError::RangeNotSameDevice);
        return;
    };
    let in_order = step.b().compare(CompareOp::Le, first, last);
    step.require(in_order, OperationError::RangeOrder);
    let stride = match start {
        Operand::Word(..) => step.width.words(),
        Operand::Constant(_)
        | Operand::WideCounter(_)
        | Operand::Digits(..)
        | Operand::Bit(..)
        | Operand::WordBit(..) => 1,
    };
    let stride = constant(step, i64::from(stride));
    let one = constant(step, 1);
    let b = step.b();
    let distance = b.binary(BinOp::Sub, last, first);
    let steps = b.binary(BinOp::Div, distance, stride);
    let count = b.binary(BinOp::Add, steps, one);
    if let Operand::Word(area, _) = start {
        let b = step.b();
        let span = b.binary(BinOp::Mul, count, stride);
        let end = b.binary(BinOp::Add, first, span);
        let len = b.constant(Type::I32, i64::from(area.count()));
        let fits = b.compare(CompareOp::Le, end, len);
        step.require(fits, OperationError::ReadOutOfRange);
    }
    let op = if largest { TableOp::Max } else { TableOp::Min };
    call_table(step, op, &start, count, &destination);
}

fn call_table(step: &mut Step, op: TableOp, source: &Operand, count: Value, destination: &Operand) {
    let (source, destination) = (step.l.place(source), step.l.place(destination));
    let width = helpers::width_arg(step.width);
    let b = step.b();
    let op = b.number(op.code());
    let width = b.number(width);
    b.call(Helper::Table, vec![op, source, count, width, destination]);
}

/// MEAN S D N: N <= 0 records 4084H.
pub fn mean(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = step.source_value(n);
    step.require_within(n, 1, i64::from(i32::MAX));
    let count = step.b().truncate(n, Type::I32);
    let width = step.width;
    let source = step.resolve(s, width, Units::Dynamic(count), true);
    let destination = step.destination(d);
    step.commit();
    call_table(step, TableOp::Mean, &source, count, &destination);
}

/// WSUM S D N: the sum at twice the width; N < 0 records 4084H.
pub fn sum(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let n = step.source_value(n);
    step.require_within(n, 0, i64::from(i32::MAX));
    let count = step.b().truncate(n, Type::I32);
    let width = step.width;
    let source = step.resolve(s, width, Units::Dynamic(count), true);
    let units = if matches!(d, WordRef::Digits(..)) { 1 } else { 2 };
    let destination = step.resolve(d, width, Units::Checked(units), false);
    step.commit();
    call_table(step, TableOp::Sum, &source, count, &destination);
}

/// SORT / SORT2 / DSORT2: with the rung OFF the job stops; with it ON the
/// operands are checked (N1 1-32, N2 1-6, N3 1-N2, else 4084H) and the
/// runtime runs one scan of the job.
pub fn sort(step: &mut Step, run: &Execution, [s, n1, n2, d, n3]: [&WordRef; 5], row_major: bool) {
    let job = step.b().number(run.job);
    let off = step.b().not(run.power);
    step.when(off, |step| {
        step.b().call(Helper::SortStop, vec![job]);
    });
    step.skip_unless(run.power);
    let count_width = if row_major { step.width } else { Width::Single };
    let counts = [n1, n2, n3].map(|n| step.resolve(n, count_width, Units::Checked(1), true));
    step.commit();
    let [rows, columns, key] = counts.map(|n| step.read_at(&n, count_width));
    step.require_within(rows, 1, 32);
    step.require_within(columns, 1, 6);
    let at_least_one = step.b().constant(Type::I64, 1);
    let b = step.b();
    let above = b.compare(CompareOp::Ge, key, at_least_one);
    let below = b.compare(CompareOp::Le, key, columns);
    let key_ok = b.and(above, below);
    step.require(key_ok, OperationError::DataOutOfRange);
    let [rows, columns, key] = [rows, columns, key].map(|v| step.b().truncate(v, Type::I32));
    let cells = step.b().binary(BinOp::Mul, rows, columns);
    let width = step.width;
    let source = step.resolve(s, width, Units::Dynamic(cells), true);
    let destination = step.resolve(d, width, Units::Dynamic(cells), false);
    step.commit();
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    let flags = if row_major { SORT_ROW_MAJOR } else { 0 }
        | if width == Width::Double { SORT_WIDE } else { 0 }
        | if run.pulse { SORT_AT_ONCE } else { 0 };
    let line = step.line;
    let b = step.b();
    let flags = b.number(flags);
    let line = b.number(line);
    b.call(
        Helper::SortScan,
        vec![job, source, destination, rows, columns, key, flags, line],
    );
}
