//! The front end of ladderc: from a file's bytes to a checked program.
//!
//! `source` (decoding, spans; a GX Developer project, `gxdev`, becomes an
//! IL listing there) → `syntax` (tokens, statements; plain IL or a
//! vendor export) → `check` (`CheckedProgram` in `program`, with
//! `diagnostics`). `isa` declares the instruction set once; everything
//! downstream asks it. `host_device` names the devices a host reads and
//! writes.
//!
//! Invariant: this crate knows nothing of how a program runs or is compiled
//! (no interpreter, IR, code generator, engine or server).

pub mod check;
pub mod diagnostics;
pub mod gxdev;
pub mod host_device;
pub mod isa;
pub mod logic;
pub mod program;
pub mod source;
pub mod syntax;
