//! Entry points that compiled programs call (C ABI). The interpreter calls the
//! same `Memory` methods directly, so both engines share this bookkeeping.
//!
//! Every helper takes the device image first. A null image is ignored; device
//! numbers outside their area are ignored by the methods they call.

use crate::memory::Memory;
use crate::place::Place;

/// # Safety
/// `mem` is null or points to a `Memory` no one else is using.
unsafe fn memory<'a>(mem: *mut Memory) -> Option<&'a mut Memory> {
    // SAFETY: the caller passes the image it was given (see each helper).
    unsafe { mem.as_mut() }
}

/// `OUT Tn preset` with the rung result `coil` (0 or 1).
///
/// # Safety
/// `mem` is null or the program's device image.
#[no_mangle]
pub unsafe extern "C" fn ladder_rt_timer_coil(mem: *mut Memory, timer: u32, coil: u32, preset: i32) {
    if let Some(mem) = unsafe { memory(mem) } {
        mem.timer_coil(timer, coil != 0, preset);
    }
}

/// `OUT Cn preset` with the rung result `coil` (0 or 1).
///
/// # Safety
/// `mem` is null or the program's device image.
#[no_mangle]
pub unsafe extern "C" fn ladder_rt_counter_coil(mem: *mut Memory, counter: u32, coil: u32, preset: i32) {
    if let Some(mem) = unsafe { memory(mem) } {
        mem.counter_coil(counter, coil != 0, preset);
    }
}

/// `RST Tn`.
///
/// # Safety
/// `mem` is null or the program's device image.
#[no_mangle]
pub unsafe extern "C" fn ladder_rt_reset_timer(mem: *mut Memory, timer: u32) {
    if let Some(mem) = unsafe { memory(mem) } {
        mem.reset_timer(timer);
    }
}

/// `RST Cn`.
///
/// # Safety
/// `mem` is null or the program's device image.
#[no_mangle]
pub unsafe extern "C" fn ladder_rt_reset_counter(mem: *mut Memory, counter: u32) {
    if let Some(mem) = unsafe { memory(mem) } {
        mem.reset_counter(counter);
    }
}

/// A SET transfer out of the block of `state`.
///
/// # Safety
/// `mem` is null or the program's device image.
#[no_mangle]
pub unsafe extern "C" fn ladder_rt_schedule_state_off(mem: *mut Memory, state: u32) {
    if let Some(mem) = unsafe { memory(mem) } {
        mem.schedule_state_off(state);
    }
}

/// BMOV/FMOV of `n` units between places encoded as by `Place::encode`. The
/// compiled code has checked that both places hold `n` units; a place that
/// does not decode is ignored.
///
/// # Safety
/// `mem` is null or the program's device image.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn ladder_rt_block_move(
    mem: *mut Memory,
    source_kind: u32,
    source_index: u32,
    source_digits: u32,
    destination_kind: u32,
    destination_index: u32,
    destination_digits: u32,
    n: u32,
    flags: u32,
) {
    let source = Place::decode(source_kind, source_index, source_digits);
    let destination = Place::decode(destination_kind, destination_index, destination_digits);
    if let (Some(mem), Some(source), Some(destination)) = (unsafe { memory(mem) }, source, destination) {
        mem.block_move(
            source,
            destination,
            n,
            if flags & BLOCK_MOVE_WIDE != 0 {
                crate::host::Width::Double
            } else {
                crate::host::Width::Single
            },
            flags & BLOCK_MOVE_FILL != 0,
        );
    }
}

/// Steps 1-2 of the scan, for the scan entry point of compiled objects. The
/// symbol carries the layout tag (`layout::TAGGED_BEGIN_SCAN`).
///
/// # Safety
/// `mem` is null or the program's device image.
#[export_name = "ladder_rt_begin_scan_v1_137856"]
pub unsafe extern "C" fn ladder_rt_begin_scan(mem: *mut Memory, elapsed_ms: u32) {
    if let Some(mem) = unsafe { memory(mem) } {
        mem.begin_scan(elapsed_ms);
    }
}

/// `ladder_rt_block_move` flag: 32-bit units.
pub const BLOCK_MOVE_WIDE: u32 = 1;
/// `ladder_rt_block_move` flag: fill (FMOV) instead of move (BMOV).
pub const BLOCK_MOVE_FILL: u32 = 2;

/// The helpers by name with their addresses, for a JIT to resolve imports.
pub fn symbols() -> [(&'static str, *const u8); 9] {
    [
        ("ladder_rt_timer_coil", ladder_rt_timer_coil as *const u8),
        ("ladder_rt_counter_coil", ladder_rt_counter_coil as *const u8),
        ("ladder_rt_reset_timer", ladder_rt_reset_timer as *const u8),
        ("ladder_rt_reset_counter", ladder_rt_reset_counter as *const u8),
        (
            "ladder_rt_schedule_state_off",
            ladder_rt_schedule_state_off as *const u8,
        ),
        ("ladder_rt_block_move", ladder_rt_block_move as *const u8),
        (crate::layout::TAGGED_BEGIN_SCAN, ladder_rt_begin_scan as *const u8),
        ("ladder_begin_scan", crate::capi::ladder_begin_scan as *const u8),
        ("ladder_end_scan", crate::capi::ladder_end_scan as *const u8),
    ]
}
