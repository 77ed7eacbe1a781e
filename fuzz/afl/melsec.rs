//! AFL++ target: see `ladderc_fuzz::melsec`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::melsec(data));
}
