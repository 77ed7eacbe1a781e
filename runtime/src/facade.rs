//! The runtime's functions as methods of `Memory`: an image with the full
//! layout is an image like any other, so each method hands the call to
//! `Image` (one piece of code for every layout). Hosts, the interpreter and
//! tests call them on a `Memory`.
//!
//! Here and not in `memory.rs` so that the dependencies point one way: the
//! struct (`memory.rs`) names no other part of the runtime, every part may
//! name the struct, and this file names every part (nothing imports it:
//! the methods come with the type).

use crate::calendar::CalendarTime;
use crate::device::{BitArea, Width, WordArea};
use crate::force::ForceError;
use crate::host::{Basic, Device};
use crate::hsc::HscCompare;
use crate::image::{AsImage, AsImageMut, ImageMut, ImageRef};
use crate::machine::MachineUse;
use crate::memory::Memory;
use crate::pulse::PulseRequest;
use crate::special::OperationError;

impl Memory {
    /// The image, to read through the runtime's code.
    pub fn view(&self) -> ImageRef<'_> {
        self.as_image()
    }

    /// The image, to read and write through the runtime's code.
    pub fn image(&mut self) -> ImageMut<'_> {
        self.as_image_mut()
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
