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
            // A cut in the program's NOP padding (after END) is a smaller
            // program memory, still the whole program; any other cut is an
            // error inside the file.
            match decode(data) {
                Err(error) => assert!(error.offset <= cut, "{which} cut at {cut}: {error:?}"),
                Ok(()) => assert!(which == 0 && cut >= 0x46D, "{which} cut at {cut} decodes"),
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
        memory: Some(100),
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
