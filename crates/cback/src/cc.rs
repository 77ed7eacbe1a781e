//! Running the system's C compiler: the one place ladderc starts it. Its
//! callers are the C route's cross targets (`targets.rs`), the native hosts
//! the `aot` and `c` engines link, and the FMU's shared library (those two
//! through `ladder_engine::aot::toolchain`, which re-exports this module).
//! Each caller gives its own arguments and says what failed; the compiler's
//! own messages follow.

use std::process::Command;

/// Whether `compiler` runs on this machine: `compiler --version` succeeds.
pub fn runs(compiler: &str) -> bool {
    run(compiler, "", |cc| {
        cc.arg("--version");
    })
    .is_ok()
}

/// Runs `compiler` with what `setup` gives it (arguments, a working
/// folder). An error says `cannot run {compiler}: ...` when it could not be
/// started, else `failed` and then what the compiler wrote to its standard
/// error.
pub fn run(compiler: &str, failed: &str, setup: impl FnOnce(&mut Command)) -> Result<(), String> {
    let mut command = Command::new(compiler);
    setup(&mut command);
    let output = command.output().map_err(|e| format!("cannot run {compiler}: {e}"))?;
    if output.status.success() {
        Ok(())
    } else {
        Err(format!("{failed}:\n{}", String::from_utf8_lossy(&output.stderr)))
    }
}
