//! AFL++ target: see `ladderc_fuzz::gx_developer`.

fn main() {
    afl::fuzz!(|data: &[u8]| ladderc_fuzz::gx_developer(data));
}
