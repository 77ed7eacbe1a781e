//! Pulse and positioning outputs (docs/language.md, "Machine programs"): PLSY,
//! PLSR, PLSV, DRVI, DRVA, ZRN, DSZR and PWM generate no pulses; the model
//! advances each output's registers as the pulses would:
//!
//! | output | current address | busy | pulses output (PLSY/PLSR) |
//! |---|---|---|---|
//! | Y0 | D8341,D8340 | M8340 | D8141,D8140 |
//! | Y1 | D8351,D8350 | M8350 | D8143,D8142 |
//! | Y2 | D8361,D8360 | M8360 | |
//! | Y3 | D8371,D8370 | M8370 | |
//!
//! (D8137,D8136 count the pulses of Y0 and Y1 together.) An instruction
//! starts in the scan its drive turns ON, if no other instruction drives
//! the output (else it waits until its drive has been OFF); from the next
//! scan on it moves by frequency × the elapsed time reported to that scan
//! (fractions of a pulse carried over), PLSR along its acceleration and
//! deceleration ramp. It completes when it reaches its target (PLSY/PLSR:
//! the pulse count, 0 = without end; DRVI: the start address + the
//! distance; DRVA: the address), or for ZRN/DSZR when its near-point input
//! has been seen ON and then OFF (the address is then 0). Every execution
//! writes M8029: ON while the instruction has completed and its drive is
//! still ON. A drive that turns OFF stops the output at once. The pulse
//! output's Y device itself is not written; the direction output is (ON:
//! toward larger addresses).
//!
//! The program's instruction kernels decide the operands; this one model
//! (the machine) is shared by every engine, as timers are.
//!
//! What an instruction reads when its drive turns ON and what at every
//! execution follows the manual (docs/language.md, "Machine programs"): PLSY
//! takes its pulse count S2 when it starts (0: without end, for the whole
//! drive) and its frequency S1 at every execution; PLSR takes S1, S2 and S3
//! when it starts; DRVI/DRVA keep the target they started with; PLSV, ZRN
//! and DSZR read their operands at every execution. A value changed while
//! the output runs takes effect at the next drive.

use crate::device::{Width, PULSE_OUTPUTS};
use crate::image::{Image, ImageMut};
use crate::layout::{Array, Scalar};
use crate::memory::InstanceState;
#[cfg(test)]
use crate::memory::Memory;
use crate::place::Place;

pub use crate::special::M_EXECUTION_COMPLETE;
/// D8340: the current address of Y0 (a pair); Y1-Y3 follow every 10.
pub const D_CURRENT_ADDRESS: u32 = 8340;
/// M8340: Y0 is outputting pulses; Y1-Y3 follow every 10.
pub const M_BUSY: u32 = 8340;
/// M8342: zero return of Y0 toward larger addresses (default: smaller).
pub const M_ZERO_RETURN_FORWARD: u32 = 8342;
/// D8140: the pulses PLSY/PLSR output on Y0 (a pair); D8142 for Y1.
pub const D_PULSE_COUNT: u32 = 8140;
/// D8136: the pulses of Y0 and Y1 together (a pair).
pub const D_PULSE_TOTAL: u32 = 8136;
/// D8345: DSZR's creep speed for Y0; D8346 (pair) its zero-return speed;
/// Y1-Y3 have their own every 10 (D8355/D8356, ...).
pub const D_CREEP_SPEED: u32 = 8345;
pub const D_ZERO_RETURN_SPEED: u32 = 8346;
/// FX3U's defaults when the registers hold 0.
pub const DEFAULT_CREEP_SPEED: i32 = 1_000;
pub const DEFAULT_ZERO_RETURN_SPEED: i32 = 50_000;

/// Which instruction drives an output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum PulseKind {
    /// PLSY: `amount` pulses at `frequency` (amount 0: without end).
    Plsy = 0,
    /// PLSR: `amount` pulses up to `frequency`, ramps of `ramp_ms`.
    Plsr = 1,
    /// PLSV: at the signed `frequency` while driven.
    Plsv = 2,
    /// DRVI: `amount` pulses from the start address (signed).
    Drvi = 3,
    /// DRVA: to the address `amount`.
    Drva = 4,
    /// ZRN: at `frequency` until the near point, then at `creep` until it is released.
    Zrn = 5,
    /// DSZR: as ZRN, at the speeds of D8346 and D8345.
    Dszr = 6,
}

impl PulseKind {
    pub const ALL: [PulseKind; 7] = [
        PulseKind::Plsy,
        PulseKind::Plsr,
        PulseKind::Plsv,
        PulseKind::Drvi,
        PulseKind::Drva,
        PulseKind::Zrn,
        PulseKind::Dszr,
    ];

    pub fn from_code(code: u32) -> Option<PulseKind> {
        PulseKind::ALL.into_iter().find(|&k| k as u32 == code)
    }
}

/// One execution of a pulse instruction with its operands' values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PulseRequest {
    pub kind: PulseKind,
    /// 0-3 for Y0-Y3.
    pub output: u32,
    pub frequency: i32,
    pub amount: i32,
    pub ramp_ms: i32,
    pub creep: i32,
    /// The near-point input's value now (ZRN, DSZR).
    pub near_point: bool,
    /// The direction output, a packed place (`NO_PLACE`: none).
    pub direction: u32,
}

impl PulseRequest {
    /// Operands with which the instruction can move: a frequency above 0
    /// (PLSV: any, its sign is the direction) and PLSR's pulse count and
    /// ramp time not below 1 and 0.
    pub fn can_start(&self) -> bool {
        match self.kind {
            PulseKind::Plsv | PulseKind::Dszr => true,
            PulseKind::Plsy | PulseKind::Drvi | PulseKind::Drva => self.frequency > 0,
            PulseKind::Zrn => self.frequency > 0 && self.creep > 0,
            PulseKind::Plsr => self.frequency > 0 && self.amount > 0 && self.ramp_ms >= 0,
        }
    }
}

/// A packed place value that names no place.
pub const NO_PLACE: u32 = 0;

/// `InstanceState::phase` values.
const IDLE: u32 = 0;
const RUNNING: u32 = 1;
const COMPLETE: u32 = 2;
/// Its output was busy when the drive turned ON: waits for the drive to turn OFF.
const REFUSED: u32 = 3;

/// ZRN/DSZR `InstanceState::c` while running: before and after the near point.
const APPROACHING: i32 = 0;
const CREEPING: i32 = 1;

impl<B: AsRef<[u8]>> Image<'_, B> {
    fn pair(&self, first: u32) -> i32 {
        crate::memory::join_words(self.get_i16(Array::D, first), self.get_i16(Array::D, first + 1))
    }

    /// The current address of pulse output Y`output` (0-3).
    pub fn current_address(&self, output: u32) -> i32 {
        self.pair(D_CURRENT_ADDRESS + 10 * output)
    }
}

impl ImageMut<'_> {
    fn set_pair(&mut self, first: u32, value: i32) {
        let (low, high) = crate::memory::split_words(value);
        self.set_i16(Array::D, first, low);
        self.set_i16(Array::D, first + 1, high);
    }

    /// One execution of pulse instruction `instance` with its rung's power.
    /// Returns false (and does nothing) when the output is not Y0-Y3.
    pub fn pulse_output(&mut self, instance: u32, power: bool, request: &PulseRequest) -> bool {
        let Some(mut state) = self.instance(instance).filter(|_| request.output <= 3) else {
            return false;
        };
        if power && state.phase == IDLE && !request.can_start() {
            return false; // it would never move nor complete
        }
        let owner = instance + 1;
        let output = request.output;
        if !power {
            if state.phase == RUNNING {
                self.release(output);
            }
            state = InstanceState::default();
        } else {
            if state.phase == IDLE {
                let current_owner = self.get_u32(Array::PulseOwner, output);
                if current_owner != 0 && current_owner != owner {
                    state.phase = REFUSED;
                } else {
                    state = self.start(owner, output, request);
                }
                self.set_instance(instance, state);
                if state.phase == RUNNING {
                    // The start scan: no time has passed for the pulses yet.
                    state = self.advance(output, state, request, 0);
                }
            } else if state.phase == RUNNING {
                let elapsed = self.scalar(Scalar::ElapsedMs);
                state = self.advance(output, state, request, elapsed);
            }
            if state.phase == RUNNING || (request.kind == PulseKind::Plsv && state.phase != REFUSED) {
                self.write_direction(request, state);
            }
        }
        self.set_instance(instance, state);
        self.set_u8(
            Array::M,
            M_EXECUTION_COMPLETE,
            u8::from(power && state.phase == COMPLETE),
        );
        true
    }

    fn start(&mut self, owner: u32, output: u32, request: &PulseRequest) -> InstanceState {
        self.set_u32(Array::PulseOwner, output, owner);
        self.set_u32(Array::PulseRemainder, output, 0);
        self.set_u8(Array::M, M_BUSY + 10 * output, 1);
        let here = self.current_address(output);
        let target = match request.kind {
            PulseKind::Drvi => here.wrapping_add(request.amount),
            PulseKind::Drva => request.amount,
            PulseKind::Plsy | PulseKind::Plsr | PulseKind::Plsv | PulseKind::Zrn | PulseKind::Dszr => 0,
        };
        InstanceState {
            phase: RUNNING,
            // a: pulses output so far; b: ms since the start; c: target
            // address (DRVI/DRVA), zero-return phase (ZRN/DSZR) or the pulse
            // count taken at the start (PLSY/PLSR); d, e: PLSR's frequency
            // and ramp time taken at the start.
            a: 0,
            b: 0,
            c: match request.kind {
                PulseKind::Zrn | PulseKind::Dszr if request.near_point => CREEPING,
                PulseKind::Zrn | PulseKind::Dszr => APPROACHING,
                PulseKind::Plsy | PulseKind::Plsr => request.amount,
                PulseKind::Plsv | PulseKind::Drvi | PulseKind::Drva => target,
            },
            d: request.frequency,
            e: request.ramp_ms,
        }
    }

    fn release(&mut self, output: u32) {
        self.set_u32(Array::PulseOwner, output, 0);
        self.set_u32(Array::PulseRemainder, output, 0);
        self.set_u8(Array::M, M_BUSY + 10 * output, 0);
    }

    /// Pulses at a constant `frequency` for `elapsed` ms, with the output's
    /// carried fraction.
    fn steady_pulses(&mut self, output: u32, frequency: i32, elapsed: u32) -> i64 {
        let total = u64::from(self.get_u32(Array::PulseRemainder, output))
            + u64::from(frequency.unsigned_abs()) * u64::from(elapsed);
        self.set_u32(Array::PulseRemainder, output, (total % 1000) as u32);
        (total / 1000) as i64
    }

    fn advance(
        &mut self,
        output: u32,
        mut state: InstanceState,
        request: &PulseRequest,
        elapsed: u32,
    ) -> InstanceState {
        let here = i64::from(self.current_address(output));
        let since = state.b as u32;
        state.b = since.saturating_add(elapsed).min(i32::MAX as u32) as i32;
        // (pulses this time, direction: +1 / -1, completed)
        let (pulses, direction, done) = match request.kind {
            // The pulse count (and PLSR's frequency and ramp) as they were
            // when the drive turned ON; PLSY's frequency as it is now.
            PulseKind::Plsy => {
                let pulses = self.steady_pulses(output, request.frequency, elapsed);
                counted(pulses, i64::from(state.a), state.c)
            }
            PulseKind::Plsr => {
                let total = i64::from(state.c.max(0));
                let now = ramp_position(state.d, state.e, total, state.b as u32);
                let pulses = (now - i64::from(state.a)).max(0);
                counted(pulses, i64::from(state.a), state.c)
            }
            PulseKind::Plsv => {
                let pulses = self.steady_pulses(output, request.frequency, elapsed);
                (pulses, if request.frequency < 0 { -1 } else { 1 }, false)
            }
            PulseKind::Drvi | PulseKind::Drva => {
                let target = i64::from(state.c);
                let pulses = self.steady_pulses(output, request.frequency, elapsed);
                let left = (target - here).abs();
                (pulses.min(left), if target < here { -1 } else { 1 }, pulses >= left)
            }
            PulseKind::Zrn | PulseKind::Dszr => {
                let forward = self.get_u8(Array::M, M_ZERO_RETURN_FORWARD + 10 * output) != 0;
                let (speed, creep) = match request.kind {
                    PulseKind::Dszr => self.zero_return_speeds(output),
                    PulseKind::Zrn
                    | PulseKind::Plsy
                    | PulseKind::Plsr
                    | PulseKind::Plsv
                    | PulseKind::Drvi
                    | PulseKind::Drva => (request.frequency, request.creep),
                };
                let speed = if state.c == CREEPING { creep } else { speed };
                let pulses = self.steady_pulses(output, speed, elapsed);
                let mut done = false;
                if state.c == APPROACHING && request.near_point {
                    state.c = CREEPING;
                } else if state.c == CREEPING && !request.near_point {
                    done = true;
                }
                (pulses, if forward { 1 } else { -1 }, done)
            }
        };
        state.a = (i64::from(state.a) + pulses).min(i64::from(i32::MAX)) as i32;
        let moved = (here + direction * pulses) as i32;
        let address = D_CURRENT_ADDRESS + 10 * output;
        self.set_pair(address, moved);
        if matches!(request.kind, PulseKind::Plsy | PulseKind::Plsr) && output < 2 {
            let count = D_PULSE_COUNT + 2 * output;
            self.set_pair(count, self.pair(count).wrapping_add(pulses as i32));
            self.set_pair(D_PULSE_TOTAL, self.pair(D_PULSE_TOTAL).wrapping_add(pulses as i32));
        }
        if done {
            if matches!(request.kind, PulseKind::Zrn | PulseKind::Dszr) {
                self.set_pair(address, 0);
            }
            self.release(output);
            state.phase = COMPLETE;
        }
        state
    }

    fn zero_return_speeds(&self, output: u32) -> (i32, i32) {
        let speed = self.pair(D_ZERO_RETURN_SPEED + 10 * output);
        let creep = i32::from(self.get_i16(Array::D, D_CREEP_SPEED + 10 * output));
        (
            if speed == 0 { DEFAULT_ZERO_RETURN_SPEED } else { speed },
            if creep == 0 { DEFAULT_CREEP_SPEED } else { creep },
        )
    }

    fn write_direction(&mut self, request: &PulseRequest, state: InstanceState) {
        let Some(place) = Place::unpack(request.direction) else {
            return;
        };
        let here = i64::from(self.current_address(request.output));
        let forward = match request.kind {
            PulseKind::Plsv => request.frequency >= 0,
            PulseKind::Drvi | PulseKind::Drva => i64::from(state.c) >= here,
            PulseKind::Zrn | PulseKind::Dszr => self.get_u8(Array::M, M_ZERO_RETURN_FORWARD + 10 * request.output) != 0,
            PulseKind::Plsy | PulseKind::Plsr => true,
        };
        place.write(self, Width::Single, i64::from(forward));
    }

    /// An execution of pulse instruction `instance` with its drive OFF:
    /// a running output stops at once; M8029 OFF.
    pub fn pulse_stop(&mut self, instance: u32) {
        let owner = instance + 1;
        if let Some(output) = (0..PULSE_OUTPUTS).find(|&o| self.get_u32(Array::PulseOwner, o) == owner) {
            if self.instance(instance).is_some_and(|s| s.phase == RUNNING) {
                self.release(output);
            }
        }
        if self.instance(instance).is_some() {
            self.set_instance(instance, InstanceState::default());
        }
        self.set_u8(Array::M, M_EXECUTION_COMPLETE, 0);
    }

    /// One execution of PWM instance `instance`: with power the output bit
    /// `output` (a packed place) is ON for the first `width_ms` of every
    /// `period_ms`, counted from the scan the drive turned ON; without
    /// power it is OFF.
    pub fn pulse_width(&mut self, instance: u32, power: bool, width_ms: u32, period_ms: u32, output: u32) {
        let (Some(mut state), Some(place)) = (self.instance(instance), Place::unpack(output)) else {
            return;
        };
        let on = if power && period_ms > 0 {
            let running = state.phase == RUNNING;
            state.phase = RUNNING;
            let elapsed = self.scalar(Scalar::ElapsedMs);
            let time = if running {
                ((u64::from(state.a as u32) + u64::from(elapsed)) % u64::from(period_ms)) as u32
            } else {
                0
            };
            state.a = time as i32;
            time < width_ms
        } else {
            state = InstanceState::default();
            false
        };
        self.set_instance(instance, state);
        place.write(self, Width::Single, i64::from(on));
    }
}

/// (pulses now, direction, completed) of a counted output: `amount` 0 is
/// without end.
fn counted(pulses: i64, so_far: i64, amount: i32) -> (i64, i64, bool) {
    if amount <= 0 {
        return (pulses, 1, false);
    }
    let left = i64::from(amount) - so_far;
    (pulses.min(left), 1, pulses >= left)
}

/// PLSR: the pulses output `t` ms after the start, accelerating linearly to
/// `frequency` in `ramp_ms`, decelerating as fast to stop at `total`
/// (integer arithmetic in thousandths of a pulse, so every engine and host
/// agrees).
pub fn ramp_position(frequency: i32, ramp_ms: i32, total: i64, t: u32) -> i64 {
    let f = i128::from(frequency.max(0));
    let ramp = i128::from(ramp_ms.max(0));
    let goal = i128::from(total) * 1000;
    let t = i128::from(t);
    if f == 0 {
        return 0;
    }
    let milli = if ramp == 0 {
        f * t
    } else if goal >= f * ramp {
        // Trapezoid: up for `ramp`, steady, down for `ramp`; the whole
        // move takes ramp + goal / f.
        let end_of_steady = goal / f;
        if t <= ramp {
            f * t * t / (2 * ramp)
        } else if t <= end_of_steady {
            f * ramp / 2 + f * (t - ramp)
        } else {
            let left = f * (ramp - t) + goal;
            if left <= 0 {
                goal
            } else {
                goal - left * left / (2 * ramp * f)
            }
        }
    } else {
        // Triangle: the peak comes at tp = sqrt(goal·ramp/f).
        let peak = isqrt(goal * ramp / f);
        if t <= peak {
            f * t * t / (2 * ramp)
        } else if t >= 2 * peak {
            goal
        } else {
            let rest = 2 * peak - t;
            goal - f * rest * rest / (2 * ramp)
        }
    };
    (milli.clamp(0, goal) / 1000) as i64
}

/// The integer square root, rounded down (no floating point: the runtime
/// builds without a standard library).
fn isqrt(n: i128) -> i128 {
    if n <= 0 {
        return 0;
    }
    // Newton's method from above converges to the floor of the root.
    let mut x = n;
    let mut y = (x + 1) / 2;
    while y < x {
        x = y;
        y = (x + n / x) / 2;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::BitArea;

    fn request(kind: PulseKind, frequency: i32, amount: i32) -> PulseRequest {
        PulseRequest {
            kind,
            output: 0,
            frequency,
            amount,
            ramp_ms: 0,
            creep: 0,
            near_point: false,
            direction: NO_PLACE,
        }
    }

    fn scan(mem: &mut Memory, ms: u32, instance: u32, power: bool, request: &PulseRequest) {
        mem.scan_with(ms, |m| {
            m.pulse_output(instance, power, request);
        });
    }

    #[test]
    fn plsy_outputs_its_pulses_then_completes() {
        let mut mem = Memory::new_boxed();
        let plsy = request(PulseKind::Plsy, 1000, 100);
        scan(&mut mem, 10, 0, true, &plsy);
        assert_eq!((mem.m[8340], mem.current_address(0)), (1, 0), "the start scan");
        for _ in 0..9 {
            scan(&mut mem, 10, 0, true, &plsy);
        }
        assert_eq!((mem.current_address(0), mem.m[8029]), (90, 0));
        scan(&mut mem, 10, 0, true, &plsy);
        assert_eq!((mem.current_address(0), mem.m[8029], mem.m[8340]), (100, 1, 0));
        assert_eq!((mem.d[8140], mem.d[8136]), (100, 100));
        scan(&mut mem, 10, 0, true, &plsy);
        assert_eq!((mem.current_address(0), mem.m[8029]), (100, 1), "stays complete");
        scan(&mut mem, 10, 0, false, &plsy);
        assert_eq!(mem.m[8029], 0);
    }

    #[test]
    fn fractions_of_pulses_carry_over() {
        let mut mem = Memory::new_boxed();
        let plsy = request(PulseKind::Plsy, 150, 0);
        for _ in 0..11 {
            scan(&mut mem, 10, 0, true, &plsy);
        }
        assert_eq!(mem.current_address(0), 15, "10 scans of 1.5 pulses");
    }

    #[test]
    fn drvi_and_drva_move_to_their_targets_and_a_busy_output_refuses() {
        let mut mem = Memory::new_boxed();
        let direction = Place::Bit(BitArea::Y, 4).pack().unwrap();
        let drvi = PulseRequest {
            direction,
            ..request(PulseKind::Drvi, 2000, -50)
        };
        let other = request(PulseKind::Plsy, 100, 10);
        mem.scan_with(10, |m| {
            m.pulse_output(0, true, &drvi);
            m.pulse_output(1, true, &other);
        });
        assert_eq!(mem.instance[1].phase, REFUSED);
        assert_eq!(mem.y[4], 0, "toward smaller addresses");
        for _ in 0..3 {
            scan(&mut mem, 10, 0, true, &drvi);
        }
        assert_eq!((mem.current_address(0), mem.m[8029]), (-50, 1));
        scan(&mut mem, 10, 0, false, &drvi);
        let drva = request(PulseKind::Drva, 1000, 10);
        for _ in 0..8 {
            scan(&mut mem, 10, 0, true, &drva);
        }
        assert_eq!((mem.current_address(0), mem.m[8029]), (10, 1));
    }

    #[test]
    fn zero_return_completes_when_the_near_point_is_released() {
        let mut mem = Memory::new_boxed();
        mem.set_word_pair(crate::WordArea::D, D_CURRENT_ADDRESS, 5000);
        let mut zrn = PulseRequest {
            creep: 100,
            ..request(PulseKind::Zrn, 10_000, 0)
        };
        scan(&mut mem, 10, 0, true, &zrn);
        scan(&mut mem, 10, 0, true, &zrn);
        assert_eq!(mem.current_address(0), 4900);
        zrn.near_point = true;
        scan(&mut mem, 10, 0, true, &zrn);
        assert_eq!(mem.current_address(0), 4800);
        scan(&mut mem, 10, 0, true, &zrn);
        assert_eq!(mem.current_address(0), 4799, "creeping");
        zrn.near_point = false;
        scan(&mut mem, 10, 0, true, &zrn);
        assert_eq!((mem.current_address(0), mem.m[8029], mem.m[8340]), (0, 1, 0));
    }

    #[test]
    fn ramps_reach_the_total_and_never_go_back() {
        for (f, ramp, total) in [(1000, 100, 500), (1000, 100, 20), (5000, 0, 50), (30, 1000, 7)] {
            let mut last = 0;
            for t in 0..5000 {
                let p = ramp_position(f, ramp, total, t);
                assert!(p >= last && p <= total, "{f} {ramp} {total} at {t}");
                last = p;
            }
            assert_eq!(last, total, "{f} {ramp} {total}");
        }
        assert_eq!(ramp_position(1000, 100, 500, 100), 50, "the ramp's area");
    }

    #[test]
    fn integer_roots() {
        for n in [0i128, 1, 2, 3, 4, 15, 16, 17, 1 << 40, (1 << 62) + 12345] {
            let r = isqrt(n);
            assert!(r * r <= n && (r + 1) * (r + 1) > n, "{n}");
        }
    }

    #[test]
    fn pwm_follows_width_and_period() {
        let mut mem = Memory::new_boxed();
        let y0 = Place::Bit(BitArea::Y, 0).pack().unwrap();
        let mut seen = Vec::new();
        for _ in 0..6 {
            mem.scan_with(10, |m| m.pulse_width(3, true, 20, 50, y0));
            seen.push(mem.y[0]);
        }
        assert_eq!(seen, [1, 1, 0, 0, 0, 1]);
        mem.scan_with(10, |m| m.pulse_width(3, false, 20, 50, y0));
        assert_eq!(mem.y[0], 0);
    }
}
