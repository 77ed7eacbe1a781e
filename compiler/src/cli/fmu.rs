//! `ladderc build --emit fmu`: the program as an FMI 3.0 or 2.0
//! co-simulation FMU for this machine (the `ladder-fmu` crate), written
//! only when the whole FMU was built.

use super::output;
use super::status;
use clap::ValueEnum;
use ladder_fmu::{build, FmiVersion, FmuOptions};
use ladder_front::diagnostics::Shown;
use std::path::{Path, PathBuf};

/// The scan period an FMU starts with unless `--scan-ms` says.
pub const DEFAULT_SCAN_MS: u32 = 10;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FmiArg {
    /// FMI 3.0.
    #[value(name = "3")]
    Three,
    /// FMI 2.0.
    #[value(name = "2")]
    Two,
}

pub fn export(
    program: &Path,
    output: Option<PathBuf>,
    target: Option<&str>,
    fmi: FmiArg,
    scan_ms: u32,
    shown: Shown,
) -> u8 {
    if let Some(target) = target {
        say_err!("error: --target {target}: FMUs are built for this machine (x86_64 Linux) only");
        return status::UNUSABLE;
    }
    if !(1..=60_000).contains(&scan_ms) {
        say_err!("error: --scan-ms is 1 to 60000");
        return status::UNUSABLE;
    }
    if super::is_standard_stream(program) {
        say_err!("error: an FMU is built from a program file (its name names the model), not standard input");
        return status::UNUSABLE;
    }
    let output = match output {
        Some(path) if super::is_standard_stream(&path) => {
            say_err!("error: an FMU is a file: name it with -o");
            return status::UNUSABLE;
        }
        Some(path) => path,
        None => program.with_extension("fmu"),
    };
    // Checked before compiling: a refused output is refused however the
    // program is.
    let target = match output::prepare(&output, &[program]) {
        Ok(target) => target,
        Err(error) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    let checked = match super::compile_file(program, shown) {
        Ok(checked) => checked,
        Err(code) => return code,
    };
    let options = FmuOptions {
        fmi: match fmi {
            FmiArg::Three => FmiVersion::Three,
            FmiArg::Two => FmiVersion::Two,
        },
        period_ms: scan_ms,
        model_name: program
            .file_stem()
            .map_or_else(|| "program".to_string(), |stem| stem.to_string_lossy().into_owned()),
        source_text: String::from_utf8_lossy(&std::fs::read(program).unwrap_or_default()).into_owned(),
    };
    let bytes = match build(&checked, &options) {
        Ok(bytes) => bytes,
        Err(message) => {
            say_err!("error: {message}");
            return status::FAILED;
        }
    };
    if let Err((path, error)) = output::write_all_atomically(&[(&target, &bytes)]) {
        say_err!("error: cannot write {}: {error}", path.display());
        return status::FAILED;
    }
    status::OK
}
