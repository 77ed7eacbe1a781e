//! Alarms: ANS, ANR.

use super::{Execution, Outcome, Step};
use crate::access::effective_index;
use ladder_front::program::{Address, BitRef, WordRef};
use ladder_runtime::device::TIMER_COUNT;
use ladder_runtime::special::{FIRST_ALARM_STATE, LAST_ALARM_STATE};
use ladder_runtime::{OperationError, Place, Width};

/// ANS S N D: timer S (T0-T199, 100 ms) times while the rung is ON; once it
/// reaches N (N × 100 ms) the alarm state D (S900-S999) is set. With the rung
/// OFF the timer is cleared. N outside 1-32767, S outside T0-T199 or D
/// outside S900-S999 is 4084H (checked while the rung is ON).
pub fn set(step: &mut Step, run: &Execution, s: &Address, n: &WordRef, d: &BitRef) -> Outcome {
    let timer = effective_index(step.mem, *s);
    if !run.power {
        if (0..200).contains(&timer) {
            step.mem.timer_coil(timer as u32, false, 0);
        }
        return Ok(());
    }
    if !(0..i64::from(TIMER_COUNT)).contains(&timer) {
        step.fail_read();
    }
    let judging = step.count(n);
    let alarm = step.bits(d, 1, false);
    step.commit()?;
    let (Some(judging), Some(alarm)) = (judging, alarm) else {
        return Ok(());
    };
    let judging = step.read_at(judging, Width::Single);
    let state = match alarm {
        Place::Bit(_, state) => state,
        Place::Constant(_) | Place::Word(..) | Place::WideCounter(_) | Place::Digits(..) | Place::WordBit(..) => 0,
    };
    if !(1..=32767).contains(&judging)
        || !(0..200).contains(&timer)
        || !(FIRST_ALARM_STATE..=LAST_ALARM_STATE).contains(&state)
    {
        return Err(OperationError::DataOutOfRange);
    }
    let timer = timer as u32;
    step.mem.timer_coil(timer, true, judging as i32);
    if step.mem.timer_contact[timer as usize] != 0 {
        alarm.write(step.mem, Width::Single, 1);
    }
    Ok(())
}

/// ANR: the lowest alarm state S900-S999 that is ON turns OFF.
pub fn reset(step: &mut Step) -> Outcome {
    if let Some(state) = (FIRST_ALARM_STATE..=LAST_ALARM_STATE).find(|&s| step.mem.s[s as usize] != 0) {
        step.mem.s[state as usize] = 0;
    }
    Ok(())
}
