//! Handy, display and table instructions: SER, ABSD, INCD, RAMP, TTMR,
//! STMR, SEGD, SEGL, ASCI, HEX, CCD.
//!
//! M8029 ("execution complete") is written by every execution of INCD,
//! RAMP and SEGL: ON in the scan they complete (RAMP in hold mode: while
//! it stays at S2), OFF otherwise.

use super::{Execution, Outcome, Step};
use ladder_front::program::{BitRef, CounterRef, WordRef};
use ladder_runtime::special::{M_EIGHT_BIT_MODE_FX, M_EXECUTION_COMPLETE, M_RAMP_HOLD};
use ladder_runtime::{OperationError, Place, Width};

impl Step<'_> {
    fn run_of(&self, place: Place, count: u32, width: Width) -> Vec<i64> {
        (0..count)
            .map(|unit| self.read_at(place.nth(unit, width), width))
            .collect()
    }

    fn put(&mut self, place: Place, values: &[i64], width: Width) {
        for (unit, &value) in (0..).zip(values) {
            self.write_at(place.nth(unit, width), width, value);
        }
    }

    fn set_complete(&mut self, on: bool) {
        self.mem.m[M_EXECUTION_COMPLETE as usize] = u8::from(on);
    }

    fn eight_bit(&self) -> bool {
        self.mem.m[M_EIGHT_BIT_MODE_FX as usize] != 0
    }
}

/// SER/DSER S1 S2 D n: of n values from S1, D = how many equal S2, D+1 the
/// first and D+2 the last position of a match (0 without), D+3 the
/// position of the smallest and D+4 of the largest (the last of equals);
/// n 1-256 (DSER 1-128), else 4084H.
pub fn search(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = step.source_value(n)?;
    let limit = if step.width == Width::Double { 128 } else { 256 };
    if !(1..=limit).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let n = n as u32;
    let table = step.resolve(s1, step.width, n, true);
    let key = step.source(s2);
    let d = step.resolve(d, step.width, 5, false);
    step.commit()?;
    let (Some(table), Some(key), Some(d)) = (table, key, d) else {
        return Ok(());
    };
    let key = step.read(key);
    let values = step.run_of(table, n, step.width);
    let matches: Vec<i64> = (0..).zip(&values).filter(|(_, &v)| v == key).map(|(i, _)| i).collect();
    let mut smallest = 0;
    let mut largest = 0;
    for (i, &value) in values.iter().enumerate() {
        if value <= values[smallest] {
            smallest = i;
        }
        if value >= values[largest] {
            largest = i;
        }
    }
    let results = [
        matches.len() as i64,
        matches.first().copied().unwrap_or(0),
        matches.last().copied().unwrap_or(0),
        smallest as i64,
        largest as i64,
    ];
    step.put(d, &results, step.width);
    Ok(())
}

/// ABSD/DABSD S1 S2 D n: output k (of n bits from D) is ON while the
/// counter value S2 lies from the rising point S1+2k (included) to the
/// falling point S1+2k+1 (excluded); past the end of the count when the
/// rising point is above the falling one. n 1-64, else 4084H.
pub fn absolute_drum(step: &mut Step, s1: &WordRef, s2: &WordRef, d: &BitRef, n: &WordRef) -> Outcome {
    let n = step.count_value(n)?;
    if !(1..=64).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let n = n as u32;
    let table = step.resolve(s1, step.width, 2 * n, true);
    let counter = step.source(s2);
    let d = step.bits(d, n, false);
    step.commit()?;
    let (Some(table), Some(counter), Some(d)) = (table, counter, d) else {
        return Ok(());
    };
    let value = step.read(counter);
    let points = step.run_of(table, 2 * n, step.width);
    for k in 0..n {
        let (rising, falling) = (points[2 * k as usize], points[2 * k as usize + 1]);
        let on = if rising <= falling {
            rising <= value && value < falling
        } else {
            value >= rising || value < falling
        };
        step.write_at(d.nth(k, Width::Single), Width::Single, i64::from(on));
    }
    Ok(())
}

/// INCD S1 S2 D n (every scan): step k (counter S2+1) lasts until counter
/// S2 reaches S1+k; then S2 is reset and the next step starts; after the
/// last step M8029 is ON for that scan and it starts again at step 0.
/// Output D+k is ON during step k. With the rung OFF both counters and the
/// outputs are cleared. n 1-64, else 4084H.
pub fn incremental_drum(
    step: &mut Step,
    run: &Execution,
    s1: &WordRef,
    s2: &CounterRef,
    d: &BitRef,
    n: &WordRef,
) -> Outcome {
    let n = step.count_value(n)?;
    if !(1..=64).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let n = n as u32;
    let table = step.resolve(s1, Width::Single, n, true);
    let counter = crate::access::effective_index(step.mem, s2.0);
    if !(0..=198).contains(&counter) {
        step.fail_read();
    }
    let d = step.bits(d, n, false);
    step.commit()?;
    let (Some(table), Some(d)) = (table, d) else {
        return Ok(());
    };
    let counter = counter as u32;
    let mut done = false;
    let current = if run.power {
        let mut current = i64::from(step.mem.counter_value[counter as usize + 1]).clamp(0, i64::from(n) - 1);
        let target = step.read_at(table.nth(current as u32, Width::Single), Width::Single);
        if i64::from(step.mem.counter_value[counter as usize]) >= target {
            step.mem.reset_counter(counter);
            current += 1;
            if current == i64::from(n) {
                current = 0;
                done = true;
            }
        }
        step.mem.counter_value[counter as usize + 1] = current as i16;
        Some(current as u32)
    } else {
        step.mem.reset_counter(counter);
        step.mem.reset_counter(counter + 1);
        None
    };
    for k in 0..n {
        step.write_at(d.nth(k, Width::Single), Width::Single, i64::from(current == Some(k)));
    }
    // With the rung OFF the instruction only clears; M8029 is left alone.
    if run.power {
        step.set_complete(done);
    }
    Ok(())
}

/// RAMP S1 S2 D n (every scan): from the scan the rung turns ON, D+1
/// counts scans up to n and D = S1 + (S2 − S1) × D+1 / n (truncated);
/// M8029 ON when it arrives. Then with M8026 ON it stays at S2 (M8029
/// stays ON), else it starts again from S1. With the rung OFF it stops
/// where it is. n 1-32767, else 4084H.
pub fn ramp(step: &mut Step, run: &Execution, s1: &WordRef, s2: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let instance = run.job as usize;
    if !run.power {
        if let Some(state) = step.mem.instance.get_mut(instance) {
            *state = Default::default();
        }
        return Ok(());
    }
    let n = step.count_value(n)?;
    if !(1..=32_767).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let from = step.count(s1);
    let to = step.count(s2);
    let d = step.resolve(d, Width::Single, 2, false);
    step.commit()?;
    let (Some(from), Some(to), Some(d)) = (from, to, d) else {
        return Ok(());
    };
    let (from, to) = (step.read_at(from, Width::Single), step.read_at(to, Width::Single));
    // The ramp starts in the first scan it runs after its rung was OFF.
    let Some(state) = step.mem.instance.get_mut(instance) else {
        return Ok(());
    };
    let was_on = state.phase != 0;
    state.phase = 1;
    let count_place = d.nth(1, Width::Single);
    let counted = step.read_at(count_place, Width::Single);
    let hold = step.mem.m[M_RAMP_HOLD as usize] != 0;
    let count = if !was_on || (counted >= n && !hold) {
        0
    } else {
        (counted + 1).clamp(0, n)
    };
    step.write_at(count_place, Width::Single, count);
    step.write_at(d, Width::Single, from + (to - from) * count / n);
    step.set_complete(count == n);
    Ok(())
}

/// TTMR D n (every scan): while the rung is ON, D+1 counts its ON time in
/// 100 ms (the milliseconds below kept in the instance state); when it
/// turns OFF, D = D+1 × 10^n / 10 and D+1 = 0. n 0-2, else 4084H.
pub fn teaching_timer(step: &mut Step, run: &Execution, d: &WordRef, n: &WordRef) -> Outcome {
    let n = step.count_value(n)?;
    if !(0..=2).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let d = step.resolve(d, Width::Single, 2, false);
    step.commit()?;
    let Some(d) = d else { return Ok(()) };
    let elapsed = i64::from(step.mem.elapsed_ms);
    let Some(state) = step.mem.instance.get_mut(run.job as usize) else {
        return Ok(());
    };
    let was_on = state.phase != 0;
    state.phase = u32::from(run.power);
    let time_place = d.nth(1, Width::Single);
    if run.power {
        let ms = if was_on { i64::from(state.a) + elapsed } else { 0 };
        let ms = ms.min(i64::from(i16::MAX) * 100);
        state.a = ms as i32;
        step.write_at(time_place, Width::Single, ms / 100);
    } else if was_on {
        state.a = 0;
        let tenths = step.read_at(time_place, Width::Single);
        step.write_at(d, Width::Single, tenths * 10i64.pow(n as u32) / 10);
        step.write_at(time_place, Width::Single, 0);
    }
    Ok(())
}

/// STMR S m D (every scan), with timer S showing the time since the rung
/// last changed (100 ms): D is an OFF-delay (OFF m × 100 ms after the rung
/// turns OFF), D+1 a one-shot of m after OFF, D+2 a one-shot of m after
/// ON, D+3 an ON- and OFF-delay. m 1-32767, else 4084H.
pub fn special_timer(
    step: &mut Step,
    run: &Execution,
    s: &ladder_front::program::Address,
    m: &WordRef,
    d: &BitRef,
) -> Outcome {
    let m = step.count_value(m)?;
    if !(1..=32_767).contains(&m) {
        return Err(OperationError::DataOutOfRange);
    }
    let timer = crate::access::effective_index(step.mem, *s);
    if !(0..=199).contains(&timer) {
        step.fail_read();
    }
    let d = step.bits(d, 4, false);
    step.commit()?;
    let Some(d) = d else { return Ok(()) };
    let timer = timer as usize;
    let elapsed = i64::from(step.mem.elapsed_ms);
    let Some(state) = step.mem.instance.get_mut(run.job as usize) else {
        return Ok(());
    };
    // phase: 0 never ON, 1 ON, 2 OFF after ON; a: ms since the change;
    // b: D+3 at the change to OFF.
    let ms = if (state.phase == 1) == run.power && state.phase != 0 {
        (i64::from(state.a) + elapsed).min(m * 100)
    } else {
        if !run.power {
            state.b = i32::from(state.phase == 1 && i64::from(state.a) >= m * 100);
        }
        0
    };
    if state.phase == 0 && !run.power {
        return Ok(());
    }
    state.phase = if run.power { 1 } else { 2 };
    state.a = ms as i32;
    let running = ms < m * 100;
    let delayed_on = state.b != 0;
    let outputs = if run.power {
        [true, false, running, !running]
    } else {
        [running, running, false, running && delayed_on]
    };
    step.mem.timer_value[timer] = (ms / 100) as i16;
    for (unit, on) in (0..).zip(outputs) {
        step.write_at(d.nth(unit, Width::Single), Width::Single, i64::from(on));
    }
    Ok(())
}

/// The seven segments (g..a in bits 6..0) of the hex digits 0-F.
const SEGMENTS: [i64; 16] = [
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x27, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
];

/// SEGD S D: the low byte of D = the segments of the low 4 bits of S; the
/// high byte is kept.
pub fn segment_decode(step: &mut Step, s: &WordRef, d: &WordRef) -> Outcome {
    let s = step.source(s);
    let d = step.destination(d);
    step.commit()?;
    let (Some(s), Some(d)) = (s, d) else { return Ok(()) };
    let digit = step.read(s) & 0xF;
    let kept = step.read(d) & !0xFF;
    step.write(d, kept | SEGMENTS[digit as usize]);
    Ok(())
}

/// SEGL S D n (every scan): shows S (and S+1 for n 4-7) as four BCD digits
/// on D..D+3 (second set D+10..D+13) with the digit strobes D+4..D+7 (ones
/// first), one digit every 3 scans: data, strobe ON, strobe OFF. M8029 is
/// ON in the 12th scan of each cycle. n 0-7 (bit 0: negative data logic,
/// bit 1: negative strobe logic); S above 9999, or n out of range, 4084H.
pub fn segment_latch(step: &mut Step, run: &Execution, s: &WordRef, d: &BitRef, n: &WordRef) -> Outcome {
    let instance = run.job as usize;
    if !run.power {
        if let Some(state) = step.mem.instance.get_mut(instance) {
            *state = Default::default();
        }
        return Ok(());
    }
    let n = step.count_value(n)?;
    if !(0..=7).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let sets = if n >= 4 { 2 } else { 1 };
    let s = step.resolve(s, Width::Single, sets, true);
    // D..D+7, and the second set's D+10..D+13 (octal: 8 further).
    let d = step.bits(d, if sets == 2 { 12 } else { 8 }, false);
    step.commit()?;
    let (Some(s), Some(d)) = (s, d) else { return Ok(()) };
    let values = step.run_of(s, sets, Width::Single);
    if values.iter().any(|v| !(0..=9999).contains(v)) {
        return Err(OperationError::DataOutOfRange);
    }
    let Some(state) = step.mem.instance.get_mut(instance) else {
        return Ok(());
    };
    let phase = state.a.rem_euclid(12) as u32;
    state.a = ((phase + 1) % 12) as i32;
    let (digit, part) = (phase / 3, phase % 3);
    let data_low = n & 1 != 0;
    let strobe_low = n & 2 != 0;
    for (set, &value) in values.iter().enumerate() {
        let bcd = (value / 10i64.pow(digit)) % 10;
        let first = 8 * set as u32;
        for bit in 0..4 {
            let on = (bcd >> bit) & 1 != 0;
            step.write_at(
                d.nth(first + bit, Width::Single),
                Width::Single,
                i64::from(on != data_low),
            );
        }
    }
    for strobe in 0..4 {
        let on = part == 1 && strobe == digit;
        step.write_at(
            d.nth(4 + strobe, Width::Single),
            Width::Single,
            i64::from(on != strobe_low),
        );
    }
    step.set_complete(phase == 11);
    Ok(())
}

/// The n bytes of a block: both bytes of each word, low first, or (8-bit
/// mode) the low byte of each word.
fn bytes_of(step: &Step, place: Place, n: u32, eight_bit: bool) -> Vec<i64> {
    (0..n)
        .map(|i| {
            let (word, shift) = if eight_bit { (i, 0) } else { (i / 2, 8 * (i % 2)) };
            (step.read_at(place.nth(word, Width::Single), Width::Single) >> shift) & 0xFF
        })
        .collect()
}

/// Words that hold `n` characters (bytes).
fn words_for(n: u32, eight_bit: bool) -> u32 {
    if eight_bit {
        n
    } else {
        n.div_ceil(2)
    }
}

/// ASCI S D n: the n lowest hex digits of S (S+1 more significant, ...) as
/// ASCII characters from D, the most significant first (M8161: one
/// character per word, else two, the first in the low byte). n 1-256.
pub fn ascii(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = character_count(step, n)?;
    let eight_bit = step.eight_bit();
    let s = step.resolve(s, Width::Single, n.div_ceil(4), true);
    let d = step.resolve(d, Width::Single, words_for(n, eight_bit), false);
    step.commit()?;
    let (Some(s), Some(d)) = (s, d) else { return Ok(()) };
    let words = step.run_of(s, n.div_ceil(4), Width::Single);
    let digit = |k: u32| (words[(k / 4) as usize] >> (4 * (k % 4))) & 0xF;
    let characters: Vec<i64> = (0..n)
        .rev()
        .map(|k| {
            let value = digit(k);
            if value < 10 {
                0x30 + value
            } else {
                0x37 + value
            }
        })
        .collect();
    let words: Vec<i64> = if eight_bit {
        characters
    } else {
        characters
            .chunks(2)
            .map(|pair| pair[0] | (pair.get(1).copied().unwrap_or(0) << 8))
            .collect()
    };
    step.put(d, &words, Width::Single);
    Ok(())
}

/// n of ASCI, HEX and CCD: 1-256 characters or bytes, else 4084H.
fn character_count(step: &mut Step, n: &WordRef) -> Result<u32, OperationError> {
    let n = step.count_value(n)?;
    if !(1..=256).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    Ok(n as u32)
}

/// HEX S D n: n ASCII hex characters from S (as ASCI lays them out) as a
/// number in D, D+1, ... (the last character is the lowest digit; unused
/// digits of the last word 0). A character that is not 0-9 or A-F is
/// 4084H. n 1-256.
pub fn hex(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = character_count(step, n)?;
    let eight_bit = step.eight_bit();
    let s = step.resolve(s, Width::Single, words_for(n, eight_bit), true);
    let d = step.resolve(d, Width::Single, n.div_ceil(4), false);
    step.commit()?;
    let (Some(s), Some(d)) = (s, d) else { return Ok(()) };
    let characters = bytes_of(step, s, n, eight_bit);
    let mut digits = Vec::with_capacity(n as usize);
    for character in characters.iter().rev() {
        let digit = match *character as u8 {
            c @ b'0'..=b'9' => c - b'0',
            c @ b'A'..=b'F' => c - b'A' + 10,
            _ => return Err(OperationError::DataOutOfRange),
        };
        digits.push(i64::from(digit));
    }
    let words: Vec<i64> = digits
        .chunks(4)
        .map(|chunk| chunk.iter().enumerate().fold(0, |word, (i, &d)| word | (d << (4 * i))))
        .collect();
    step.put(d, &words, Width::Single);
    Ok(())
}

/// CCD S D n: D = the sum of n bytes from S, D+1 = their exclusive OR
/// (horizontal parity). n 1-256.
pub fn check_code(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = character_count(step, n)?;
    let eight_bit = step.eight_bit();
    let s = step.resolve(s, Width::Single, words_for(n, eight_bit), true);
    let d = step.resolve(d, Width::Single, 2, false);
    step.commit()?;
    let (Some(s), Some(d)) = (s, d) else { return Ok(()) };
    let bytes = bytes_of(step, s, n, eight_bit);
    let sum: i64 = bytes.iter().sum();
    let parity = bytes.iter().fold(0, |x, b| x ^ b);
    step.put(d, &[sum, parity], Width::Single);
    Ok(())
}
