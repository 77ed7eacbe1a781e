//! `ladderc check`: diagnostics only.

use super::status;
use ladder_front::diagnostics::Shown;
use std::path::Path;

pub fn run(program: &Path, shown: Shown) -> u8 {
    match super::compile_file(program, shown) {
        Ok(_) => status::OK,
        Err(code) => code,
    }
}
