//! The codecs on the sample project (testsuite/gxdeveloper/3floor_elevator,
//! MIT) and on broken files.

use super::*;
use crate::source::SourceFile;

fn sample() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testsuite/gxdeveloper/3floor_elevator")
}

fn bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap()
}

#[test]
fn the_sample_is_located_from_each_of_its_files() {
    let dir = sample();
    let project = locate(&dir).unwrap();
    assert_eq!(project, Project::in_folder(&dir));
    assert_eq!(locate(&dir.join("Gppw.gps")), Some(project.clone()));
    assert_eq!(locate(&project.program), Some(project));
    assert_eq!(locate(&dir.join("param.wpa")), None);
}

#[test]
fn the_sample_reads_as_a_listing() {
    let listing = read(&locate(&sample()).unwrap()).unwrap();
    let lines: Vec<&str> = listing.lines().collect();
    assert!(lines.contains(&"//@ cpu FX2N"), "{listing}");
    assert!(lines.contains(&"//@ memory 2000"));
    assert!(lines
        .contains(&"//@ latch M500-M1023,S500-S999,C100-C199,C220-C255,D200-D511,M1024-M3071,T246-T255,D512-D7999"));
    assert!(lines.contains(&"//@ encoding Big5"));
    assert!(lines.contains(&"0\tLD\tM99"));
    assert!(lines.contains(&"1\tMC\tN0 M100"));
    assert!(lines.contains(&"168\tEND"));
    assert!(lines.iter().any(|l| l.starts_with("//@ comment Y011 ")));
    assert_eq!(lines.iter().filter(|l| l.starts_with("//@ comment")).count(), 40);
    let timer = lines.iter().find(|l| l.contains("OUT\tT0")).unwrap();
    assert!(timer.ends_with("OUT\tT0 K30"), "{timer}");
    let instructions = lines
        .iter()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .count();
    assert_eq!(instructions, 159);
}

#[test]
fn the_sample_compiles_without_errors() {
    let file = SourceFile::read(&sample()).unwrap();
    let (program, diagnostics) = crate::check::compile_source(&file);
    assert!(program.is_some(), "{diagnostics:?}");
    assert!(file.name.ends_with("MAIN.wpg"));
}

#[test]
fn the_sample_writes_back_byte_for_byte() {
    let project = locate(&sample()).unwrap();
    let file = SourceFile::read(&sample()).unwrap();
    let (program, comments) = write::encode(&file, &write::Defaults::default()).unwrap();
    assert_eq!(program, bytes(&project.program));
    assert_eq!(comments, bytes(&project.comments));
}

#[test]
fn a_lone_program_file_is_recognised_by_content() {
    let project = locate(&sample()).unwrap();
    let file = SourceFile::from_bytes("copy.bin", &bytes(&project.program));
    assert!(file.text.contains("0\tLD\tM99"), "{:?}", file.decode_error);
    assert!(!file.text.contains("//@ comment"));
}

#[test]
fn every_truncation_and_corruption_is_one_error() {
    let project = locate(&sample()).unwrap();
    let files = [
        bytes(&project.program),
        bytes(&project.comments),
        bytes(&project.parameters),
    ];
    for (which, original) in files.iter().enumerate() {
        let decode = |data: &[u8]| match which {
            0 => wpg::decode(data).map(|_| ()),
            1 => wcd::decode(data).map(|_| ()),
            _ => wpa::decode(data).map(|_| ()),
        };
        decode(original).unwrap();
        for cut in (0..original.len()).step_by(7) {
            let data = &original[..cut];
            // A cut in the program's NOP padding (after END) reads only
            // where it leaves a whole number of thousands of steps (a
            // smaller program memory, still the whole program); any other
            // cut is an error inside the file.
            // (The program ends at 0x46D after 169 steps; a NOP is two bytes.)
            let whole = |cut: usize| {
                cut >= 0x46D && (cut - 0x46D).is_multiple_of(2) && (169 + (cut - 0x46D) / 2).is_multiple_of(1000)
            };
            match decode(data) {
                Err(error) => assert!(error.offset <= cut, "{which} cut at {cut}: {error:?}"),
                Ok(()) => assert!(which == 0 && whole(cut), "{which} cut at {cut} decodes"),
            }
        }
        for at in 0..original.len().min(600) {
            let mut data = original.clone();
            data[at] ^= 0x5A;
            let _ = decode(&data);
        }
    }
    let mut cut = bytes(&project.program);
    cut.truncate(0x50);
    let file = SourceFile::from_bytes("MAIN.wpg", &cut);
    let (program, diagnostics) = crate::check::compile_source(&file);
    assert!(program.is_none());
    assert_eq!(diagnostics.len(), 1);
    assert_eq!(diagnostics[0].code, crate::diagnostics::Code::UndecodableProject);
    assert!(
        diagnostics[0].message.contains("byte offset"),
        "{}",
        diagnostics[0].message
    );
}

#[test]
fn a_program_without_end_is_written_with_one() {
    let file = SourceFile::new("t.il", "LD M0\nWAND D0 D2 D4\n");
    let defaults = write::Defaults {
        cpu: None,
        memory: Some(1000),
    };
    let (main, _) = write::encode(&file, &defaults).unwrap();
    let listing = listing_of(("MAIN.wpg", &main), None, None).unwrap();
    assert!(listing.ends_with("0\tLD\tM0\n1\tWAND\tD0 D2 D4\n8\tEND\n"), "{listing}");
}

#[test]
fn an_instruction_ladderc_does_not_run_is_e0032_at_its_step() {
    // SFR has a known code; ladderc does not implement it.
    let file = SourceFile::new("t.il", "LD X0\nSFR D0 K1\nEND\n");
    let (main, _) = write::encode(&file, &write::Defaults::default()).unwrap();
    let project = SourceFile::from_bytes("MAIN.wpg", &main);
    let (program, diagnostics) = crate::check::compile_source(&project);
    assert!(program.is_none());
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert_eq!(diagnostics[0].code, crate::diagnostics::Code::UnsupportedFx);
    assert!(
        diagnostics[0].notes.iter().any(|n| n == "at MAIN.wpg step 1"),
        "{diagnostics:?}"
    );
}

/// A program file: the header, `records` and END, with NOPs to `steps`.
fn program_of(body: &[&[u8]], steps: usize) -> Vec<u8> {
    let mut bytes = records::header(8, &[0x03, 0x03, 0x01]);
    bytes.extend([0x04, 0x00, 0xFF, 0xFF]);
    for payload in body {
        records::push(&mut bytes, payload);
    }
    records::push(&mut bytes, &[0x34]);
    for _ in body.len() + 1..steps {
        records::push(&mut bytes, &[]);
    }
    bytes
}

#[test]
fn a_program_past_the_largest_memory_stops_at_the_step_that_passes_it() {
    // 70,000 NOPs: reading stops at the 64,001st step's record.
    let nops: Vec<&[u8]> = vec![&[]; 70_000];
    let bytes = program_of(&nops, 0);
    let error = wpg::decode(&bytes).unwrap_err();
    assert_eq!(error.offset, 0x44 + 64_000 * 2, "{error:?}");
    assert!(error.expected.contains("64000"), "{error:?}");
    // 64,000 steps in all is the largest program memory, and reads.
    let full = program_of(&[], 64_000);
    assert_eq!(wpg::decode(&full).unwrap().capacity, 64_000);
    // Statements take no steps, but they are bounded as well.
    let statements: Vec<&[u8]> = vec![&[0x80, 0x00, b'x']; 70_000];
    let error = wpg::decode(&program_of(&statements, 0)).unwrap_err();
    assert_eq!(error.offset, 0x44 + 64_000 * 5, "{error:?}");
}

#[test]
fn a_program_cut_in_its_nops_is_an_error_at_the_end() {
    let project = locate(&sample()).unwrap();
    let original = bytes(&project.program);
    let cut = &original[..4001];
    let error = wpg::decode(cut).unwrap_err();
    assert_eq!(error.offset, 4001, "{error:?}");
    assert!(error.expected.contains("NOPs"), "{error:?}");
    let file = SourceFile::from_bytes("MAIN.wpg", cut);
    assert!(file.decode_error.is_some(), "{}", file.text);
    // One thousand steps more than the parameters' 2000: the size does not
    // match them.
    let mut longer = original.clone();
    for _ in 0..1000 {
        records::push(&mut longer, &[]);
    }
    let parameters = bytes(&project.parameters);
    let error = listing_of(("MAIN.wpg", &longer), None, Some(("param.wpa", &parameters))).unwrap_err();
    assert_eq!(error.file, "MAIN.wpg");
    assert_eq!(error.error.offset, longer.len(), "{error}");
    assert!(listing_of(("MAIN.wpg", &original), None, Some(("param.wpa", &parameters))).is_ok());
}

/// A copy of the sample in a scratch folder.
fn sample_copy(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ladder-front-gxdev-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for file in ["Gppw.gps", "param.wpa", "Pou/Body/MAIN.wpg", "Others/COMMENT.wcd"] {
        let to = dir.join(file);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(sample().join(file), to).unwrap();
    }
    dir
}

#[test]
fn a_file_that_cannot_be_read_is_a_read_error_and_a_broken_comment_file_is_named() {
    let dir = sample_copy("read");
    let project = Project::in_folder(&dir);
    // A broken COMMENT.wcd: the error is COMMENT.wcd's.
    std::fs::write(&project.comments, &bytes(&project.comments)[..100]).unwrap();
    let file = SourceFile::read(&dir).unwrap();
    assert!(file.name.ends_with("COMMENT.wcd"), "{}", file.name);
    let (_, diagnostics) = crate::check::compile_source(&file);
    assert!(diagnostics[0].message.contains("COMMENT.wcd"), "{diagnostics:?}");
    // No MAIN.wpg: not a decode error but a file that cannot be read.
    std::fs::remove_file(&project.program).unwrap();
    assert!(matches!(read(&project), Err(ReadFailure::Read(_))));
    assert!(SourceFile::read(&dir).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn more_comment_ranges_than_the_file_holds_are_refused() {
    // Every other device: one range each.
    let comments: Vec<(u8, u32, String)> = (0..6553).map(|n| (records::code::D, n * 2, "c".to_string())).collect();
    let error = wcd::encode(8, &comments, text::Encoding::ShiftJis).unwrap_err();
    assert!(error.contains("6552"), "{error}");
    let fits = wcd::encode(8, &comments[..6552], text::Encoding::ShiftJis).unwrap();
    assert_eq!(wcd::decode(&fits).unwrap().entries.len(), 6552);
}
