//! cargo-fuzz target: see `ladderc_fuzz::gx_developer`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::gx_developer(data));
