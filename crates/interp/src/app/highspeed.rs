//! High-speed counters and pulse outputs: DHSCS, DHSCR, DHSZ, SPD, PLSY,
//! PLSR, PLSV, DRVI, DRVA, ZRN, DSZR, PWM.
//!
//! These instructions decide their operands; what happens between scans
//! (counting at the input refresh, moving an output by frequency × time)
//! is the machine around the program, in the runtime (`hsc`, `pulse`), the
//! same for every engine as timers are.

use super::{Execution, Outcome, Step};
use crate::access::effective_index;
use ladder_front::program::PulseOperands;
use ladder_front::program::{BitRef, CounterRef, WordRef};
use ladder_runtime::hsc::HscCompare;
use ladder_runtime::pulse::{PulseRequest, NO_PLACE};
use ladder_runtime::{BitArea, OperationError, Place, Width};

/// The number of a bit device of `area` (not of a word bit).
fn bit_number(place: Place, area: BitArea) -> Option<u32> {
    if let Place::Bit(found, n) = place {
        (found == area).then_some(n)
    } else {
        None
    }
}

/// DHSCS/DHSCR S1 S2 D and DHSZ S1 S2 S D (`values` the one or two compare
/// values): registers the compare while driven, withdraws it when not.
pub fn compare(
    step: &mut Step,
    run: &Execution,
    kind: HscCompare,
    values: &[&WordRef],
    counter: &CounterRef,
    d: &BitRef,
) -> Outcome {
    let places: Vec<_> = values.iter().map(|v| step.resolve(v, Width::Double, 1, true)).collect();
    let number = effective_index(step.mem, counter.0);
    let in_range =
        (i64::from(ladder_runtime::hsc::FIRST_HSC)..=i64::from(ladder_runtime::hsc::LAST_HSC)).contains(&number);
    if !in_range {
        step.fail_read();
    }
    let outputs = if kind == HscCompare::Zone { 3 } else { 1 };
    let d = step.bits(d, outputs, false);
    step.commit()?;
    let Some(d) = d else { return Ok(()) };
    let mut read = [0i32; 2];
    for (value, place) in read.iter_mut().zip(&places) {
        *value = place.map_or(0, |p| step.read_at(p, Width::Double) as i32);
    }
    let destination = d.pack().unwrap_or(NO_PLACE);
    step.mem
        .high_speed_compare(run.job, kind, run.power, number as u32, read, destination);
    Ok(())
}

/// SPD S1 S2 D: the rising edges of input S1 (X0-X5) over S2 ms: D = the
/// count of the last whole period, D+1 the count so far, D+2 the time left
/// (DSPD: pairs). S1 not X0-X5 or S2 below 1: 4084H.
pub fn speed(step: &mut Step, s1: &BitRef, s2: &WordRef, d: &WordRef) -> Outcome {
    let width = step.width;
    let input = step.bits(s1, 1, true);
    let period = step.source(s2);
    let d = step.resolve(d, width, 3, false);
    step.commit()?;
    let (Some(input), Some(period), Some(d)) = (input, period, d) else {
        return Ok(());
    };
    let Some(x) = bit_number(input, BitArea::X).filter(|&n| n <= 5) else {
        return Err(OperationError::DataOutOfRange);
    };
    let period = step.read(period);
    if period < 1 {
        return Err(OperationError::DataOutOfRange);
    }
    let edges = i64::from(step.mem.input_edges[x as usize]);
    let elapsed = i64::from(step.mem.elapsed_ms);
    let (result, counting, left) = (d, d.nth(1, width), d.nth(2, width));
    let mut count = step.read_at(counting, width);
    let mut remaining = step.read_at(left, width);
    if remaining <= 0 {
        remaining = period;
        count = 0;
    }
    count += edges;
    remaining -= elapsed;
    if remaining <= 0 {
        step.write_at(result, width, count);
        count = 0;
        remaining = period;
    }
    step.write_at(counting, width, count);
    step.write_at(left, width, remaining);
    Ok(())
}

/// PLSY, PLSR, PLSV, DRVI, DRVA, ZRN, DSZR (every scan): with the drive ON
/// the output (Y0-Y3, else 4084H) runs or keeps running; OFF stops it.
pub fn pulse(step: &mut Step, run: &Execution, operands: &PulseOperands) -> Outcome {
    if !run.power {
        step.mem.pulse_stop(run.job);
        return Ok(());
    }
    let width = step.width;
    let source = |word: Option<&WordRef>, step: &mut Step| word.map(|w| step.resolve(w, width, 1, true));
    let frequency = source(operands.frequency, step);
    let amount = source(operands.amount, step);
    let ramp = source(operands.ramp, step);
    let creep = source(operands.creep, step);
    let near_point = operands.near_point.map(|b| step.bits(b, 1, true));
    if let Some(zero_signal) = operands.zero_signal {
        step.bits(zero_signal, 1, true);
    }
    let output = step.bits(operands.output, 1, false);
    let direction = operands.direction.map(|b| step.bits(b, 1, false));
    step.commit()?;
    let value =
        |place: Option<Option<Place>>, step: &Step| place.flatten().map_or(0, |p| step.read_at(p, width) as i32);
    let Some(output) = output.and_then(|p| bit_number(p, BitArea::Y)).filter(|&n| n <= 3) else {
        return Err(OperationError::DataOutOfRange);
    };
    let request = PulseRequest {
        kind: operands.kind,
        output,
        frequency: value(frequency, step),
        amount: value(amount, step),
        ramp_ms: value(ramp, step),
        creep: value(creep, step),
        near_point: near_point
            .flatten()
            .is_some_and(|p| step.read_at(p, Width::Single) != 0),
        direction: direction.flatten().and_then(|p| p.pack()).unwrap_or(NO_PLACE),
    };
    if step.mem.pulse_output(run.job, true, &request) {
        Ok(())
    } else {
        Err(OperationError::DataOutOfRange) // operands it cannot start with
    }
}

/// PWM S1 S2 D (every scan): D (Y0-Y3) ON for S1 ms of every S2 ms while
/// driven; S1 above S2 or S2 below 1 is 4084H.
pub fn pulse_width(step: &mut Step, run: &Execution, s1: &WordRef, s2: &WordRef, d: &BitRef) -> Outcome {
    let width_place = step.source(s1);
    let period_place = step.source(s2);
    let d = step.bits(d, 1, false);
    step.commit()?;
    let (Some(width_place), Some(period_place), Some(d)) = (width_place, period_place, d) else {
        return Ok(());
    };
    if bit_number(d, BitArea::Y).is_none_or(|n| n > 3) {
        return Err(OperationError::DataOutOfRange);
    }
    let (on_ms, period) = (step.read(width_place), step.read(period_place));
    if run.power && (period < 1 || !(0..=period).contains(&on_ms)) {
        return Err(OperationError::DataOutOfRange);
    }
    let output = d.pack().unwrap_or(NO_PLACE);
    step.mem
        .pulse_width(run.job, run.power, on_ms.max(0) as u32, period.max(0) as u32, output);
    Ok(())
}
