//! Large programs are compiled as several functions (cut where only memory
//! passes between them; master-control powers travel in a stack slot). Here
//! every program is cut after every few IR instructions, so the random
//! programs of the differential test, with MC regions, jumps and STL blocks,
//! all take that path on the JIT and the object-file path, and must still
//! leave the interpreter's image after every scan.

use crate::common;

use crate::common::differential;
use proptest::strategy::Just;

#[test]
fn programs_compiled_in_parts_match_the_interpreter() {
    ladder_codegen::set_chunk_instructions(8);
    let test = "programs_compiled_in_parts_match_the_interpreter";
    let aot = differential::native_hosts(test);
    let seed = differential::seed(test);
    let totals = differential::check(test, differential::case(common::program()), seed, 45, 100, &aot);
    assert_eq!(totals.programs, 45);
}

/// FX-structured programs in parts: loop counts travel in the stack slot
/// with the MC powers (a loop is never cut: its back edge forbids it), and
/// each subroutine is cut on its own.
#[test]
fn fx_programs_compiled_in_parts_match_the_interpreter() {
    ladder_codegen::set_chunk_instructions(8);
    let test = "fx_programs_compiled_in_parts_match_the_interpreter";
    let aot = differential::native_hosts(test);
    let seed = differential::seed(test);
    let totals = differential::check(test, differential::case(common::fx::fx_program()), seed, 30, 100, &aot);
    assert_eq!(totals.programs, 30);
}

/// Master-control rungs ending in a data instruction (a branch, so a block
/// boundary after which no value of the rung lives): cut into many parts,
/// with the MC power crossing them. (Cuts are only made where no SSA value
/// crosses; a program that is one long block stays one function.)
#[test]
fn a_program_cut_into_parts_keeps_master_control_across_them() {
    ladder_codegen::set_chunk_instructions(8);
    let rungs: String = (0..40)
        .map(|i| format!("LDI M{}\nOUT Y{}\nLDI M{}\nINC D{i}\n", 100 + i, i % 8, 200 + i))
        .collect();
    let text = format!("LD X0\nMC N0 M0\n{rungs}MCR N0\nLD X1\nMC N0 M1\n{rungs}MCR N0\n");
    let program = differential::compile(&text);
    let object = ladder_engine::pipeline::Lowered::new(&program)
        .object(&Default::default(), &Default::default())
        .expect("compiles")
        .output;
    let parts = String::from_utf8_lossy(&object).matches(".part").count();
    assert!(parts > 10, "{parts} parts");
    let totals = differential::check(
        "a_program_cut_into_parts_keeps_master_control_across_them",
        differential::case(Just(text)),
        7,
        30,
        30,
        &[],
    );
    assert_eq!(totals.programs, 30);
}
