//! The firmware-host flow end to end: `ladderc build`, link with the runtime
//! library and a C host using the header, run; plus memory safety under
//! valgrind and atomic output.

use crate::common::tools::{self, interpreter_csv, ladderc, link_host, link_host_with, scratch, workspace};
use std::path::Path;
use std::process::Command;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Builds `program` to an object in `dir` and links it with the example host.
fn example_host(program: &Path, dir: &Path) -> std::path::PathBuf {
    example_host_with(&[], program, dir)
}

fn example_host_with(flags: &[&str], program: &Path, dir: &Path) -> std::path::PathBuf {
    let object = dir.join("program.o");
    let output = ladderc(&["build", program.to_str().unwrap(), "-o", object.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let host = dir.join("host");
    link_host_with(flags, &[&workspace().join("examples/host/main.c"), &object], &host);
    host
}

#[test]
fn example_host_runs_the_traffic_light_like_the_interpreter() {
    let dir = scratch("host");
    let program = workspace().join("examples/traffic_light.il");
    let host = example_host(&program, dir.path());
    let output = Command::new(&host).args(["80", "100"]).output().unwrap();
    assert!(output.status.success());
    assert_eq!(text(&output.stdout), interpreter_csv(&program, 80, 100, &[]));
}

#[test]
fn example_host_passes_inputs() {
    let dir = scratch("inputs");
    let program = workspace().join("examples/motor_start_stop.il");
    let host = example_host(&program, dir.path());
    let output = Command::new(&host).args(["5", "10", "X1=1", "X3=1"]).output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let csv = text(&output.stdout);
    assert_eq!(csv, interpreter_csv(&program, 5, 10, &["X1=1", "X3=1"]));
    assert!(
        csv.lines().nth(1).unwrap().starts_with("1,1,0,1"),
        "forward runs:\n{csv}"
    );
}

#[test]
fn prefixes_let_two_programs_share_one_firmware() {
    let dir = scratch("prefix");
    let d = dir.path();
    for (name, prefix) in [("traffic_light", "traffic_"), ("motor_start_stop", "motor_")] {
        let source = workspace().join(format!("examples/{name}.il"));
        let object = d.join(format!("{name}.o"));
        let output = ladderc(&[
            "build",
            source.to_str().unwrap(),
            "-o",
            object.to_str().unwrap(),
            "--prefix",
            prefix,
        ]);
        assert!(output.status.success(), "{}", text(&output.stderr));
    }
    let main = d.join("two.c");
    std::fs::write(
        &main,
        r#"#include <stdio.h>
#include "ladder_runtime.h"
LADDER_DECLARE_PROGRAM(traffic_);
LADDER_DECLARE_PROGRAM(motor_);
static uint32_t a[LADDER_MEMORY_SIZE / 4 + 1], b[LADDER_MEMORY_SIZE / 4 + 1];
int main(void) {
    LadderMemory *traffic = ladder_init(a, sizeof a), *motor = ladder_init(b, sizeof b);
    ladder_set_input(motor, 1, 1);
    ladder_set_input(motor, 3, 1);
    for (int i = 0; i < 3; i++) { traffic_scan(traffic, 100); motor_scan(motor, 100); }
    printf("%d %d %d\n", ladder_get_output(traffic, 0), ladder_get_output(motor, 0), ladder_get_output(traffic, 2));
    return 0;
}
"#,
    )
    .unwrap();
    let host = d.join("two");
    link_host(
        &[&main, &d.join("traffic_light.o"), &d.join("motor_start_stop.o")],
        &host,
    );
    let output = Command::new(&host).output().unwrap();
    assert_eq!(text(&output.stdout), "1 1 0\n");
}

#[test]
fn failed_build_writes_nothing_and_removes_nothing() {
    let dir = scratch("atomic");
    let bad = dir.path().join("bad.il");
    std::fs::write(&bad, "LD X0\nOUT X1\n").unwrap();
    let object = dir.path().join("bad.o");
    let fresh = dir.path().join("fresh.o");
    std::fs::write(&object, b"an earlier object").unwrap();
    for output in [&object, &fresh] {
        let result = ladderc(&["build", bad.to_str().unwrap(), "-o", output.to_str().unwrap()]);
        assert_eq!(result.status.code(), Some(1));
        assert!(text(&result.stderr).contains("E0003"));
    }
    assert_eq!(std::fs::read(&object).unwrap(), b"an earlier object", "left as it was");
    assert!(!fresh.exists(), "no output for a failed build");
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["bad.il", "bad.o"], "no temporary files either");
}

/// 300 scans sweep every offset register across its whole range.
const SWEEP: [&str; 3] = ["300", "10", "X0=1"];

#[test]
fn host_under_valgrind_never_touches_memory_outside_the_image() {
    if let Err(why) = tools::ensure("valgrind", &["--version"], &["valgrind"]) {
        tools::skip("host_under_valgrind_never_touches_memory_outside_the_image", &why);
        return;
    }
    let dir = scratch("valgrind");
    let program = workspace().join("testsuite/programs/offsets_out_of_range.il");
    // The image on the heap, exactly sized, with wide redzones around it.
    let host = example_host_with(&["-DLADDER_HOST_HEAP"], &program, dir.path());
    let output = Command::new("valgrind")
        .args(["--error-exitcode=99", "--leak-check=no", "--redzone-size=4096"])
        .arg(&host)
        .args(SWEEP)
        .output()
        .unwrap();
    let report = text(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "valgrind found errors:\n{report}");
    assert!(report.contains("ERROR SUMMARY: 0 errors"), "{report}");
    assert!(
        report.contains("operation error 4085H"),
        "the host saw the recorded errors:\n{report}"
    );
}

#[test]
fn guarded_host_never_touches_memory_outside_the_image() {
    let dir = scratch("guarded");
    let program = workspace().join("testsuite/programs/offsets_out_of_range.il");
    let host = example_host_with(&["-DLADDER_HOST_GUARDED"], &program, dir.path());
    let output = Command::new(&host).args(SWEEP).output().unwrap();
    assert!(
        output.status.success(),
        "the host faulted ({:?}):\n{}",
        output.status,
        text(&output.stderr)
    );
    // Compiled code and interpreter agree on the whole sweep.
    let interp = interpreter_csv(&program, 300, 10, &["X0=1"]);
    assert_eq!(text(&output.stdout), interp);
}

/// SORT2, SORT, CRC, BCC, MEAN, ANS and ANR in a firmware build: the
/// program's object, the example host (static storage) and the `no_std`
/// runtime library link with the C library alone (`-nodefaultlibs -lc`), the
/// host needs no other shared library and prints what the interpreter prints;
/// a driver that hashes the whole image after every scan, linked the same
/// way, sees exactly the interpreter's image.
#[test]
fn firmware_host_runs_tables_checks_and_alarms_like_the_interpreter() {
    let test = "firmware_host_runs_tables_checks_and_alarms_like_the_interpreter";
    let library = match tools::firmware_runtime_library() {
        Ok(library) => library,
        Err(why) => return tools::skip(test, &why),
    };
    let dir = scratch("tables");
    let program = workspace().join("testsuite/programs/tables_and_alarms.il");
    let object = dir.path().join("program.o");
    let output = ladderc(&["build", program.to_str().unwrap(), "-o", object.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let host = dir.path().join("host");
    let main = workspace().join("examples/host/main.c");
    tools::link_firmware_host(&[], &[&main, &object], &library, &host);
    assert_eq!(shared_libraries(&host), ["libc.so.6"], "the host needs libc alone");
    eprintln!(
        "firmware runtime library {} bytes, example host with this program {} bytes",
        std::fs::metadata(&library).unwrap().len(),
        std::fs::metadata(&host).unwrap().len()
    );
    let output = Command::new(&host)
        .args(["120", "10", "X0=1", "X1=1"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let csv = text(&output.stdout);
    assert_eq!(csv, interpreter_csv(&program, 120, 10, &["X0=1", "X1=1"]));
    assert!(
        csv.lines().nth(4).unwrap().starts_with("4,1,"),
        "SORT2 done at scan 4:\n{csv}"
    );
    assert!(
        csv.lines().any(|l| l.split(',').nth(2) == Some("1")),
        "the alarm set SM248:\n{csv}"
    );

    std::fs::write(dir.path().join("layout.h"), tools::layout_header()).unwrap();
    let driver = dir.path().join("digest");
    let include = dir.path().display().to_string();
    tools::link_firmware_host(
        &["-I", &include, "-Wno-unused-parameter"],
        &[&workspace().join("testsuite/cross/image_digest.c"), &object],
        &library,
        &driver,
    );
    let output = Command::new(&driver).arg("300").output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    // The driver's input pattern does reach the interesting states.
    let seen = states_seen(&program, 300);
    assert_eq!(seen, [true; 4], "SORT2 done, S900 set, S900 reset by ANR, CRC computed");
    let expected = tools::interpreter_digests(&program, 300);
    let actual = text(&output.stdout);
    let first_difference = expected.lines().zip(actual.lines()).find(|(e, a)| e != a);
    assert!(
        first_difference.is_none() && expected.lines().count() == actual.lines().count(),
        "the compiled image differs from the interpreter's, first at {first_difference:?}"
    );
}

/// The shared libraries an executable names (`NEEDED` in its dynamic section).
fn shared_libraries(executable: &Path) -> Vec<String> {
    let output = Command::new("readelf")
        .arg("-d")
        .arg(executable)
        .output()
        .expect("readelf (binutils, installed with gcc) runs");
    text(&output.stdout)
        .lines()
        .filter(|line| line.contains("(NEEDED)"))
        .filter_map(|line| Some(line.split_once('[')?.1.trim_end_matches(']').to_string()))
        .collect()
}

/// Whether, under the digest driver's input pattern, SM229 turned ON, S900
/// turned ON, S900 turned OFF again, and D300 (the CRC) was written.
fn states_seen(program: &Path, scans: u32) -> [bool; 4] {
    let source = ladder_front::source::SourceFile::read(program).unwrap();
    let (checked, _) = ladder_front::check::compile_source(&source);
    let checked = checked.expect("the program compiles");
    let interpreter = ladder_interp::Interpreter::new(&checked);
    let mut mem = ladder_runtime::Memory::new_boxed();
    let mut seen = [false; 4];
    for scan in 1..=scans {
        let pattern = scan.wrapping_mul(2654435761) >> 13;
        for x in 0..8 {
            mem.input_image[x] = ((pattern >> x) & 1) as u8;
        }
        let alarm_before = mem.s[900];
        interpreter.scan(&mut mem, 10);
        seen[0] |= mem.sm[229] == 1;
        seen[1] |= mem.s[900] == 1;
        seen[2] |= alarm_before == 1 && mem.s[900] == 0;
        seen[3] |= mem.d[300] != 0;
    }
    seen
}

/// The C API as the header promises it, from C: a null image is ignored by
/// every function and by the compiled scan entry point; unknown kinds are
/// BAD_ARGUMENT, values that do not fit BAD_VALUE; an input written between
/// scans reaches X at the next input refresh.
#[test]
fn the_c_api_keeps_the_header_s_promises() {
    let dir = scratch("capi");
    let d = dir.path();
    let program = d.join("p.il");
    std::fs::write(&program, "LD X0\nOUT Y0\n").unwrap();
    let object = d.join("p.o");
    let output = ladderc(&["build", program.to_str().unwrap(), "-o", object.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let main = d.join("main.c");
    std::fs::write(
        &main,
        r#"#include <stdio.h>
#include "ladder_runtime.h"
LADDER_DECLARE_PROGRAM(ladder_program_);
static uint32_t storage[LADDER_MEMORY_SIZE / 4 + 1];
#define CHECK(e) do { if (!(e)) { printf("failed: %s\n", #e); return 1; } } while (0)
int main(void) {
    int32_t value = 0;
    ladder_program_scan(NULL, 10);
    CHECK(ladder_set_input(NULL, 0, 1) == LADDER_STATUS_BAD_ARGUMENT);
    CHECK(ladder_read(NULL, LADDER_DEVICE_D, 0, &value) == LADDER_STATUS_BAD_ARGUMENT);
    CHECK(ladder_force(NULL, LADDER_DEVICE_Y, 0, 1) == LADDER_STATUS_BAD_ARGUMENT);
    CHECK(ladder_get_output(NULL, 0) == -1);
    LadderMemory *mem = ladder_init(storage, sizeof storage);
    CHECK(mem != NULL);
    CHECK(ladder_force(mem, 99, 0, 1) == LADDER_STATUS_BAD_ARGUMENT);
    CHECK(ladder_unforce(mem, 99, 0) == LADDER_STATUS_BAD_ARGUMENT);
    CHECK(ladder_force(mem, LADDER_DEVICE_D, 0, 1) == LADDER_STATUS_NOT_FORCEABLE);
    CHECK(ladder_write(mem, LADDER_DEVICE_D, 0, 70000) == LADDER_STATUS_BAD_VALUE);
    CHECK(ladder_write(mem, LADDER_DEVICE_D, 0, -32768) == LADDER_STATUS_OK);
    CHECK(ladder_write(mem, LADDER_DEVICE_M, 0, 2) == LADDER_STATUS_BAD_VALUE);
    CHECK(ladder_set_input(mem, 0, 1) == LADDER_STATUS_OK);
    CHECK(ladder_read(mem, LADDER_DEVICE_X, 0, &value) == LADDER_STATUS_OK && value == 0);
    ladder_program_scan(mem, 10);
    CHECK(ladder_read(mem, LADDER_DEVICE_X, 0, &value) == LADDER_STATUS_OK && value == 1);
    CHECK(ladder_get_output(mem, 0) == 1);
    printf("ok\n");
    return 0;
}
"#,
    )
    .unwrap();
    let host = d.join("capi");
    link_host(&[&main, &object], &host);
    let output = Command::new(&host).output().unwrap();
    assert_eq!(text(&output.stdout), "ok\n", "{}", text(&output.stderr));
}
