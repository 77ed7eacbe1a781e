//! Program files as ladderc reads them (docs/language.md, "Program files"): plain IL
//! with or without a UTF-8 byte-order mark, CRLF, UTF-16 with a mark, and
//! GX Works2 CSV exports; and `ladderc import`, whose IL compiles to the
//! same program as the export (checked on the real FX2N export and on every
//! hand-made export in `testsuite/programs/gxworks2/`).

use crate::common::tools::{ladderc, scratch, workspace};
use ladder_front::check::compile_source;
use ladder_front::program::{CheckedProgram, Line, Op};
use ladder_front::source::SourceFile;
use std::path::{Path, PathBuf};

fn compile(path: &Path) -> CheckedProgram {
    let source = SourceFile::read(path).unwrap();
    let (program, diagnostics) = compile_source(&source);
    program.unwrap_or_else(|| panic!("{} does not compile: {diagnostics:?}", path.display()))
}

/// The instructions without their source lines: what runs.
fn ops(program: &CheckedProgram) -> Vec<Op> {
    program.instructions.iter().map(|i| i.op.clone()).collect()
}

/// The readable exports of `testsuite/programs/gxworks2/` and of
/// `testsuite/programs/exports/` (one program in every editor's format).
fn exports() -> Vec<PathBuf> {
    let mut exports: Vec<PathBuf> = ["testsuite/programs/gxworks2", "testsuite/programs/exports"]
        .into_iter()
        .flat_map(|dir| std::fs::read_dir(workspace().join(dir)).unwrap())
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "csv"))
        .filter(|path| {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            !name.starts_with("bad_") && !name.starts_with("melsec_") && name != "device_comments.csv"
        })
        .collect();
    exports.sort();
    exports
}

#[test]
fn every_editors_export_is_the_same_program() {
    let dir = workspace().join("testsuite/programs/exports");
    let formats = [
        "gx_developer_comma.csv",
        "step_csv_headerless.csv",
        "tsv_unquoted_double_bom.csv",
    ];
    let programs: Vec<Vec<Op>> = formats.iter().map(|f| ops(&compile(&dir.join(f)))).collect();
    assert!(programs[0].len() >= 7, "LD OR ANI OUT OUT LD MOV: {:?}", programs[0]);
    assert!(programs.iter().all(|p| *p == programs[0]), "{programs:?}");
}

#[test]
fn import_refuses_other_cpus_and_exports_that_do_not_compile() {
    let dir = scratch("import-foreign");
    let existing = dir.path().join("kept.il");
    std::fs::write(&existing, "LD X0\nOUT Y0\n").unwrap();
    let melsec = workspace().join("testsuite/programs/exports/melsec_l_export.csv");
    let output = ladderc(&["import", melsec.to_str().unwrap(), "-o", existing.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("E0047") && stderr.contains("MELSEC-L"), "{stderr}");
    assert_eq!(
        stderr.matches("error[").count(),
        1,
        "one error, not a cascade:\n{stderr}"
    );
    assert!(!stderr.contains("warning["), "the one thing reported:\n{stderr}");
    // A step list of three fields (Delta's WPLSoft) is one E0048, not an
    // error per row.
    let delta = dir.path().join("delta.csv");
    let rows: String = (0..38).map(|step| format!("{step:06},LD,M{}\n", 1000 + step)).collect();
    std::fs::write(&delta, rows).unwrap();
    let output = ladderc(&["check", delta.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.matches("error[").count(), 1, "{stderr}");
    assert!(stderr.contains("E0048") && stderr.contains("WPLSoft"), "{stderr}");
    // Readable rows, but a program that does not compile: nothing written.
    let broken = dir.path().join("broken.csv");
    std::fs::write(&broken, "0,,LD,X0,,,,,\n1,,FROBNICATE,Y0,,,,,\n2,,END,,,,,,\n").unwrap();
    let target = dir.path().join("broken.il");
    let output = ladderc(&["import", broken.to_str().unwrap(), "-o", target.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("broken.csv:2:"));
    assert!(!target.exists(), "an export that does not compile is not written");
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "LD X0\nOUT Y0\n");
}

#[test]
fn importing_then_compiling_gives_the_same_program() {
    let exports = exports();
    assert!(
        exports.iter().any(|p| p.ends_with("gxworks2_fx2n_main.csv")),
        "the real export is among {exports:?}"
    );
    let dir = scratch("import");
    for export in exports {
        let il = dir.path().join(export.with_extension("il").file_name().unwrap());
        let output = ladderc(&["import", export.to_str().unwrap(), "-o", il.to_str().unwrap()]);
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        let text = std::fs::read_to_string(&il).unwrap();
        assert!(text.contains("// imported from"), "{text}");
        assert_eq!(ops(&compile(&export)), ops(&compile(&il)), "{}", export.display());
        let from_csv = compile(&export);
        assert!(!from_csv.instructions.is_empty());
    }
}

#[test]
fn the_real_export_keeps_its_step_numbers_and_structure() {
    let export = workspace().join("testsuite/programs/gxworks2/gxworks2_fx2n_main.csv");
    let output = ladderc(&["import", export.to_str().unwrap()]);
    assert!(output.status.success());
    let il = String::from_utf8(output.stdout).unwrap();
    for line in [
        "0\tLD\tX000",
        "72\tMOV\tK0 D0",
        "77\tADD\tD0 K1 D0",
        "583\tCALL\tP0",
        "624\tFEND",
        "625\tP0",
        "627\tEND",
    ] {
        assert!(il.lines().any(|l| l == line), "no line `{line}` in\n{il}");
    }
    let program = compile(&export);
    assert_eq!(program.subroutines.len(), 1, "P0 after FEND");
    assert!(program
        .instructions
        .iter()
        .any(|i| matches!(i.op, Op::Line(Line::LoopStart { .. }))));
}

#[test]
fn import_refuses_what_it_cannot_convert_and_writes_nothing() {
    let dir = scratch("import-refusals");
    let existing = dir.path().join("kept.il");
    std::fs::write(&existing, "LD X0\nOUT Y0\n").unwrap();
    // Plain IL needs no import.
    let plain = dir.path().join("plain.il");
    std::fs::write(&plain, "LD X0\nOUT Y0\n").unwrap();
    let output = ladderc(&["import", plain.to_str().unwrap(), "-o", existing.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("not an instruction-list export"));
    // A row that cannot be read: a diagnostic at its line.
    let bad = dir.path().join("bad.csv");
    std::fs::write(
        &bad,
        "\"MAIN\"\r\n\"PLC\"\t\"FX3U\"\r\n\"Step\"\t\"Statement\"\t\"Instruction\"\t\"Device\"\t\"\"\t\"PI\"\t\"Note\"\r\n\"0\"\t\"\"\t\"LD\"\t\"X0\r\n",
    )
    .unwrap();
    let output = ladderc(&["import", bad.to_str().unwrap(), "-o", existing.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("E0045") && stderr.contains("bad.csv:4:"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "LD X0\nOUT Y0\n");
    assert!(!dir.path().join("bad.il").exists());
}

#[test]
fn encodings_and_line_ends_are_read_as_the_file_says() {
    let dir = scratch("encodings");
    let text = "LD X0\r\nOUT Y0\r\n";
    let utf16: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(text.encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    let with_mark: Vec<u8> = [0xEF, 0xBB, 0xBF].into_iter().chain(text.bytes()).collect();
    let plain = compile_bytes(&dir, "plain.il", text.as_bytes());
    assert_eq!(ops(&compile_bytes(&dir, "utf16.il", &utf16)), ops(&plain));
    assert_eq!(ops(&compile_bytes(&dir, "mark.il", &with_mark)), ops(&plain));
    // Shift-JIS bytes without a mark: one clear error naming the marks.
    let sjis = dir.path().join("sjis.il");
    std::fs::write(&sjis, b"LD X0 ; \x83\x82\x81[\x83^\r\nOUT Y0\r\n").unwrap();
    let output = ladderc(&["check", sjis.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("E0046") && stderr.contains("FF FE"), "{stderr}");
    assert_eq!(stderr.matches("error[").count(), 1, "{stderr}");
}

fn compile_bytes(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> CheckedProgram {
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    compile(&path)
}
