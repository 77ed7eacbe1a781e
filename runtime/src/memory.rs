//! The device image with the full layout: every device, plus the
//! per-program bookkeeping the scan needs (timer remainders, edge slots, STL
//! flags, forces).
//!
//! The struct is `#[repr(C)]` so native code and C hosts address fields by
//! fixed offsets (see `layout`). Apart from its header, all-zero bytes are a
//! valid, freshly initialised image; `new_boxed` and `ladder_init` write the
//! header, without which the C API and compiled code refuse the image.

use crate::calendar::CalendarTime;
use crate::device::{
    BitArea, WordArea, COUNTER_COUNT, EDGE_SLOT_COUNT, HSC_INPUTS, PULSE_OUTPUTS, SORT_INSTANCES, STATE_COUNT,
    STATE_INSTANCES, TIMER_COUNT, WIDE_COUNTER_COUNT,
};
use crate::force::ForceError;
use crate::host::{Basic, Device, Width};
use crate::hsc::HscCompare;
use crate::image::{AsImage, AsImageMut, ImageMut, ImageRef};
use crate::layout::ImageHeader;
use crate::machine::MachineUse;
use crate::pulse::PulseRequest;
use crate::special::OperationError;
use bytemuck::{Pod, Zeroable};

const IO_POINTS: usize = BitArea::X.count() as usize;
const STATES: usize = STATE_COUNT as usize;
const TIMERS: usize = TIMER_COUNT as usize;
const COUNTERS: usize = COUNTER_COUNT as usize;

/// The device image with the full layout: every device of the machine
/// model, plus the per-program bookkeeping the scan needs (timer
/// remainders, edge slots, STL flags, forces). The runtime reads and writes
/// it through `Image` (`image.rs`), as it does compact images; the fields
/// are for code that knows it has the full layout (the interpreter, hosts).
/// Arrays are in `layout::Array` order. Bits are one byte each (0 or 1).
#[derive(Clone, Copy, Zeroable, Pod)]
#[repr(C)]
pub struct Memory {
    /// Which layout this is (`ImageHeader::FULL`; `new_boxed` writes it).
    pub header: ImageHeader,

    // ---- the scan's scalars (`layout::Scalar`) ----
    /// Number of devices currently forced (lets the scan skip the tables).
    pub forced_count: u32,
    /// Non-zero when some `stl_pending_off` entry is set.
    pub stl_pending_any: u32,
    /// Milliseconds the host reported for the current scan.
    pub elapsed_ms: u32,
    /// Completed scans since initialisation (saturating).
    pub scan_count: u32,
    /// The elapsed times reported to all scans so far, this one included,
    /// modulo one minute (the clock relays M8011-M8014 follow it).
    pub clock_ms: u32,
    /// FOR/NEXT repetitions in the current scan (the loop watchdog).
    pub loop_repetitions: u32,
    /// The calendar clock (D8013-D8019): seconds since 1980-01-01 00:00:00
    /// and milliseconds below the second.
    pub calendar_seconds: u32,
    pub calendar_ms: u32,
    /// `CALENDAR_FOUR_DIGIT_YEAR`: D8018 shows four digits.
    pub calendar_flags: u32,
    /// Writes by the program to devices the image lacks (only a compact
    /// layout can lack one; see `image.rs`).
    pub layout_misses: u32,
    /// The calendar's time as D8013-D8019 show it, worked out once per
    /// second: for `calendar_cache_at` - 1 seconds (0: nothing yet), the
    /// second, minute, hour, day, month and day of the week packed as
    /// `calendar::pack` does, and the year.
    pub calendar_cache_at: u32,
    pub calendar_cache_time: u32,
    pub calendar_cache_year: u32,

    // ---- bit devices ----
    pub x: [u8; IO_POINTS],
    pub y: [u8; IO_POINTS],
    pub m: [u8; BitArea::M.count() as usize],
    pub s: [u8; STATES],
    pub sm: [u8; BitArea::Sm.count() as usize],
    pub timer_contact: [u8; TIMERS],
    pub counter_contact: [u8; COUNTERS],

    // ---- word devices ----
    pub d: [i16; WordArea::D.count() as usize],
    pub sd: [i16; WordArea::Sd.count() as usize],
    pub r: [i16; WordArea::R.count() as usize],
    pub timer_value: [i16; TIMERS],
    pub counter_value: [i16; WordArea::CounterValue.count() as usize],
    /// Current values of the 32-bit counters C200–C255.
    pub wide_counter_value: [i32; WIDE_COUNTER_COUNT as usize],
    /// Index registers: Z0, V0, Z1, V1, ... (`device::index_register_word`).
    pub index: [i16; WordArea::Index.count() as usize],

    // ---- scan bookkeeping ----
    /// Milliseconds below the timer's resolution carried to the next scan.
    pub timer_remainder_ms: [u16; TIMERS],
    /// 1 when the timer's coil was ON at its previous execution.
    pub timer_coil_was_on: [u8; TIMERS],
    /// 1 when the counter's coil was ON at its previous execution.
    pub counter_coil_was_on: [u8; COUNTERS],
    /// 1 when a SET transfer left the state to be turned OFF at the next scan.
    pub stl_pending_off: [u8; STATES],
    /// 1 when the state's block last ran with its state ON.
    pub stl_block_active: [u8; STATES],
    /// Previous-scan slots of the program's edge instructions.
    pub edge_slot: [u8; EDGE_SLOT_COUNT as usize],
    /// Each SORT/SORT2/DSORT2 instruction's job: `SORT_IDLE`,
    /// `SORT_RUNNING`, `SORT2_RUNNING` or `SORT_DONE`.
    pub sort_state: [u8; SORT_INSTANCES as usize],
    /// Scans a running sort has executed.
    pub sort_scans: [u8; SORT_INSTANCES as usize],
    /// What the host last wrote to the inputs; copied to X at each scan.
    pub input_image: [u8; IO_POINTS],
    /// Y as it was at the end of the latest scan.
    pub output_image: [u8; IO_POINTS],
    /// Force tables: `FORCE_NONE`, `FORCE_OFF` or `FORCE_ON` per device.
    pub force_x: [u8; IO_POINTS],
    pub force_y: [u8; IO_POINTS],
    pub force_m: [u8; BitArea::M.count() as usize],
    pub force_timer: [u8; TIMERS],
    pub force_counter: [u8; COUNTERS],

    // ---- the machine around the program (hsc.rs, pulse.rs, calendar.rs) ----
    /// Rising edges a host reported for X0-X7 since the previous input
    /// refresh, for the high-speed counters (`ladder_add_pulses`).
    pub pulses_pending: [u32; HSC_INPUTS as usize],
    /// Rising edges of X0-X7 the latest input refresh saw: level changes
    /// plus reported pulses.
    pub input_edges: [u32; HSC_INPUTS as usize],
    /// The state of each instruction that keeps one between scans (pulse
    /// and positioning outputs, high-speed compares, HOUR, SEGL, ...), by
    /// the instance number the compiler gave it.
    pub instance: [InstanceState; STATE_INSTANCES as usize],
    /// The instance that drives each pulse output Y0-Y3 (its number + 1;
    /// 0 when the output is free).
    pub pulse_owner: [u32; PULSE_OUTPUTS as usize],
    /// Pulses × 1000 not yet output (frequency × milliseconds carried to
    /// the next scan), per pulse output.
    pub pulse_remainder: [u32; PULSE_OUTPUTS as usize],

    // ---- special-function units (last: the largest area) ----
    /// Buffer memories of units 0-7 (`Un\Gm`).
    pub buffer: [i16; WordArea::Buffer.count() as usize],
}

/// What an instruction that keeps state between scans remembers: a phase
/// and five numbers, whose meaning each instruction documents (hsc.rs,
/// pulse.rs and the compiled/ helpers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct InstanceState {
    pub phase: u32,
    pub a: i32,
    pub b: i32,
    pub c: i32,
    pub d: i32,
    pub e: i32,
}

/// Sort job: not started (its input was OFF, or it could not start).
pub const SORT_IDLE: u8 = 0;
/// Sort job: a SORT in progress.
pub const SORT_RUNNING: u8 = 1;
/// Sort job: a SORT2 or DSORT2 in progress.
pub const SORT2_RUNNING: u8 = 2;
/// Sort job: finished; starts again only after its input was OFF.
pub const SORT_DONE: u8 = 3;

/// Force-table entry: the device follows the program and the host.
pub const FORCE_NONE: u8 = 0;
/// Force-table entry: the device is forced OFF.
pub const FORCE_OFF: u8 = 1;
/// Force-table entry: the device is forced ON.
pub const FORCE_ON: u8 = 2;

impl Memory {
    /// A freshly initialised image on the heap (it is too large for most
    /// stacks): every device 0, the header written.
    #[cfg(feature = "std")]
    pub fn new_boxed() -> Box<Memory> {
        let mut mem: Box<Memory> = bytemuck::zeroed_box();
        mem.header = ImageHeader::FULL;
        mem
    }

    /// The image, to read through the runtime's code.
    pub fn view(&self) -> ImageRef<'_> {
        self.as_image()
    }

    /// The image, to read and write through the runtime's code.
    pub fn image(&mut self) -> ImageMut<'_> {
        self.as_image_mut()
    }

    pub fn bits(&self, area: BitArea) -> &[u8] {
        match area {
            BitArea::X => &self.x,
            BitArea::Y => &self.y,
            BitArea::M => &self.m,
            BitArea::S => &self.s,
            BitArea::Sm => &self.sm,
            BitArea::TimerContact => &self.timer_contact,
            BitArea::CounterContact => &self.counter_contact,
        }
    }

    pub fn bits_mut(&mut self, area: BitArea) -> &mut [u8] {
        match area {
            BitArea::X => &mut self.x,
            BitArea::Y => &mut self.y,
            BitArea::M => &mut self.m,
            BitArea::S => &mut self.s,
            BitArea::Sm => &mut self.sm,
            BitArea::TimerContact => &mut self.timer_contact,
            BitArea::CounterContact => &mut self.counter_contact,
        }
    }

    pub fn words(&self, area: WordArea) -> &[i16] {
        match area {
            WordArea::D => &self.d,
            WordArea::Sd => &self.sd,
            WordArea::R => &self.r,
            WordArea::TimerValue => &self.timer_value,
            WordArea::CounterValue => &self.counter_value,
            WordArea::Index => &self.index,
            WordArea::Buffer => &self.buffer,
        }
    }

    pub fn words_mut(&mut self, area: WordArea) -> &mut [i16] {
        match area {
            WordArea::D => &mut self.d,
            WordArea::Sd => &mut self.sd,
            WordArea::R => &mut self.r,
            WordArea::TimerValue => &mut self.timer_value,
            WordArea::CounterValue => &mut self.counter_value,
            WordArea::Index => &mut self.index,
            WordArea::Buffer => &mut self.buffer,
        }
    }

    /// `image::digest` of the image.
    pub fn digest(&self) -> u64 {
        self.view().digest()
    }
}

/// Methods of `Image` offered on `Memory`: one piece of code, since
/// `Memory` is an image with the full layout.
macro_rules! through_image {
    (view: $(
        $(#[$doc:meta])*
        fn $name:ident(&self $(, $arg:ident: $ty:ty)*) $(-> $ret:ty)?;
    )*) => {
        impl Memory {
            $(
                $(#[$doc])*
                pub fn $name(&self $(, $arg: $ty)*) $(-> $ret)? {
                    self.view().$name($($arg),*)
                }
            )*
        }
    };
    (image: $(
        $(#[$doc:meta])*
        fn $name:ident(&mut self $(, $arg:ident: $ty:ty)*) $(-> $ret:ty)?;
    )*) => {
        impl Memory {
            $(
                $(#[$doc])*
                pub fn $name(&mut self $(, $arg: $ty)*) $(-> $ret)? {
                    self.image().$name($($arg),*)
                }
            )*
        }
    };
}

through_image! {
    view:
    /// Reads bit `index` of `area`; `None` when it is outside the area.
    fn bit(&self, area: BitArea, index: u32) -> Option<bool>;
    fn word(&self, area: WordArea, index: u32) -> Option<i16>;
    /// 32-bit value of the pair (index+1, index): low word at `index`. A
    /// pair never crosses the end of its run (a buffer memory's unit).
    fn word_pair(&self, area: WordArea, index: u32) -> Option<i32>;
    /// Current value of counter C200–C255 (`counter` is the device number).
    fn wide_counter(&self, counter: u32) -> Option<i32>;
    /// Value of the 4·`digits` consecutive bits starting at `start`
    /// (`KnM0`): first device is bit 0.
    fn digits(&self, area: BitArea, start: u32, digits: u32) -> Option<i32>;
    /// The latest operation error code, when M8067 is ON.
    fn operation_error(&self) -> Option<u16>;
    /// The forced value of a device, or `None` when it is not forced.
    fn forced(&self, area: BitArea, index: u32) -> Option<bool>;
    /// The current address of pulse output Y`output` (`pulse.rs`).
    fn current_address(&self, output: u32) -> i32;
    /// The calendar clock's time now.
    fn calendar(&self) -> CalendarTime;
    /// Reads a basic device (`host.rs`).
    fn basic(&self, device: Basic) -> Option<i32>;
    /// Reads a device as a host would (`host.rs`).
    fn read_device(&self, device: Device, width: Width) -> Option<i32>;
}

through_image! {
    image:
    /// Writes bit `index` of `area`; returns false when it is outside the area.
    fn set_bit(&mut self, area: BitArea, index: u32, on: bool) -> bool;
    fn set_word(&mut self, area: WordArea, index: u32, value: i16) -> bool;
    fn set_word_pair(&mut self, area: WordArea, index: u32, value: i32) -> bool;
    fn set_wide_counter(&mut self, counter: u32, value: i32) -> bool;
    /// Writes the low 4·`digits` bits of `value` to the bits from `start`.
    fn set_digits(&mut self, area: BitArea, start: u32, digits: u32, value: i32) -> bool;
    /// Records an operation error: M8067 ON, D8067 = code, D8069 = line.
    fn record_error(&mut self, error: OperationError, line: u32);
    /// Steps 1 and 2 of the scan (`scan.rs`).
    fn begin_scan(&mut self, elapsed_ms: u32);
    /// Step 4 of the scan.
    fn end_scan(&mut self);
    /// Steps 1 and 2 keeping the parts `machine` of the machine (`machine.rs`).
    fn begin_scan_for(&mut self, elapsed_ms: u32, machine: MachineUse);
    /// Step 4 keeping the parts `machine` of the machine.
    fn end_scan_for(&mut self, machine: MachineUse);
    /// A SET transfer inside the block of `source`.
    fn schedule_state_off(&mut self, source: u32);
    /// The loop watchdog at a NEXT (`scan.rs`).
    fn loop_may_repeat(&mut self, line: u32) -> bool;
    /// `OUT Tn preset` with the rung result `coil` (`timer.rs`).
    fn timer_coil(&mut self, timer: u32, coil: bool, preset: i32);
    /// `RST Tn`.
    fn reset_timer(&mut self, timer: u32);
    /// `OUT Cn preset` with the rung result `coil` (`counter.rs`).
    fn counter_coil(&mut self, counter: u32, coil: bool, preset: i32);
    /// `RST Cn`.
    fn reset_counter(&mut self, counter: u32);
    /// Forces a device (`force.rs`).
    fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), ForceError>;
    /// Ends a force.
    fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), ForceError>;
    /// Adds rising edges of X0-X7 for the high-speed counters (`hsc.rs`).
    fn add_pulses(&mut self, input: u32, count: u32) -> bool;
    /// DHSCS/DHSCR/DHSZ (`hsc.rs`).
    fn high_speed_compare(&mut self, instance: u32, kind: HscCompare, power: bool, counter: u32, values: [i32; 2], destination: u32);
    /// One execution of a pulse instruction (`pulse.rs`).
    fn pulse_output(&mut self, instance: u32, power: bool, request: &PulseRequest) -> bool;
    /// A pulse instruction with its drive OFF.
    fn pulse_stop(&mut self, instance: u32);
    /// One execution of PWM.
    fn pulse_width(&mut self, instance: u32, power: bool, width_ms: u32, period_ms: u32, output: u32);
    /// Sets the calendar clock (`calendar.rs`).
    fn set_calendar(&mut self, time: CalendarTime) -> bool;
    /// Writes a device as a host would (`host.rs`).
    fn write_device(&mut self, device: Device, width: Width, value: i32) -> bool;
}

impl Memory {
    /// A whole scan around `program`, for engines that run in-process,
    /// keeping every part of the machine up to date.
    pub fn scan_with(&mut self, elapsed_ms: u32, program: impl FnOnce(&mut Memory)) {
        self.scan_using(elapsed_ms, MachineUse::ALL, program);
    }

    /// A whole scan around `program` keeping the parts `machine` of the
    /// machine up to date (what a compiled program using them does).
    pub fn scan_using(&mut self, elapsed_ms: u32, machine: MachineUse, program: impl FnOnce(&mut Memory)) {
        self.begin_scan_for(elapsed_ms, machine);
        program(self);
        self.end_scan_for(machine);
    }
}

/// Joins a low and a high word into one 32-bit value.
pub fn join_words(low: i16, high: i16) -> i32 {
    (i32::from(high) << 16) | i32::from(low as u16)
}

/// Splits a 32-bit value into (low, high) words.
pub fn split_words(value: i32) -> (i16, i16) {
    (value as i16, (value >> 16) as i16)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeroed_image_is_clean() {
        let mem = Memory::new_boxed();
        assert_eq!(mem.bit(BitArea::M, 0), Some(false));
        assert_eq!(mem.operation_error(), None);
    }

    #[test]
    fn words_pair_low_word_first() {
        let mut mem = Memory::new_boxed();
        assert!(mem.set_word_pair(WordArea::D, 10, 0x0001_8000));
        assert_eq!(mem.word(WordArea::D, 10), Some(-32768));
        assert_eq!(mem.word(WordArea::D, 11), Some(1));
        assert_eq!(mem.word_pair(WordArea::D, 10), Some(0x0001_8000));
        assert!(!mem.set_word_pair(WordArea::D, 8511, 1), "high word would be D8512");
        assert_eq!(mem.word_pair(WordArea::D, 8511), None);
    }

    #[test]
    fn digit_groups_are_little_endian_bits() {
        let mut mem = Memory::new_boxed();
        assert!(mem.set_digits(BitArea::M, 0, 4, 0xA5F0u16 as i16 as i32));
        assert_eq!(mem.bit(BitArea::M, 4), Some(true));
        assert_eq!(mem.bit(BitArea::M, 0), Some(false));
        assert_eq!(mem.digits(BitArea::M, 0, 4), Some(0xA5F0));
        assert_eq!(mem.digits(BitArea::M, 4, 1), Some(0xF));
        // K1..K3 read zero-extended; K8 reads all 32 bits.
        assert!(mem.set_digits(BitArea::M, 100, 8, -1));
        assert_eq!(mem.digits(BitArea::M, 100, 8), Some(-1));
        assert_eq!(mem.digits(BitArea::M, 100, 3), Some(0xFFF));
        assert_eq!(mem.digits(BitArea::X, 250, 2), None, "X250..X257 runs past X377");
    }

    #[test]
    fn operation_error_sets_flag_code_and_line() {
        let mut mem = Memory::new_boxed();
        mem.record_error(OperationError::WriteOutOfRange, 12);
        assert_eq!(mem.operation_error(), Some(0x4086));
        assert_eq!(mem.word(WordArea::D, 8069), Some(12));
    }
}
