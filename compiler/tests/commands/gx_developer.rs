//! GX Developer projects (docs/language.md, "GX Developer projects"): the
//! sample project `testsuite/gxdeveloper/3floor_elevator` checks, renders
//! with its device comments, runs with them in the watch header, imports to
//! IL that compiles to the same program and writes back to the same
//! MAIN.wpg and COMMENT.wcd; every program of `testsuite/` that has codes
//! for all its instructions goes IL → MAIN.wpg → IL to the same program.

use crate::common::tools::{ladderc, scratch, workspace};
use ladder_front::check::compile_source;
use ladder_front::gxdev;
use ladder_front::program::{CheckedProgram, Op};
use ladder_front::source::SourceFile;
use std::path::PathBuf;

fn elevator() -> PathBuf {
    workspace().join("testsuite/gxdeveloper/3floor_elevator")
}

fn compile(source: &SourceFile) -> CheckedProgram {
    let (program, diagnostics) = compile_source(source);
    program.unwrap_or_else(|| panic!("{} does not compile: {diagnostics:?}", source.name))
}

fn ops(program: &CheckedProgram) -> Vec<Op> {
    program.instructions.iter().map(|i| i.op.clone()).collect()
}

fn text(output: &std::process::Output) -> (String, String) {
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn the_elevator_checks_and_names_steps() {
    let dir = elevator();
    for path in [dir.clone(), dir.join("Gppw.gps"), dir.join("Pou/Body/MAIN.wpg")] {
        let output = ladderc(&["check", path.to_str().unwrap()]);
        let (_, stderr) = text(&output);
        assert!(output.status.success(), "{stderr}");
        assert!(!stderr.contains("error"), "{stderr}");
        // Its warnings (double coils) name the step as GX Developer shows it.
        assert!(stderr.contains("at MAIN.wpg step 117"), "{stderr}");
    }
}

#[test]
fn the_elevator_renders_and_runs_with_its_comments() {
    let dir = scratch("gx-render");
    let svg = dir.path().join("elevator.svg");
    let output = ladderc(&["render", elevator().to_str().unwrap(), "-o", svg.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output).1);
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(
        drawing.matches("class=\"dcomment\"").count() > 20,
        "device comments under contacts and coils"
    );
    assert!(drawing.contains("UP"), "the comment of Y010");
    let output = ladderc(&[
        "run",
        elevator().to_str().unwrap(),
        "--scans",
        "2",
        "--watch",
        "Y10,Y11",
    ]);
    let (stdout, stderr) = text(&output);
    assert!(output.status.success(), "{stderr}");
    let first: Vec<&str> = stdout.lines().take(2).collect();
    assert!(first[0].starts_with("# Y10: ") && first[0].contains("UP"), "{stdout}");
    assert!(first[1].starts_with("# Y11: ") && first[1].contains("DOWN"), "{stdout}");
    let vcd = dir.path().join("elevator.vcd");
    let output = ladderc(&[
        "run",
        elevator().to_str().unwrap(),
        "--scans",
        "2",
        "--watch",
        "Y10",
        "--vcd",
        vcd.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    let waves = std::fs::read_to_string(&vcd).unwrap();
    assert!(waves.contains("Y10_") && waves.contains("UP"), "{waves}");
}

#[test]
fn the_elevator_imports_to_the_same_program_and_writes_back_byte_for_byte() {
    let dir = scratch("gx-import");
    let il = dir.path().join("elevator.il");
    let output = ladderc(&["import", elevator().to_str().unwrap(), "-o", il.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output).1);
    let from_project = compile(&SourceFile::read(&elevator()).unwrap());
    let from_il = compile(&SourceFile::read(&il).unwrap());
    assert_eq!(ops(&from_il), ops(&from_project));
    // Written into a copy of the project without its program and comments.
    let copy = dir.path().join("project");
    for file in ["Gppw.gps", "Gppw.gpj", "param.wpa", "Project.inf"] {
        std::fs::create_dir_all(&copy).unwrap();
        std::fs::copy(elevator().join(file), copy.join(file)).unwrap();
    }
    let output = ladderc(&[
        "import",
        il.to_str().unwrap(),
        "--to-gx-developer",
        copy.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output).1);
    let original = gxdev::Project::in_folder(&elevator());
    let written = gxdev::Project::in_folder(&copy);
    assert_eq!(
        std::fs::read(&written.program).unwrap(),
        std::fs::read(&original.program).unwrap()
    );
    assert_eq!(
        std::fs::read(&written.comments).unwrap(),
        std::fs::read(&original.comments).unwrap()
    );
    // The written project reads as the same program again.
    assert_eq!(ops(&compile(&SourceFile::read(&copy).unwrap())), ops(&from_project));
}

#[test]
fn a_broken_project_is_one_error_and_nothing_else() {
    let dir = scratch("gx-broken");
    let copy = dir.path().join("project");
    std::fs::create_dir_all(copy.join("Pou/Body")).unwrap();
    std::fs::copy(elevator().join("Gppw.gps"), copy.join("Gppw.gps")).unwrap();
    let mut program = std::fs::read(elevator().join("Pou/Body/MAIN.wpg")).unwrap();
    program.truncate(0x200);
    program.push(0x09);
    std::fs::write(copy.join("Pou/Body/MAIN.wpg"), &program).unwrap();
    let output = ladderc(&["check", copy.to_str().unwrap()]);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.matches("error[").count(), 1, "{stderr}");
    assert!(
        stderr.contains("E0053") && stderr.contains("byte offset 510"),
        "{stderr}"
    );
}

/// Every program under `testsuite/` (program files and inline programs of
/// scenarios).
fn programs() -> Vec<(String, String)> {
    let mut found = Vec::new();
    let mut pending = vec![workspace().join("testsuite")];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path: PathBuf = entry.unwrap().path();
            let name = path.display().to_string();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "il") {
                found.push((name, SourceFile::read(&path).unwrap().text));
            } else if path.extension().is_some_and(|e| e == "scn") {
                let text = std::fs::read_to_string(&path).unwrap();
                if let Ok(scenario) = ladder_engine::scenario::parse_scenario(&path, &text) {
                    if let ladder_engine::scenario::ProgramSource::Inline { text, .. } = scenario.program {
                        found.push((name, text));
                    }
                }
            }
        }
    }
    found.sort();
    found
}

#[test]
fn testsuite_programs_go_through_main_wpg_and_back() {
    let defaults = gxdev::write::Defaults {
        cpu: Some(0x08),
        memory: Some(64_000),
    };
    let (mut written, mut without_code) = (0, 0);
    for (name, text) in programs() {
        let source = SourceFile::new(name.clone(), text);
        let (Some(program), _) = compile_source(&source) else {
            continue; // a scenario about a program that does not compile
        };
        let Ok((main, _)) = gxdev::write::encode(&source, &defaults) else {
            without_code += 1; // an instruction GX Developer's code is not known for
            continue;
        };
        let listing = gxdev::listing_of((&name, &main), None, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        let back = SourceFile::new(format!("{name} (MAIN.wpg)"), listing.clone());
        let (again, diagnostics) = compile_source(&back);
        let Some(again) = again else {
            panic!("{name}: the written program does not compile: {diagnostics:?}\n{listing}");
        };
        assert_eq!(ops(&again), ops(&program), "{name}:\n{listing}");
        written += 1;
    }
    eprintln!(
        "{written} programs went through MAIN.wpg and back; {without_code} use instructions without a known code"
    );
    assert!(
        written >= 90,
        "{written} programs written, {without_code} without codes"
    );
}

#[test]
fn a_gx_works2_comment_export_beside_il_gives_its_comments() {
    let dir = scratch("gx-comment-csv");
    let csv = workspace().join("testsuite/programs/exports/device_comments.csv");
    std::fs::copy(csv, dir.path().join("names.csv")).unwrap();
    let program = dir.path().join("conveyor.il");
    std::fs::write(&program, "//@ comments names.csv\nLD X0\nOR Y0\nANI X1\nOUT Y0\n").unwrap();
    let output = ladderc(&["run", program.to_str().unwrap(), "--scans", "1", "--watch", "X0,Y0"]);
    let (stdout, stderr) = text(&output);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stdout.starts_with("# X0: Start button\n# Y0: Conveyor motor\n"),
        "{stdout}"
    );
    std::fs::remove_file(dir.path().join("names.csv")).unwrap();
    let output = ladderc(&["check", program.to_str().unwrap()]);
    assert_eq!(
        output.status.code(),
        Some(2),
        "a comment file that cannot be read: {}",
        text(&output).1
    );
}

#[test]
fn the_cpu_of_the_parameters_rules_out_fx3_devices_and_instructions() {
    let dir = scratch("gx-cpu");
    let program = dir.path().join("fx2n.il");
    std::fs::write(&program, "//@ cpu FX2N\nLD X0\nMEP\nMOV K1 R0\nMOV K1 D0\n").unwrap();
    let output = ladderc(&["check", program.to_str().unwrap()]);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.matches("error[E0054]").count(), 2, "{stderr}");
    std::fs::write(&program, "//@ cpu FX3U\nLD X0\nMEP\nMOV K1 R0\nMOV K1 D0\n").unwrap();
    assert!(ladderc(&["check", program.to_str().unwrap()]).status.success());
}

#[test]
fn d8069_records_the_step_of_a_project() {
    let dir = scratch("gx-d8069");
    let program = dir.path().join("index.il");
    // The third instruction is at line 3 and at step 6 (MOV takes 5 steps).
    std::fs::write(&program, "LD M8000\nMOV K9000 Z0\nMOV K1 D0Z0\nEND\n").unwrap();
    let project = dir.path().join("project");
    let output = ladderc(&[
        "import",
        program.to_str().unwrap(),
        "--to-gx-developer",
        project.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output).1);
    for (path, expected, place) in [(&program, "3", "at line 3"), (&project, "6", "at MAIN.wpg step 6")] {
        let output = ladderc(&[
            "run",
            path.to_str().unwrap(),
            "--scans",
            "1",
            "--watch",
            "D8069",
            "--format",
            "csv",
        ]);
        let (stdout, stderr) = text(&output);
        assert_eq!(
            stdout.lines().nth(1),
            Some(format!("1,{expected}").as_str()),
            "{stdout}"
        );
        assert!(stderr.contains(place), "{stderr}");
    }
}

/// A copy of the elevator project in `dir`.
fn elevator_copy(dir: &std::path::Path) -> PathBuf {
    let copy = dir.join("project");
    for file in ["Gppw.gps", "param.wpa", "Pou/Body/MAIN.wpg", "Others/COMMENT.wcd"] {
        let to = copy.join(file);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(elevator().join(file), to).unwrap();
    }
    copy
}

/// Every file and folder under `dir`, as paths relative to it.
fn tree(dir: &std::path::Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            found.push(path.strip_prefix(dir).unwrap().display().to_string());
            if path.is_dir() && !path.is_symlink() {
                pending.push(path);
            }
        }
    }
    found.sort();
    found
}

fn import_to(program: &std::path::Path, project: &std::path::Path) -> std::process::Output {
    ladderc(&[
        "import",
        program.to_str().unwrap(),
        "--to-gx-developer",
        project.to_str().unwrap(),
    ])
}

#[test]
fn a_program_is_checked_against_the_cpu_of_the_project_it_is_written_to() {
    let dir = scratch("gx-to-cpu");
    let project = elevator_copy(dir.path());
    let before = std::fs::read(project.join("Pou/Body/MAIN.wpg")).unwrap();
    let program = dir.path().join("fx3.il");
    std::fs::write(&program, "LD X0\nMOV K1 R0\nEND\n").unwrap();
    let output = import_to(&program, &project);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("error[E0054]"), "the elevator is an FX2N: {stderr}");
    assert_eq!(std::fs::read(project.join("Pou/Body/MAIN.wpg")).unwrap(), before);
    // Its own `//@ memory` line against the parameters' 2000 steps.
    std::fs::write(&program, "//@ memory 4000\nLD X0\nOUT Y0\nEND\n").unwrap();
    let output = import_to(&program, &project);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("declares 2000 steps"), "{stderr}");
    assert_eq!(std::fs::read(project.join("Pou/Body/MAIN.wpg")).unwrap(), before);
}

#[test]
fn more_comments_than_comment_wcd_holds_are_refused_and_nothing_is_written() {
    let dir = scratch("gx-to-comments");
    let project = elevator_copy(dir.path());
    let comments = std::fs::read(project.join("Others/COMMENT.wcd")).unwrap();
    let program = dir.path().join("many.il");
    // Every other D: 7840 runs of one device each.
    let mut text_of = String::from("LD X0\nOUT Y0\nEND\n");
    for n in 0..7840 {
        text_of.push_str(&format!("//@ comment D{} c\n", n * 2));
    }
    std::fs::write(&program, text_of).unwrap();
    let output = import_to(&program, &project);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.matches("error").count(), 1, "{stderr}");
    assert!(stderr.contains("6552"), "{stderr}");
    assert_eq!(std::fs::read(project.join("Others/COMMENT.wcd")).unwrap(), comments);
}

#[test]
fn a_program_without_comment_lines_keeps_the_projects_comments() {
    let dir = scratch("gx-to-keep");
    let project = elevator_copy(dir.path());
    let comments = std::fs::read(project.join("Others/COMMENT.wcd")).unwrap();
    let program = dir.path().join("plain.il");
    std::fs::write(&program, "LD X0\nOUT Y0\nEND\n").unwrap();
    let output = import_to(&program, &project);
    assert!(output.status.success(), "{}", text(&output).1);
    assert_eq!(std::fs::read(project.join("Others/COMMENT.wcd")).unwrap(), comments);
    let listing = SourceFile::read(&project).unwrap();
    assert!(listing.text.contains("\tOUT\tY000"), "{}", listing.text);
    assert!(listing.text.contains("//@ comment Y010 "), "{}", listing.text);
}

#[test]
fn a_failed_write_leaves_no_new_folder() {
    let dir = scratch("gx-to-fail");
    let project = dir.path().join("project");
    std::fs::create_dir_all(project.join("Pou/Body/MAIN.wpg")).unwrap();
    let program = dir.path().join("p.il");
    std::fs::write(&program, "//@ comment X0 start\nLD X0\nOUT Y0\nEND\n").unwrap();
    let before = tree(dir.path());
    let output = import_to(&program, &project);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output).1);
    assert_eq!(tree(dir.path()), before, "{}", text(&output).1);
    // A new project in a folder that does not exist yet: made, and written.
    let fresh = dir.path().join("new/project");
    let output = import_to(&program, &fresh);
    assert!(output.status.success(), "{}", text(&output).1);
    assert_eq!(
        tree(&fresh),
        ["Others", "Others/COMMENT.wcd", "Pou", "Pou/Body", "Pou/Body/MAIN.wpg"]
    );
}

#[test]
fn a_project_without_its_program_is_unreadable_not_undecodable() {
    let dir = scratch("gx-no-main");
    let project = elevator_copy(dir.path());
    std::fs::remove_file(project.join("Pou/Body/MAIN.wpg")).unwrap();
    let output = ladderc(&["check", project.to_str().unwrap()]);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(!stderr.contains("E0053"), "{stderr}");
    assert!(stderr.contains("MAIN.wpg"), "{stderr}");
}

#[cfg(unix)]
#[test]
fn the_parameters_are_read_within_the_size_bound() {
    let dir = scratch("gx-to-zero");
    let project = dir.path().join("project");
    std::fs::create_dir_all(&project).unwrap();
    // Endless zeros: read to the first NUL, then one decode error.
    std::os::unix::fs::symlink("/dev/zero", project.join("param.wpa")).unwrap();
    let program = dir.path().join("p.il");
    std::fs::write(&program, "LD X0\nOUT Y0\nEND\n").unwrap();
    let output = import_to(&program, &project);
    let (_, stderr) = text(&output);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("param.wpa cannot be decoded"), "{stderr}");
    assert_eq!(tree(&project), ["param.wpa"]);
}
