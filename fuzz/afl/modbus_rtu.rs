//! AFL++ target: see `ladderc_fuzz::modbus_rtu`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::modbus_rtu(data));
}
