//! The native engines against the reference interpreter on random
//! programs (seeded from the commit; see `common::differential`).

#[path = "../common/mod.rs"]
mod common;

mod differential;
