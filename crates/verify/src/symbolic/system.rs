//! The whole scan and one property as a transition system in an AIG: the
//! latches hold the image after a scan (power-up before the first), the
//! free inputs are the file's inputs (and the elapsed time when it is
//! ranged), and one latch, `bad`, is ON in the state after a scan that
//! breaks the claim (for `reach`: that shows the condition). The scan is
//! the one docs/language.md describes ("How a program runs"): the inputs
//! written (and the assumptions read), the input refresh, pending STL
//! states turned OFF, the first-scan and clock relays, the program's IR
//! (`encode.rs`), the outputs.

use super::aig::{Aig, Lit};
use super::encode::{self, Image, Key, Unsupported};
use super::words::{self, Word};
use crate::expr::{Compare, Expr, Term};
use crate::model::Model;
use crate::property::{Claim, Input, PropertyFile, ScanTime};
use ladder_front::host_device::HostDevice;
use ladder_runtime::layout::{Array, FULL};
use ladder_runtime::special::{
    CLOCK_CYCLE_MS, CLOCK_RELAYS, M_ALWAYS_OFF, M_ALWAYS_ON, M_FIRST_SCAN, M_NOT_FIRST_SCAN, SM_ALWAYS_OFF,
    SM_ALWAYS_ON, SM_FIRST_SCAN, SM_NOT_FIRST_SCAN,
};
use ladder_runtime::{BitArea, Device, MachineUse, Width, WordArea};
use rustc_hash::{FxHashMap, FxHashSet};

/// Bits of the clock's milliseconds (below a minute).
const CLOCK_BITS: u32 = 16;

/// A property's transition system.
#[derive(Clone)]
pub struct System {
    pub aig: Aig,
    /// ON after a scan that breaks the claim (or, for `reach`, shows it).
    pub bad: Lit,
    /// ON after a scan where the claim's condition (left of an `always`'s
    /// `->`, a `respond`'s trigger) held: asked of a proof, for vacuity.
    pub condition: Option<Lit>,
    /// The bits of each of the model's free inputs, in its order.
    pub inputs: Vec<Word>,
    /// The elapsed time's bits when it is chosen per scan.
    pub elapsed: Option<Word>,
    /// What the model takes as arbitrary values.
    pub unmodelled: Vec<String>,
    /// ON after scans whose inputs all met the assumptions and ranges (its
    /// value after scan 1 says whether any input of the first scan does).
    pub valid: Lit,
}

/// The system of `claim` on `model`'s program (`ir`) under `file`.
pub fn build(
    model: &Model,
    ir: &ladder_ir::Program,
    file: &PropertyFile,
    claim: &Claim,
) -> Result<System, Unsupported> {
    let machine = model.machine();
    if machine.contains(MachineUse::HIGH_SPEED) || machine.contains(MachineUse::ALARMS) {
        return Err(Unsupported(
            "high-speed counters and the alarm monitor are not encoded".to_string(),
        ));
    }
    // The first build learns every element the scan touches; the second
    // knows them all from the start, so an indexed store reaches each.
    let forces = &file.forces;
    let (_, known) = build_once(model, ir, claim, forces, FxHashSet::default())?;
    let (system, _) = build_once(model, ir, claim, forces, known)?;
    Ok(system.simplified())
}

impl System {
    /// The system with its constant latches folded away
    /// (`Aig::without_constant_latches`): fewer state bits for the engines
    /// and in AIGER files.
    pub fn simplified(self) -> System {
        let (aig, map) = self.aig.without_constant_latches();
        let at = |l: Lit| {
            let m = map[l.node() as usize];
            if l.negated() {
                !m
            } else {
                m
            }
        };
        System {
            bad: at(self.bad),
            condition: self.condition.map(at),
            inputs: self.inputs.iter().map(|w| w.iter().map(|&l| at(l)).collect()).collect(),
            elapsed: self.elapsed.as_ref().map(|w| w.iter().map(|&l| at(l)).collect()),
            unmodelled: self.unmodelled,
            valid: at(self.valid),
            aig,
        }
    }
}

fn build_once(
    model: &Model,
    ir: &ladder_ir::Program,
    claim: &Claim,
    forces: &[(BitArea, u32, bool)],
    known: FxHashSet<Key>,
) -> Result<(System, FxHashSet<Key>), Unsupported> {
    let mut aig = Aig::new();
    let mut latches: FxHashMap<Key, Word> = FxHashMap::default();
    let power_up = &model.power_up;
    let mut fresh_element = |aig: &mut Aig, key: Key| -> Word {
        if let Some(word) = latches.get(&key) {
            return word.clone();
        }
        let init = encode::initial(power_up, key).unwrap_or_default();
        let word: Word = init.iter().map(|&bit| aig.latch(bit == Lit::TRUE)).collect();
        latches.insert(key, word.clone());
        word
    };
    let started = aig.latch(false);
    let ok = aig.latch(true);
    let bad = aig.latch(false);
    let mut image = Image {
        aig: &mut aig,
        memory: FxHashMap::default(),
        known: known.clone(),
        elapsed: Vec::new(),
        loop_repetitions: words::constant(0, 32),
        unmodelled: Vec::new(),
        fresh_element: &mut fresh_element,
    };
    let mut keys: Vec<Key> = known.iter().copied().collect();
    keys.sort_unstable_by_key(|&(a, n)| (a as u32, n));
    for &key in &keys {
        image.read(key);
    }
    // The image after the previous scan: what `prev` reads.
    let before: FxHashMap<Key, Word> = image.memory.clone();

    // The inputs, written as a host writes them; the assumptions read them.
    let mut inputs = Vec::new();
    let mut valid = Lit::TRUE;
    let mut free_x = FxHashSet::default();
    for input in &model.inputs {
        match *input {
            Input::Bit(area, n) => {
                let bit = image.aig.input();
                image.write((Array::of_bits(area), n), Lit::TRUE, &[bit]);
                if area == BitArea::X {
                    free_x.insert(n);
                }
                inputs.push(vec![bit]);
            }
            Input::Word { device, low, high } => {
                let word: Word = (0..device.bits()).map(|_| image.aig.input()).collect();
                write_device(&mut image, device, &word);
                // A host's write of X bits (`K4X0`) goes to the input
                // image, which the refresh copies to X: they stay.
                for ((array, n), _) in device_keys(device).0 {
                    if array == Array::X {
                        free_x.insert(n);
                    }
                }
                let width = device.bits() + 2;
                let value = words::resize(&word, width, true);
                let below = words::less_signed(image.aig, &value, &words::constant(low, width));
                let above = words::less_signed(image.aig, &words::constant(high, width), &value);
                let inside = image.aig.or(below, above);
                valid = image.aig.and(valid, !inside);
                inputs.push(word);
            }
        }
    }
    for assume in &model.assumes {
        let holds = expr(&mut image, &before, assume);
        valid = image.aig.and(valid, holds);
    }

    // Step 1: the input refresh (the input image to X).
    for &(array, n) in &keys {
        if array == Array::X && !free_x.contains(&n) {
            let bit = input_image_bit(power_up, n);
            image.write((Array::X, n), Lit::TRUE, &[Lit::constant(bit)]);
        }
    }
    // Forced inputs and timer or counter contacts win over the refresh
    // (`force.rs`, step 1).
    for &(area, n, on) in forces {
        if forced_at_refresh(area) {
            image.write((Array::of_bits(area), n), Lit::TRUE, &[Lit::constant(on)]);
        }
    }
    let (elapsed, free_elapsed) = match model.scan_time {
        ScanTime::Fixed(ms) => (words::constant(i64::from(ms), 32), None),
        ScanTime::Range(low, high) => {
            let bits = 32 - high.leading_zeros();
            let word: Word = (0..bits.max(1)).map(|_| image.aig.input()).collect();
            let wide = words::resize(&word, 34, false);
            let below = words::less_signed(image.aig, &wide, &words::constant(i64::from(low), 34));
            let above = words::less_signed(image.aig, &words::constant(i64::from(high), 34), &wide);
            let outside = image.aig.or(below, above);
            valid = image.aig.and(valid, !outside);
            (words::resize(&word, 32, false), Some(word))
        }
    };
    image.elapsed = elapsed;
    // Step 2: states a SET transfer left pending turn OFF.
    for &(array, n) in &keys {
        if array == Array::StlPendingOff {
            let pending = image.read((array, n))[0];
            let state = image.read((Array::S, n))[0];
            let kept = image.aig.and(state, !pending);
            image.write((Array::S, n), Lit::TRUE, &[kept]);
            image.write((array, n), Lit::TRUE, &[Lit::FALSE]);
        }
    }
    let machine = model.machine();
    if machine.contains(MachineUse::SYSTEM_RELAYS) {
        let first = !started;
        let relays = [
            (&M_ALWAYS_ON[..], Lit::TRUE),
            (&M_ALWAYS_OFF[..], Lit::FALSE),
            (&M_FIRST_SCAN[..], first),
            (&M_NOT_FIRST_SCAN[..], !first),
        ];
        for (numbers, value) in relays {
            for &n in numbers {
                image.write((Array::M, n), Lit::TRUE, &[value]);
            }
        }
        for (n, value) in [
            (SM_ALWAYS_ON, Lit::TRUE),
            (SM_ALWAYS_OFF, Lit::FALSE),
            (SM_FIRST_SCAN, first),
            (SM_NOT_FIRST_SCAN, !first),
        ] {
            image.write((Array::Sm, n), Lit::TRUE, &[value]);
        }
    }
    // The clock relays follow the elapsed times exactly (M8011-M8014 from
    // the milliseconds the scan keeps, within a one-minute cycle).
    let clock = if machine.contains(MachineUse::CLOCK_RELAYS) {
        let init = words::constant(i64::from(power_up.clock_ms), CLOCK_BITS);
        let clock: Word = init.iter().map(|&b| image.aig.latch(b == Lit::TRUE)).collect();
        let aig = &mut *image.aig;
        let wide = |w: &[Lit]| words::resize(w, 34, false);
        let sum = words::add(aig, &wide(&clock), &wide(&image.elapsed));
        let (_, now) = words::divide_unsigned(aig, &sum, &words::constant(i64::from(CLOCK_CYCLE_MS), 34));
        let mut relays = Vec::new();
        for (relay, period) in CLOCK_RELAYS {
            let (_, phase) = words::divide_unsigned(aig, &now, &words::constant(i64::from(period), 34));
            let first_half = words::less_signed(aig, &phase, &words::constant(i64::from(period / 2), 34));
            relays.push((relay, !first_half));
        }
        for (relay, on) in relays {
            image.write((Array::M, relay), Lit::TRUE, &[on]);
        }
        Some((clock, now[..CLOCK_BITS as usize].to_vec()))
    } else {
        None
    };
    // The calendar and the scan-time registers follow real time:
    // arbitrary here.
    let timed = MachineUse::CALENDAR.with(MachineUse::SCAN_TIME);
    for &(array, n) in &keys {
        let part = match (bit_area(array), word_area(array)) {
            (Some(area), _) => MachineUse::of_bits(area, n, n + 1),
            (None, Some(area)) => MachineUse::of_words(area, n, n + 1),
            (None, None) => MachineUse::NONE,
        };
        if part.bits() & timed.bits() & machine.bits() != 0 {
            image.note("the clock, the calendar and the scan time (taken as arbitrary)");
            let bits = encode::width(array).unwrap_or(1);
            let value: Word = (0..bits).map(|_| image.aig.input()).collect();
            image.write((array, n), Lit::TRUE, &value);
        }
    }

    // Step 3: the program.
    encode::run_program(&mut image, ir)?;
    // Step 4: forced outputs and relays over the program's results.
    for &(area, n, on) in forces {
        if !forced_at_refresh(area) {
            image.write((Array::of_bits(area), n), Lit::TRUE, &[Lit::constant(on)]);
        }
    }

    // After the scan: the claim.
    let now_ok = image.aig.and(ok, valid);
    let (broken, condition) = claim_step(&mut image, &before, claim);
    let known_after = image.known.clone();
    let memory = std::mem::take(&mut image.memory);
    let unmodelled = std::mem::take(&mut image.unmodelled);
    let condition_latch = condition.map(|c| {
        let latch = aig.latch(false);
        let next = aig.and(now_ok, c);
        aig.set_next(latch, next);
        latch
    });
    let next_bad = aig.and(now_ok, broken);
    aig.set_next(bad, next_bad);
    aig.set_next(started, Lit::TRUE);
    if let Some((clock, now)) = clock {
        for (&l, &n) in clock.iter().zip(&now) {
            aig.set_next(l, n);
        }
    }
    aig.set_next(ok, now_ok);
    for (key, latch) in &latches {
        let Some(value) = memory.get(key) else { continue };
        for (&l, &v) in latch.iter().zip(value) {
            aig.set_next(l, v);
        }
    }
    Ok((
        System {
            aig,
            bad,
            condition: condition_latch,
            inputs,
            elapsed: free_elapsed,
            unmodelled,
            valid: ok,
        },
        known_after,
    ))
}

/// Whether this scan breaks the claim, and its condition; a `respond`'s
/// monitor (the scans the oldest waiting trigger still allows, 0 for none,
/// as `search::check` counts them) is kept in latches of its own.
fn claim_step(image: &mut Image, before: &FxHashMap<Key, Word>, claim: &Claim) -> (Lit, Option<Lit>) {
    match claim {
        Claim::Never(e) => (expr(image, before, e), None),
        Claim::Reach(e) => (expr(image, before, e), None),
        Claim::Always(e) => {
            let condition = match e {
                Expr::Implies(condition, _) => Some(expr(image, before, condition)),
                Expr::Bool(_)
                | Expr::Bit { .. }
                | Expr::Compare { .. }
                | Expr::Not(_)
                | Expr::And(..)
                | Expr::Or(..)
                | Expr::Iff(..) => None,
            };
            (!expr(image, before, e), condition)
        }
        Claim::Respond {
            trigger,
            response,
            within,
        } => {
            let triggered = expr(image, before, trigger);
            let responded = expr(image, before, response);
            let bits = 33 - within.leading_zeros();
            let monitor: Word = (0..bits).map(|_| image.aig.latch(false)).collect();
            let aig = &mut *image.aig;
            let is = |aig: &mut Aig, n: i64| words::equal(aig, &monitor, &words::constant(n, bits));
            let none = is(aig, 0);
            let last = is(aig, 1);
            let fresh_fails = if *within == 0 { triggered } else { Lit::FALSE };
            let fails = aig.or(last, fresh_fails);
            let broken = aig.and(!responded, fails);
            let counted = words::sub(aig, &monitor, &words::constant(1, bits));
            let started = words::mux(
                aig,
                triggered,
                &words::constant(i64::from(*within), bits),
                &words::constant(0, bits),
            );
            let waiting = words::mux(aig, none, &started, &counted);
            let next = words::mux(aig, responded, &words::constant(0, bits), &waiting);
            for (&l, &n) in monitor.iter().zip(&next) {
                aig.set_next(l, n);
            }
            (broken, Some(triggered))
        }
    }
}

/// An expression's value, `now` being the image as it stands and
/// `before` the image after the previous scan.
fn expr(image: &mut Image, before: &FxHashMap<Key, Word>, e: &Expr) -> Lit {
    match e {
        Expr::Bool(b) => Lit::constant(*b),
        Expr::Bit { device, prev } => {
            let (word, _) = read_device(image, before, *device, *prev);
            let any: Vec<Lit> = word;
            image.aig.or_all(any)
        }
        Expr::Compare { left, op, right } => {
            let a = term(image, before, left);
            let b = term(image, before, right);
            let aig = &mut *image.aig;
            match op {
                Compare::Eq => words::equal(aig, &a, &b),
                Compare::Ne => !words::equal(aig, &a, &b),
                Compare::Lt => words::less_signed(aig, &a, &b),
                Compare::Gt => words::less_signed(aig, &b, &a),
                Compare::Le => !words::less_signed(aig, &b, &a),
                Compare::Ge => !words::less_signed(aig, &a, &b),
            }
        }
        Expr::Not(a) => !expr(image, before, a),
        Expr::And(a, b) => {
            let (a, b) = (expr(image, before, a), expr(image, before, b));
            image.aig.and(a, b)
        }
        Expr::Or(a, b) => {
            let (a, b) = (expr(image, before, a), expr(image, before, b));
            image.aig.or(a, b)
        }
        Expr::Implies(a, b) => {
            let (a, b) = (expr(image, before, a), expr(image, before, b));
            image.aig.implies(a, b)
        }
        Expr::Iff(a, b) => {
            let (a, b) = (expr(image, before, a), expr(image, before, b));
            image.aig.iff(a, b)
        }
    }
}

/// Comparisons are made at this width: every term fits, signed.
const COMPARE_BITS: u32 = 66;

fn term(image: &mut Image, before: &FxHashMap<Key, Word>, t: &Term) -> Word {
    match t {
        Term::Number(n) => words::constant(*n, COMPARE_BITS),
        Term::Device { device, prev } => {
            let (word, signed) = read_device(image, before, *device, *prev);
            words::resize(&word, COMPARE_BITS, signed)
        }
    }
}

/// The elements of a device, lowest bit first, and whether its value is
/// signed (as `expr::read` reads it).
fn device_keys(device: HostDevice) -> (Vec<(Key, Option<u8>)>, bool) {
    let double = device.width == Width::Double;
    match device.device {
        Device::Bit(area, n) => (vec![((Array::of_bits(area), n), None)], false),
        Device::WordBit(area, n, bit) => (vec![((Array::of_words(area), n), Some(bit))], false),
        Device::Word(area, n) if double => (
            vec![
                ((Array::of_words(area), n), None),
                ((Array::of_words(area), n + 1), None),
            ],
            true,
        ),
        Device::Word(area, n) => (vec![((Array::of_words(area), n), None)], true),
        Device::Digits(area, n, digits) => (
            (n..n + 4 * u32::from(digits))
                .map(|k| ((Array::of_bits(area), k), None))
                .collect(),
            digits == 4 || digits == 8,
        ),
        Device::WideCounter(n) => (vec![((Array::WideCounterValue, n), None)], true),
    }
}

fn read_device(image: &mut Image, before: &FxHashMap<Key, Word>, device: HostDevice, prev: bool) -> (Word, bool) {
    let (keys, signed) = device_keys(device);
    let mut word = Vec::new();
    for (key, bit) in keys {
        let value = if prev {
            // Every element the scan touches is in `before`; one that is
            // not keeps its power-up value throughout.
            match before.get(&key) {
                Some(w) => w.clone(),
                None => image.read(key),
            }
        } else {
            image.read(key)
        };
        match bit {
            Some(b) => word.push(value.get(usize::from(b)).copied().unwrap_or(Lit::FALSE)),
            None => word.extend(value),
        }
    }
    (word, signed)
}

fn write_device(image: &mut Image, device: HostDevice, value: &[Lit]) {
    let (keys, _) = device_keys(device);
    let mut at = 0usize;
    for (key, bit) in keys {
        let bits = encode::width(key.0).unwrap_or(1) as usize;
        match bit {
            Some(b) => {
                let mut word = image.read(key);
                if let (Some(slot), Some(&v)) = (word.get_mut(usize::from(b)), value.get(at)) {
                    *slot = v;
                }
                image.write(key, Lit::TRUE, &word);
                at += 1;
            }
            None => {
                let part: Word = (at..at + bits)
                    .map(|i| value.get(i).copied().unwrap_or(Lit::FALSE))
                    .collect();
                image.write(key, Lit::TRUE, &part);
                at += bits;
            }
        }
    }
}

/// Whether a forced device of `area` takes its value at the input refresh
/// (X, timer and counter contacts) rather than after the program (Y, M).
fn forced_at_refresh(area: BitArea) -> bool {
    match area {
        BitArea::X | BitArea::TimerContact | BitArea::CounterContact => true,
        // S and SM cannot be forced (`force` refuses them before this).
        BitArea::Y | BitArea::M | BitArea::S | BitArea::Sm => false,
    }
}

fn input_image_bit(mem: &ladder_runtime::Memory, n: u32) -> bool {
    FULL.offset(Array::InputImage, n)
        .and_then(|offset| bytemuck::bytes_of(mem).get(offset).copied())
        .is_some_and(|b| b != 0)
}

fn bit_area(array: Array) -> Option<BitArea> {
    BitArea::ALL.into_iter().find(|&area| Array::of_bits(area) == array)
}

fn word_area(array: Array) -> Option<WordArea> {
    WordArea::ALL.into_iter().find(|&area| Array::of_words(area) == array)
}
