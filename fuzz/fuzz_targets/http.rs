//! cargo-fuzz target: see `ladderc_fuzz::http`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::http(data));
