//! The device image: every device, plus the per-program bookkeeping the scan
//! needs (timer remainders, edge slots, STL flags, forces).
//!
//! The struct is `#[repr(C)]` so native code and C hosts address fields by
//! fixed offsets (see `layout`). All-zero bytes are a valid, freshly
//! initialised image: that is the state a firmware host gets from `memset`.

use crate::device::{
    BitArea, WordArea, COUNTER_COUNT, EDGE_SLOT_COUNT, HSC_INPUTS, PULSE_OUTPUTS, SORT_INSTANCES, STATE_COUNT,
    STATE_INSTANCES, TIMER_COUNT, WIDE_COUNTER_COUNT,
};
use crate::special::{OperationError, D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
use bytemuck::{Pod, Zeroable};

const IO_POINTS: usize = BitArea::X.count() as usize;
const STATES: usize = STATE_COUNT as usize;
const TIMERS: usize = TIMER_COUNT as usize;
const COUNTERS: usize = COUNTER_COUNT as usize;

/// Device memory of one running program. Bits are one byte each (0 or 1).
#[derive(Clone, Copy, Zeroable, Pod)]
#[repr(C)]
pub struct Memory {
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
    /// The calendar clock (D8013-D8019): seconds since 1980-01-01 00:00:00
    /// and milliseconds below the second.
    pub calendar_seconds: u32,
    pub calendar_ms: u32,
    /// `CALENDAR_FOUR_DIGIT_YEAR`: D8018 shows four digits.
    pub calendar_flags: u32,
    /// Padding, kept 0, so that the layout has no implicit holes.
    pub reserved: u32,

    // ---- special-function units (last: the largest area) ----
    /// Buffer memories of units 0-7 (`Un\Gm`).
    pub buffer: [i16; WordArea::Buffer.count() as usize],
}

/// What an instruction that keeps state between scans remembers: a phase
/// and three numbers, whose meaning each instruction documents (hsc.rs,
/// pulse.rs and the compiled/ helpers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct InstanceState {
    pub phase: u32,
    pub a: i32,
    pub b: i32,
    pub c: i32,
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
    /// A freshly initialised image on the heap (it is too large for most stacks).
    #[cfg(feature = "std")]
    pub fn new_boxed() -> Box<Memory> {
        bytemuck::zeroed_box()
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

    /// Reads bit `index` of `area`; `None` when it is outside the area.
    pub fn bit(&self, area: BitArea, index: u32) -> Option<bool> {
        self.bits(area).get(index as usize).map(|&b| b != 0)
    }

    /// Writes bit `index` of `area`; returns false when it is outside the area.
    pub fn set_bit(&mut self, area: BitArea, index: u32, on: bool) -> bool {
        match self.bits_mut(area).get_mut(index as usize) {
            Some(cell) => {
                *cell = on as u8;
                true
            }
            None => false,
        }
    }

    pub fn word(&self, area: WordArea, index: u32) -> Option<i16> {
        self.words(area).get(index as usize).copied()
    }

    pub fn set_word(&mut self, area: WordArea, index: u32, value: i16) -> bool {
        match self.words_mut(area).get_mut(index as usize) {
            Some(cell) => {
                *cell = value;
                true
            }
            None => false,
        }
    }

    /// 32-bit value of the pair (index+1, index): low word at `index`. A
    /// pair never crosses the end of its run (a buffer memory's unit).
    pub fn word_pair(&self, area: WordArea, index: u32) -> Option<i32> {
        let high_index = Self::pair_high(area, index)?;
        Some(join_words(self.word(area, index)?, self.word(area, high_index)?))
    }

    pub fn set_word_pair(&mut self, area: WordArea, index: u32, value: i32) -> bool {
        let Some(high_index) = Self::pair_high(area, index) else {
            return false;
        };
        let (low, high) = split_words(value);
        self.set_word(area, index, low) && self.set_word(area, high_index, high)
    }

    fn pair_high(area: WordArea, index: u32) -> Option<u32> {
        let high_index = index.checked_add(1)?;
        (index < area.count() && high_index < area.reach(index).1).then_some(high_index)
    }

    /// Current value of counter C200–C255 (`counter` is the device number).
    pub fn wide_counter(&self, counter: u32) -> Option<i32> {
        let slot = counter.checked_sub(crate::device::FIRST_WIDE_COUNTER)?;
        self.wide_counter_value.get(slot as usize).copied()
    }

    pub fn set_wide_counter(&mut self, counter: u32, value: i32) -> bool {
        let Some(slot) = counter.checked_sub(crate::device::FIRST_WIDE_COUNTER) else {
            return false;
        };
        match self.wide_counter_value.get_mut(slot as usize) {
            Some(cell) => {
                *cell = value;
                true
            }
            None => false,
        }
    }

    /// Value of the 4·`digits` consecutive bits starting at `start`
    /// (`KnM0`): first device is bit 0; missing high bits read as 0.
    pub fn digits(&self, area: BitArea, start: u32, digits: u32) -> Option<i32> {
        let bits = self.bits(area);
        let count = 4 * digits as usize;
        let slice = bits.get(start as usize..(start as usize).checked_add(count)?)?;
        Some(
            slice
                .iter()
                .enumerate()
                .fold(0u32, |acc, (i, &b)| acc | (u32::from(b != 0) << i)) as i32,
        )
    }

    /// Writes the low 4·`digits` bits of `value` to the bits from `start`.
    pub fn set_digits(&mut self, area: BitArea, start: u32, digits: u32, value: i32) -> bool {
        let count = 4 * digits as usize;
        let bits = self.bits_mut(area);
        let Some(end) = (start as usize).checked_add(count) else {
            return false;
        };
        let Some(slice) = bits.get_mut(start as usize..end) else {
            return false;
        };
        for (i, cell) in slice.iter_mut().enumerate() {
            *cell = ((value as u32 >> i) & 1) as u8;
        }
        true
    }

    /// Records an operation error: M8067 ON, D8067 = code, D8069 = line.
    /// Errors stay until the program or the host clears them.
    pub fn record_error(&mut self, error: OperationError, line: u32) {
        self.m[M_OPERATION_ERROR as usize] = 1;
        self.d[D_ERROR_CODE as usize] = error.code() as i16;
        // D8069 is one word: lines past 32767 keep their low 16 bits.
        self.d[D_ERROR_LINE as usize] = line as u16 as i16;
    }

    /// The latest operation error code, when M8067 is ON.
    pub fn operation_error(&self) -> Option<u16> {
        (self.m[M_OPERATION_ERROR as usize] != 0).then(|| self.d[D_ERROR_CODE as usize] as u16)
    }
}

impl Memory {
    /// FNV-1a over the image's 64-bit little-endian words: how test drivers
    /// (and hosts) compare whole images cheaply.
    pub fn digest(&self) -> u64 {
        bytemuck::bytes_of(self)
            .chunks_exact(8)
            .fold(0xcbf2_9ce4_8422_2325u64, |hash, word| {
                let mut bytes = [0u8; 8];
                bytes.copy_from_slice(word);
                (hash ^ u64::from_le_bytes(bytes)).wrapping_mul(0x0000_0100_0000_01b3)
            })
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
