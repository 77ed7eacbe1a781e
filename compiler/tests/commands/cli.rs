//! The `ladderc` binary end to end: exit statuses, diagnostics on stderr,
//! tables on stdout.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `ladderc` with `args` in `dir` (other command tests use it too).
pub(crate) fn ladderc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("ladderc runs")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ladderc-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub(crate) fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn check_reports_location_code_and_underline() {
    let dir = temp_dir("check");
    std::fs::write(dir.join("bad.il"), "LD X0\n  LDD X1\nOUT Y0\n").unwrap();
    let output = ladderc(&["check", "bad.il"], &dir);
    assert_eq!(output.status.code(), Some(1));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("error[E0001]: unknown instruction `LDD`"), "{stderr}");
    assert!(stderr.contains("bad.il:2:3"), "{stderr}");
    assert!(stderr.contains("2 │   LDD X1\n  │   ^^^"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn check_accepts_good_programs_and_shows_warnings() {
    let dir = temp_dir("good");
    std::fs::write(dir.join("ok.il"), "LD X0\nOUT Y0\nEND\nLD X1\nOUT Y1\n").unwrap();
    let output = ladderc(&["check", "ok.il"], &dir);
    assert_eq!(output.status.code(), Some(0));
    assert!(text(&output.stderr).contains("warning[W0001]"));
}

#[test]
fn unreadable_files_exit_2() {
    let dir = temp_dir("missing");
    assert_eq!(ladderc(&["check", "nope.il"], &dir).status.code(), Some(2));
    assert_eq!(ladderc(&["run", "nope.il"], &dir).status.code(), Some(2));
    let output = ladderc(&["test", "nope.scn"], &dir);
    assert_eq!(output.status.code(), Some(2));
    std::fs::write(dir.join("bad.scn"), "program p.il\nfrobnicate\n").unwrap();
    let output = ladderc(&["test", "bad.scn"], &dir);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("bad.scn:2: error: unknown directive"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn run_prints_a_table_or_csv() {
    let dir = temp_dir("run");
    std::fs::write(dir.join("p.il"), "LD X0\nOUT Y0\nLD X0\nINC D0\n").unwrap();
    let output = ladderc(
        &["run", "p.il", "--scans", "3", "--set", "X0=1", "--watch", "Y0,D0"],
        &dir,
    );
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert_eq!(
        text(&output.stdout),
        "scan  Y0      D0\n   1   1       1\n   2   1       2\n   3   1       3\n"
    );
    let output = ladderc(
        &["run", "p.il", "--scans", "2", "--format", "csv", "--watch", "D0"],
        &dir,
    );
    assert_eq!(text(&output.stdout), "scan,D0\n1,0\n2,0\n");
    let output = ladderc(&["run", "p.il", "--scans", "1"], &dir);
    assert_eq!(
        text(&output.stdout),
        "scan  Y0\n   1   0\n",
        "default watch: the driven Y coils"
    );
    let output = ladderc(&["run", "p.il", "--set", "Q9=1"], &dir);
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn test_reports_failures_and_summary() {
    let dir = temp_dir("test");
    std::fs::write(
        dir.join("a.scn"),
        "program <<\nLD X0\nOUT Y0\n>>\nset X0 1\nscan\nexpect Y0 1\nexpect Y0 0\n",
    )
    .unwrap();
    std::fs::write(dir.join("b.scn"), "program <<\nLD X0\nOUT Y0\n>>\nscan\nexpect Y0 0\n").unwrap();
    let output = ladderc(&["test", ".", "--engine", "interp"], &dir);
    assert_eq!(output.status.code(), Some(1));
    let stdout = text(&output.stdout);
    assert!(stdout.contains("a.scn:8: [interp] expected Y0 = 0, got 1"), "{stdout}");
    assert_eq!(stdout.lines().last(), Some("1 passed, 1 failed"));
}

#[test]
fn explain_prints_the_explanation() {
    let dir = temp_dir("explain");
    let output = ladderc(&["explain", "E0010"], &dir);
    assert_eq!(output.status.code(), Some(0));
    assert!(text(&output.stdout).starts_with("E0010: ANB/ORB without two blocks"));
    assert_eq!(ladderc(&["explain", "E9999"], &dir).status.code(), Some(2));
}

mod file_safety {
    //! `ladderc build` never destroys a file: the findings of the
    //! reliability review, one test each.

    use super::{ladderc, temp_dir, text};
    use std::path::Path;

    const GOOD: &str = "LD X0\nOUT Y0\n";
    const BAD: &str = "LD X0\nOUT X1\n";

    fn is_object(path: &Path) -> bool {
        std::fs::read(path).is_ok_and(|b| b.starts_with(b"\x7fELF"))
    }

    #[test]
    fn the_program_is_never_its_own_output() {
        let dir = temp_dir("same-file");
        for (program, text_of_program) in [("mine.il", BAD), ("ok.il", GOOD)] {
            std::fs::write(dir.join(program), text_of_program).unwrap();
            let output = ladderc(&["build", program, "-o", program], &dir);
            assert_eq!(output.status.code(), Some(2), "{program}");
            assert!(
                text(&output.stderr).contains("is the input"),
                "{}",
                text(&output.stderr)
            );
            assert_eq!(std::fs::read_to_string(dir.join(program)).unwrap(), text_of_program);
        }
        // A program named like its default output, `prog.o`.
        std::fs::write(dir.join("prog.o"), GOOD).unwrap();
        let output = ladderc(&["build", "prog.o"], &dir);
        assert_eq!(output.status.code(), Some(2));
        assert_eq!(std::fs::read_to_string(dir.join("prog.o")).unwrap(), GOOD);
    }

    #[cfg(unix)]
    #[test]
    fn links_to_the_program_are_the_program() {
        let dir = temp_dir("links");
        std::fs::write(dir.join("p.il"), GOOD).unwrap();
        std::fs::hard_link(dir.join("p.il"), dir.join("hard.o")).unwrap();
        std::os::unix::fs::symlink("p.il", dir.join("soft.o")).unwrap();
        for output in ["hard.o", "soft.o"] {
            let result = ladderc(&["build", "p.il", "-o", output], &dir);
            assert_eq!(result.status.code(), Some(2), "{output}");
        }
        assert_eq!(std::fs::read_to_string(dir.join("p.il")).unwrap(), GOOD);
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_written_through() {
        let dir = temp_dir("symlink");
        std::fs::write(dir.join("p.il"), GOOD).unwrap();
        std::fs::write(dir.join("target.o"), b"old").unwrap();
        std::os::unix::fs::symlink("target.o", dir.join("link.o")).unwrap();
        let output = ladderc(&["build", "p.il", "-o", "link.o"], &dir);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
        let link = std::fs::symlink_metadata(dir.join("link.o")).unwrap();
        assert!(link.file_type().is_symlink(), "the link is kept");
        assert!(is_object(&dir.join("target.o")), "its target holds the object");
        std::os::unix::fs::symlink("nowhere.o", dir.join("dangling.o")).unwrap();
        let output = ladderc(&["build", "p.il", "-o", "dangling.o"], &dir);
        assert_eq!(output.status.code(), Some(2));
        assert!(text(&output.stderr).contains("does not exist"));
    }

    #[cfg(unix)]
    #[test]
    fn only_regular_files_are_replaced() {
        let dir = temp_dir("special");
        std::fs::write(dir.join("p.il"), GOOD).unwrap();
        let fifo = dir.join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        std::fs::create_dir_all(dir.join("folder")).unwrap();
        for (output, kind) in [("pipe", "named pipe"), ("folder", "directory"), ("/dev/null", "device")] {
            let result = ladderc(&["build", "p.il", "-o", output], &dir);
            assert_eq!(result.status.code(), Some(2), "{output}");
            assert!(text(&result.stderr).contains(kind), "{}", text(&result.stderr));
        }
        use std::os::unix::fs::FileTypeExt;
        assert!(
            std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(),
            "the pipe is still there"
        );
        assert!(dir.join("folder").is_dir());
        assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
    }

    #[test]
    fn a_successful_build_replaces_only_its_output() {
        let dir = temp_dir("success");
        std::fs::write(dir.join("p.il"), GOOD).unwrap();
        std::fs::write(dir.join("p.o"), b"old").unwrap();
        let output = ladderc(&["build", "p.il"], &dir);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
        assert!(is_object(&dir.join("p.o")));
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(names, ["p.il", "p.o"]);
    }

    #[test]
    fn prefixes_are_c_identifiers_outside_the_runtime_names() {
        let dir = temp_dir("prefix");
        std::fs::write(dir.join("p.il"), GOOD).unwrap();
        for prefix in ["", "ladder_end_", "ladder_begin_", "9x", "a-b"] {
            let output = ladderc(&["build", "p.il", "--prefix", prefix, "-o", "x.o"], &dir);
            assert_eq!(output.status.code(), Some(2), "{prefix:?}");
            let stderr = text(&output.stderr);
            assert!(stderr.contains("--prefix") && !stderr.contains("Signature"), "{stderr}");
            assert!(!dir.join("x.o").exists());
        }
        let output = ladderc(&["build", "p.il", "--prefix", "motor_", "-o", "x.o"], &dir);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    }
}

mod bounded_input {
    use super::{ladderc, temp_dir, text};

    #[cfg(unix)]
    #[test]
    fn endless_input_ends_at_once() {
        let dir = temp_dir("dev-zero");
        let started = std::time::Instant::now();
        let output = ladderc(&["check", "/dev/zero"], &dir);
        assert_eq!(output.status.code(), Some(1));
        let stderr = text(&output.stderr);
        assert!(stderr.contains("error[E0009]: this is not a text file"), "{stderr}");
        assert!(stderr.contains("/dev/zero:1:1"), "{stderr}");
        std::fs::write(dir.join("z.scn"), "program /dev/zero\nscan\n").unwrap();
        let output = ladderc(&["test", "z.scn"], &dir);
        assert_eq!(output.status.code(), Some(1), "{}", text(&output.stdout));
        assert!(started.elapsed().as_secs() < 30, "reading stopped early");
    }

    #[test]
    fn binary_data_is_one_clear_error() {
        let dir = temp_dir("binary");
        std::fs::write(dir.join("b.il"), b"LD X0\nOUT Y0\n\x7fELF\x02\x00\x00garbage").unwrap();
        let output = ladderc(&["check", "b.il"], &dir);
        assert_eq!(output.status.code(), Some(1));
        let stderr = text(&output.stderr);
        assert!(stderr.contains("E0009") && stderr.contains("b.il:3:6"), "{stderr}");
        assert_eq!(stderr.matches("error[").count(), 1, "{stderr}");
    }

    #[test]
    fn files_past_the_limit_are_refused() {
        let dir = temp_dir("large");
        let path = dir.join("huge.il");
        let spaces = vec![b' '; (ladder_front::source::MAX_SOURCE_BYTES + 1) as usize];
        std::fs::write(&path, spaces).unwrap();
        let output = ladderc(&["check", "huge.il"], &dir);
        assert_eq!(output.status.code(), Some(2));
        assert!(
            text(&output.stderr).contains("larger than 64 MiB"),
            "{}",
            text(&output.stderr)
        );
        std::fs::remove_file(&path).unwrap();
    }
}

#[test]
fn render_draws_programs_and_destroys_nothing() {
    let dir = temp_dir("render");
    std::fs::write(dir.join("p.il"), "// start\nLD X0\nOR Y0\nANI X1\nOUT Y0\nMOV K5 D0\n").unwrap();
    std::fs::write(dir.join("bad.il"), "LD X0\nOUT X1\n").unwrap();
    // SVG on standard output.
    let output = ladderc(&["render", "p.il"], &dir);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let svg = text(&output.stdout);
    assert!(svg.starts_with("<svg"), "{svg}");
    for shown in ["X000", "X001", "Y000", "MOV", "K5", "D0", ">start<", "END"] {
        assert!(svg.contains(shown), "{shown} missing from {svg}");
    }
    // An HTML page by the output's extension.
    let output = ladderc(&["render", "p.il", "-o", "p.html"], &dir);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let page = std::fs::read_to_string(dir.join("p.html")).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("<svg"), "{page}");
    // A program that does not compile: its diagnostic, exit 1, the old
    // output left as it was.
    std::fs::write(dir.join("old.svg"), "kept").unwrap();
    let output = ladderc(&["render", "bad.il", "-o", "old.svg"], &dir);
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("bad.il:2:"), "{}", text(&output.stderr));
    assert_eq!(std::fs::read_to_string(dir.join("old.svg")).unwrap(), "kept");
    // Never over its own input.
    let output = ladderc(&["render", "p.il", "-o", "p.il"], &dir);
    assert_eq!(output.status.code(), Some(2));
    assert!(std::fs::read_to_string(dir.join("p.il"))
        .unwrap()
        .starts_with("// start"));
}

#[test]
fn an_empty_program_is_a_warning() {
    let dir = temp_dir("empty");
    std::fs::write(dir.join("empty.il"), "").unwrap();
    std::fs::write(dir.join("comments.il"), "// LD X0\n// OUT Y0\n").unwrap();
    for file in ["empty.il", "comments.il"] {
        let output = ladderc(&["check", file], &dir);
        assert_eq!(output.status.code(), Some(0), "a warning, not an error");
        let stderr = text(&output.stderr);
        assert!(
            stderr.contains("warning[W0004]") && stderr.contains(&format!("{file}:1:1")),
            "{stderr}"
        );
    }
}
