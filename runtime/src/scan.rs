//! The scan sequence around the program (docs/language.md, "The scan"):
//!
//! 1. input refresh (input image to X, forced X over it; the high-speed
//!    counters count the edges it saw; the clock and the scan-time
//!    registers advance);
//! 2. states left pending by a SET transfer turn OFF; special relays update;
//! 3. the program runs (compiled code or the interpreter);
//! 4. forced Y and M are written over the results; Y goes to the output image.

use crate::device::HSC_INPUTS;
use crate::image::ImageMut;
use crate::layout::{Array, Scalar};
use crate::machine::MachineUse;
use crate::special::{
    OperationError, CLOCK_CYCLE_MS, CLOCK_RELAYS, FIRST_ALARM_STATE, LAST_ALARM_STATE, LOOP_REPETITION_LIMIT,
    M_ALWAYS_OFF, M_ALWAYS_ON, M_FIRST_SCAN, M_NOT_FIRST_SCAN, SD_ALARM_LOWEST, SM_ALARM_ACTIVE, SM_ALARM_MONITOR,
    SM_ALWAYS_OFF, SM_ALWAYS_ON, SM_FIRST_SCAN, SM_NOT_FIRST_SCAN,
};

impl ImageMut<'_> {
    /// The input refresh alone, as a CPU in STOP refreshes its inputs
    /// without scanning: the input image to X, forced X over it (no edge
    /// counted, no clock advanced).
    pub fn refresh_inputs(&mut self) {
        self.copy_bytes(Array::InputImage, Array::X);
        if self.scalar(Scalar::ForcedCount) > 0 {
            self.apply_forced_inputs();
        }
    }

    /// Steps 1 and 2: everything that happens before the program runs,
    /// with every part of the machine kept up to date.
    pub fn begin_scan(&mut self, elapsed_ms: u32) {
        self.begin_scan_for(elapsed_ms, MachineUse::ALL);
    }

    /// Steps 1 and 2 for a program that uses the parts `machine` of the
    /// machine (`machine.rs`): the others are left as they are.
    pub fn begin_scan_for(&mut self, elapsed_ms: u32, machine: MachineUse) {
        self.set_scalar(Scalar::ElapsedMs, elapsed_ms);
        // The sum cannot overflow in 64 bits; the clock stays below a minute.
        let clock = u64::from(self.scalar(Scalar::ClockMs)) + u64::from(elapsed_ms);
        let clock = if clock < u64::from(CLOCK_CYCLE_MS) {
            clock
        } else {
            clock % u64::from(CLOCK_CYCLE_MS)
        };
        self.set_scalar(Scalar::ClockMs, clock as u32);
        self.set_scalar(Scalar::LoopRepetitions, 0);
        // A compact image of a program without high-speed counters has no
        // edge counts to keep.
        let high_speed = machine.contains(MachineUse::HIGH_SPEED) && self.holds(Array::InputEdges, 0);
        let mut previous = [0u8; HSC_INPUTS as usize];
        if high_speed {
            for (x, level) in (0..).zip(previous.iter_mut()) {
                *level = self.get_u8(Array::X, x);
            }
        }
        self.copy_bytes(Array::InputImage, Array::X);
        if self.scalar(Scalar::ForcedCount) > 0 {
            self.apply_forced_inputs();
        }
        if high_speed {
            self.refresh_high_speed_inputs(previous);
        }
        if machine.contains(MachineUse::SCAN_TIME) {
            self.record_scan_time(elapsed_ms);
        }
        self.advance_calendar(elapsed_ms, machine.contains(MachineUse::CALENDAR));
        if self.scalar(Scalar::StlPendingAny) != 0 {
            self.turn_off_pending_states();
        }
        if machine.contains(MachineUse::SYSTEM_RELAYS) {
            self.update_system_relays();
        }
        if machine.contains(MachineUse::CLOCK_RELAYS) {
            for (relay, period) in CLOCK_RELAYS {
                self.set_u8(Array::M, relay, u8::from(clock as u32 % period >= period / 2));
            }
        }
    }

    /// Step 4: everything that happens after the program ran, with every
    /// part of the machine kept up to date.
    pub fn end_scan(&mut self) {
        self.end_scan_for(MachineUse::ALL);
    }

    /// Step 4 for a program that uses the parts `machine` of the machine.
    pub fn end_scan_for(&mut self, machine: MachineUse) {
        if machine.contains(MachineUse::ALARMS) && self.get_u8(Array::Sm, SM_ALARM_MONITOR.number) != 0 {
            self.update_alarm_monitor();
        }
        if self.scalar(Scalar::ForcedCount) > 0 {
            self.apply_forced_outputs();
        }
        self.copy_bytes(Array::Y, Array::OutputImage);
        let scans = self.scalar(Scalar::ScanCount).saturating_add(1);
        self.set_scalar(Scalar::ScanCount, scans);
    }

    /// A SET transfer inside the block of `source`: the source state turns
    /// OFF at step 2 of the next scan.
    pub fn schedule_state_off(&mut self, source: u32) {
        if self.set_u8(Array::StlPendingOff, source, 1) {
            self.set_scalar(Scalar::StlPendingAny, 1);
        }
    }

    /// A NEXT whose loop has repetitions left asks whether the watchdog lets
    /// it go back to its FOR. Past `LOOP_REPETITION_LIMIT` repetitions in
    /// this scan it records 6509H against `line` and the loop ends.
    pub fn loop_may_repeat(&mut self, line: u32) -> bool {
        let repetitions = self.scalar(Scalar::LoopRepetitions);
        if repetitions >= LOOP_REPETITION_LIMIT {
            self.record_error(OperationError::LoopWatchdog, line);
            return false;
        }
        self.set_scalar(Scalar::LoopRepetitions, repetitions + 1);
        true
    }

    /// With SM249 ON: SM248 shows whether an alarm state S900-S999 is ON
    /// and SD249 the lowest one that is (0 when none is).
    fn update_alarm_monitor(&mut self) {
        let lowest = (FIRST_ALARM_STATE..=LAST_ALARM_STATE).find(|&s| self.get_u8(Array::S, s) != 0);
        self.set_u8(Array::Sm, SM_ALARM_ACTIVE.number, u8::from(lowest.is_some()));
        self.set_i16(Array::Sd, SD_ALARM_LOWEST, lowest.map_or(0, |s| s as i16));
    }

    fn turn_off_pending_states(&mut self) {
        self.zip_bytes(Array::StlPendingOff, Array::S, |pending, state| {
            if *pending != 0 {
                *state = 0;
                *pending = 0;
            }
        });
        self.set_scalar(Scalar::StlPendingAny, 0);
    }

    fn update_system_relays(&mut self) {
        let first = self.scalar(Scalar::ScanCount) == 0;
        self.set_u8(Array::Sm, SM_ALWAYS_ON, 1);
        self.set_u8(Array::Sm, SM_ALWAYS_OFF, 0);
        self.set_u8(Array::Sm, SM_FIRST_SCAN, first as u8);
        self.set_u8(Array::Sm, SM_NOT_FIRST_SCAN, (!first) as u8);
        for (relays, on) in [
            (&M_ALWAYS_ON[..], true),
            (&M_ALWAYS_OFF[..], false),
            (&M_FIRST_SCAN[..], first),
            (&M_NOT_FIRST_SCAN[..], !first),
        ] {
            for &n in relays {
                self.set_u8(Array::M, n, on as u8);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::memory::Memory;

    #[test]
    fn first_scan_relays() {
        let mut mem = Memory::new_boxed();
        mem.begin_scan(10);
        assert_eq!((mem.m[8002], mem.m[8003], mem.sm[2], mem.sm[3]), (1, 0, 1, 0));
        assert_eq!((mem.m[8000], mem.m[8001], mem.m[8150], mem.m[8151]), (1, 0, 1, 1));
        mem.end_scan();
        mem.begin_scan(10);
        assert_eq!((mem.m[8002], mem.m[8003], mem.m[8150], mem.sm[2]), (0, 1, 0, 0));
    }

    #[test]
    fn clock_relays_follow_the_accumulated_time() {
        let mut mem = Memory::new_boxed();
        let mut seen = Vec::new();
        for _ in 0..4 {
            mem.scan_with(250, |_| {});
            seen.push(mem.m[8013]);
        }
        assert_eq!(seen, [0, 1, 1, 0], "t = 250, 500, 750, 1000");
        mem.scan_with(u32::MAX, |_| {});
        assert_eq!(mem.clock_ms, ((1000 + u64::from(u32::MAX)) % 60_000) as u32);
        mem.scan_with(5, |_| {});
        assert!(mem.clock_ms < 60_000);
    }

    #[test]
    fn loop_watchdog_counts_repetitions_per_scan() {
        let mut mem = Memory::new_boxed();
        mem.begin_scan(10);
        assert!((0..crate::special::LOOP_REPETITION_LIMIT).all(|_| mem.loop_may_repeat(7)));
        assert_eq!(mem.operation_error(), None);
        assert!(!mem.loop_may_repeat(9));
        assert_eq!(mem.operation_error(), Some(0x6509));
        assert_eq!(mem.d[8069], 9);
        mem.end_scan();
        mem.begin_scan(10);
        assert!(mem.loop_may_repeat(7), "the count starts again every scan");
    }

    #[test]
    fn inputs_and_outputs_pass_through_images() {
        let mut mem = Memory::new_boxed();
        mem.input_image[3] = 1;
        mem.scan_with(10, |m| m.y[5] = m.x[3]);
        assert_eq!(mem.output_image[5], 1);
    }

    #[test]
    fn alarm_monitor_follows_the_alarm_states_while_enabled() {
        let mut mem = Memory::new_boxed();
        mem.s[905] = 1;
        mem.scan_with(10, |_| {});
        assert_eq!((mem.sm[248], mem.sd[249]), (0, 0), "SM249 OFF: not monitored");
        mem.sm[249] = 1;
        mem.s[901] = 1;
        mem.scan_with(10, |_| {});
        assert_eq!((mem.sm[248], mem.sd[249]), (1, 901));
        mem.s[901] = 0;
        mem.s[905] = 0;
        mem.scan_with(10, |_| {});
        assert_eq!((mem.sm[248], mem.sd[249]), (0, 0));
    }

    #[test]
    fn pending_state_turns_off_at_next_scan_start() {
        let mut mem = Memory::new_boxed();
        mem.s[4] = 1;
        mem.schedule_state_off(4);
        assert_eq!(mem.s[4], 1, "stays ON until the next scan");
        mem.begin_scan(10);
        assert_eq!(mem.s[4], 0);
        assert_eq!(mem.stl_pending_any, 0);
    }
}
