//! `OUT Tn` and `OUT Cn` (C0-C199) written inline: the runtime's timer and
//! counter coils (`runtime/src/timer.rs`, `counter.rs`) once more, as IR.
//! A compiled scan then does not call the runtime for every timer and
//! counter (each call finds the image's layout and checks every access),
//! and the accesses are fixed offsets that code generation folds. The
//! interpreter runs the runtime's coils, so the differential test compares
//! the two on every engine.
//!
//! 32-bit counters (their direction relays, high-speed counting) and the
//! timer ANS drives (its number may be indexed) still call the runtime.

use crate::builder::Builder;
use crate::CompareOp;
use crate::{BinOp, BlockId, Bookkeeping, Cell, Index, Inst, Terminator, Type, Value};
use ladder_runtime::device::{TimerClass, FIRST_WIDE_COUNTER, TIMER_COUNT};
use ladder_runtime::{BitArea, WordArea};

/// Whether `timer`'s coil is lowered inline (every timer the image has).
pub fn inline_timer(timer: u32) -> bool {
    timer < TIMER_COUNT
}

/// Whether `counter`'s coil is lowered inline: the 16-bit up counters.
pub fn inline_counter(counter: u32) -> bool {
    counter < FIRST_WIDE_COUNTER
}

/// `OUT Tn preset` with the rung result `coil` (a Bit) and `preset` (I32),
/// for a timer `inline_timer` accepts. As the runtime: the coil's state is
/// kept first; a forced timer changes nothing more; with the coil OFF a
/// timer that is not retentive is cleared; with it ON the timer adds the
/// scan's elapsed time from the scan after the coil turned ON, carrying
/// the remainder below its resolution and stopping at the preset (at most
/// 32767); the contact is ON once the value reaches the preset.
pub fn timer(b: &mut Builder, timer: u32, coil: Value, preset: Value) {
    let class = TimerClass::of(timer);
    let (was_on, done) = unless_forced(b, [Bookkeeping::TimerCoil, Bookkeeping::TimerForced], timer, coil);
    let (on, off) = (b.create_block(), b.create_block());
    b.terminate(Terminator::Branch {
        condition: coil,
        then: on,
        otherwise: off,
    });

    b.switch_to(off);
    if !class.retentive {
        let zero = b.constant(Type::I16, 0);
        let index = Index::Fixed(timer);
        b.store(
            Cell::Word {
                area: WordArea::TimerValue,
                index,
            },
            zero,
        );
        b.store(
            Cell::Bookkeeping {
                field: Bookkeeping::TimerRemainder,
                index: timer,
            },
            zero,
        );
        let off = b.bit(false);
        b.store_bit(BitArea::TimerContact, index, off);
    }
    b.terminate(Terminator::Jump(done));

    b.switch_to(on);
    b.if_then(was_on, |b| advance(b, timer, class.resolution_ms, preset));
    let value = b.load(Cell::Word {
        area: WordArea::TimerValue,
        index: Index::Fixed(timer),
    });
    let value = b.extend(value, Type::I32, true);
    let reached = b.compare(CompareOp::Ge, value, preset);
    b.store_bit(BitArea::TimerContact, Index::Fixed(timer), reached);
    b.jump_to(done);
}

/// What both coils do first, as the runtime's: keep the coil's `state`
/// and go on only when the device is not `forced`. Returns the coil's
/// previous state and the block after the coil (a forced device jumps
/// there); the builder continues in the block for a device that is not
/// forced.
fn unless_forced(b: &mut Builder, [state, forced]: [Bookkeeping; 2], index: u32, coil: Value) -> (Value, BlockId) {
    let was_on = b.load(Cell::Bookkeeping { field: state, index });
    b.store(Cell::Bookkeeping { field: state, index }, coil);
    let forced = b.load(Cell::Bookkeeping { field: forced, index });
    let (live, done) = (b.create_block(), b.create_block());
    b.terminate(Terminator::Branch {
        condition: forced,
        then: done,
        otherwise: live,
    });
    b.switch_to(live);
    (was_on, done)
}

/// Adds the elapsed time to a timer whose coil stays ON.
fn advance(b: &mut Builder, timer: u32, resolution_ms: u32, preset: Value) {
    let remainder = b.load(Cell::Bookkeeping {
        field: Bookkeeping::TimerRemainder,
        index: timer,
    });
    let remainder = b.extend(remainder, Type::I64, false);
    let elapsed = b.push(Inst::LoadElapsed);
    let elapsed = b.extend(elapsed, Type::I64, false);
    let total = b.binary(BinOp::Add, remainder, elapsed);
    // Both are unsigned and below 2^33, so signed division is exact.
    let (counts, left) = if resolution_ms == 1 {
        (total, b.constant(Type::I64, 0))
    } else {
        let resolution = b.constant(Type::I64, i64::from(resolution_ms));
        let counts = b.binary(BinOp::Div, total, resolution);
        let counted = b.binary(BinOp::Mul, counts, resolution);
        (counts, b.binary(BinOp::Sub, total, counted))
    };
    let left = b.truncate(left, Type::I16);
    b.store(
        Cell::Bookkeeping {
            field: Bookkeeping::TimerRemainder,
            index: timer,
        },
        left,
    );
    let value = b.load(Cell::Word {
        area: WordArea::TimerValue,
        index: Index::Fixed(timer),
    });
    let value = b.extend(value, Type::I64, true);
    let preset = b.extend(preset, Type::I64, true);
    let most = b.constant(Type::I64, i64::from(i16::MAX));
    let preset_below_most = b.compare(CompareOp::Lt, preset, most);
    let limit = b.select(preset_below_most, preset, most);
    let below_limit = b.compare(CompareOp::Lt, value, limit);
    let sum = b.binary(BinOp::Add, value, counts);
    let sum_below_limit = b.compare(CompareOp::Lt, sum, limit);
    let capped = b.select(sum_below_limit, sum, limit);
    let new = b.select(below_limit, capped, value);
    let new = b.truncate(new, Type::I16);
    b.store(
        Cell::Word {
            area: WordArea::TimerValue,
            index: Index::Fixed(timer),
        },
        new,
    );
}

/// `OUT Cn preset` of a 16-bit counter (`inline_counter`) with the rung
/// result `coil` (a Bit) and `preset` (I32). As the runtime: the coil's
/// state is kept first; a forced counter changes nothing more; a rising
/// coil adds 1 below the preset; the contact is ON at or above the preset.
pub fn counter(b: &mut Builder, counter: u32, coil: Value, preset: Value) {
    let (was_on, done) = unless_forced(b, [Bookkeeping::CounterCoil, Bookkeeping::CounterForced], counter, coil);
    {
        let index = Index::Fixed(counter);
        let value = b.load(Cell::Word {
            area: WordArea::CounterValue,
            index,
        });
        let value = b.extend(value, Type::I32, true);
        let was_off = b.not(was_on);
        let rising = b.and(coil, was_off);
        let below = b.compare(CompareOp::Lt, value, preset);
        let counts = b.and(rising, below);
        let step = b.extend(counts, Type::I32, false);
        // value < preset <= 32767 when it counts, so this cannot overflow.
        let new = b.binary(BinOp::Add, value, step);
        let stored = b.truncate(new, Type::I16);
        b.store(
            Cell::Word {
                area: WordArea::CounterValue,
                index,
            },
            stored,
        );
        let reached = b.compare(CompareOp::Ge, new, preset);
        b.store_bit(BitArea::CounterContact, index, reached);
    }
    b.jump_to(done);
}
