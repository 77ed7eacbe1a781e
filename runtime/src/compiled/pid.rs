//! PID (FNC 88) in compiled code: the interpreter's velocity form and work
//! area, written apart from it, with the same floating-point expressions in
//! the same order so that every engine agrees bit for bit.

use crate::device::Width;
use crate::image::ImageMut;
use crate::layout::Scalar;
use crate::place::Place;
use crate::special::OperationError;

/// One execution of PID instance `instance` with its rung ON; `block` the
/// checked 25-word parameter block, `mv` the checked output. The error it
/// records (against `line`), if any.
pub fn pid(mem: &mut ImageMut<'_>, instance: u32, sv: i64, pv: i64, block: Place, mv: Place, line: u32) {
    if let Err(error) = step(mem, instance, sv as f64, pv as f64, block, mv) {
        mem.record_error(error, line);
    }
}

fn word(mem: &ImageMut<'_>, block: Place, offset: u32) -> i64 {
    i64::from(block.nth(offset, Width::Single).read(mem, Width::Single))
}

fn set_word(mem: &mut ImageMut<'_>, block: Place, offset: u32, value: i64) {
    block.nth(offset, Width::Single).write(mem, Width::Single, value);
}

fn real(mem: &ImageMut<'_>, block: Place, offset: u32) -> f64 {
    let bits = block.nth(offset, Width::Single).read(mem, Width::Double) as u32;
    f64::from(f32::from_bits(bits))
}

fn set_real(mem: &mut ImageMut<'_>, block: Place, offset: u32, value: f64) {
    let bits = (value as f32).to_bits();
    block
        .nth(offset, Width::Single)
        .write(mem, Width::Double, i64::from(bits as i32));
}

/// `value` if it lies in `range`, else `error`.
fn within(value: i64, range: core::ops::RangeInclusive<i64>, error: OperationError) -> Result<(), OperationError> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(error)
    }
}

fn step(
    mem: &mut ImageMut<'_>,
    instance: u32,
    sv: f64,
    pv: f64,
    block: Place,
    mv: Place,
) -> Result<(), OperationError> {
    let Some(mut state) = mem.instance(instance) else {
        return Ok(());
    };
    let running = state.phase != 0;
    let ts = word(mem, block, 0);
    let action = word(mem, block, 1);
    let alpha = word(mem, block, 2);
    let kp = word(mem, block, 3);
    let ti = word(mem, block, 4);
    let kd = word(mem, block, 5);
    let td = word(mem, block, 6);
    within(ts, 1..=32_767, OperationError::PidSamplingTime)?;
    within(alpha, 0..=99, OperationError::PidInputFilter)?;
    within(kp, 1..=32_767, OperationError::PidProportionalGain)?;
    within(ti, 0..=i64::MAX, OperationError::PidIntegralTime)?;
    within(kd, 0..=200, OperationError::PidDerivativeGain)?;
    within(td, 0..=i64::MAX, OperationError::PidDerivativeTime)?;
    let reverse = action & 1 != 0;
    let mut warning: Result<(), OperationError> = Ok(());
    let mut alarm_setting = |mem: &ImageMut<'_>, offset: u32, bit: i64| {
        if action & bit == 0 {
            return None;
        }
        let value = word(mem, block, offset);
        if value < 0 {
            warning = Err(OperationError::PidAlarmSetting);
            return None;
        }
        Some(value)
    };
    let up_in = alarm_setting(mem, 20, 2);
    let down_in = alarm_setting(mem, 21, 2);
    let up_out = alarm_setting(mem, 22, 4);
    let down_out = alarm_setting(mem, 23, 4);
    let limited = action & 0x20 != 0;
    let (mut upper, mut lower) = (word(mem, block, 22), word(mem, block, 23));
    if limited && upper < lower {
        warning = Err(OperationError::PidLimitOrder);
        core::mem::swap(&mut upper, &mut lower);
    }
    let deviation = |pvf: f64| if reverse { sv - pvf } else { pvf - sv };
    if !running {
        state.phase = 1;
        mem.set_instance(instance, state);
        set_word(mem, block, 7, 0);
        set_word(mem, block, 8, 1);
        set_real(mem, block, 9, pv);
        set_real(mem, block, 11, pv);
        set_real(mem, block, 13, deviation(pv));
        set_real(mem, block, 15, 0.0);
        set_real(mem, block, 17, 0.0);
        return warning;
    }
    let waited = word(mem, block, 7) + i64::from(mem.scalar(Scalar::ElapsedMs));
    if waited < ts {
        set_word(mem, block, 7, waited.min(32_767));
        return warning;
    }
    let left = waited - ts;
    set_word(mem, block, 7, if left < ts { left } else { 0 });
    let previous = real(mem, block, 9);
    let before = real(mem, block, 11);
    let last_error = real(mem, block, 13);
    let last_derivative = real(mem, block, 15);
    let carried = real(mem, block, 17);
    let filter = alpha as f64 / 100.0;
    let pvf = pv + filter * (previous - pv);
    let ev = deviation(pvf);
    let (ts, ti, td) = (ts as f64, ti as f64 * 100.0, td as f64 * 10.0);
    let gain = kd as f64 / 100.0;
    let derivative = if td == 0.0 {
        0.0
    } else if reverse {
        td / (ts + gain * td) * (2.0 * previous - pvf - before) + gain * td / (ts + gain * td) * last_derivative
    } else {
        td / (ts + gain * td) * (pvf - 2.0 * previous + before) + gain * td / (ts + gain * td) * last_derivative
    };
    let integral = if ti == 0.0 { 0.0 } else { ts / ti * ev };
    let delta = kp as f64 / 100.0 * ((ev - last_error) + integral + derivative);
    let old = i64::from(mv.read(mem, Width::Single));
    let exact = old as f64 + carried + delta;
    let floor = libm::floor(exact);
    let mut new = floor.clamp(-32_768.0, 32_767.0) as i64;
    let mut fraction = exact - floor;
    if limited && !(lower..=upper).contains(&new) {
        new = new.clamp(lower, upper);
        fraction = 0.0;
    }
    let pv_change = pvf - previous;
    let mv_change = new - old;
    let mut alarms = word(mem, block, 24) & !0xF;
    if up_in.is_some_and(|limit| pv_change > limit as f64) {
        alarms |= 1;
    }
    if down_in.is_some_and(|limit| -pv_change > limit as f64) {
        alarms |= 2;
    }
    if up_out.is_some_and(|limit| mv_change > limit) {
        alarms |= 4;
    }
    if down_out.is_some_and(|limit| -mv_change > limit) {
        alarms |= 8;
    }
    set_word(mem, block, 24, alarms);
    set_real(mem, block, 9, pvf);
    set_real(mem, block, 11, previous);
    set_real(mem, block, 13, ev);
    set_real(mem, block, 15, derivative);
    set_real(mem, block, 17, fraction);
    mv.write(mem, Width::Single, new);
    warning
}
