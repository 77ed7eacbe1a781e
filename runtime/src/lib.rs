//! Runtime of ladderc programs: the device image, the scan sequence around the
//! program, forced I/O, and the timer/counter bookkeeping that the reference
//! interpreter and compiled code share.

pub mod capi;
pub mod compiled;
pub mod counter;
pub mod device;
pub mod force;
pub mod helpers;
pub mod host;
pub mod layout;
pub mod memory;
pub mod place;
pub mod scan;
pub mod special;
pub mod timer;

pub use device::{BitArea, TimerClass, WordArea};
pub use force::ForceError;
pub use host::{AccessError, Basic, BasicAccess, Device, Width};
pub use memory::Memory;
pub use place::Place;
pub use special::OperationError;
