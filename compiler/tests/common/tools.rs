//! External tools the native tests need, installed on demand.

use ladder_runtime::layout;
use ladder_runtime::Memory;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Whether `program --version` (or `args`) runs.
pub fn runs(program: &str, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Makes sure `program` runs, installing the Debian `packages` if needed
/// (the machine allows apt-get as root). `Err` says why it could not, for a
/// skip message.
pub fn ensure(program: &str, version_args: &[&str], packages: &[&str]) -> Result<(), String> {
    if runs(program, version_args) {
        return Ok(());
    }
    if !runs("apt-get", &["--version"]) {
        return Err(format!("{program} is not installed and apt-get is not available"));
    }
    // Serialise installs across test threads and processes.
    let _guard = INSTALL.lock().unwrap_or_else(|e| e.into_inner());
    if runs(program, version_args) {
        return Ok(());
    }
    // Wait for a package manager that another test process is running.
    let lock = ["-o", "DPkg::Lock::Timeout=300"];
    let update = Command::new("apt-get").args(lock).args(["update", "-qq"]).output();
    let install = Command::new("apt-get")
        .args(lock)
        .args(["install", "-y", "-qq", "--no-install-recommends"])
        .args(packages)
        .env("DEBIAN_FRONTEND", "noninteractive")
        .output();
    if runs(program, version_args) {
        return Ok(());
    }
    let why = match (update, install) {
        (_, Ok(output)) => String::from_utf8_lossy(&output.stderr)
            .lines()
            .last()
            .unwrap_or("")
            .to_string(),
        (_, Err(e)) => e.to_string(),
    };
    Err(format!(
        "{program} could not be installed ({}): {why}",
        packages.join(" ")
    ))
}

static INSTALL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Prints a skip message the test output shows (never a silent pass).
pub fn skip(test: &str, why: &str) {
    eprintln!("SKIPPED {test}: {why}");
    println!("SKIPPED {test}: {why}");
}

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .to_path_buf()
}

/// A fresh directory for one test's files.
pub fn scratch(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("ladderc-{name}-"))
        .tempdir()
        .expect("temp dir")
}

/// Runs `ladderc` with `args`; panics with its stderr when it fails.
pub fn ladderc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(args)
        .output()
        .expect("ladderc runs")
}

/// Links C sources and objects with the host's runtime library.
pub fn link_host(sources: &[&Path], output: &Path) {
    link_host_with(&[], sources, output);
}

/// `link_host` with extra compiler flags (`-DNAME`).
pub fn link_host_with(flags: &[&str], sources: &[&Path], output: &Path) {
    let compiler = ladder_engine::aot::toolchain::c_compiler().expect("a C compiler (gcc is part of every machine)");
    let runtime = ladder_engine::aot::toolchain::runtime_library().expect("the runtime library cargo built");
    let status = Command::new(compiler)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror"])
        .args(flags)
        .arg("-I")
        .arg(workspace().join("runtime/include"))
        .args(sources)
        .arg(runtime)
        .args(ladder_engine::aot::toolchain::NATIVE_LIBS)
        .arg("-o")
        .arg(output)
        .status()
        .expect("cc runs");
    assert!(status.success(), "linking {} failed", output.display());
}

/// `ladderc build PROGRAM --target TRIPLE -o OUTPUT`.
pub fn build_for_target(program: &Path, triple: &str, output: &Path) -> std::process::Output {
    ladderc(&[
        "build",
        program.to_str().unwrap(),
        "--target",
        triple,
        "-o",
        output.to_str().unwrap(),
    ])
}

/// The firmware build of the runtime (`no_std`, panics abort), built once per
/// test process by a nested cargo in its own target directory (so it never
/// waits on the lock of the build that runs the tests). `Err` says why not.
pub fn firmware_runtime_library() -> Result<PathBuf, String> {
    static LIBRARY: std::sync::OnceLock<Result<PathBuf, String>> = std::sync::OnceLock::new();
    LIBRARY.get_or_init(build_firmware_runtime).clone()
}

fn build_firmware_runtime() -> Result<PathBuf, String> {
    cargo_firmware_runtime(None)
}

/// `cargo build -p ladder-runtime --profile firmware --no-default-features`
/// (for `triple`, or the host) in its own target directory; the library.
fn cargo_firmware_runtime(triple: Option<&str>) -> Result<PathBuf, String> {
    let target = workspace().join("target/firmware-runtime");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let output = Command::new(cargo)
        .current_dir(workspace())
        .args(["build", "--quiet", "-p", "ladder-runtime", "--profile", "firmware"])
        .arg("--no-default-features")
        .args(triple.map(|triple| ["--target", triple]).iter().flatten())
        .arg("--target-dir")
        .arg(&target)
        .output()
        .map_err(|e| format!("cargo could not run: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "`cargo build -p ladder-runtime --profile firmware --no-default-features{}` failed:\n{}",
            triple.map_or(String::new(), |triple| format!(" --target {triple}")),
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    Ok(triple
        .map_or(target.clone(), |triple| target.join(triple))
        .join("firmware/libladder_runtime.a"))
}

/// Links C sources and objects with the firmware runtime library and the C
/// library only (`-nodefaultlibs -lc`: not even libgcc), without dropping
/// unused sections (a firmware's linker script may keep them all).
pub fn link_firmware_host(flags: &[&str], sources: &[&Path], library: &Path, output: &Path) {
    let compiler = ladder_engine::aot::toolchain::c_compiler().expect("a C compiler (gcc is part of every machine)");
    let status = Command::new(compiler)
        .args(["-std=c99", "-Os", "-Wall", "-Wextra", "-Werror"])
        .args(flags)
        .arg("-I")
        .arg(workspace().join("runtime/include"))
        .args(sources)
        .arg(library)
        .args(["-nodefaultlibs", "-lc", "-o"])
        .arg(output)
        .status()
        .expect("cc runs");
    assert!(status.success(), "linking {} with only libc failed", output.display());
}

/// `ladderc run --engine interp` in the CSV the example host prints
/// (`scan,Y0,...,Y7`), with `--set` for each of `sets`.
pub fn interpreter_csv(program: &Path, scans: u32, scan_ms: u32, sets: &[&str]) -> String {
    let (scans, scan_ms) = (scans.to_string(), scan_ms.to_string());
    let mut args = vec![
        "run",
        program.to_str().unwrap(),
        "--engine",
        "interp",
        "--format",
        "csv",
    ];
    args.extend([
        "--scans",
        &scans,
        "--scan-ms",
        &scan_ms,
        "--watch",
        "Y0,Y1,Y2,Y3,Y4,Y5,Y6,Y7",
    ]);
    for set in sets {
        args.extend(["--set", set]);
    }
    let output = ladderc(&args);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// `layout.h` for the emulation harness, from the runtime's layout.
pub fn layout_header() -> String {
    use std::mem::offset_of;
    let mut header = String::from("/* Generated by the ladderc tests. */\n");
    let fields = [
        ("HEADER", offset_of!(Memory, header)),
        ("X", offset_of!(Memory, x)),
        ("Y", offset_of!(Memory, y)),
        ("M", offset_of!(Memory, m)),
        ("S", offset_of!(Memory, s)),
        ("SM", offset_of!(Memory, sm)),
        ("D", offset_of!(Memory, d)),
        ("STL_PENDING_OFF", offset_of!(Memory, stl_pending_off)),
        ("INPUT_IMAGE", offset_of!(Memory, input_image)),
        ("OUTPUT_IMAGE", offset_of!(Memory, output_image)),
        ("STL_PENDING_ANY", offset_of!(Memory, stl_pending_any)),
        ("ELAPSED_MS", offset_of!(Memory, elapsed_ms)),
        ("SCAN_COUNT", offset_of!(Memory, scan_count)),
        ("CLOCK_MS", offset_of!(Memory, clock_ms)),
        ("LOOP_REPETITIONS", offset_of!(Memory, loop_repetitions)),
        ("PULSES_PENDING", offset_of!(Memory, pulses_pending)),
        ("INPUT_EDGES", offset_of!(Memory, input_edges)),
        ("CALENDAR_SECONDS", offset_of!(Memory, calendar_seconds)),
        ("CALENDAR_MS", offset_of!(Memory, calendar_ms)),
        ("CALENDAR_FLAGS", offset_of!(Memory, calendar_flags)),
        ("CALENDAR_CACHE_AT", offset_of!(Memory, calendar_cache_at)),
        ("CALENDAR_CACHE_TIME", offset_of!(Memory, calendar_cache_time)),
        ("CALENDAR_CACHE_YEAR", offset_of!(Memory, calendar_cache_year)),
        ("SD", offset_of!(Memory, sd)),
    ];
    for (name, offset) in fields {
        writeln!(header, "#define OFFSET_{name} {offset}ul").unwrap();
    }
    writeln!(header, "#define MEMORY_SIZE {}ul", layout::MEMORY_SIZE).unwrap();
    writeln!(header, "#define FULL_MAGIC {}u", layout::FULL_MAGIC).unwrap();
    writeln!(
        header,
        "#define LOOP_REPETITION_LIMIT {}u",
        ladder_runtime::special::LOOP_REPETITION_LIMIT
    )
    .unwrap();
    writeln!(header, "#define LADDER_TAGGED_BEGIN_SCAN {}", layout::TAGGED_BEGIN_SCAN).unwrap();
    writeln!(header, "#define LADDER_TAGGED_END_SCAN {}", layout::TAGGED_END_SCAN).unwrap();
    use ladder_runtime::MachineUse;
    for (name, part) in [
        ("SYSTEM_RELAYS", MachineUse::SYSTEM_RELAYS),
        ("CLOCK_RELAYS", MachineUse::CLOCK_RELAYS),
        ("CALENDAR", MachineUse::CALENDAR),
        ("SCAN_TIME", MachineUse::SCAN_TIME),
        ("HIGH_SPEED", MachineUse::HIGH_SPEED),
        ("ALARMS", MachineUse::ALARMS),
    ] {
        writeln!(header, "#define MACHINE_{name} {}u", part.bits()).unwrap();
    }
    header
}

/// The interpreter's digests, in the driver's format.
pub fn interpreter_digests(program: &Path, scans: u32) -> String {
    let source = ladder_front::source::SourceFile::read(program).unwrap();
    let (checked, diagnostics) = ladder_front::check::compile_source(&source);
    let checked = checked.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let interpreter = ladder_interp::Interpreter::new(&checked);
    // The parts of the machine the built object's scan keeps.
    let lowered = ladder_engine::pipeline::Lowered::new(&checked);
    let machine = ladder_ir::image::machine_use(&checked, lowered.ir(), &[]);
    let mut mem = Memory::new_boxed();
    let mut out = String::new();
    for scan in 1..=scans {
        let pattern = scan.wrapping_mul(2654435761) >> 13;
        for x in 0..8 {
            mem.input_image[x] = ((pattern >> x) & 1) as u8;
        }
        interpreter.scan_using(&mut mem, 10, machine);
        let hash = bytemuck::bytes_of(&*mem).iter().fold(0xcbf29ce484222325u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x100000001b3)
        });
        writeln!(out, "{scan} {hash:016x}").unwrap();
    }
    out
}

/// Makes sure Python 3 can import `module`, installing `package` from PyPI
/// if needed (and Python itself from Debian's packages). `Err` says why it
/// could not, for a skip message.
pub fn ensure_python_module(module: &str, package: &str) -> Result<(), String> {
    ensure("python3", &["--version"], &["python3", "python3-pip"])?;
    let imports = || runs("python3", &["-c", &format!("import {module}")]);
    if imports() {
        return Ok(());
    }
    let _guard = INSTALL.lock().unwrap_or_else(|e| e.into_inner());
    if !runs("python3", &["-m", "pip", "--version"]) {
        ensure("pip3", &["--version"], &["python3-pip"])?;
    }
    let mut last = String::new();
    for extra in [
        &[][..],
        &["--break-system-packages"][..],
        &["--user", "--break-system-packages"][..],
    ] {
        if imports() {
            break;
        }
        let output = Command::new("python3")
            .args(["-m", "pip", "install", "-q", package])
            .args(extra)
            .output();
        last = match output {
            Ok(output) => String::from_utf8_lossy(&output.stderr)
                .lines()
                .last()
                .unwrap_or("")
                .to_string(),
            Err(e) => e.to_string(),
        };
    }
    if imports() {
        Ok(())
    } else {
        Err(format!(
            "the Python module {module} could not be installed (pip install {package}): {last}"
        ))
    }
}

/// The firmware build of the runtime for a Rust target (`thumbv7m-none-eabi`),
/// adding the target's standard library with rustup when it is missing (a
/// download from the Rust project's distribution server). `Err` says why it
/// could not, for a skip message.
pub fn cross_firmware_runtime_library(triple: &str) -> Result<PathBuf, String> {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string());
    let installed = Command::new(&rustc)
        .args(["--print", "target-libdir", "--target", triple])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
        .is_some_and(|dir| dir.read_dir().is_ok_and(|mut d| d.next().is_some()));
    if !installed {
        let _guard = INSTALL.lock().unwrap_or_else(|e| e.into_inner());
        let toolchain = std::env::var("RUSTUP_TOOLCHAIN").ok();
        let mut rustup = Command::new("rustup");
        rustup.args(["target", "add", triple]);
        if let Some(toolchain) = toolchain {
            rustup.args(["--toolchain", &toolchain]);
        }
        match rustup.output() {
            Ok(output) if output.status.success() => {}
            Ok(output) => {
                return Err(format!(
                    "`rustup target add {triple}` failed: {}",
                    String::from_utf8_lossy(&output.stderr).lines().last().unwrap_or("")
                ))
            }
            Err(e) => return Err(format!("rustup is not available to add {triple}: {e}")),
        }
    }
    cargo_firmware_runtime(Some(triple))
}
