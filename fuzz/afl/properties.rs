//! AFL++ target: see `ladderc_fuzz::properties`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::properties(data));
}
