//! The program on the controller it usually lives on, emulated: the traffic
//! light and the GX Works2 sample built by `ladderc build --target
//! thumbv7m-none-eabi` (the C back end and arm-none-eabi-gcc), linked with
//! the runtime built for that target and the Cortex-M example host
//! (examples/cortex-m: SysTick as the scan period), run on QEMU's MPS2
//! AN385 board (Cortex-M3); every scan's outputs equal `ladderc run`'s.
//! The tools come from Debian's packages and rustup; where they cannot be
//! installed the test says so and skips.

mod common;

use common::tools::{cross_firmware_runtime_library, ensure, interpreter_csv, ladderc, scratch, skip, workspace};
use std::path::Path;
use std::process::Command;

const TRIPLE: &str = "thumbv7m-none-eabi";

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Builds `program` into a firmware image for the Cortex-M3 host; returns
/// the image and its `size` line (text, data, bss).
fn firmware(program: &Path, dir: &Path, runtime: &Path, scans: u32, scan_ms: u32) -> (std::path::PathBuf, String) {
    let object = dir.join("program.o");
    let output = ladderc(&[
        "build",
        program.to_str().unwrap(),
        "--target",
        TRIPLE,
        "-o",
        object.to_str().unwrap(),
    ]);
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
    let test = "programs_run_on_an_emulated_cortex_m3_like_the_interpreter";
    // The compiler and its C library (newlib: a compiler installed without
    // recommended packages has none, so both are checked).
    let newlib = "test -e \"$(arm-none-eabi-gcc -print-file-name=nosys.specs)\"";
    let tools = ensure("sh", &["-c", newlib], &["gcc-arm-none-eabi", "libnewlib-arm-none-eabi"])
        .and_then(|()| ensure("qemu-system-arm", &["--version"], &["qemu-system-arm"]));
    if let Err(why) = tools {
        skip(test, &why);
        return;
    }
    let runtime = match cross_firmware_runtime_library(TRIPLE) {
        Ok(runtime) => runtime,
        Err(why) => {
            skip(test, &why);
            return;
        }
    };
    let dir = scratch("cortex-m");
    for (name, scans, scan_ms) in [
        ("examples/traffic_light.il", 300, 100),
        ("testsuite/programs/gxworks2/gxworks2_fx2n_main.csv", 200, 10),
    ] {
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
