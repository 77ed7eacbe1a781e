//! cargo-fuzz target: see `ladderc_fuzz::melsec`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::melsec(data));
