//! Runtime of ladderc programs: the device image, the scan sequence around the
//! program, forced I/O, and the timer/counter bookkeeping that the reference
//! interpreter and compiled code share.
//!
//! Without the `std` feature (on by default) the crate is `no_std` and does not
//! allocate: that build is the static library a firmware links (with nothing
//! but libc, which the compiler's own `memcpy`/`memset` calls come from). The
//! `std` feature adds host conveniences: device names as strings, heap images,
//! the helper symbol list for a JIT and the C prototypes.

#![cfg_attr(not(any(feature = "std", test)), no_std)]

pub mod calendar;
pub mod capi;
pub mod compiled;
pub mod counter;
pub mod device;
mod facade;
pub mod force;
pub mod helpers;
pub mod host;
pub mod hsc;
pub mod image;
pub mod layout;
pub mod machine;
pub mod memory;
pub mod place;
pub mod pulse;
pub mod real;
pub mod scan;
pub mod special;
pub mod timer;

pub use device::{BitArea, TimerClass, Width, WordArea};
pub use force::ForceError;
pub use host::{AccessError, Basic, BasicAccess, Device};
pub use image::{AsImage, AsImageMut, Image, ImageMut, ImageRef};
pub use machine::MachineUse;
pub use memory::Memory;
pub use place::Place;
pub use special::OperationError;

/// A panic in the firmware library (an index the runtime's own checks should
/// have kept in range) stops the program at once: there is no unwinding and no
/// message without `std`, and continuing with a broken image would be worse.
#[cfg(not(any(feature = "std", test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    extern "C" {
        fn abort() -> !;
    }
    // SAFETY: `abort` from the C library takes no arguments and never returns.
    unsafe { abort() }
}

/// The precompiled `core` refers to the unwinder's personality routine in its
/// unwind tables. With `panic = "abort"` nothing unwinds, so it is never
/// called; defining it lets a firmware link without `--gc-sections` (the
/// symbol is otherwise undefined).
#[cfg(not(any(feature = "std", test)))]
#[no_mangle]
extern "C" fn rust_eh_personality() {}
