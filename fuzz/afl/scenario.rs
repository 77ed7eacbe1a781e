//! AFL++ target: see `ladderc_fuzz::scenario`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::scenario(data));
}
