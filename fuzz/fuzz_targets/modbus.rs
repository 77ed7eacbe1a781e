//! cargo-fuzz target: see `ladderc_fuzz::modbus`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::modbus(data));
