//! The program on the controllers it usually lives on, emulated, through the
//! C back end and the system's cross compilers:
//!
//! - Cortex-M3: the traffic light and the GX Works2 sample built by
//!   `ladderc build --target thumbv7m-none-eabi` (arm-none-eabi-gcc),
//!   linked with the runtime built for that target and the Cortex-M example
//!   host (examples/cortex-m: SysTick as the scan period), run on QEMU's
//!   MPS2 AN385 board;
//! - 32-bit Arm Linux (armhf): the same programs built by `ladderc build
//!   --target armv7-unknown-linux-gnueabihf` (arm-linux-gnueabihf-gcc),
//!   linked statically with the example host and the runtime built for that
//!   target, run by `qemu-arm` (user-mode emulation).
//!
//! Every scan's outputs equal `ladderc run`'s. The tools come from Debian's
//! packages and rustup; where they cannot be installed the test says so and
//! skips.

use crate::common::tools::{
    build_for_target, cross_firmware_runtime_library, ensure, interpreter_csv, scratch, skip, workspace,
};
use std::path::Path;
use std::process::Command;

const TRIPLE: &str = "thumbv7m-none-eabi";
const ARMHF: &str = "armv7-unknown-linux-gnueabihf";

/// The programs each controller runs: (file, scans, scan period in ms).
const PROGRAMS: [(&str, u32, u32); 2] = [
    ("examples/traffic_light.il", 300, 100),
    ("testsuite/programs/gxworks2/gxworks2_fx2n_main.csv", 200, 10),
];

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Builds `program` into a firmware image for the Cortex-M3 host; returns
/// the image and its `size` line (text, data, bss).
fn firmware(program: &Path, dir: &Path, runtime: &Path, scans: u32, scan_ms: u32) -> (std::path::PathBuf, String) {
    let object = dir.join("program.o");
    let output = build_for_target(program, TRIPLE, &object);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let host = workspace().join("examples/cortex-m");
    let elf = dir.join("firmware.elf");
    let output = Command::new("arm-none-eabi-gcc")
        .args([
            "-mcpu=cortex-m3",
            "-mthumb",
            "-std=c99",
            "-O2",
            "-ffunction-sections",
            "-fdata-sections",
        ])
        .args(["-nostartfiles", "-specs=nosys.specs", "-Wall", "-Wextra", "-Werror"])
        .arg(format!("-DSCANS={scans}"))
        .arg(format!("-DSCAN_MS={scan_ms}"))
        .arg("-T")
        .arg(host.join("link.ld"))
        .arg("-I")
        .arg(workspace().join("runtime/include"))
        // program.h, which `ladderc build` wrote beside program.o.
        .arg("-I")
        .arg(dir)
        .arg(host.join("main.c"))
        .arg(host.join("startup.c"))
        .arg(&object)
        .arg(runtime)
        .args(["-lm", "-Wl,--gc-sections", "-Wl,--no-warn-execstack", "-o"])
        .arg(&elf)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "linking the firmware:\n{}",
        text(&output.stderr)
    );
    let size = Command::new("arm-none-eabi-size").arg(&elf).output().unwrap();
    (elf, text(&size.stdout).lines().nth(1).unwrap_or("").to_string())
}

/// Installs what a test needs when it is missing — the cross compiler with
/// its C library (`compiler_check`, a shell test, and `packages`) and the
/// emulator (program, package) — and builds the runtime for `triple`; the
/// runtime library, or `None` after saying why the test skips.
fn tools_and_runtime(
    test: &str,
    compiler_check: &str,
    packages: &[&str],
    (emulator, emulator_package): (&str, &str),
    triple: &str,
) -> Option<std::path::PathBuf> {
    let ready = ensure("sh", &["-c", compiler_check], packages)
        .and_then(|()| ensure(emulator, &["--version"], &[emulator_package]))
        .and_then(|()| cross_firmware_runtime_library(triple));
    ready.map_err(|why| skip(test, &why)).ok()
}

fn run_on_qemu(elf: &Path) -> String {
    let output = Command::new("timeout")
        .args([
            "120",
            "qemu-system-arm",
            "-M",
            "mps2-an385",
            "-nographic",
            "-monitor",
            "none",
            "-serial",
            "none",
        ])
        // Virtual time by instructions (2^5 ns each: about the board's
        // 25 MHz), and an idle CPU (the firmware's `wfi` between scans)
        // skips ahead to SysTick's next interrupt: 300 scans of 100 ms take
        // as long as their instructions, not 30 s. Each scan is told its
        // period (SCAN_MS), so the outputs do not depend on time.
        .args(["-icount", "shift=5,sleep=off"])
        .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(elf)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "qemu: {:?}\n{}",
        output.status,
        text(&output.stderr)
    );
    // Semihosting writes to the console: stdout or stderr, by QEMU version.
    let mut all = text(&output.stdout);
    all.push_str(&text(&output.stderr));
    all
}

#[test]
fn programs_run_on_an_emulated_cortex_m3_like_the_interpreter() {
    // The compiler and its C library (newlib: a compiler installed without
    // recommended packages has none, so both are checked).
    let Some(runtime) = tools_and_runtime(
        "programs_run_on_an_emulated_cortex_m3_like_the_interpreter",
        "test -e \"$(arm-none-eabi-gcc -print-file-name=nosys.specs)\"",
        &["gcc-arm-none-eabi", "libnewlib-arm-none-eabi"],
        ("qemu-system-arm", "qemu-system-arm"),
        TRIPLE,
    ) else {
        return;
    };
    let dir = scratch("cortex-m");
    for (name, scans, scan_ms) in PROGRAMS {
        let program = workspace().join(name);
        if !program.exists() {
            panic!("{} is missing", program.display());
        }
        let (elf, size) = firmware(&program, dir.path(), &runtime, scans, scan_ms);
        eprintln!("{name} on Cortex-M3 (text data bss ...): {size}");
        let printed = run_on_qemu(&elf);
        let csv: String = printed
            .lines()
            .filter(|line| line.starts_with("scan,") || line.starts_with(|c: char| c.is_ascii_digit()))
            .map(|line| format!("{line}\n"))
            .collect();
        assert_eq!(csv, interpreter_csv(&program, scans, scan_ms, &[]), "{name}");
    }
}

/// Builds `program` for armhf Linux and links it statically with the
/// example host and the runtime built for that target.
fn armhf_executable(program: &Path, dir: &Path, runtime: &Path) -> std::path::PathBuf {
    let object = dir.join("program-armhf.o");
    let output = build_for_target(program, ARMHF, &object);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let executable = dir.join("host-armhf");
    let output = Command::new("arm-linux-gnueabihf-gcc")
        .args(["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-static", "-I"])
        .arg(workspace().join("runtime/include"))
        .arg(workspace().join("examples/host/main.c"))
        .arg(&object)
        .arg(runtime)
        .args(["-lm", "-o"])
        .arg(&executable)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "linking the armhf host:\n{}",
        text(&output.stderr)
    );
    executable
}

#[test]
fn programs_run_on_emulated_armhf_linux_like_the_interpreter() {
    // The cross compiler with its C library, and user-mode QEMU.
    let Some(runtime) = tools_and_runtime(
        "programs_run_on_emulated_armhf_linux_like_the_interpreter",
        "test -e \"$(arm-linux-gnueabihf-gcc -print-file-name=libc.a)\"",
        &["gcc-arm-linux-gnueabihf", "libc6-dev-armhf-cross"],
        ("qemu-arm", "qemu-user"),
        ARMHF,
    ) else {
        return;
    };
    let dir = scratch("armhf");
    for (name, scans, scan_ms) in PROGRAMS {
        let program = workspace().join(name);
        let executable = armhf_executable(&program, dir.path(), &runtime);
        let machine = Command::new("file").arg(&executable).output().map(|o| text(&o.stdout));
        if let Ok(description) = machine {
            assert!(description.contains("ARM"), "not an Arm executable: {description}");
        }
        let output = Command::new("timeout")
            .args(["120", "qemu-arm"])
            .arg(&executable)
            .args([scans.to_string(), scan_ms.to_string()])
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "qemu-arm: {:?}\n{}",
            output.status,
            text(&output.stderr)
        );
        assert_eq!(
            text(&output.stdout),
            interpreter_csv(&program, scans, scan_ms, &[]),
            "{name} on armhf"
        );
    }
}
