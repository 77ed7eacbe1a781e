//! Compact images as a user builds them: `ladderc build --image compact`
//! writes the object (Cranelift's) or the C, and beside it a header with the
//! image's size and every device's offset; the example host built with that
//! header runs the program like the interpreter, also on exactly the
//! image's bytes between inaccessible pages (a stray access faults); the
//! devices the host names are in the image; and a header ladderc did not
//! write is never replaced. (The differential test and `ladderc test
//! --engine c-compact` check compact images against the interpreter on
//! random programs and every scenario.)

use crate::common::tools::{interpreter_csv, ladderc, link_host_with, scratch, workspace};
use std::path::{Path, PathBuf};
use std::process::Command;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// How the program reaches the host.
#[derive(Clone, Copy, Debug)]
enum Route {
    /// Cranelift's object file.
    Object,
    /// The C back end's source.
    C,
}

/// `ladderc build PROGRAM --image compact` into `dir` (with `extra`
/// arguments); the output and the header ladderc wrote beside it.
fn build_compact(program: &Path, route: Route, dir: &Path, extra: &[&str]) -> (PathBuf, PathBuf) {
    let output = dir.join(match route {
        Route::Object => "program.o",
        Route::C => "program.c",
    });
    let mut args = vec![
        "build",
        program.to_str().unwrap(),
        "--image",
        "compact",
        "-o",
        output.to_str().unwrap(),
    ];
    if let Route::C = route {
        args.extend(["--emit", "c"]);
    }
    args.extend(extra);
    let result = ladderc(&args);
    assert!(result.status.success(), "{}", text(&result.stderr));
    let note = text(&result.stderr);
    assert!(note.contains("note: compact image: "), "{note}");
    let header = dir.join("program.h");
    assert!(header.exists(), "no header beside {}", output.display());
    (output, header)
}

/// `<PREFIX>IMAGE_SIZE` of a header.
fn image_size(header: &Path) -> u32 {
    let text = std::fs::read_to_string(header).unwrap();
    text.lines()
        .find_map(|line| line.strip_prefix("#define LADDER_PROGRAM_IMAGE_SIZE "))
        .and_then(|size| size.trim_end_matches('u').parse().ok())
        .unwrap_or_else(|| panic!("no image size in\n{text}"))
}

/// The example host linked with the program and its header.
fn host(program: &Path, header: &Path, dir: &Path, flags: &[&str]) -> PathBuf {
    let executable = dir.join("host");
    let include = format!("-I{}", dir.display());
    let program_header = format!("-DPROGRAM_HEADER=\"{}\"", header.file_name().unwrap().to_str().unwrap());
    let mut all = vec!["-O2", include.as_str(), program_header.as_str()];
    all.extend(flags);
    link_host_with(&all, &[&workspace().join("examples/host/main.c"), program], &executable);
    executable
}

#[test]
fn the_traffic_light_needs_a_few_hundred_bytes_and_runs_like_the_interpreter() {
    let program = workspace().join("examples/traffic_light.il");
    for route in [Route::Object, Route::C] {
        let dir = scratch("compact-traffic-light");
        let (output, header) = build_compact(&program, route, dir.path(), &[]);
        let size = image_size(&header);
        assert!(size < 400, "{route:?}: the traffic light's image is {size} bytes");
        let header_text = std::fs::read_to_string(&header).unwrap();
        for device in ["Y0", "Y2", "X0", "X1", "T0", "TN2", "S2"] {
            assert!(
                header_text.contains(&format!("#define LADDER_PROGRAM_{device} ")),
                "{device} is not named:\n{header_text}"
            );
        }
        let executable = host(&output, &header, dir.path(), &[]);
        let run = Command::new(&executable).args(["300", "100"]).output().unwrap();
        assert!(run.status.success(), "{}", text(&run.stderr));
        assert_eq!(text(&run.stdout), interpreter_csv(&program, 300, 100, &[]), "{route:?}");
    }
}

#[test]
fn compiled_code_never_touches_memory_outside_a_compact_image() {
    // Every run-time index out of range, swept over the index registers'
    // whole range, on exactly the image's bytes between inaccessible pages.
    let program = workspace().join("testsuite/programs/offsets_out_of_range.il");
    for route in [Route::Object, Route::C] {
        let dir = scratch("compact-guarded");
        let (output, header) = build_compact(&program, route, dir.path(), &[]);
        let executable = host(&output, &header, dir.path(), &["-DLADDER_HOST_GUARDED"]);
        let run = Command::new(&executable).args(["300", "10", "X0=1"]).output().unwrap();
        assert!(
            run.status.success(),
            "{route:?}: the host faulted ({:?}):\n{}",
            run.status,
            text(&run.stderr)
        );
        assert_eq!(
            text(&run.stdout),
            interpreter_csv(&program, 300, 10, &["X0=1"]),
            "{route:?}"
        );
    }
}

#[test]
fn the_devices_the_host_names_are_in_the_image() {
    let dir = scratch("compact-host-devices");
    let program = workspace().join("examples/motor_start_stop.il");
    let plain = build_compact(&program, Route::C, dir.path(), &[]).1;
    let plain_size = image_size(&plain);
    let plain_text = std::fs::read_to_string(&plain).unwrap();
    assert!(!plain_text.contains("D201"), "{plain_text}");
    let (_, header) = build_compact(
        &program,
        Route::C,
        dir.path(),
        &["--host-devices", "Y0..Y7,D200:32", "--host-devices", "M100"],
    );
    let text = std::fs::read_to_string(&header).unwrap();
    for device in ["Y7", "M100"] {
        assert!(
            text.contains(&format!("#define LADDER_PROGRAM_{device} ")),
            "{device}:\n{text}"
        );
    }
    // The program uses D0: one run from D0 to D201 (the pair D201, D200).
    assert!(text.contains("#define LADDER_PROGRAM_D0_TO_D201_COUNT 202u"), "{text}");
    assert!(image_size(&header) > plain_size);
    // A bad list is refused before anything is written.
    let output = dir.path().join("bad.c");
    let result = ladderc(&[
        "build",
        program.to_str().unwrap(),
        "--image",
        "compact",
        "--emit",
        "c",
        "--host-devices",
        "Q7",
        "-o",
        output.to_str().unwrap(),
    ]);
    assert_eq!(
        result.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(!output.exists() && !dir.path().join("bad.h").exists());
}

#[test]
fn a_header_ladderc_did_not_write_is_never_replaced() {
    let dir = scratch("compact-header");
    let program = workspace().join("examples/traffic_light.il");
    let object = dir.path().join("program.o");
    let mine = dir.path().join("program.h");
    std::fs::write(&mine, "/* my own header */\n").unwrap();
    let result = ladderc(&[
        "build",
        program.to_str().unwrap(),
        "--image",
        "compact",
        "-o",
        object.to_str().unwrap(),
    ]);
    assert_eq!(result.status.code(), Some(2), "{}", text(&result.stderr));
    assert!(
        text(&result.stderr).contains("not written by ladderc"),
        "{}",
        text(&result.stderr)
    );
    assert_eq!(std::fs::read_to_string(&mine).unwrap(), "/* my own header */\n");
    assert!(!object.exists(), "a refused build wrote the object");
    // --header names another file; one ladderc wrote is replaced.
    let elsewhere = dir.path().join("traffic_light_image.h");
    for _ in 0..2 {
        let result = ladderc(&[
            "build",
            program.to_str().unwrap(),
            "--image",
            "compact",
            "--header",
            elsewhere.to_str().unwrap(),
            "-o",
            object.to_str().unwrap(),
        ]);
        assert!(result.status.success(), "{}", text(&result.stderr));
    }
    assert!(std::fs::read_to_string(&elsewhere)
        .unwrap()
        .contains("LADDER_PROGRAM_IMAGE_SIZE"));
    assert_eq!(std::fs::read_to_string(&mine).unwrap(), "/* my own header */\n");
    // A header that cannot be written (no file can be made in /proc) fails
    // the build before the object is replaced: the pair stays as it was.
    std::fs::write(&object, b"an older object").unwrap();
    let result = ladderc(&[
        "build",
        program.to_str().unwrap(),
        "--image",
        "compact",
        "--header",
        "/proc/ladderc-test-header.h",
        "-o",
        object.to_str().unwrap(),
    ]);
    assert_eq!(result.status.code(), Some(1), "{}", text(&result.stderr));
    assert_eq!(std::fs::read(&object).unwrap(), b"an older object");
}

/// Firmware projects are often C++: the header ladderc writes declares the
/// entry points and the layout table with C linkage there too, so a C++
/// host links with the object as a C host does.
#[test]
fn a_cpp_host_links_with_the_program_and_its_header() {
    let Some(compiler) = ["g++", "c++", "clang++"].into_iter().find(|c| {
        Command::new(c)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    }) else {
        eprintln!("SKIPPED a_cpp_host_links_with_the_program_and_its_header: no C++ compiler (g++, c++, clang++)");
        return;
    };
    let dir = scratch("compact-cpp");
    let program = workspace().join("examples/traffic_light.il");
    let (object, _header) = build_compact(&program, Route::Object, dir.path(), &[]);
    let source = dir.path().join("host.cpp");
    std::fs::write(
        &source,
        r#"#include <cstdio>
#include "program.h"
alignas(LADDER_PROGRAM_IMAGE_ALIGN) static unsigned char storage[LADDER_PROGRAM_IMAGE_SIZE];
int main() {
    LadderMemory *mem = ladder_program_init(storage, sizeof storage);
    if (mem == nullptr || ladder_program_layout[0] == 0) return 2;
    ladder_write(mem, LADDER_DEVICE_X, 0, 1);
    for (int scan = 0; scan < 3; scan++) ladder_program_scan(mem, 100);
    int32_t y0 = -1;
    ladder_read(mem, LADDER_DEVICE_Y, 0, &y0);
    std::printf("%d %d\n", (int)y0, (int)storage[LADDER_PROGRAM_Y0]);
    return 0;
}
"#,
    )
    .unwrap();
    let executable = dir.path().join("host");
    let runtime = ladder_engine::aot::toolchain::runtime_library().expect("the runtime library cargo built");
    let built = Command::new(compiler)
        .args(["-std=c++17", "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(workspace().join("runtime/include"))
        .arg("-I")
        .arg(dir.path())
        .arg(&source)
        .arg(&object)
        .arg(runtime)
        .args(ladder_engine::aot::toolchain::NATIVE_LIBS)
        .arg("-o")
        .arg(&executable)
        .output()
        .unwrap();
    assert!(built.status.success(), "{}", text(&built.stderr));
    let run = Command::new(&executable).output().unwrap();
    assert!(run.status.success(), "{}", text(&run.stderr));
    // Y0 as the C API reads it and as the header's offset finds it agree.
    let answer = text(&run.stdout);
    let values: Vec<&str> = answer.split_whitespace().collect();
    assert_eq!(values.len(), 2, "{answer}");
    assert_eq!(values[0], values[1], "{answer}");
}
