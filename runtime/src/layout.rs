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
    }
}

/// Offset of the 32-bit counter values (C200 first, four bytes each).
pub const WIDE_COUNTER_OFFSET: usize = offset_of!(Memory, wide_counter_value);
/// Offset of the edge-instruction slots (one byte each).
pub const EDGE_SLOT_OFFSET: usize = offset_of!(Memory, edge_slot);
/// Offset of the per-state "block last ran active" flags (one byte each).
pub const STL_BLOCK_ACTIVE_OFFSET: usize = offset_of!(Memory, stl_block_active);

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(
            i32::from_ne_bytes(bytes[c201..c201 + 4].try_into().unwrap()),
            7
        );
        assert_eq!(MEMORY_ALIGN, 4);
        assert_eq!(WIDE_COUNTER_OFFSET % 4, 0);
    }
}
