//! The bytes of x86-64 code for bit logic. A long program's scan runs from
//! the instruction decoders and is bound by the bytes of its code
//! (`crates/codegen/src/near.rs`), so devices are addressed from base
//! registers near them (one-byte displacements instead of four), and a
//! rung's inversions are carried along by De Morgan, made only where an
//! inverted value leaves the logic (`crates/codegen/src/translate.rs`).

use crate::common::tools::{ladderc, scratch};
use object::{Object, ObjectSection, ObjectSymbol};
use std::fmt::Write as _;

const RUNGS: usize = 100;

/// `RUNGS` rungs of eight instructions, each with three inversions, on
/// relays M1000-M1205 and M1500-M1699 (two areas of a few hundred bytes,
/// far from the image's start).
fn program() -> String {
    let mut text = String::new();
    for rung in 0..RUNGS {
        let at = 1000 + (rung * 7) % 200;
        let out = 1500 + (rung * 3) % 200;
        writeln!(
            text,
            "LD M{at}\nANI M{}\nORI M{}\nAND M{}\nLDI M{}\nOR M{}\nANB\nOUT M{out}",
            at + 1,
            at + 2,
            at + 3,
            at + 4,
            at + 5
        )
        .unwrap();
    }
    text
}

/// The bytes of the object's program body.
fn body(object: &[u8]) -> Vec<u8> {
    let file = object::File::parse(object).expect("an object file");
    assert_eq!(file.architecture(), object::Architecture::X86_64);
    let symbol = file
        .symbols()
        .find(|s| s.name() == Ok("ladder_program_body"))
        .expect("the program's body");
    let section = file
        .section_by_index(symbol.section_index().expect("in a section"))
        .unwrap();
    let data = section.data().unwrap();
    let start = (symbol.address() - section.address()) as usize;
    data[start..start + symbol.size() as usize].to_vec()
}

#[test]
fn bit_logic_is_short_on_x86_64() {
    let dir = scratch("code-size");
    let source = dir.path().join("logic.il");
    std::fs::write(&source, program()).unwrap();
    let output = dir.path().join("logic.o");
    let result = ladderc(&[
        "build",
        source.to_str().unwrap(),
        "--target",
        "x86_64-unknown-linux-gnu",
        "-o",
        output.to_str().unwrap(),
    ]);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let body = body(&std::fs::read(&output).unwrap());
    let instructions = RUNGS * 8;
    // Measured: 5.4 bytes per instruction; 8.0 with every displacement
    // four bytes and each inversion made where it occurs.
    let per_instruction = body.len() as f64 / instructions as f64;
    assert!(
        per_instruction < 6.0,
        "{} bytes of code for {instructions} instructions",
        body.len()
    );
    // `xor r32, 1` (83 /6 ib, with or without REX.B): these rungs store
    // no inverted value, so none is made (about two a rung when every
    // inversion was made where it occurs); the count is of byte patterns,
    // which other instructions' bytes could form by chance, hence not 0.
    let xors = body
        .windows(3)
        .filter(|w| w[0] == 0x83 && (0xf0..=0xf7).contains(&w[1]) && w[2] == 1)
        .count();
    assert!(xors <= 5, "{xors} XORs by 1 in {RUNGS} rungs");
}
