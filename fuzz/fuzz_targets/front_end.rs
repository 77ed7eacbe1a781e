//! cargo-fuzz target: see `ladderc_fuzz::front_end`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::front_end(data));
