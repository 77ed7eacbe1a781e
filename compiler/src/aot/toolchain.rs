//! What building a native host needs: a C compiler and the runtime's static
//! library, found on this machine.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The C header of the runtime, as built into this ladderc.
pub const RUNTIME_HEADER: &str = include_str!("../../../runtime/include/ladder_runtime.h");

/// System libraries the Rust runtime library needs on Linux.
pub const NATIVE_LIBS: &[&str] = &["-lgcc_s", "-lutil", "-lrt", "-lpthread", "-lm", "-ldl", "-lc"];

/// The C compiler: `$CC`, else `cc`, if it runs.
pub fn c_compiler() -> Result<String, String> {
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
    match Command::new(&compiler).arg("--version").output() {
        Ok(output) if output.status.success() => Ok(compiler),
        _ => Err(format!("no C compiler found (tried `{compiler}`; set CC)")),
    }
}

/// The runtime static library: `$LADDERC_RUNTIME_LIB`, else the newest
/// next to this executable as cargo builds it (`libladder_runtime.a` or
/// `deps/libladder_runtime-*.a`: `cargo test` rebuilds only the latter, so
/// an older `libladder_runtime.a` from a `cargo build` must not win).
pub fn runtime_library() -> Result<PathBuf, String> {
    if let Some(path) = std::env::var_os("LADDERC_RUNTIME_LIB") {
        let path = PathBuf::from(path);
        return if path.is_file() {
            Ok(path)
        } else {
            Err(format!("LADDERC_RUNTIME_LIB={} is not a file", path.display()))
        };
    }
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate ladderc: {e}"))?;
    let dir = exe.parent().unwrap_or(Path::new("."));
    let mut places = vec![dir.to_path_buf(), dir.join("deps")];
    if let Some(parent) = dir.parent() {
        places.extend([parent.to_path_buf(), parent.join("deps")]);
    }
    let newest = places
        .iter()
        .filter_map(|place| std::fs::read_dir(place).ok())
        .flatten()
        .filter_map(Result::ok)
        .filter(|entry| {
            let name = entry.file_name().to_string_lossy().into_owned();
            name == "libladder_runtime.a" || (name.starts_with("libladder_runtime-") && name.ends_with(".a"))
        })
        .filter_map(|entry| Some((entry.metadata().ok()?.modified().ok()?, entry.path())))
        .max();
    newest.map(|(_, path)| path).ok_or_else(|| {
        "the runtime library libladder_runtime.a was not found next to ladderc; \
         build it with `cargo build --release -p ladder-runtime` or set LADDERC_RUNTIME_LIB"
            .to_string()
    })
}

/// Compiles and links `sources` (C files and objects) with the runtime into
/// `output`, with the runtime header available as `ladder_runtime.h`.
pub fn link_host(
    compiler: &str,
    work: &Path,
    sources: &[PathBuf],
    runtime: &Path,
    output: &Path,
) -> Result<(), String> {
    std::fs::write(work.join("ladder_runtime.h"), RUNTIME_HEADER).map_err(|e| e.to_string())?;
    let result = Command::new(compiler)
        .args(["-std=c99", "-O2"])
        .arg("-I")
        .arg(work)
        .args(sources)
        .arg(runtime)
        .args(NATIVE_LIBS)
        .arg("-o")
        .arg(output)
        .output()
        .map_err(|e| format!("cannot run {compiler}: {e}"))?;
    if result.status.success() {
        Ok(())
    } else {
        Err(format!(
            "linking the host failed:\n{}",
            String::from_utf8_lossy(&result.stderr)
        ))
    }
}
