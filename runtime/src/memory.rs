//! The device image with the full layout: every device, plus the
//! per-program bookkeeping the scan needs (timer remainders, edge slots, STL
//! flags, forces).
//!
//! The struct is `#[repr(C)]` so native code and C hosts address fields by
//! fixed offsets (see `layout`). Apart from its header (`ImageHeader`, the
//! first bytes of every image, of any layout), all-zero bytes are a valid,
//! freshly initialised image; `new_boxed` and `ladder_init` write the
//! header, without which the C API and compiled code refuse the image.
//! Here too: what an instruction keeps between scans (`InstanceState`), the
//! sort jobs' and force tables' values, and how 32-bit values are words.
//!
//! A leaf of the crate: it names the device counts (`device.rs`) and
//! nothing else, so every part of the runtime may name it. The runtime's
//! functions are methods of `Memory` through `facade.rs`.

use crate::device::{
    BitArea, WordArea, COUNTER_COUNT, EDGE_SLOT_COUNT, HSC_INPUTS, PULSE_OUTPUTS, SORT_INSTANCES, STATE_COUNT,
    STATE_INSTANCES, TIMER_COUNT, WIDE_COUNTER_COUNT,
};
use bytemuck::{Pod, Zeroable};

const IO_POINTS: usize = BitArea::X.count() as usize;
const STATES: usize = STATE_COUNT as usize;
const TIMERS: usize = TIMER_COUNT as usize;
const COUNTERS: usize = COUNTER_COUNT as usize;

/// `ImageHeader::magic` of an image with the full layout ("LDRF").
pub const FULL_MAGIC: u32 = u32::from_le_bytes(*b"LDRF");
/// `ImageHeader::magic` of an image with a compact layout ("LDRC").
pub const COMPACT_MAGIC: u32 = u32::from_le_bytes(*b"LDRC");

/// The first bytes of every image: which layout the rest has. Written by
/// `ladder_init` or `ladder_init_layout`; an image whose magic is neither
/// (storage that was never initialised) is refused by every entry point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct ImageHeader {
    /// `FULL_MAGIC` or `COMPACT_MAGIC`.
    pub magic: u32,
    /// Bytes of the image.
    pub size: u32,
    /// A compact image's layout table, by address (low and high 32 bits);
    /// 0 for the full layout.
    pub layout_low: u32,
    pub layout_high: u32,
}

impl ImageHeader {
    /// The header of a full image.
    pub const FULL: ImageHeader = ImageHeader {
        magic: FULL_MAGIC,
        size: size_of::<Memory>() as u32,
        layout_low: 0,
        layout_high: 0,
    };
}

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
}

/// Joins a low and a high word into one 32-bit value.
pub fn join_words(low: i16, high: i16) -> i32 {
    (i32::from(high) << 16) | i32::from(low as u16)
}

/// Splits a 32-bit value into (low, high) words.
pub fn split_words(value: i32) -> (i16, i16) {
    (value as i16, (value >> 16) as i16)
}
