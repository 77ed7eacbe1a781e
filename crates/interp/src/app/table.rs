//! Tables and sorting: MAX, MIN, MEAN, WSUM, SORT, SORT2, DSORT2.

use super::{Execution, Outcome, Step};
use crate::access::effective_index;
use ladder_front::program::WordRef;
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER};
use ladder_runtime::memory::{SORT2_RUNNING, SORT_DONE, SORT_IDLE, SORT_RUNNING};
use ladder_runtime::special::{SM_DESCENDING, SM_SORT_DONE};
use ladder_runtime::{OperationError, Place, Width, WordArea};

/// Which run of devices an address lies in: both ends of a MAX/MIN range
/// must name the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Run {
    Words(WordArea),
    WideCounters,
}

/// The device an end of a range names (not its value), or None outside its
/// area.
fn end(step: &Step, word: &WordRef) -> Option<(Run, u32)> {
    let within = |index: i64, first: u32, len: u32| (i64::from(first)..i64::from(len)).contains(&index);
    match *word {
        WordRef::Word(area, address) => {
            let index = effective_index(step.mem, address);
            within(index, 0, area.count()).then_some((Run::Words(area), index as u32))
        }
        WordRef::WideCounter(address) => {
            let index = effective_index(step.mem, address);
            within(index, FIRST_WIDE_COUNTER, COUNTER_COUNT).then_some((Run::WideCounters, index as u32))
        }
        // Constants and digit groups are not in the device table.
        WordRef::Constant(_) | WordRef::Digits(..) => None,
    }
}

/// LIMIT S1 S2 S3 D: S3 kept within S1 (lower) and S2 (upper); a lower
/// limit above the upper one is 4084H and D is left as it is.
pub fn limit([low, high, value]: [i64; 3], _: Width) -> Result<i64, OperationError> {
    if low > high {
        return Err(OperationError::DataOutOfRange);
    }
    Ok(value.clamp(low, high))
}

/// MAX/MIN S1 S2 D: the largest (smallest) value of the devices from S1 to
/// S2 — for 32-bit words the pairs starting at S1, S1+2, ... up to S2.
/// 4093H when S1 and S2 are not the same device, 4094H when S1 is after S2.
pub fn extreme(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &WordRef, largest: bool) -> Outcome {
    let first = end(step, s1);
    let last = end(step, s2);
    if first.is_none() || last.is_none() {
        step.fail_read();
    }
    let destination = step.destination(d);
    step.commit()?;
    let (Some((run, first)), Some((other, last)), Some(destination)) = (first, last, destination) else {
        return Ok(());
    };
    if run != other {
        return Err(OperationError::RangeNotSameDevice);
    }
    if first > last {
        return Err(OperationError::RangeOrder);
    }
    let (start, step_size) = match run {
        Run::Words(area) => (Place::Word(area, first), step.width.words()),
        Run::WideCounters => (Place::WideCounter(first), 1),
    };
    let count = (last - first) / step_size + 1;
    // The whole run must lie in the area (the high word of the last pair).
    let fits = match run {
        Run::Words(area) => first + count * step.width.words() <= area.count(),
        Run::WideCounters => true,
    };
    if !fits {
        return Err(OperationError::ReadOutOfRange);
    }
    let values = (0..count).map(|unit| step.read(start.nth(unit, step.width)));
    let result = if largest { values.max() } else { values.min() };
    step.write(destination, result.unwrap_or(0));
    Ok(())
}

/// MEAN S D N: the mean of N values from S, the fraction dropped (toward
/// zero). N <= 0 is 4084H.
pub fn mean(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = step.source_value(n)?;
    if n <= 0 {
        return Err(OperationError::DataOutOfRange);
    }
    let source = step.resolve(s, step.width, u32::try_from(n).unwrap_or(u32::MAX), true);
    let destination = step.destination(d);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let sum: i64 = (0..n as u32).map(|unit| step.read(source.nth(unit, step.width))).sum();
    step.write(destination, sum / n);
    Ok(())
}

/// WSUM S D N: the sum of N values from S into D at twice the width (a
/// 32-bit pair; two pairs for DWSUM; a digit group keeps its own bits). N < 0
/// is 4084H; N = 0 gives 0.
pub fn sum(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = step.source_value(n)?;
    if n < 0 {
        return Err(OperationError::DataOutOfRange);
    }
    let width = step.width;
    let source = step.resolve(s, width, u32::try_from(n).unwrap_or(u32::MAX), true);
    let units = if matches!(d, WordRef::Digits(..)) { 1 } else { 2 };
    let destination = step.resolve(d, width, units, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let total: i64 = (0..n as u32).map(|unit| step.read(source.nth(unit, width))).sum();
    match width {
        Width::Single => destination.write(step.mem, Width::Double, total),
        Width::Double => {
            destination.write(step.mem, Width::Double, total);
            if units == 2 {
                destination
                    .nth(1, Width::Double)
                    .write(step.mem, Width::Double, total >> 32);
            }
        }
    }
    Ok(())
}

/// SORT (column by column, ascending) and SORT2/DSORT2 (`row_major`: row
/// by row, SM165 descending). With its input ON the instruction checks its
/// operands, then starts its job if it is not running (4089H if one SORT,
/// or two SORT2/DSORT2, are already in progress), counts the scan, and in the
/// N1-th scan — at once for a P form — sorts the rows of S by column N3,
/// stably, into D and turns SM229 ON. SM229 then shows whether this
/// instruction has finished. With its input OFF the job ends: a finished
/// sort starts again only after its input was OFF once. A scan that records
/// an error changes nothing else.
pub fn sort(step: &mut Step, run: &Execution, [s, n1, n2, d, n3]: [&WordRef; 5], row_major: bool) -> Outcome {
    let job = run.job as usize;
    if !run.power {
        step.mem.sort_state[job] = SORT_IDLE;
        step.mem.sort_scans[job] = 0;
        return Ok(());
    }
    // SORT's counts are 16-bit; SORT2's follow its width (DSORT2: 32-bit).
    let count_width = if row_major { step.width } else { Width::Single };
    let counts = [n1, n2, n3].map(|n| step.resolve(n, count_width, 1, true));
    step.commit()?;
    let [rows, columns, key] = counts.map(|place| place.map_or(0, |p| step.read_at(p, count_width)));
    if !(1..=32).contains(&rows) || !(1..=6).contains(&columns) || !(1..=columns).contains(&key) {
        return Err(OperationError::DataOutOfRange);
    }
    let (rows, columns, key) = (rows as u32, columns as u32, key as u32);
    let source = step.resolve(s, step.width, rows * columns, true);
    let destination = step.resolve(d, step.width, rows * columns, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let mem = &mut *step.mem;
    let running = if row_major { SORT2_RUNNING } else { SORT_RUNNING };
    if mem.sort_state[job] == SORT_IDLE {
        let limit = if row_major { 2 } else { 1 };
        if mem.sort_state.iter().filter(|&&state| state == running).count() >= limit {
            mem.sm[SM_SORT_DONE.number as usize] = 0;
            return Err(OperationError::TooManyInstructions);
        }
        mem.sort_state[job] = running;
        mem.sort_scans[job] = 0;
    }
    if mem.sort_state[job] == running {
        mem.sort_scans[job] = mem.sort_scans[job].saturating_add(1);
        if run.pulse || u32::from(mem.sort_scans[job]) >= rows {
            let descending = row_major && mem.sm[SM_DESCENDING.number as usize] != 0;
            let unit = |row: u32, column: u32| {
                if row_major {
                    row * columns + column
                } else {
                    column * rows + row
                }
            };
            let width = step.width;
            let mut table: Vec<Vec<i64>> = (0..rows)
                .map(|row| {
                    (0..columns)
                        .map(|column| i64::from(source.nth(unit(row, column), width).read(mem, width)))
                        .collect()
                })
                .collect();
            let key = (key - 1) as usize;
            // `sort_by` is stable: rows with equal keys keep their order.
            if descending {
                table.sort_by(|a, b| b[key].cmp(&a[key]));
            } else {
                table.sort_by(|a, b| a[key].cmp(&b[key]));
            }
            for (row, values) in (0..).zip(&table) {
                for (column, &value) in (0..).zip(values) {
                    destination.nth(unit(row, column), width).write(mem, width, value);
                }
            }
            mem.sort_state[job] = SORT_DONE;
        }
    }
    mem.sm[SM_SORT_DONE.number as usize] = u8::from(mem.sort_state[job] == SORT_DONE);
    Ok(())
}
