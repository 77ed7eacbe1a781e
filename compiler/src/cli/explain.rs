//! `ladderc explain CODE`.

use super::status;
use ladder_front::diagnostics::Code;

/// `explain CODE`, or with no code every code with its title.
pub fn run(code: Option<&str>) -> u8 {
    let Some(code) = code else {
        for &code in Code::ALL {
            say!("{code}  {}", code.title());
        }
        say!("\n`ladderc explain CODE` explains one of them.");
        return status::OK;
    };
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
