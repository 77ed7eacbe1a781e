//! The C back end as a user meets it: `ladderc build --emit c` for every
//! program of the test suite and the examples compiles warning-free with
//! `-std=c99 -pedantic -Wall -Wextra -Werror` (gcc, and clang where it is
//! installed), and the example host built from the C file prints what the
//! interpreter prints, also with every run-time index out of range under a
//! guarded image. (The differential test runs the C route on every random
//! program.)

use crate::common;

use crate::common::tools::{build_for_target, interpreter_csv, ladderc, link_host_with, scratch, skip, workspace};
use std::path::{Path, PathBuf};
use std::process::Command;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Every program file the test suite and the examples hold.
fn programs() -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![workspace().join("testsuite/programs"), workspace().join("examples")];
    while let Some(dir) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "il" || e == "csv") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

fn emit_c(program: &Path, output: &Path) -> bool {
    let result = ladderc(&[
        "build",
        program.to_str().unwrap(),
        "--emit",
        "c",
        "-o",
        output.to_str().unwrap(),
    ]);
    result.status.success()
}

#[test]
fn generated_c_compiles_without_warnings_on_gcc_and_clang() {
    let dir = scratch("c-warnings");
    let mut compilers = vec!["gcc"];
    if Command::new("clang")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
    {
        compilers.push("clang");
    } else {
        skip(
            "generated_c_compiles_without_warnings_on_gcc_and_clang (clang)",
            "clang is not installed",
        );
    }
    let mut compiled = 0;
    for (i, program) in programs().iter().enumerate() {
        let c = dir.path().join(format!("p{i}.c"));
        // Programs that do not check (fixtures of diagnostics) have no C.
        if !emit_c(program, &c) {
            assert!(!c.exists(), "a failed build wrote {}", c.display());
            continue;
        }
        for compiler in &compilers {
            let output = Command::new(compiler)
                .args(["-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror", "-O2", "-c"])
                .arg(&c)
                .arg("-o")
                .arg(dir.path().join(format!("p{i}.o")))
                .output()
                .unwrap();
            assert!(
                output.status.success(),
                "{compiler} on the C of {}:\n{}",
                program.display(),
                text(&output.stderr)
            );
        }
        compiled += 1;
    }
    assert!(compiled >= 15, "only {compiled} programs compiled");
}

/// The example host with the program's C file instead of its object.
fn c_host(flags: &[&str], program: &Path, dir: &Path) -> PathBuf {
    let c = dir.join("program.c");
    assert!(emit_c(program, &c));
    let host = dir.join("host");
    link_host_with(flags, &[&workspace().join("examples/host/main.c"), &c], &host);
    host
}

#[test]
fn the_c_route_runs_the_traffic_light_like_the_interpreter() {
    let dir = scratch("c-host");
    let program = workspace().join("examples/traffic_light.il");
    let host = c_host(&["-O2"], &program, dir.path());
    let output = Command::new(&host).args(["300", "100"]).output().unwrap();
    assert!(output.status.success());
    assert_eq!(text(&output.stdout), interpreter_csv(&program, 300, 100, &[]));
}

#[test]
fn the_c_route_never_touches_memory_outside_the_image() {
    let dir = scratch("c-guarded");
    let program = workspace().join("testsuite/programs/offsets_out_of_range.il");
    let host = c_host(&["-O2", "-DLADDER_HOST_GUARDED"], &program, dir.path());
    // Index registers swept over their whole range (as the object-file test does).
    let sweep = ["300", "10", "X0=1"];
    let output = Command::new(&host).args(sweep).output().unwrap();
    assert!(
        output.status.success(),
        "the host faulted ({:?}):\n{}",
        output.status,
        text(&output.stderr)
    );
    assert_eq!(text(&output.stdout), interpreter_csv(&program, 300, 10, &["X0=1"]));
}

/// A target Cranelift lacks: with the cross compiler, an object for that
/// CPU (installed from Debian's packages when missing); the C file and the
/// command that builds it where there is none.
#[test]
fn thirty_two_bit_targets_go_through_the_c_back_end() {
    let dir = scratch("c-targets");
    let program = workspace().join("examples/traffic_light.il");
    let object = dir.path().join("m3.o");
    match common::tools::ensure(
        "arm-none-eabi-gcc",
        &["--version"],
        &["gcc-arm-none-eabi", "libnewlib-arm-none-eabi"],
    ) {
        Ok(()) => {
            let output = build_for_target(&program, "thumbv7m-none-eabi", &object);
            assert!(output.status.success(), "{}", text(&output.stderr));
            let bytes = std::fs::read(&object).unwrap();
            let file = object::File::parse(&*bytes).expect("an object file");
            assert_eq!(file.architecture(), object::Architecture::Arm, "a Cortex-M object");
            use object::{Object as _, ObjectSymbol as _};
            assert!(
                file.symbols()
                    .any(|s| s.name() == Ok("ladder_program_scan") && s.is_definition()),
                "the entry point is defined"
            );
        }
        Err(why) => skip(
            "thirty_two_bit_targets_go_through_the_c_back_end (Cortex-M object)",
            &why,
        ),
    }
    // A triple whose compiler this machine lacks (no RISC-V toolchain is
    // installed here): the C file and how to build it.
    if ["riscv64-unknown-elf-gcc", "riscv32-unknown-elf-gcc"]
        .iter()
        .any(|c| Command::new(c).arg("--version").output().is_ok())
    {
        skip(
            "thirty_two_bit_targets_go_through_the_c_back_end (no-compiler case)",
            "a RISC-V compiler is installed",
        );
        return;
    }
    // The object asked for is not made: status 1, and an older object is
    // left as it was (a build script must not link it as this program's).
    let requested = dir.path().join("rv.o");
    std::fs::write(&requested, b"an older object").unwrap();
    let output = build_for_target(&program, "riscv32imac-unknown-none-elf", &requested);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("-march=rv32imac"), "{stderr}");
    assert!(stderr.contains("was not built"), "{stderr}");
    assert_eq!(std::fs::read(&requested).unwrap(), b"an older object");
    let c = std::fs::read_to_string(dir.path().join("rv.c")).expect("the C file");
    assert!(c.contains("void ladder_program_scan(LadderMemory *mem, uint32_t elapsed_ms)"));
    // Again: the C file ladderc wrote is replaced. One it did not write is not.
    let output = build_for_target(&program, "riscv32imac-unknown-none-elf", &requested);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    let mine = dir.path().join("mine.o");
    std::fs::write(dir.path().join("mine.c"), "int mine(void) { return 42; }\n").unwrap();
    let output = build_for_target(&program, "riscv32imac-unknown-none-elf", &mine);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert!(
        text(&output.stderr).contains("not written by ladderc"),
        "{}",
        text(&output.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("mine.c")).unwrap(),
        "int mine(void) { return 42; }\n"
    );
    assert!(!dir.path().join("mine.h").exists(), "nothing written beside it");
}

/// Timers are calls of the runtime on a microcontroller (flash is short
/// there, a call cheap) and code of their own everywhere else; the C says
/// which (`--emit c` needs no cross compiler).
#[test]
fn timers_call_the_runtime_only_on_microcontrollers() {
    let dir = scratch("c-coils");
    let program = workspace().join("examples/traffic_light.il");
    for (target, calls) in [
        (Some("thumbv7m-none-eabi"), true),
        (Some("riscv32imac-unknown-none-elf"), true),
        (Some("armv7-unknown-linux-gnueabihf"), false),
        (None, false),
    ] {
        let c = dir.path().join(format!("{}.c", target.unwrap_or("host")));
        let mut args = vec![
            "build",
            program.to_str().unwrap(),
            "--emit",
            "c",
            "-o",
            c.to_str().unwrap(),
        ];
        args.extend(target.iter().flat_map(|target| ["--target", *target]));
        let result = ladderc(&args);
        assert!(
            result.status.success(),
            "{target:?}: {}",
            String::from_utf8_lossy(&result.stderr)
        );
        let source = std::fs::read_to_string(&c).unwrap();
        let called = source.contains("ladder_rt_timer_coil((LadderMemory *)m");
        assert_eq!(called, calls, "{target:?}: timers called: {called}");
        // Inline, the timers keep their state in the image themselves.
        assert_eq!(source.contains("TimerCoilWasOn"), !calls, "{target:?}");
    }
}
