//! The scan sequence around the program (DIALECT.md, "The scan"):
//!
//! 1. input refresh (input image to X, forced X over it; the high-speed
//!    counters count the edges it saw; the clock and the scan-time
//!    registers advance);
//! 2. states left pending by a SET transfer turn OFF; special relays update;
//! 3. the program runs (compiled code or the interpreter);
//! 4. forced Y and M are written over the results; Y goes to the output image.

use crate::device::HSC_INPUTS;
use crate::memory::Memory;
use crate::special::{
    OperationError, CLOCK_CYCLE_MS, CLOCK_RELAYS, FIRST_ALARM_STATE, LAST_ALARM_STATE, LOOP_REPETITION_LIMIT,
    M_ALWAYS_OFF, M_ALWAYS_ON, M_FIRST_SCAN, M_NOT_FIRST_SCAN, SD_ALARM_LOWEST, SM_ALARM_ACTIVE, SM_ALARM_MONITOR,
    SM_ALWAYS_OFF, SM_ALWAYS_ON, SM_FIRST_SCAN, SM_NOT_FIRST_SCAN,
};

impl Memory {
    /// Steps 1 and 2: everything that happens before the program runs.
    pub fn begin_scan(&mut self, elapsed_ms: u32) {
        self.elapsed_ms = elapsed_ms;
        // In 64 bits the sum cannot overflow; the modulus keeps t below a minute.
        self.clock_ms = ((u64::from(self.clock_ms) + u64::from(elapsed_ms)) % u64::from(CLOCK_CYCLE_MS)) as u32;
        self.loop_repetitions = 0;
        let mut previous = [0u8; HSC_INPUTS as usize];
        previous.copy_from_slice(&self.x[..HSC_INPUTS as usize]);
        self.x = self.input_image;
        if self.forced_count > 0 {
            self.apply_forced_inputs();
        }
        self.refresh_high_speed_inputs(previous);
        self.advance_calendar(elapsed_ms);
        if self.stl_pending_any != 0 {
            self.turn_off_pending_states();
        }
        self.update_system_relays();
    }

    /// Step 4: everything that happens after the program ran.
    pub fn end_scan(&mut self) {
        if self.sm[SM_ALARM_MONITOR.number as usize] != 0 {
            self.update_alarm_monitor();
        }
        if self.forced_count > 0 {
            self.apply_forced_outputs();
        }
        self.output_image = self.y;
        self.scan_count = self.scan_count.saturating_add(1);
    }

    /// A whole scan around `program`, for engines that run in-process.
    pub fn scan_with(&mut self, elapsed_ms: u32, program: impl FnOnce(&mut Memory)) {
        self.begin_scan(elapsed_ms);
        program(self);
        self.end_scan();
    }

    /// A SET transfer inside the block of `source`: the source state turns
    /// OFF at step 2 of the next scan.
    pub fn schedule_state_off(&mut self, source: u32) {
        if let Some(flag) = self.stl_pending_off.get_mut(source as usize) {
            *flag = 1;
            self.stl_pending_any = 1;
        }
    }

    /// A NEXT whose loop has repetitions left asks whether the watchdog lets
    /// it go back to its FOR. Past `LOOP_REPETITION_LIMIT` repetitions in
    /// this scan it records 6509H against `line` and the loop ends.
    pub fn loop_may_repeat(&mut self, line: u32) -> bool {
        if self.loop_repetitions >= LOOP_REPETITION_LIMIT {
            self.record_error(OperationError::LoopWatchdog, line);
            return false;
        }
        self.loop_repetitions += 1;
        true
    }

    /// With SM249 ON: SM248 shows whether an alarm state S900-S999 is ON
    /// and SD249 the lowest one that is (0 when none is).
    fn update_alarm_monitor(&mut self) {
        let lowest = (FIRST_ALARM_STATE..=LAST_ALARM_STATE).find(|&s| self.s[s as usize] != 0);
        self.sm[SM_ALARM_ACTIVE.number as usize] = u8::from(lowest.is_some());
        self.sd[SD_ALARM_LOWEST as usize] = lowest.map_or(0, |s| s as i16);
    }

    fn turn_off_pending_states(&mut self) {
        for (state, pending) in self.s.iter_mut().zip(self.stl_pending_off.iter_mut()) {
            if *pending != 0 {
                *state = 0;
                *pending = 0;
            }
        }
        self.stl_pending_any = 0;
    }

    fn update_system_relays(&mut self) {
        let first = self.scan_count == 0;
        self.sm[SM_ALWAYS_ON as usize] = 1;
        self.sm[SM_ALWAYS_OFF as usize] = 0;
        self.sm[SM_FIRST_SCAN as usize] = first as u8;
        self.sm[SM_NOT_FIRST_SCAN as usize] = (!first) as u8;
        for (relays, on) in [
            (&M_ALWAYS_ON[..], true),
            (&M_ALWAYS_OFF[..], false),
            (&M_FIRST_SCAN[..], first),
            (&M_NOT_FIRST_SCAN[..], !first),
        ] {
            for &n in relays {
                self.m[n as usize] = on as u8;
            }
        }
        for (relay, period) in CLOCK_RELAYS {
            self.m[relay as usize] = u8::from(self.clock_ms % period >= period / 2);
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
