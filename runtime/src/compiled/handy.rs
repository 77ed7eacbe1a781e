//! Handy, display and table instructions of compiled code (SER, ABSD,
//! INCD, RAMP, TTMR, STMR, SEGD, SEGL, ASCI, HEX, CCD): the rules of the
//! interpreter's kernels, written apart from them. Places and counts are
//! checked by the caller.

use crate::device::Width;
use crate::image::ImageMut;
use crate::layout::{Array, Scalar};
use crate::memory::InstanceState;
use crate::place::Place;
use crate::special::{M_EIGHT_BIT_MODE_FX, M_EXECUTION_COMPLETE, M_RAMP_HOLD};

fn get(mem: &ImageMut<'_>, place: Place, unit: u32, width: Width) -> i64 {
    i64::from(place.nth(unit, width).read(mem, width))
}

fn set(mem: &mut ImageMut<'_>, place: Place, unit: u32, width: Width, value: i64) {
    place.nth(unit, width).write(mem, width, value);
}

fn complete(mem: &mut ImageMut<'_>, on: bool) {
    mem.set_u8(Array::M, M_EXECUTION_COMPLETE, u8::from(on));
}

/// SER: count, first, last match of `key`, positions of the smallest and
/// largest (the last of equals) among `n` values.
pub fn search(mem: &mut ImageMut<'_>, table: Place, n: u32, key: i64, destination: Place, width: Width) {
    let (mut count, mut first, mut last, mut low, mut high) = (0i64, None, 0i64, 0u32, 0u32);
    for i in 0..n {
        let value = get(mem, table, i, width);
        if value == key {
            count += 1;
            first.get_or_insert(i64::from(i));
            last = i64::from(i);
        }
        if value <= get(mem, table, low, width) {
            low = i;
        }
        if value >= get(mem, table, high, width) {
            high = i;
        }
    }
    let results = [count, first.unwrap_or(0), last, i64::from(low), i64::from(high)];
    for (unit, value) in (0..).zip(results) {
        set(mem, destination, unit, width, value);
    }
}

/// ABSD: output k ON for rising ≤ value < falling, wrapping when the
/// rising point is above the falling one.
pub fn absolute_drum(mem: &mut ImageMut<'_>, table: Place, n: u32, value: i64, outputs: Place, width: Width) {
    for k in 0..n {
        let rising = get(mem, table, 2 * k, width);
        let falling = get(mem, table, 2 * k + 1, width);
        let on = match rising.cmp(&falling) {
            core::cmp::Ordering::Greater => !(falling..rising).contains(&value),
            core::cmp::Ordering::Less | core::cmp::Ordering::Equal => (rising..falling).contains(&value),
        };
        set(mem, outputs, k, Width::Single, i64::from(on));
    }
}

/// INCD with counters `counter` (measure) and `counter + 1` (step).
pub fn incremental_drum(mem: &mut ImageMut<'_>, table: Place, n: u32, counter: u32, outputs: Place, power: bool) {
    let (measure, steps) = (counter, counter + 1);
    if steps >= Array::CounterValue.end() {
        return;
    }
    let mut finished = false;
    let active = if power {
        let last = i64::from(n) - 1;
        let mut current = i64::from(mem.get_i16(Array::CounterValue, steps)).max(0).min(last);
        if i64::from(mem.get_i16(Array::CounterValue, measure)) >= get(mem, table, current as u32, Width::Single) {
            mem.reset_counter(counter);
            finished = current == last;
            current = if finished { 0 } else { current + 1 };
        }
        mem.set_i16(Array::CounterValue, steps, current as i16);
        Some(current)
    } else {
        mem.reset_counter(counter);
        mem.reset_counter(counter + 1);
        None
    };
    for k in 0..n {
        set(mem, outputs, k, Width::Single, i64::from(active == Some(i64::from(k))));
    }
    if power {
        complete(mem, finished);
    }
}

/// An instance whose instruction ran with its rung OFF: it starts afresh.
pub fn instance_off(mem: &mut ImageMut<'_>, instance: u32) {
    if mem.instance(instance).is_some() {
        mem.set_instance(instance, InstanceState::default());
    }
}

/// RAMP with its rung ON: `target` holds D and D+1.
pub fn ramp(mem: &mut ImageMut<'_>, instance: u32, from: i64, to: i64, target: Place, n: i64) {
    let Some(mut state) = mem.instance(instance) else {
        return;
    };
    let started = state.phase == 0;
    state.phase = 1;
    mem.set_instance(instance, state);
    let counted = get(mem, target, 1, Width::Single);
    let hold = mem.get_u8(Array::M, M_RAMP_HOLD) != 0;
    let count = if started {
        0
    } else if counted >= n {
        if hold {
            n
        } else {
            0
        }
    } else {
        (counted + 1).max(0)
    };
    set(mem, target, 1, Width::Single, count);
    set(mem, target, 0, Width::Single, from + (to - from) * count / n);
    complete(mem, count == n);
}

/// TTMR: D+1 = ON time in 100 ms; D = D+1 × 10^n / 10 when it turns OFF.
pub fn teaching_timer(mem: &mut ImageMut<'_>, instance: u32, power: bool, target: Place, n: u32) {
    let elapsed = i64::from(mem.scalar(Scalar::ElapsedMs));
    let Some(mut state) = mem.instance(instance) else {
        return;
    };
    let was_on = state.phase == 1;
    state.phase = u32::from(power);
    if power {
        let ms = if was_on {
            (i64::from(state.a) + elapsed).min(32_767 * 100)
        } else {
            0
        };
        state.a = ms as i32;
        mem.set_instance(instance, state);
        set(mem, target, 1, Width::Single, ms / 100);
    } else if was_on {
        state.a = 0;
        mem.set_instance(instance, state);
        let tenths = get(mem, target, 1, Width::Single);
        let scale = [1, 10, 100][n.min(2) as usize];
        set(mem, target, 0, Width::Single, tenths * scale / 10);
        set(mem, target, 1, Width::Single, 0);
    } else {
        mem.set_instance(instance, state);
    }
}

/// STMR with timer `timer` (checked), `m` × 100 ms, four outputs.
pub fn special_timer(mem: &mut ImageMut<'_>, instance: u32, power: bool, timer: u32, m: i64, outputs: Place) {
    let period = m * 100;
    let elapsed = i64::from(mem.scalar(Scalar::ElapsedMs));
    let Some(mut state) = mem.instance(instance) else {
        return;
    };
    // phase 0: never ON; 1: ON; 2: OFF after ON.
    let phase = if power { 1 } else { 2 };
    if state.phase == 0 && !power {
        return;
    }
    let same = state.phase == phase;
    if !same && !power {
        state.b = i32::from(state.phase == 1 && i64::from(state.a) >= period);
    }
    let ms = if same {
        (i64::from(state.a) + elapsed).min(period)
    } else {
        0
    };
    state.phase = phase;
    state.a = ms as i32;
    let timing = ms < period;
    let on_delay_was_on = state.b == 1;
    let bits = match phase {
        1 => [true, false, timing, !timing],
        _ => [timing, timing, false, timing && on_delay_was_on],
    };
    mem.set_instance(instance, state);
    mem.set_i16(Array::TimerValue, timer, (ms / 100) as i16);
    for (unit, on) in (0..).zip(bits) {
        set(mem, outputs, unit, Width::Single, i64::from(on));
    }
}

/// SEGD: the segments of a hex digit.
pub fn segments(digit: u32) -> i32 {
    const TABLE: [u8; 16] = [
        0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x27, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
    ];
    i32::from(TABLE[(digit & 0xF) as usize])
}

/// SEGL with its rung ON: the first `sets` of `values`, outputs from
/// `outputs`; false (nothing written) when a value is above 9999.
pub fn segment_latch(
    mem: &mut ImageMut<'_>,
    instance: u32,
    values: [i64; 2],
    sets: u32,
    outputs: Place,
    n: u32,
) -> bool {
    let sets = sets.clamp(1, 2);
    if values[..sets as usize].iter().any(|&v| !(0..10_000).contains(&v)) {
        return false;
    }
    let Some(mut state) = mem.instance(instance) else {
        return true;
    };
    let phase = (state.a.rem_euclid(12)) as u32;
    state.a = ((phase + 1) % 12) as i32;
    mem.set_instance(instance, state);
    let digit = phase / 3;
    let strobe_on = phase % 3 == 1;
    let (data_inverted, strobe_inverted) = (n & 1 == 1, n & 2 == 2);
    let mut divisor = 1;
    for _ in 0..digit {
        divisor *= 10;
    }
    for (set_number, value) in (0..sets).zip(values) {
        let bcd = value / divisor % 10;
        for bit in 0..4 {
            let on = (bcd >> bit) & 1 == 1;
            set(
                mem,
                outputs,
                8 * set_number + bit,
                Width::Single,
                i64::from(on ^ data_inverted),
            );
        }
    }
    for strobe in 0..4 {
        let on = strobe_on && strobe == digit;
        set(mem, outputs, 4 + strobe, Width::Single, i64::from(on ^ strobe_inverted));
    }
    complete(mem, phase == 11);
    true
}

/// The three character conversions, with the one code each that compiled
/// code passes to `ladder_rt_characters`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CharacterOp {
    /// ASCI: hex digits to ASCII characters.
    Ascii,
    /// HEX: ASCII characters to hex digits.
    Hex,
    /// CCD: the sum and the horizontal parity of the characters.
    CheckCode,
}

impl CharacterOp {
    pub const fn code(self) -> u32 {
        match self {
            CharacterOp::Ascii => 0,
            CharacterOp::Hex => 1,
            CharacterOp::CheckCode => 2,
        }
    }

    pub const fn from_code(code: u32) -> Option<CharacterOp> {
        match code {
            0 => Some(CharacterOp::Ascii),
            1 => Some(CharacterOp::Hex),
            2 => Some(CharacterOp::CheckCode),
            _ => None,
        }
    }
}

/// ASCI, HEX or CCD over `n` characters; M8161 decides one or two per
/// word. False when HEX met a character that is not a hex digit.
pub fn characters(mem: &mut ImageMut<'_>, op: CharacterOp, source: Place, destination: Place, n: u32) -> bool {
    let eight_bit = mem.get_u8(Array::M, M_EIGHT_BIT_MODE_FX) != 0;
    let byte_at = |mem: &ImageMut<'_>, place: Place, i: u32| -> i64 {
        if eight_bit {
            get(mem, place, i, Width::Single) & 0xFF
        } else {
            (get(mem, place, i / 2, Width::Single) >> (8 * (i % 2))) & 0xFF
        }
    };
    match op {
        CharacterOp::Ascii => {
            // The source words first: D may overlap S (at most 256
            // characters, 64 words).
            let n = n.min(256);
            let mut words = [0i64; 64];
            for (k, word) in (0..n.div_ceil(4)).zip(words.iter_mut()) {
                *word = get(mem, source, k, Width::Single);
            }
            // Character i is hex digit n-1-i of the multi-word number.
            let character = |i: u32| {
                let k = n - 1 - i;
                let digit = (words[(k / 4) as usize] >> (4 * (k % 4))) & 0xF;
                if digit > 9 {
                    digit - 10 + i64::from(b'A')
                } else {
                    digit + i64::from(b'0')
                }
            };
            if eight_bit {
                for i in 0..n {
                    set(mem, destination, i, Width::Single, character(i));
                }
            } else {
                for word in 0..n.div_ceil(2) {
                    let low = character(2 * word);
                    let high = if 2 * word + 1 < n { character(2 * word + 1) } else { 0 };
                    set(mem, destination, word, Width::Single, low | (high << 8));
                }
            }
            true
        }
        CharacterOp::Hex => {
            let mut words = [0i64; 64];
            for i in 0..n {
                let digit = match byte_at(mem, source, i) as u8 {
                    c @ b'0'..=b'9' => c - b'0',
                    c @ b'A'..=b'F' => c - b'A' + 10,
                    _ => return false,
                };
                // The last character is digit 0.
                let k = n - 1 - i;
                words[(k / 4) as usize] |= i64::from(digit) << (4 * (k % 4));
            }
            for (word, &value) in (0..n.div_ceil(4)).zip(words.iter()) {
                set(mem, destination, word, Width::Single, value);
            }
            true
        }
        CharacterOp::CheckCode => {
            let (mut sum, mut parity) = (0i64, 0i64);
            for i in 0..n {
                let byte = byte_at(mem, source, i);
                sum += byte;
                parity ^= byte;
            }
            set(mem, destination, 0, Width::Single, sum);
            set(mem, destination, 1, Width::Single, parity);
            true
        }
    }
}
