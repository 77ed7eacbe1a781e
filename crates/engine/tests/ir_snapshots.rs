//! Snapshots of the optimised IR of the seed examples, the example programs
//! and a small program of each instruction family (from the scenarios), so
//! that a change in lowering shows up in review. Accept intended changes
//! with `INSTA_UPDATE=always cargo test -p ladder-engine --test ir_snapshots` and
//! review the diff.

use ladder_engine::scenario::{parse_scenario, ProgramSource};
use ladder_front::check::compile_source;
use ladder_front::source::SourceFile;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .expect("workspace root")
        .to_path_buf()
}

fn ir_of(name: &str, text: &str) -> String {
    let (program, diagnostics) = compile_source(&SourceFile::new(name, text));
    let program = program.unwrap_or_else(|| panic!("{name} does not compile: {diagnostics:?}"));
    ladder_engine::pipeline::Lowered::new(&program).ir().to_string()
}

fn snapshot_file(relative: &str) {
    let path = workspace().join(relative);
    let text = std::fs::read_to_string(&path).unwrap();
    let name = path.file_stem().unwrap().to_string_lossy().into_owned();
    insta::assert_snapshot!(name, ir_of(relative, &text));
}

/// The inline program of a scenario file.
fn snapshot_scenario(relative: &str) {
    let path = workspace().join(relative);
    let scenario = parse_scenario(&path, &std::fs::read_to_string(&path).unwrap()).unwrap();
    let ProgramSource::Inline { text, .. } = scenario.program else {
        panic!("{relative} has no inline program")
    };
    let name = path.file_stem().unwrap().to_string_lossy().into_owned();
    insta::assert_snapshot!(name, ir_of(relative, &text));
}

#[test]
fn stl_seed_examples() {
    snapshot_file("testsuite/programs/seeds/stl_example1_set_vs_st.il");
    snapshot_file("testsuite/programs/seeds/stl_example2_selective_branches.il");
    snapshot_file("testsuite/programs/seeds/stl_example3_parallel_branches.il");
}

#[test]
fn same_device_seed_examples() {
    for name in ["out_twice", "set_rst", "pls_different_timing", "plf_different_timing"] {
        snapshot_scenario(&format!("testsuite/scenarios/seeds/same_device/{name}.scn"));
    }
}

#[test]
fn transition_contact_seed_examples() {
    for name in [
        "coil_before_contact",
        "contact_before_coil",
        "set_reset_pair",
        "jump_skips_coil",
    ] {
        snapshot_scenario(&format!("testsuite/scenarios/seeds/transition/{name}.scn"));
    }
}

#[test]
fn example_programs() {
    snapshot_file("examples/traffic_light.il");
    snapshot_file("examples/motor_start_stop.il");
    snapshot_scenario("testsuite/scenarios/fx/master_control.scn");
    snapshot_scenario("testsuite/scenarios/data/offset_errors.scn");
}

/// FX structure: each subroutine a function of its own, a loop a back edge
/// with its count in a local and the watchdog asked before each repetition.
#[test]
fn fx_structure() {
    snapshot_file("testsuite/programs/fx/fx_station.il");
    snapshot_scenario("testsuite/scenarios/fx_structure/loop_nested_indexed_table.scn");
}

/// Snapshots of the scenarios `folder/name.scn`, one per name.
fn snapshot_scenarios(folder: &str, names: &[&str]) {
    for name in names {
        snapshot_scenario(&format!("testsuite/scenarios/{folder}/{name}.scn"));
    }
}

/// ADD/SUB with their flags, MUL/DIV, the 32-bit D forms, INC/DEC.
#[test]
fn arithmetic() {
    snapshot_scenarios("data", &["add_flags", "arithmetic"]);
}

/// CMP, DCMP and ZCP; comparison contacts (LD=, AND<, OR>=, the D forms).
#[test]
fn comparisons() {
    snapshot_scenarios("data", &["compare_instructions", "comparison_contacts"]);
}

/// MOV with digit groups and timer/counter values, DMOV; BMOV, FMOV, DFMOV.
#[test]
fn moves() {
    snapshot_scenarios("data", &["move_and_digits", "block_moves"]);
}

/// SFTLP and ROLP.
#[test]
fn shifts_and_rotations() {
    snapshot_scenarios("app/fx_data", &["sftl_example", "rol_example"]);
}

/// BCD and BIN.
#[test]
fn conversions() {
    snapshot_scenarios("app/fx_data", &["bcd_example", "bin_example"]);
}

/// OUT C of a 16-bit counter and of 32-bit C200 (with its direction relay);
/// OUT T of a 100 ms timer and of retentive T250/T246.
#[test]
fn counters_and_timers() {
    snapshot_scenarios(
        "fx",
        &["counter_16bit", "counter_32bit", "timer_100ms", "timer_retentive"],
    );
}

/// LDP/LDF, ANDP/ANDF, ORP/ORF; the pulse (P) forms of INC, MOV and DADD.
#[test]
fn edges_and_pulse_forms() {
    snapshot_scenarios("fx", &["edge_contacts"]);
    snapshot_scenarios("data", &["pulse_forms"]);
}

/// V and Z index registers on every kind of device; a FOR/NEXT loop filling
/// a table through Z0; a loop calling a subroutine (CALL/SRET).
#[test]
fn index_registers_loops_and_calls() {
    snapshot_scenarios(
        "fx_structure",
        &["index_registers_devices", "loop_fills_table", "loop_calls_subroutine"],
    );
}

/// ANS with its alarm relays, ANR and ANRP.
#[test]
fn alarms() {
    snapshot_scenarios("app", &["ans_example", "anr"]);
}
