//! The ahead-of-time engine: the program compiled to an object file, linked
//! with the runtime library into a host executable by the system C compiler,
//! and driven through the C API as a firmware host would.

mod engine;
pub mod toolchain;

pub use engine::AotEngine;
