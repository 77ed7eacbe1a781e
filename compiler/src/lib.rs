//! ladderc: a compiler for Mitsubishi-FX/Wecon-style PLC instruction lists.
//!
//! This crate is the command line (`cli`, one module per command) over the
//! layered crates: `ladder-front` (source → checked program),
//! `ladder-interp` (the reference interpreter), `ladder-ir` (lowering, IR
//! passes, the image), `ladder-codegen` (Cranelift) and `ladder-cback`
//! (portable C), `ladder-diagram` (the ladder diagram), `ladder-engine`
//! (engines, the build pipeline, scenarios) and `ladder-serve` (the soft
//! PLC). docs/architecture.md draws the layers.

pub mod cli;
