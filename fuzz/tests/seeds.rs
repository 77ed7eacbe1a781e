//! Every fuzz target over the seeds the fuzzers start from (the example
//! programs, the test programs, scenario files, Modbus and HTTP requests
//! as `run-afl.sh` writes them), so CI runs the targets' logic on every
//! commit and a target that panics on its own seeds is found before a
//! fuzzing campaign.

use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .to_path_buf()
}

fn files(dir: &Path, extension: &str, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files(&path, extension, out);
        } else if path.extension().is_some_and(|e| e == extension) {
            out.push(path);
        }
    }
    out.sort();
}

fn programs() -> Vec<PathBuf> {
    let mut found = Vec::new();
    files(&workspace().join("examples"), "il", &mut found);
    files(&workspace().join("testsuite/programs"), "il", &mut found);
    assert!(found.len() >= 10, "found the seed programs: {found:?}");
    found
}

#[test]
fn front_end_and_pipeline_take_every_seed_program() {
    for path in programs() {
        let bytes = std::fs::read(&path).unwrap();
        ladderc_fuzz::front_end(&bytes);
        ladderc_fuzz::pipeline(&bytes);
    }
}

#[test]
fn scenario_takes_scenario_files() {
    let mut found = Vec::new();
    files(&workspace().join("testsuite/scenarios"), "scn", &mut found);
    assert!(found.len() >= 100, "found the scenarios");
    // Every seventh file: the whole suite runs in the testsuite's tests.
    for path in found.iter().step_by(7) {
        ladderc_fuzz::scenario(&std::fs::read(path).unwrap());
    }
}

#[test]
fn properties_takes_property_files() {
    let mut found = Vec::new();
    files(&workspace().join("testsuite/properties"), "prop", &mut found);
    assert!(found.len() >= 12, "found the property files");
    // Inline programs only: the target names its file `fuzz.prop`, so a
    // `program FILE` is not found, which is one of the errors it takes.
    for path in &found {
        ladderc_fuzz::properties(&std::fs::read(path).unwrap());
    }
    ladderc_fuzz::properties(b"program <<\nLD X0\nOUT Y0\n>>\nnever Y0 & \xff\xfe\n");
}

#[test]
fn modbus_takes_requests_and_garbage() {
    let seeds: [&[u8]; 6] = [
        b"\x01\x00\x01\x00\x00\x00\x06\x01\x03\x00\x00\x00\x0a",
        b"\x01\x00\x02\x00\x00\x00\x06\x01\x05\x00\x00\xff\x00\x00\x03\x00\x00\x00\x06\x01\x05\x00\x00\x12\x34",
        b"\x00\x00\x04\x00\x00\x00\x0b\x01\x10\x00\x00\x00\x02\x04\x00\x01\x00\x02",
        b"\x01\x00\x05\x00\x00\x00\x08\x01\x0f\x4e\x20\x00\x09\x02\xff\x01",
        b"\x01\x00\x06\x00\x00\x00\x03\x01\x2b\x0e",
        b"\x01\xff\xff\xff\xff\xff",
    ];
    for seed in seeds {
        ladderc_fuzz::modbus(seed);
    }
}

#[test]
fn melsec_takes_every_frame_kind_and_garbage() {
    let seeds: [&[u8]; 8] = [
        // 1E binary: read M100-M107; random write X0; remote STOP; model.
        b"\x01\x00\xff\x0a\x00\x64\x00\x00\x00\x20\x4d\x08\x00",
        b"\x01\x04\xff\x0a\x00\x01\x00\x00\x00\x00\x00\x20\x58\x01\x14\xff\x0a\x00\x15\xff\x0a\x00",
        // 1E ASCII: read D100 as two words; unknown command.
        b"\x0101FF000A4420000000640200",
        b"\x0117FF000A",
        // 3E binary: read D100 x3; write M5; 4E binary: read X0 as bits.
        b"\x01\x50\x00\x00\xff\xff\x03\x00\x0c\x00\x10\x00\x01\x04\x00\x00\x64\x00\x00\xa8\x03\x00",
        b"\x01\x54\x00\x34\x12\x00\x00\x00\xff\xff\x03\x00\x0c\x00\x10\x00\x01\x04\x01\x00\x00\x00\x00\x9c\x08\x00",
        // 3E ASCII: read D100 x3; loopback.
        b"\x00500000FF03FF000018001004010000D*0001000003500000FF03FF0000120010061900000003ABC",
        b"\x01\x50\x00\x00\xff\xff\x03\x00\xff\xff",
    ];
    for seed in seeds {
        ladderc_fuzz::melsec(seed);
    }
}

#[test]
fn modbus_rtu_takes_frames_noise_and_broadcasts() {
    let seeds: [&[u8]; 4] = [
        // Read holding register 0 from unit 1; the same with a bad CRC.
        b"\x01\x08\x01\x03\x00\x00\x00\x01\x84\x0a\x08\x01\x03\x00\x00\x00\x01\x00\x00",
        // A broadcast write of D0 (unit 0), then another unit.
        b"\x01\x08\x00\x06\x00\x00\x00\x07\xc9\xd9\x08\x02\x03\x00\x00\x00\x01\x84\x39",
        // Write coils with a byte count that does not match; too short.
        b"\x01\x0a\x01\x0f\x00\x00\x00\x09\x01\xff\x00\x00\x02\x01\x03",
        b"\x00\xff\x01",
    ];
    for seed in seeds {
        ladderc_fuzz::modbus_rtu(seed);
    }
}

#[test]
fn http_takes_requests() {
    let seeds: [&[u8]; 6] = [
        b"GET /api/devices?watch=Y0..Y7,D10:32,D0:hex",
        b"POST /api/set\n{\"device\": \"D20:32\", \"value\": 100000}",
        b"POST /api/force\n{\"device\": \"X0\", \"value\": \"on\"}",
        b"POST /api/control\n{\"action\": \"step\", \"scans\": 3}",
        b"POST /api/program?allow_empty=1\nLD X0\nOUT Y0\n",
        b"GET /api/ladder/state?rungs=0,1,2",
    ];
    for seed in seeds {
        ladderc_fuzz::http(seed);
    }
}

#[test]
fn gx_developer_takes_the_sample_project_whole_cut_and_flipped() {
    let dir = workspace().join("testsuite/gxdeveloper/3floor_elevator");
    let files = [
        dir.join("Pou/Body/MAIN.wpg"),
        dir.join("Others/COMMENT.wcd"),
        dir.join("param.wpa"),
    ];
    for (which, path) in files.iter().enumerate() {
        let bytes = std::fs::read(path).unwrap();
        let seed = |body: &[u8]| [&[which as u8][..], body].concat();
        ladderc_fuzz::gx_developer(&seed(&bytes));
        for cut in (0..bytes.len()).step_by(97) {
            ladderc_fuzz::gx_developer(&seed(&bytes[..cut]));
        }
        for at in (0..bytes.len().min(400)).step_by(3) {
            let mut flipped = bytes.clone();
            flipped[at] = flipped[at].wrapping_add(0x41);
            ladderc_fuzz::gx_developer(&seed(&flipped));
        }
    }
}
