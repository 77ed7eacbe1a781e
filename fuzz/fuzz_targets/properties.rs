//! cargo-fuzz target: see `ladderc_fuzz::properties`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::properties(data));
