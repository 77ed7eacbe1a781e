//! AFL++ target: see `ladderc_fuzz::pipeline`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::pipeline(data));
}
