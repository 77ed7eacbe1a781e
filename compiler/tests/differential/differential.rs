//! Differential testing of the native code against the reference
//! interpreter, the project's strongest safety net: random programs drawn
//! from the instruction table (see `common`) with STL, MC/MCR, CJ, edges,
//! timers of every resolution and counters, driven by random inputs, host
//! writes, forces and elapsed times up to a whole `u32`; after every scan
//! the whole device image of the JIT, of the object-file path and of the C
//! route (the C back end's source compiled by gcc -O2; both linked with the
//! runtime library into a C host) must equal the interpreter's, and so must
//! every device of the C route's compact image (`--image compact`: only the
//! devices the program and its host use; every other batch of programs). A
//! divergence is shrunk and written out as a scenario file.
//!
//! CI runs 240 programs (four tests of 40 random programs, so both cores
//! work, and 40 each of memory-forwarding and FX-structured programs: the
//! share that keeps CI within its time; the seed changes with every commit,
//! so the programs do too, and the suite covers more with every commit).
//! The long run is an ignored test:
//!
//! ```text
//! LADDER_DIFFERENTIAL_SCANS=1000000 cargo test --release -p ladderc \
//!     --test differential -- --ignored --nocapture long_run
//! ```
//!
//! `LADDER_DIFFERENTIAL_SEED` fixes the seed (it is printed on failure).

use crate::common;

use crate::common::differential::{self, Totals};
use crate::common::tools;
use proptest::strategy::{BoxedStrategy, Strategy};

/// Programs each CI test runs (see the module comment).
const PROGRAMS_PER_TEST: usize = 40;

fn run_share(test: &str, share: u64) -> Totals {
    run_programs(test, share, common::program().boxed(), PROGRAMS_PER_TEST)
}

fn run_programs(test: &str, share: u64, programs: BoxedStrategy<String>, count: usize) -> Totals {
    let aot = differential::native_hosts(test);
    let seed = differential::seed(test).wrapping_add(share);
    let totals = differential::check(test, differential::case(programs), seed, count, 100, &aot);
    eprintln!(
        "{test}: {} programs, {} scans, {} on the object-file path, {} on the C route, {} with a compact \
         image: every image equal",
        totals.programs, totals.scans, totals.aot_programs, totals.c_programs, totals.compact_programs
    );
    assert_eq!(totals.programs, count);
    totals
}

/// Programs made to exercise the compiler's memory forwarding (see
/// `common::memory_rung`).
#[test]
fn memory_forwarding_matches_the_interpreter() {
    run_programs(
        "memory_forwarding_matches_the_interpreter",
        5,
        common::memory_program().boxed(),
        PROGRAMS_PER_TEST,
    );
}

/// FX-structured programs: index registers, FOR/NEXT loops (the IR's back
/// edges) up to the watchdog, subroutines compiled once and called, and an
/// STL sequence closed by RET (see `common::fx`).
#[test]
fn fx_structure_matches_the_interpreter() {
    run_programs(
        "fx_structure_matches_the_interpreter",
        6,
        common::fx::fx_program().boxed(),
        PROGRAMS_PER_TEST,
    );
}

#[test]
fn every_engine_matches_the_interpreter_1() {
    run_share("every_engine_matches_the_interpreter_1", 1);
}

#[test]
fn every_engine_matches_the_interpreter_2() {
    run_share("every_engine_matches_the_interpreter_2", 2);
}

#[test]
fn every_engine_matches_the_interpreter_3() {
    run_share("every_engine_matches_the_interpreter_3", 3);
}

#[test]
fn every_engine_matches_the_interpreter_4() {
    run_share("every_engine_matches_the_interpreter_4", 4);
}

/// The harness itself: a case whose native code is made to differ is
/// caught, located and written out as a scenario that the interpreter
/// passes and that names the differing device.
#[test]
fn a_divergence_becomes_a_scenario() {
    use common::stimulus::{HostAction, Step};
    let case = differential::Case {
        program: "LD X0\nOUT Y0\n".to_string(),
        steps: vec![
            Step {
                actions: vec![HostAction::Input(0, true)],
                elapsed_ms: 10,
            },
            Step {
                actions: vec![],
                elapsed_ms: u32::MAX,
            },
        ],
    };
    let program = differential::compile(&case.program);
    let expected = differential::interpreter_image(&case, &ladder_engine::pipeline::Lowered::new(&program), 2);
    let mut wrong = expected.clone();
    wrong.y[0] = 0;
    let divergence = differential::Divergence {
        engine: "jit",
        scan: 1,
        differences: common::image::differences(&expected, &wrong),
    };
    let text = differential::scenario(&case, &divergence);
    assert!(text.contains("# y[0]: interpreter 1, jit 0"), "{text}");
    assert!(text.contains("set X0 1\n"), "{text}");
    assert!(text.contains("scan-ms 4294967295\nscan\nexpect Y0 1\n"), "{text}");
    let path = differential::write_scenario("harness-self-test", &text);
    let output = tools::ladderc(&["test", "--engine", "interp", path.to_str().unwrap()]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stdout));
}

/// The long run: LADDER_DIFFERENTIAL_SCANS program-scans (default one
/// million) on every engine, reporting its counts.
#[test]
#[ignore = "long run: about a million program-scans; see the module comment"]
fn long_run() {
    let target: usize = std::env::var("LADDER_DIFFERENTIAL_SCANS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let aot = differential::native_hosts("long_run");
    let seed = differential::seed("long_run");
    let started = std::time::Instant::now();
    let mut totals = Totals::default();
    let mut round = 0;
    while totals.scans < target {
        let part = differential::check(
            "long_run",
            differential::case(common::program()),
            seed.wrapping_add(round),
            1000,
            200,
            &aot,
        );
        totals.programs += part.programs;
        totals.scans += part.scans;
        totals.aot_programs += part.aot_programs;
        totals.c_programs += part.c_programs;
        round += 1;
        eprintln!(
            "long_run: {} programs, {} program-scans, {} programs on the object-file path, {} on the C route, {:.0?}",
            totals.programs,
            totals.scans,
            totals.aot_programs,
            totals.c_programs,
            started.elapsed()
        );
    }
}

/// A logic stack read while empty: the checker refuses such a program
/// (E0010, E0011), but the engines must still agree on what it would do,
/// and they do by the same rule: the value read is OFF. The program is
/// checked with its MPS and then loses it, as no source can say.
#[test]
fn an_empty_logic_stack_reads_off_on_every_engine() {
    // Each program without its instruction 1: an MRD and MPP without MPS,
    // an ORB without a block before it.
    for text in [
        "LD X0\nMPS\nAND X1\nOUT Y0\nMRD\nOUT Y1\nMPP\nOUT Y2\n",
        "LD X0\nLD X1\nAND X2\nORB\nOUT Y0\n",
    ] {
        let mut program = differential::compile(text);
        program.instructions.remove(1);
        program.main_end -= 1;
        let interpreter = ladder_interp::Interpreter::new(&program);
        let jit = ladder_engine::pipeline::Lowered::new(&program).jit().expect("compiles");
        let (mut expected, mut actual) = (ladder_runtime::Memory::new_boxed(), ladder_runtime::Memory::new_boxed());
        for mem in [&mut expected, &mut actual] {
            mem.input_image[..3].fill(1);
        }
        interpreter.scan(&mut expected, 10);
        actual.scan_with(10, |mem| jit.run(mem));
        assert_eq!(&expected.y[..3], &actual.y[..3], "{text}");
    }
}
