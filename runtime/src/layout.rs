//! Byte offsets of the device image, for code that addresses `Memory` through
//! a pointer (compiled programs). The struct is `#[repr(C)]` with integer
//! arrays only, so the layout is the same on every 64-bit target ladderc
//! builds for.

use crate::device::{BitArea, WordArea};
use crate::memory::Memory;
use core::mem::offset_of;

/// Size of `Memory` in bytes.
pub const MEMORY_SIZE: usize = size_of::<Memory>();
/// Alignment of `Memory` in bytes.
pub const MEMORY_ALIGN: usize = align_of::<Memory>();

/// Names this layout in the symbol that compiled objects import
/// (`ladder_rt_begin_scan_<tag>`), so that an object linked against a runtime
/// with another layout fails to link instead of corrupting memory. Change it
/// whenever an offset changes; `layout_fingerprint_is_recorded` insists.
pub const LAYOUT_TAG: &str = "v4_666504";

/// The begin-scan entry compiled objects call; carries the layout tag.
pub const TAGGED_BEGIN_SCAN: &str = "ladder_rt_begin_scan_v4_666504";

/// The end-scan entry compiled objects call (the C API's `ladder_end_scan`).
pub const END_SCAN: &str = "ladder_end_scan";

/// Offset of a bit area's first byte (one byte per bit).
pub const fn bit_area_offset(area: BitArea) -> usize {
    match area {
        BitArea::X => offset_of!(Memory, x),
        BitArea::Y => offset_of!(Memory, y),
        BitArea::M => offset_of!(Memory, m),
        BitArea::S => offset_of!(Memory, s),
        BitArea::Sm => offset_of!(Memory, sm),
        BitArea::TimerContact => offset_of!(Memory, timer_contact),
        BitArea::CounterContact => offset_of!(Memory, counter_contact),
    }
}

/// Offset of a word area's first word (two bytes per word).
pub const fn word_area_offset(area: WordArea) -> usize {
    match area {
        WordArea::D => offset_of!(Memory, d),
        WordArea::Sd => offset_of!(Memory, sd),
        WordArea::R => offset_of!(Memory, r),
        WordArea::TimerValue => offset_of!(Memory, timer_value),
        WordArea::CounterValue => offset_of!(Memory, counter_value),
        WordArea::Index => offset_of!(Memory, index),
        WordArea::Buffer => offset_of!(Memory, buffer),
    }
}

/// Offset of the 32-bit counter values (C200 first, four bytes each).
pub const WIDE_COUNTER_OFFSET: usize = offset_of!(Memory, wide_counter_value);
/// Offset of the instance states (`InstanceState`, 16 bytes each).
pub const INSTANCE_OFFSET: usize = offset_of!(Memory, instance);
/// Offset of the edge-instruction slots (one byte each).
pub const EDGE_SLOT_OFFSET: usize = offset_of!(Memory, edge_slot);
/// Offset of the per-state "block last ran active" flags (one byte each).
pub const STL_BLOCK_ACTIVE_OFFSET: usize = offset_of!(Memory, stl_block_active);

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field's offset, in order: a change here changes the layout.
    fn fingerprint() -> String {
        let offsets = [
            offset_of!(Memory, x),
            offset_of!(Memory, y),
            offset_of!(Memory, m),
            offset_of!(Memory, s),
            offset_of!(Memory, sm),
            offset_of!(Memory, timer_contact),
            offset_of!(Memory, counter_contact),
            offset_of!(Memory, d),
            offset_of!(Memory, sd),
            offset_of!(Memory, r),
            offset_of!(Memory, timer_value),
            offset_of!(Memory, counter_value),
            offset_of!(Memory, wide_counter_value),
            offset_of!(Memory, index),
            offset_of!(Memory, timer_remainder_ms),
            offset_of!(Memory, timer_coil_was_on),
            offset_of!(Memory, counter_coil_was_on),
            offset_of!(Memory, stl_pending_off),
            offset_of!(Memory, stl_block_active),
            offset_of!(Memory, edge_slot),
            offset_of!(Memory, sort_state),
            offset_of!(Memory, sort_scans),
            offset_of!(Memory, input_image),
            offset_of!(Memory, output_image),
            offset_of!(Memory, force_x),
            offset_of!(Memory, force_y),
            offset_of!(Memory, force_m),
            offset_of!(Memory, force_timer),
            offset_of!(Memory, force_counter),
            offset_of!(Memory, forced_count),
            offset_of!(Memory, stl_pending_any),
            offset_of!(Memory, elapsed_ms),
            offset_of!(Memory, scan_count),
            offset_of!(Memory, clock_ms),
            offset_of!(Memory, loop_repetitions),
            offset_of!(Memory, pulses_pending),
            offset_of!(Memory, input_edges),
            offset_of!(Memory, instance),
            offset_of!(Memory, pulse_owner),
            offset_of!(Memory, pulse_remainder),
            offset_of!(Memory, calendar_seconds),
            offset_of!(Memory, calendar_ms),
            offset_of!(Memory, calendar_flags),
            offset_of!(Memory, reserved),
            offset_of!(Memory, buffer),
            MEMORY_SIZE,
        ];
        offsets.map(|o| o.to_string()).join(",")
    }

    #[test]
    fn layout_fingerprint_is_recorded() {
        assert_eq!(
            fingerprint(),
            "0,256,512,9024,13120,14144,14656,14912,31936,33984,99520,100544,100944,101168,101200,102224,102736,102992,107088,111184,127568,127632,127696,127952,128208,128464,128720,137232,137744,138000,138004,138008,138012,138016,138020,138024,138056,138088,142184,142200,142216,142220,142224,142228,142232,666504",
            "the memory layout changed: bump LAYOUT_TAG (and the tagged symbol) and record the new fingerprint"
        );
        assert_eq!(TAGGED_BEGIN_SCAN, format!("ladder_rt_begin_scan_{LAYOUT_TAG}"));
    }

    #[test]
    fn offsets_address_the_fields() {
        let mut mem = Memory::new_boxed();
        mem.m[17] = 1;
        mem.d[5] = -2;
        mem.wide_counter_value[1] = 7;
        let bytes = bytemuck::bytes_of(&*mem);
        assert_eq!(bytes[bit_area_offset(BitArea::M) + 17], 1);
        let d5 = word_area_offset(WordArea::D) + 2 * 5;
        assert_eq!(i16::from_ne_bytes([bytes[d5], bytes[d5 + 1]]), -2);
        let c201 = WIDE_COUNTER_OFFSET + 4;
        assert_eq!(i32::from_ne_bytes(bytes[c201..c201 + 4].try_into().unwrap()), 7);
        assert_eq!(MEMORY_ALIGN, 4);
        assert_eq!(WIDE_COUNTER_OFFSET % 4, 0);
    }
}
