//! High-speed counters C235-C255 (docs/language.md, "Machine programs").
//!
//! There are no interrupts: each counter counts, at the input refresh, the
//! rising edges of its FX3U inputs that the refresh saw (a level change of X
//! plus the edges a host reported with `ladder_add_pulses`), while its coil
//! was ON at its last execution. The high-speed compares DHSCS, DHSCR and
//! DHSZ registered by their last execution compare then, as the counter
//! moves, and their outputs change then. The counter's own contact follows
//! its `OUT Cn` as for every counter.
//!
//! Inputs (FX3U): one-phase counters count one input up or down (M8235-
//! M8245 ON: down); one-phase two-input counters count one input up and
//! another down; two-phase counters count the rising edges of phase A, up
//! while phase B is OFF and down while it is ON (A leading B counts up).
//! M8246-M8255 show the direction of the two-input and two-phase counters
//! (ON: down). A reset input holds the counter at 0 while ON; a start input
//! lets it count only while ON.

use crate::device::HSC_INPUTS;
use crate::image::ImageMut;
use crate::layout::Array;
#[cfg(test)]
use crate::memory::Memory;
use crate::memory::FORCE_NONE;
use crate::place::Place;

/// The first high-speed counter.
pub const FIRST_HSC: u32 = 235;
/// The last high-speed counter.
pub const LAST_HSC: u32 = 255;
/// M8000 + n: the direction relay of counter Cn (set by the program for
/// C235-C245, shown by the runtime for C246-C255).
pub const M_HSC_DIRECTION_BASE: u32 = 8000;

/// How a high-speed counter counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HscInputs {
    /// Rising edges of one input, up or down by the counter's M relay.
    OnePhase { input: u8 },
    /// Rising edges of `up` count up, of `down` count down.
    TwoInputs { up: u8, down: u8 },
    /// Rising edges of phase `a`, up while `b` is OFF, down while ON.
    TwoPhase { a: u8, b: u8 },
}

/// A high-speed counter's wiring: its count inputs, and its reset and
/// start inputs if it has them (X numbers 0-7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HscWiring {
    pub inputs: HscInputs,
    pub reset: Option<u8>,
    pub start: Option<u8>,
}

/// The wiring of counter `counter` (C235-C255), as the FX3U manual's table
/// assigns inputs; `None` for other counters.
pub const fn wiring(counter: u32) -> Option<HscWiring> {
    use HscInputs::{OnePhase, TwoInputs, TwoPhase};
    let (inputs, reset, start) = match counter {
        235..=240 => (
            OnePhase {
                input: (counter - 235) as u8,
            },
            None,
            None,
        ),
        241 => (OnePhase { input: 0 }, Some(1), None),
        242 => (OnePhase { input: 2 }, Some(3), None),
        243 => (OnePhase { input: 4 }, Some(5), None),
        244 => (OnePhase { input: 0 }, Some(1), Some(6)),
        245 => (OnePhase { input: 2 }, Some(3), Some(7)),
        246 => (TwoInputs { up: 0, down: 1 }, None, None),
        247 => (TwoInputs { up: 0, down: 1 }, Some(2), None),
        248 => (TwoInputs { up: 3, down: 4 }, Some(5), None),
        249 => (TwoInputs { up: 0, down: 1 }, Some(2), Some(6)),
        250 => (TwoInputs { up: 3, down: 4 }, Some(5), Some(7)),
        251 => (TwoPhase { a: 0, b: 1 }, None, None),
        252 => (TwoPhase { a: 0, b: 1 }, Some(2), None),
        253 => (TwoPhase { a: 3, b: 4 }, Some(5), None),
        254 => (TwoPhase { a: 0, b: 1 }, Some(2), Some(6)),
        255 => (TwoPhase { a: 3, b: 4 }, Some(5), Some(7)),
        _ => return None,
    };
    Some(HscWiring { inputs, reset, start })
}

/// The compare an instance of DHSCS, DHSCR or DHSZ registered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HscCompare {
    /// DHSCS: the bit turns ON when the counter reaches the value.
    Set,
    /// DHSCR: the bit turns OFF when the counter reaches the value.
    Reset,
    /// DHSZ: three bits from the place show below / within / above the zone.
    Zone,
}

/// `InstanceState::phase` of a registered compare: the kind in the low
/// byte, the counter number above it (0: nothing registered).
const fn compare_phase(kind: HscCompare, counter: u32) -> u32 {
    kind.code() | (counter << 8)
}

fn compare_of(phase: u32) -> Option<(HscCompare, u32)> {
    Some((HscCompare::from_code(phase & 0xFF)?, phase >> 8))
}

impl HscCompare {
    /// The one code of each compare: what compiled code passes to
    /// `ladder_rt_high_speed_compare`, and the low byte of a registered
    /// compare's phase (where 0 means none is registered).
    pub const fn code(self) -> u32 {
        match self {
            HscCompare::Set => 1,
            HscCompare::Reset => 2,
            HscCompare::Zone => 3,
        }
    }

    pub const fn from_code(code: u32) -> Option<HscCompare> {
        match code {
            1 => Some(HscCompare::Set),
            2 => Some(HscCompare::Reset),
            3 => Some(HscCompare::Zone),
            _ => None,
        }
    }
}

impl ImageMut<'_> {
    /// Adds `count` rising edges of input X`input` (0-7) before the next
    /// input refresh; false for another input. A compact image of a
    /// program without high-speed counters takes them and drops them:
    /// nothing would count them.
    pub fn add_pulses(&mut self, input: u32, count: u32) -> bool {
        if input >= HSC_INPUTS {
            return false;
        }
        let pending = self.get_u32(Array::PulsesPending, input);
        self.set_u32(Array::PulsesPending, input, pending.saturating_add(count));
        true
    }

    /// At the input refresh (after forces): the rising edges of X0-X7 since
    /// the previous refresh, then every high-speed counter counts them.
    pub(crate) fn refresh_high_speed_inputs(&mut self, previous: [u8; HSC_INPUTS as usize]) {
        if !self.holds(Array::InputEdges, 0) {
            return; // a compact image of a program without high-speed counters
        }
        let mut any = false;
        for (input, &before) in (0..).zip(previous.iter()) {
            let level_rose = u32::from(self.get_u8(Array::X, input) != 0 && before == 0);
            let pending = self.get_u32(Array::PulsesPending, input);
            self.set_u32(Array::PulsesPending, input, 0);
            let edges = level_rose.saturating_add(pending);
            self.set_u32(Array::InputEdges, input, edges);
            any |= edges != 0;
        }
        // Reset inputs act on levels, so they are looked at every scan.
        for counter in FIRST_HSC..=LAST_HSC {
            if self.get_u8(Array::CounterCoilWasOn, counter) != 0 {
                self.count_high_speed(counter, any);
            }
        }
    }

    fn count_high_speed(&mut self, counter: u32, any_edges: bool) {
        let Some(wiring) = wiring(counter) else {
            return;
        };
        if self.get_u8(Array::ForceCounter, counter) != FORCE_NONE {
            return; // a forced counter does not count
        }
        let before = self.get_i32(Array::WideCounterValue, counter);
        let level = |image: &Self, x: u8| image.get_u8(Array::X, u32::from(x)) != 0;
        if wiring.reset.is_some_and(|x| level(self, x)) {
            // A reset is no count: like a value the program writes, it is
            // not compared (DHSCS/DHSCR/DHSZ act on counting only).
            self.set_i32(Array::WideCounterValue, counter, 0);
            return;
        }
        if !any_edges || wiring.start.is_some_and(|x| !level(self, x)) {
            return;
        }
        let edges = |image: &Self, input: u8| i64::from(image.get_u32(Array::InputEdges, u32::from(input)));
        let direction_relay = M_HSC_DIRECTION_BASE + counter;
        let steps = match wiring.inputs {
            HscInputs::OnePhase { input } => {
                let down = self.get_u8(Array::M, direction_relay) != 0;
                if down {
                    -edges(self, input)
                } else {
                    edges(self, input)
                }
            }
            HscInputs::TwoInputs { up, down } => {
                let (ups, downs) = (edges(self, up), edges(self, down));
                if ups != downs {
                    self.set_u8(Array::M, direction_relay, u8::from(downs > ups));
                }
                ups - downs
            }
            HscInputs::TwoPhase { a, b } => {
                let down = level(self, b);
                if edges(self, a) != 0 {
                    self.set_u8(Array::M, direction_relay, u8::from(down));
                }
                if down {
                    -edges(self, a)
                } else {
                    edges(self, a)
                }
            }
        };
        if steps != 0 {
            // 32-bit counters wrap around.
            let after = (i64::from(before) + steps) as i32;
            self.set_high_speed_value(counter, before, after);
        }
    }

    /// The counter moves from `before` to `after`; the compares registered
    /// on it see every value it passes.
    fn set_high_speed_value(&mut self, counter: u32, before: i32, after: i32) {
        self.set_i32(Array::WideCounterValue, counter, after);
        if before == after {
            return;
        }
        // The instances the image holds (one segment: a copy of its run).
        let run = self.layout().runs[Array::Instance.segments().start];
        {
            for index in run.first..run.first.saturating_add(run.count) {
                let Some(state) = self.instance(index) else {
                    continue;
                };
                let Some((kind, registered)) = compare_of(state.phase) else {
                    continue;
                };
                if registered != counter {
                    continue;
                }
                let Some(destination) = Place::unpack(state.c as u32) else {
                    continue;
                };
                match kind {
                    HscCompare::Set | HscCompare::Reset => {
                        // Reached: the value lies on the way from before
                        // (excluded) to after (included).
                        let (low, high) = if after > before {
                            (i64::from(before) + 1, i64::from(after))
                        } else {
                            (i64::from(after), i64::from(before) - 1)
                        };
                        if (low..=high).contains(&i64::from(state.a)) {
                            destination.write(self, crate::Width::Single, i64::from(kind == HscCompare::Set));
                        }
                    }
                    HscCompare::Zone => self.write_zone(destination, state.a, state.b, after),
                }
            }
        }
    }

    fn write_zone(&mut self, destination: Place, low: i32, high: i32, value: i32) {
        let high = high.max(low); // a reversed zone is the single value `low`, as in ZCP
        let results = [value < low, low <= value && value <= high, value > high];
        for (unit, on) in (0..).zip(results) {
            destination
                .nth(unit, crate::Width::Single)
                .write(self, crate::Width::Single, i64::from(on));
        }
    }

    /// One execution of DHSCS/DHSCR/DHSZ instance `instance`: with `power`
    /// it (re)registers its compare of `counter` with the values and the
    /// checked destination `destination` (a packed place); without, it is
    /// withdrawn. DHSZ also shows the zone of the current value at once.
    pub fn high_speed_compare(
        &mut self,
        instance: u32,
        kind: HscCompare,
        power: bool,
        counter: u32,
        values: [i32; 2],
        destination: u32,
    ) {
        let Some(mut state) = self.instance(instance) else {
            return;
        };
        if !power || wiring(counter).is_none() {
            state.phase = 0;
            self.set_instance(instance, state);
            return;
        }
        let first = state.phase == 0;
        state.phase = compare_phase(kind, counter);
        state.a = values[0];
        state.b = values[1];
        state.c = destination as i32;
        self.set_instance(instance, state);
        if kind == HscCompare::Zone && first {
            if let (Some(place), Some(value)) = (Place::unpack(destination), self.wide_counter(counter)) {
                self.write_zone(place, values[0], values[1], value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::BitArea;

    fn counting(mem: &mut Memory, counter: u32) {
        mem.counter_coil(counter, true, 1_000_000);
    }

    #[test]
    fn one_phase_counts_its_input_edges() {
        let mut mem = Memory::new_boxed();
        counting(&mut mem, 235);
        mem.input_image[0] = 1;
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(235), Some(1), "X0 rose");
        mem.add_pulses(0, 5);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(235), Some(6), "reported edges, X0 held");
        mem.m[8235] = 1;
        mem.add_pulses(0, 2);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(235), Some(4), "M8235 ON counts down");
        assert_eq!(mem.input_edges[0], 2);
    }

    #[test]
    fn a_counter_whose_coil_is_off_does_not_count() {
        let mut mem = Memory::new_boxed();
        mem.add_pulses(0, 5);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(235), Some(0));
        assert_eq!(mem.input_edges[0], 5);
    }

    #[test]
    fn reset_and_start_inputs() {
        let mut mem = Memory::new_boxed();
        counting(&mut mem, 244);
        mem.add_pulses(0, 3);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(244), Some(0), "X6 (start) OFF");
        mem.input_image[6] = 1;
        mem.add_pulses(0, 3);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(244), Some(3));
        mem.input_image[1] = 1;
        mem.add_pulses(0, 3);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(244), Some(0), "X1 (reset) ON");
    }

    #[test]
    fn two_input_and_two_phase_counters() {
        let mut mem = Memory::new_boxed();
        counting(&mut mem, 246);
        counting(&mut mem, 253);
        mem.add_pulses(0, 4);
        mem.add_pulses(1, 1);
        mem.add_pulses(3, 7);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(246), Some(3));
        assert_eq!(mem.m[8246], 0);
        assert_eq!(mem.wide_counter(253), Some(7), "B (X4) OFF: up");
        mem.input_image[4] = 1;
        mem.add_pulses(3, 2);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.wide_counter(253), Some(5), "B ON: down");
        assert_eq!(mem.m[8253], 1);
    }

    #[test]
    fn compares_see_every_value_passed() {
        let mut mem = Memory::new_boxed();
        counting(&mut mem, 235);
        let y10 = Place::Bit(BitArea::Y, 8).pack().unwrap();
        let m0 = Place::Bit(BitArea::M, 0).pack().unwrap();
        mem.high_speed_compare(0, HscCompare::Set, true, 235, [5, 0], y10);
        mem.high_speed_compare(1, HscCompare::Zone, true, 235, [3, 6], m0);
        assert_eq!((mem.m[0], mem.m[1], mem.m[2]), (1, 0, 0), "the zone shows at once");
        mem.add_pulses(0, 9);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.y[8], 1, "passed 5 on the way to 9");
        assert_eq!((mem.m[0], mem.m[1], mem.m[2]), (0, 0, 1));
        mem.high_speed_compare(0, HscCompare::Reset, true, 235, [7, 0], y10);
        mem.m[8235] = 1;
        mem.add_pulses(0, 1);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.y[8], 1, "8 is not 7");
        mem.add_pulses(0, 1);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.y[8], 0, "reached 7 counting down");
        mem.high_speed_compare(0, HscCompare::Set, false, 235, [6, 0], y10);
        mem.add_pulses(0, 1);
        mem.scan_with(10, |_| {});
        assert_eq!(mem.y[8], 0, "withdrawn");
    }
}
