//! PID (FNC 88), the velocity form of the FX3U manual, sampled by the
//! reported elapsed time (docs/language.md, "Machine programs").
//!
//! The parameter block S3..S3+24: +0 sampling time Ts (ms), +1 action (bit
//! 0 reverse, 1 input change alarm, 2 output change alarm, 5 output
//! limits), +2 input filter α (%), +3 Kp (%), +4 Ti (× 100 ms, 0 none), +5
//! derivative gain KD (%), +6 Td (× 10 ms, 0 none), +7..+19 work area,
//! +20/+21 input change alarm (up/down), +22/+23 output change alarm
//! (up/down) or output upper/lower limit, +24 alarm output (bits 0-3).
//!
//! ladderc's work area: +7 ms since the last sampling, +8 initialised,
//! +9/+10 PVf(n−1), +11/+12 PVf(n−2), +13/+14 EV(n−1), +15/+16 D(n−1),
//! +17/+18 the fraction of MV carried (real numbers in word pairs). The
//! first execution after the rung was OFF initialises it; then every Ts
//! ms: PVf = PV + α(PVf(n−1) − PV); EV = PVf − SV (forward) or SV − PVf
//! (reverse); D = Td/(Ts + KD·Td)·(±(PVf − 2PVf(n−1) + PVf(n−2))) +
//! KD·Td/(Ts + KD·Td)·D(n−1); ΔMV = Kp·((EV − EV(n−1)) + Ts/Ti·EV + D);
//! MV = D + ΔMV (with the carried fraction, rounded down), within the
//! limits. Computed in double precision, kept in single.

use super::{Execution, Outcome, Step};
use ladder_front::program::WordRef;
use ladder_runtime::{OperationError, Place, Width};

/// Words of the parameter block.
const BLOCK: u32 = 25;

struct Work {
    place: Place,
}

impl Work {
    fn word(&self, step: &Step, offset: u32) -> i64 {
        step.read_at(self.place.nth(offset, Width::Single), Width::Single)
    }

    fn set_word(&self, step: &mut Step, offset: u32, value: i64) {
        step.write_at(self.place.nth(offset, Width::Single), Width::Single, value);
    }

    /// A real number of the work area (a pair from `offset`).
    fn real(&self, step: &Step, offset: u32) -> f64 {
        let low = self.word(step, offset) as u16 as u32;
        let high = self.word(step, offset + 1) as u16 as u32;
        f64::from(f32::from_bits(low | (high << 16)))
    }

    fn set_real(&self, step: &mut Step, offset: u32, value: f64) {
        let bits = (value as f32).to_bits();
        self.set_word(step, offset, i64::from(bits as u16 as i16));
        self.set_word(step, offset + 1, i64::from((bits >> 16) as u16 as i16));
    }
}

/// PID S1 S2 S3 D (every scan; nothing happens with the rung OFF but
/// that the next execution initialises).
pub fn pid(step: &mut Step, run: &Execution, s1: &WordRef, s2: &WordRef, s3: &WordRef, d: &WordRef) -> Outcome {
    let instance = run.job as usize;
    let Some(running) = step.mem.instance.get(instance).map(|s| s.phase != 0) else {
        return Ok(());
    };
    if !run.power {
        step.mem.instance[instance].phase = 0;
        return Ok(());
    }
    let sv = step.count(s1);
    let pv = step.count(s2);
    let block = step.resolve(s3, Width::Single, BLOCK, true);
    let mv = step.destination(d);
    step.commit()?;
    let (Some(sv), Some(pv), Some(block), Some(mv)) = (sv, pv, block, mv) else {
        return Ok(());
    };
    let work = Work { place: block };
    let parameter = |offset: u32| work.word(step, offset);
    let (ts, action, alpha, kp, ti, kd, td) = (
        parameter(0),
        parameter(1),
        parameter(2),
        parameter(3),
        parameter(4),
        parameter(5),
        parameter(6),
    );
    let checks = [
        (1..=32_767)
            .contains(&ts)
            .then_some(())
            .ok_or(OperationError::PidSamplingTime),
        (0..=99)
            .contains(&alpha)
            .then_some(())
            .ok_or(OperationError::PidInputFilter),
        (1..=32_767)
            .contains(&kp)
            .then_some(())
            .ok_or(OperationError::PidProportionalGain),
        (ti >= 0).then_some(()).ok_or(OperationError::PidIntegralTime),
        (0..=200)
            .contains(&kd)
            .then_some(())
            .ok_or(OperationError::PidDerivativeGain),
        (td >= 0).then_some(()).ok_or(OperationError::PidDerivativeTime),
    ];
    for check in checks {
        check?;
    }
    let sv = step.read_at(sv, Width::Single) as f64;
    let pv = step.read_at(pv, Width::Single) as f64;
    let reverse = action & 1 != 0;
    let input_alarm = action & 2 != 0;
    let output_alarm = action & 4 != 0;
    let limits = action & 0x20 != 0;
    let mut warning = None;
    // Alarm settings below 0 switch their alarm off (6749H).
    let mut setting = |offset: u32, enabled: bool| -> Option<i64> {
        let value = work.word(step, offset);
        if !enabled {
            None
        } else if value < 0 {
            warning = Some(OperationError::PidAlarmSetting);
            None
        } else {
            Some(value)
        }
    };
    let input_limits = [setting(20, input_alarm), setting(21, input_alarm)];
    let output_limits = [setting(22, output_alarm), setting(23, output_alarm)];
    let (mut upper, mut lower) = (work.word(step, 22), work.word(step, 23));
    if limits && upper < lower {
        warning = Some(OperationError::PidLimitOrder);
        std::mem::swap(&mut upper, &mut lower);
    }
    let error = |pvf: f64| if reverse { sv - pvf } else { pvf - sv };
    if !running {
        step.mem.instance[instance].phase = 1;
        work.set_word(step, 7, 0);
        work.set_word(step, 8, 1);
        work.set_real(step, 9, pv);
        work.set_real(step, 11, pv);
        work.set_real(step, 13, error(pv));
        work.set_real(step, 15, 0.0);
        work.set_real(step, 17, 0.0);
        return warning.map_or(Ok(()), Err);
    }
    let waited = work.word(step, 7) + i64::from(step.mem.elapsed_ms);
    if waited < ts {
        work.set_word(step, 7, waited.min(32_767));
        return warning.map_or(Ok(()), Err);
    }
    // One sampling per execution: time beyond two periods is dropped.
    let left = waited - ts;
    work.set_word(step, 7, if left >= ts { 0 } else { left });
    let (previous, before) = (work.real(step, 9), work.real(step, 11));
    let (last_error, last_derivative, carried) = (work.real(step, 13), work.real(step, 15), work.real(step, 17));
    let filter = alpha as f64 / 100.0;
    let pvf = pv + filter * (previous - pv);
    let ev = error(pvf);
    let (ts, ti, td) = (ts as f64, ti as f64 * 100.0, td as f64 * 10.0);
    let gain = kd as f64 / 100.0;
    let derivative = if td == 0.0 {
        0.0
    } else {
        let change = if reverse {
            2.0 * previous - pvf - before
        } else {
            pvf - 2.0 * previous + before
        };
        td / (ts + gain * td) * change + gain * td / (ts + gain * td) * last_derivative
    };
    let integral = if ti == 0.0 { 0.0 } else { ts / ti * ev };
    let delta = kp as f64 / 100.0 * ((ev - last_error) + integral + derivative);
    let old = step.read(mv);
    let exact = old as f64 + carried + delta;
    let mut new = exact.floor().clamp(-32_768.0, 32_767.0) as i64;
    let mut fraction = exact - exact.floor();
    if limits && (new > upper || new < lower) {
        new = new.clamp(lower, upper);
        fraction = 0.0;
    }
    let pv_change = pvf - previous;
    let mv_change = new - old;
    let alarms = [
        input_limits[0].is_some_and(|limit| pv_change > limit as f64),
        input_limits[1].is_some_and(|limit| -pv_change > limit as f64),
        output_limits[0].is_some_and(|limit| mv_change > limit),
        output_limits[1].is_some_and(|limit| -mv_change > limit),
    ];
    let kept = work.word(step, 24) & !0xF;
    let bits = (0..)
        .zip(alarms)
        .fold(kept, |word, (bit, on)| word | (i64::from(on) << bit));
    work.set_word(step, 24, bits);
    work.set_real(step, 9, pvf);
    work.set_real(step, 11, previous);
    work.set_real(step, 13, ev);
    work.set_real(step, 15, derivative);
    work.set_real(step, 17, fraction);
    step.write(mv, new);
    warning.map_or(Ok(()), Err)
}
