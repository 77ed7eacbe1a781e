//! ladderc: a compiler for Mitsubishi-FX/Wecon-style PLC instruction lists.
//!
//! The pipeline, one module per stage:
//! `source` → `syntax` (tokens, statements with spans) → `check`
//! (`CheckedProgram`) → `interp` (reference interpreter).

pub mod aot;
pub mod cback;
pub mod check;
pub mod cli;
pub mod codegen;
pub mod diagnostics;
pub mod engine;
pub mod host_device;
pub mod image;
pub mod interp;
pub mod ir;
pub mod isa;
pub mod ladder;
pub mod lower;
pub mod pipeline;
pub mod program;
pub mod scenario;
pub mod serve;
pub mod source;
pub mod syntax;
pub mod waveform;
