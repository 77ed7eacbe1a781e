//! What building a native host needs: a C compiler and the runtime's static
//! library, found on this machine. The compiler runs through `cc` (the C
//! back end's), re-exported here for the FMU.

pub use ladder_cback::cc;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The C header of the runtime, as built into this ladderc.
pub const RUNTIME_HEADER: &str = include_str!("../../../../runtime/include/ladder_runtime.h");

/// System libraries the Rust runtime library needs on Linux.
pub const NATIVE_LIBS: &[&str] = &["-lgcc_s", "-lutil", "-lrt", "-lpthread", "-lm", "-ldl", "-lc"];

/// The C compiler: `$CC`, else `cc`, if it runs. Found once per process (a
/// scenario run starts an engine per scenario, and each asked again); a
/// failure is not kept, so a compiler installed meanwhile is found.
pub fn c_compiler() -> Result<String, String> {
    static FOUND: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    if let Some(compiler) = FOUND.get() {
        return Ok(compiler.clone());
    }
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
    if cc::runs(&compiler) {
        Ok(FOUND.get_or_init(|| compiler).clone())
    } else {
        Err(format!("no C compiler found (tried `{compiler}`; set CC)"))
    }
}

/// The runtime static library: `$LADDERC_RUNTIME_LIB`, else the newest
/// next to this executable as cargo builds it (`libladder_runtime.a` or
/// `deps/libladder_runtime-*.a`: `cargo test` rebuilds only the latter, so
/// an older `libladder_runtime.a` from a `cargo build` must not win).
/// Found once per process: cargo's `deps` folder holds thousands of files,
/// and a scenario run asks once per scenario and engine (a failure is not
/// kept, so a library built meanwhile is found).
pub fn runtime_library() -> Result<PathBuf, String> {
    static FOUND: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    if let Some(path) = FOUND.get() {
        return Ok(path.clone());
    }
    let path = find_runtime_library()?;
    Ok(FOUND.get_or_init(|| path).clone())
}

fn find_runtime_library() -> Result<PathBuf, String> {
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
/// `output`, with the runtime header available as `ladder_runtime.h`. The
/// runtime comes from its shared twin where one can be made
/// (`shared_runtime`), else from the archive.
pub fn link_host(
    compiler: &str,
    work: &Path,
    sources: &[PathBuf],
    runtime: &Path,
    output: &Path,
) -> Result<(), String> {
    std::fs::write(work.join("ladder_runtime.h"), RUNTIME_HEADER).map_err(|e| e.to_string())?;
    let library = shared_runtime(compiler, runtime).unwrap_or_else(|| runtime.to_path_buf());
    cc::run(compiler, "linking the host failed", |cc| {
        cc.args(["-std=c99", "-O2"])
            .args(fast_linker(compiler))
            .arg("-I")
            .arg(work)
            .args(sources)
            .arg(library)
            .args(NATIVE_LIBS)
            .arg("-o")
            .arg(output);
    })
}

/// The runtime archive as a shared library, made once beside it and kept
/// (named by the archive's size and time, so a rebuilt runtime gets its
/// own): a host per scenario and engine then links in a fraction of the
/// time it takes to pull the whole archive, std and all, into each. The
/// host records the library's path and loads it from there. `None` where
/// one cannot be made (a folder ladderc may not write, a compiler that
/// cannot link a shared library): hosts link the archive.
pub fn shared_runtime(compiler: &str, runtime: &Path) -> Option<PathBuf> {
    type Made = std::collections::HashMap<PathBuf, Option<PathBuf>>;
    static MADE: std::sync::Mutex<Option<Made>> = std::sync::Mutex::new(None);
    let mut made = MADE.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    made.get_or_insert_with(Default::default)
        .entry(runtime.to_path_buf())
        .or_insert_with(|| make_shared_runtime(compiler, runtime))
        .clone()
}

fn make_shared_runtime(compiler: &str, runtime: &Path) -> Option<PathBuf> {
    if std::env::var("LADDERC_LINKER").is_ok_and(|v| v == "default") {
        return None;
    }
    let metadata = std::fs::metadata(runtime).ok()?;
    let modified = metadata.modified().ok()?.duration_since(std::time::UNIX_EPOCH).ok()?;
    let stamp = format!("{:x}-{:x}", metadata.len(), modified.as_nanos());
    let dir = runtime.canonicalize().ok()?.parent()?.to_path_buf();
    let shared = dir.join(format!("libladder_runtime_shared-{stamp}.so"));
    if shared.is_file() {
        return Some(shared);
    }
    // Made under a name of this process's own, then renamed into place: a
    // process that finds the name finds the whole library.
    let partial = dir.join(format!(
        ".libladder_runtime_shared-{stamp}.{}.partial",
        std::process::id()
    ));
    let made = cc::run(compiler, "making the shared runtime failed", |cc| {
        cc.args(fast_linker(compiler))
            .args(["-shared", "-o"])
            .arg(&partial)
            .arg("-Wl,--whole-archive")
            .arg(runtime)
            .arg("-Wl,--no-whole-archive")
            .args(NATIVE_LIBS);
    });
    if made.is_err() || std::fs::rename(&partial, &shared).is_err() {
        let _ = std::fs::remove_file(&partial);
        return None;
    }
    // Twins of runtimes rebuilt since are of no further use once no host
    // can still be starting with them (an hour on).
    let stale = |entry: &std::fs::DirEntry| {
        entry
            .metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|at| at.elapsed().ok())
            .is_some_and(|age| age > std::time::Duration::from_secs(3600))
    };
    if let Ok(entries) = std::fs::read_dir(&dir) {
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with("libladder_runtime_shared-") && entry.path() != shared && stale(&entry) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
    Some(shared)
}

/// The C compiler's flags for lld when this machine has it (on the PATH,
/// or in the Rust toolchain that built ladderc: `rustc --print sysroot`),
/// and a test link with it works; else none (the compiler's own linker).
/// A host links against the whole runtime archive, std and all: lld does
/// that in about a quarter of the time of GNU ld, and a scenario run links
/// a host per scenario and engine. `LADDERC_LINKER=default` keeps the
/// compiler's own linker. Decided once per process, with the first
/// compiler asked (a process uses one: `$CC` or `cc`).
pub fn fast_linker(compiler: &str) -> &'static [String] {
    static FLAGS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    FLAGS.get_or_init(|| {
        if std::env::var("LADDERC_LINKER").is_ok_and(|v| v == "default") {
            return Vec::new();
        }
        lld_candidates()
            .into_iter()
            .find(|flags| links_with(compiler, flags))
            .unwrap_or_default()
    })
}

fn lld_candidates() -> Vec<Vec<String>> {
    let mut candidates = vec![vec!["-fuse-ld=lld".to_string()]];
    let printed = |what: &str| {
        Command::new("rustc")
            .args(["--print", what])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    if let (Some(sysroot), Some(host)) = (printed("sysroot"), printed("host-tuple")) {
        let wrappers = Path::new(&sysroot).join("lib/rustlib").join(host).join("bin/gcc-ld");
        if wrappers.join("ld.lld").is_file() {
            candidates.push(vec![format!("-B{}", wrappers.display()), "-fuse-ld=lld".to_string()]);
        }
    }
    candidates
}

/// Whether `compiler` links a program that starts with `flags`.
fn links_with(compiler: &str, flags: &[String]) -> bool {
    let Ok(work) = tempfile::tempdir() else {
        return false;
    };
    let source = work.path().join("probe.c");
    if std::fs::write(&source, "int main(void) { return 0; }\n").is_err() {
        return false;
    }
    let program = work.path().join("probe");
    let linked = cc::run(compiler, "the probe did not link", |cc| {
        cc.args(flags).arg(&source).arg("-o").arg(&program);
    });
    linked.is_ok() && Command::new(&program).status().is_ok_and(|s| s.success())
}

/// The scenario host's C source compiled once per process (an object's
/// bytes), so that each scenario only links.
pub fn compiled_once(compiler: &str, name: &str, source: &str) -> Result<Vec<u8>, String> {
    type Compiled = std::collections::HashMap<(String, String), Result<Vec<u8>, String>>;
    static COMPILED: std::sync::Mutex<Option<Compiled>> = std::sync::Mutex::new(None);
    let mut compiled = COMPILED.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let key = (compiler.to_string(), name.to_string());
    compiled
        .get_or_insert_with(Default::default)
        .entry(key)
        .or_insert_with(|| {
            let work = tempfile::tempdir().map_err(|e| e.to_string())?;
            std::fs::write(work.path().join("ladder_runtime.h"), RUNTIME_HEADER).map_err(|e| e.to_string())?;
            let c = work.path().join(format!("{name}.c"));
            let object = work.path().join(format!("{name}.o"));
            std::fs::write(&c, source).map_err(|e| e.to_string())?;
            cc::run(compiler, &format!("compiling {name}.c failed"), |cc| {
                cc.args(["-std=c99", "-O2", "-c", "-I"])
                    .arg(work.path())
                    .arg(&c)
                    .arg("-o")
                    .arg(&object);
            })?;
            std::fs::read(&object).map_err(|e| e.to_string())
        })
        .clone()
}
