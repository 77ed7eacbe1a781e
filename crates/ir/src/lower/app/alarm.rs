//! Alarms: ANS (a timer and a SET), ANR (through the runtime).

use super::{Execution, Step};
use crate::lower::operand::{Operand, Units};
use crate::CompareOp;
use crate::{Index, Type};
use ladder_front::program::{Address, BitRef, WordRef};
use ladder_runtime::device::TIMER_COUNT;
use ladder_runtime::helpers::Helper;
use ladder_runtime::special::{FIRST_ALARM_STATE, LAST_ALARM_STATE};
use ladder_runtime::{BitArea, OperationError, Width};

/// ANS S N D: timer S runs while the rung is ON and is cleared while it is
/// OFF; once it reaches N the alarm state D is set. While ON, N outside
/// 1-32767, S outside T0-T199 or D outside S900-S999 records 4084H.
pub fn set(step: &mut Step, run: &Execution, s: &Address, n: &WordRef, d: &BitRef) {
    let timer = match s.index_register {
        None => step.b().constant(Type::I32, i64::from(s.index)),
        Some(register) => step.l.indexed(s.index, register),
    };
    let zero = step.b().constant(Type::I32, 0);
    let below_200 = step.b().constant(Type::I32, 200);
    let b = step.b();
    let not_negative = b.compare(CompareOp::Ge, timer, zero);
    let low = b.compare(CompareOp::Lt, timer, below_200);
    let judging_timer = b.and(not_negative, low);
    let off = b.not(run.power);
    let clear = b.and(off, judging_timer);
    step.when(clear, |step| {
        let b = step.b();
        let (coil, preset) = (b.constant(Type::I32, 0), b.constant(Type::I32, 0));
        b.call(Helper::TimerCoil, vec![timer, coil, preset]);
    });
    step.skip_unless(run.power);
    let timers = step.b().constant(Type::I32, i64::from(TIMER_COUNT));
    let b = step.b();
    let exists = b.compare(CompareOp::Lt, timer, timers);
    let exists = b.and(not_negative, exists);
    step.note_read_check(exists);
    let judging = step.count(n);
    let alarm = step.bits(d, Units::Checked(1), false);
    step.commit();
    let judging = step.read_at(&judging, Width::Single);
    step.require_within(judging, 1, 32767);
    step.require(judging_timer, OperationError::DataOutOfRange);
    if let Operand::Bit(BitArea::S, index) = alarm {
        let state = match index {
            Index::Fixed(n) => step.b().constant(Type::I32, i64::from(n)),
            Index::Dynamic(v) => v,
        };
        let b = step.b();
        let first = b.constant(Type::I32, i64::from(FIRST_ALARM_STATE));
        let last = b.constant(Type::I32, i64::from(LAST_ALARM_STATE));
        let above = b.compare(CompareOp::Ge, state, first);
        let below = b.compare(CompareOp::Le, state, last);
        let alarm_state = b.and(above, below);
        step.require(alarm_state, OperationError::DataOutOfRange);
    }
    let preset = step.b().truncate(judging, Type::I32);
    let on = step.b().constant(Type::I32, 1);
    step.b().call(Helper::TimerCoil, vec![timer, on, preset]);
    let contact = step.b().load_bit(BitArea::TimerContact, Index::Dynamic(timer));
    step.when(contact, |step| {
        let on = step.b().bit(true);
        step.write_bit(&alarm, on);
    });
}

/// ANR: the runtime turns OFF the lowest alarm state that is ON.
pub fn reset(step: &mut Step) {
    step.b().call(Helper::AlarmReset, vec![]);
}
