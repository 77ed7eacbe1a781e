//! `ladderc check`: diagnostics only.

use super::status;
use std::path::Path;

pub fn run(program: &Path) -> u8 {
    match super::compile_file(program) {
        Ok(_) => status::OK,
        Err(code) => code,
    }
}
