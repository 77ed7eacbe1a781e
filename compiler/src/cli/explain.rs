//! `ladderc explain CODE`.

use super::status;
use crate::diagnostics::Code;

pub fn run(code: &str) -> u8 {
    match code.parse::<Code>() {
        Ok(code) => {
            println!("{code}: {}\n\n{}", code.title(), code.explanation());
            status::OK
        }
        Err(()) => {
            eprintln!("error: unknown diagnostic code `{code}` (codes look like E0010 or W0002)");
            status::UNUSABLE
        }
    }
}
