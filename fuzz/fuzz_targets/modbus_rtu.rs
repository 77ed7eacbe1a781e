//! cargo-fuzz target: see `ladderc_fuzz::modbus_rtu`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ladderc_fuzz::modbus_rtu(data));
