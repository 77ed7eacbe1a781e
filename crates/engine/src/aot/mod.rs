//! The ahead-of-time engine: the program compiled to an object file, linked
//! with the runtime library into a host executable by the system C compiler,
//! and driven through the C API as a firmware host would; or the same with
//! the C back end's source in place of the object (the `c` engine).

mod engine;
pub mod toolchain;

pub use engine::{AotEngine, Route};
