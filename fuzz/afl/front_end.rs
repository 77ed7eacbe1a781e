//! AFL++ target: see `ladderc_fuzz::front_end`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::front_end(data));
}
