//! AFL++ target: see `ladderc_fuzz::modbus`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::modbus(data));
}
