//! `ladderc explain CODE`.

use super::status;
use crate::diagnostics::Code;

pub fn run(code: &str) -> u8 {
    match code.parse::<Code>() {
        Ok(code) => {
            say!("{code}: {}\n\n{}", code.title(), code.explanation());
            status::OK
        }
        Err(()) => {
            say_err!("error: unknown diagnostic code `{code}` (codes look like E0010 or W0002)");
            status::UNUSABLE
        }
    }
}
