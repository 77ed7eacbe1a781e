//! Instructions per scan on a Cortex-M3: the traffic light through the
//! firmware route (ladderc's C back end with a compact image, compiled by
//! `arm-none-eabi-gcc -O2`, linked with the runtime built for
//! `thumbv7m-none-eabi`), run by `qemu-system-arm` on Arm's MPS2 AN385 board
//! with one instruction per translation block and an execution log: the
//! instructions the firmware executes for 1,010 scans less those for 10,
//! divided by 1,000. A count, not a time, so it repeats exactly on any
//! machine.
//!
//! Skipped with the reason when the cross compiler, QEMU or Rust's
//! standard library for the target is not installed (Debian:
//! `gcc-arm-none-eabi qemu-system-arm`; `rustup target add
//! thumbv7m-none-eabi`).

use ladder_engine::pipeline::ImageRequest;
use ladder_front::check::compile_source;
use ladder_front::source::SourceFile;
use std::path::{Path, PathBuf};
use std::process::Command;

const TARGET: &str = "thumbv7m-none-eabi";
const PREFIX: &str = "ladder_program_";
/// The two runs' scans: their difference is what is counted.
const SCANS: [u32; 2] = [10, 1010];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn run(command: &mut Command, what: &str) -> Result<std::process::Output, String> {
    let output = command.output().map_err(|e| format!("{what} did not run: {e}"))?;
    if output.status.success() {
        Ok(output)
    } else {
        Err(format!("{what} failed:\n{}", String::from_utf8_lossy(&output.stderr)))
    }
}

/// The runtime for the Cortex-M3, built by a nested cargo in its own target
/// folder (the one the tests use).
fn runtime() -> Result<PathBuf, String> {
    let target = workspace().join("target/firmware-runtime");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    run(
        Command::new(cargo)
            .current_dir(workspace())
            .args(["build", "--quiet", "-p", "ladder-runtime", "--profile", "firmware"])
            .args(["--no-default-features", "--target", TARGET, "--target-dir"])
            .arg(&target),
        "building the runtime for thumbv7m-none-eabi (rustup target add thumbv7m-none-eabi)",
    )?;
    Ok(target.join(TARGET).join("firmware/libladder_runtime.a"))
}

/// The traffic light as C for a compact image, with its header, in `dir`,
/// its timers compiled as `coils` says.
fn program(dir: &Path, coils: ladder_ir::Coils) -> Result<PathBuf, String> {
    let path = workspace().join("examples/traffic_light.il");
    let source = SourceFile::read(&path).map_err(|e| e.to_string())?;
    let (checked, diagnostics) = compile_source(&source);
    let checked = checked.ok_or_else(|| format!("the traffic light does not compile: {diagnostics:?}"))?;
    let options = ladder_cback::COptions {
        prefix: PREFIX.to_string(),
        source_name: "traffic_light.il".to_string(),
        ..Default::default()
    };
    let built = ladder_engine::pipeline::Lowered::with_coils(&checked, coils)
        .c_source(&options, &ImageRequest::compact(Vec::new()));
    let header = ladder_ir::image::c_header(PREFIX, "traffic_light.il", built.layout.as_ref());
    std::fs::write(dir.join("program.h"), header).map_err(|e| e.to_string())?;
    let c = dir.join("program.c");
    std::fs::write(&c, built.output).map_err(|e| e.to_string())?;
    Ok(c)
}

/// The instructions QEMU executes for the firmware running `scans` scans.
fn instructions(dir: &Path, program: &Path, runtime: &Path, scans: u32) -> Result<u64, String> {
    let host = workspace().join("examples/cortex-m");
    let elf = dir.join(format!("count{scans}.elf"));
    run(
        Command::new("arm-none-eabi-gcc")
            .args(["-mcpu=cortex-m3", "-mthumb", "-std=c99", "-O2"])
            .args([
                "-ffunction-sections",
                "-fdata-sections",
                "-nostartfiles",
                "-specs=nosys.specs",
            ])
            .arg(format!("-DSCANS={scans}"))
            .arg("-DPROGRAM_HEADER=\"program.h\"")
            .arg("-T")
            .arg(host.join("link.ld"))
            .arg("-I")
            .arg(workspace().join("runtime/include"))
            .arg("-I")
            .arg(dir)
            .arg(workspace().join("benches/firmware/count_scans.c"))
            .arg(host.join("startup.c"))
            .arg(program)
            .arg(runtime)
            .args(["-lm", "-Wl,--gc-sections", "-Wl,--no-warn-execstack", "-o"])
            .arg(&elf),
        "arm-none-eabi-gcc (apt-get install gcc-arm-none-eabi)",
    )?;
    let log = dir.join(format!("count{scans}.log"));
    run(
        Command::new("timeout")
            .args(["300", "qemu-system-arm", "-M", "mps2-an385", "-nographic"])
            .args(["-monitor", "none", "-serial", "none"])
            .args(["-semihosting-config", "enable=on,target=native"])
            // One instruction per translation block, every block logged.
            .args(["-singlestep", "-d", "exec,nochain", "-D"])
            .arg(&log)
            .arg("-kernel")
            .arg(&elf),
        "qemu-system-arm (apt-get install qemu-system-arm)",
    )?;
    let text = std::fs::read_to_string(&log).map_err(|e| e.to_string())?;
    Ok(text.lines().filter(|line| line.starts_with("Trace ")).count() as u64)
}

fn main() {
    // `cargo bench` passes `--bench`; a filter that does not name this
    // benchmark skips it.
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if !args.is_empty() && !args.iter().any(|a| "firmware_scan".contains(a.as_str())) {
        return;
    }
    // What `--target thumbv7m-none-eabi` builds (timers calling the
    // runtime), and the same with the timers inline.
    let target = ladder_cback::targets::c_target(TARGET).map_or(ladder_ir::Coils::Calls, |target| target.coils);
    for (coils, what) in [
        (target, "as the target builds it"),
        (ladder_ir::Coils::Inline, "timers inline"),
    ] {
        let counted = (|| -> Result<(u64, u64), String> {
            let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
            let runtime = runtime()?;
            let program = program(dir.path(), coils)?;
            let few = instructions(dir.path(), &program, &runtime, SCANS[0])?;
            let many = instructions(dir.path(), &program, &runtime, SCANS[1])?;
            Ok((few, many))
        })();
        match counted {
            Ok((few, many)) => {
                let per_scan = (many - few) as f64 / f64::from(SCANS[1] - SCANS[0]);
                println!(
                    "firmware_scan: traffic light on a Cortex-M3 (C route, compact image, -O2, {what}): \
                     {per_scan:.1} instructions per scan"
                );
            }
            Err(why) => return println!("firmware_scan: skipped: {why}"),
        }
    }
}
