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
