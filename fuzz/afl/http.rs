//! AFL++ target: see `ladderc_fuzz::http`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::http(data));
}
