//! Differential testing of the native code against the reference
//! interpreter: random programs (see `common`), random inputs and register
//! values, random scan times; after every scan the whole device image of the
//! two engines must be identical, byte for byte.

mod common;

use ladder_runtime::Memory;
use ladderc::check::compile_source;
use ladderc::diagnostics::render_all;
use ladderc::interp::Interpreter;
use ladderc::source::SourceFile;
use proptest::prelude::*;
use std::mem::offset_of;

/// Names the field that holds byte `offset` of the image.
fn field_at(offset: usize) -> String {
    let fields = [
        ("x", offset_of!(Memory, x)),
        ("y", offset_of!(Memory, y)),
        ("m", offset_of!(Memory, m)),
        ("s", offset_of!(Memory, s)),
        ("sm", offset_of!(Memory, sm)),
        ("timer_contact", offset_of!(Memory, timer_contact)),
        ("counter_contact", offset_of!(Memory, counter_contact)),
        ("d (2 bytes each)", offset_of!(Memory, d)),
        ("sd", offset_of!(Memory, sd)),
        ("r", offset_of!(Memory, r)),
        ("timer_value (2 bytes each)", offset_of!(Memory, timer_value)),
        ("counter_value (2 bytes each)", offset_of!(Memory, counter_value)),
        (
            "wide_counter_value (4 bytes each)",
            offset_of!(Memory, wide_counter_value),
        ),
        ("timer_remainder_ms", offset_of!(Memory, timer_remainder_ms)),
        ("timer_coil_was_on", offset_of!(Memory, timer_coil_was_on)),
        ("counter_coil_was_on", offset_of!(Memory, counter_coil_was_on)),
        ("stl_pending_off", offset_of!(Memory, stl_pending_off)),
        ("stl_block_active", offset_of!(Memory, stl_block_active)),
        ("edge_slot", offset_of!(Memory, edge_slot)),
        ("input_image", offset_of!(Memory, input_image)),
    ];
    let (name, start) = fields
        .iter()
        .rev()
        .find(|(_, start)| *start <= offset)
        .copied()
        .unwrap_or(("?", 0));
    format!("{name} + byte {}", offset - start)
}

/// One scan's stimulus: inputs X0..X7, D0..D3, and the elapsed time.
#[derive(Clone, Debug)]
struct Stimulus {
    inputs: u8,
    registers: Option<[i16; 4]>,
    elapsed_ms: u32,
}

fn stimulus() -> impl Strategy<Value = Stimulus> {
    (
        any::<u8>(),
        proptest::option::weighted(
            0.3,
            (
                -3i16..12,
                -3i16..12,
                prop_oneof![Just(-1i16), Just(9000), 0i16..5],
                -2i16..6,
            )
                .prop_map(|(a, b, c, d)| [a, b, c, d]),
        ),
        prop_oneof![Just(10u32), Just(100), 0u32..250],
    )
        .prop_map(|(inputs, registers, elapsed_ms)| Stimulus {
            inputs,
            registers,
            elapsed_ms,
        })
}

fn apply(mem: &mut Memory, stimulus: &Stimulus) {
    for bit in 0..8 {
        mem.input_image[bit] = (stimulus.inputs >> bit) & 1;
    }
    if let Some(registers) = stimulus.registers {
        mem.d[..4].copy_from_slice(&registers);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn jit_matches_interpreter(text in common::program(), stimuli in proptest::collection::vec(stimulus(), 1..25)) {
        let file = SourceFile::new("gen.il", text.as_str());
        let (program, diagnostics) = compile_source(&file);
        let Some(program) = program else {
            panic!("generated program rejected:\n{text}\n{}", render_all(&file, &diagnostics));
        };
        let jit = ladderc::pipeline::jit(&program).expect("compiles");
        let interpreter = Interpreter::new(&program);
        let mut expected = Memory::new_boxed();
        let mut actual = Memory::new_boxed();
        for (scan, stimulus) in stimuli.iter().enumerate() {
            apply(&mut expected, stimulus);
            apply(&mut actual, stimulus);
            interpreter.scan(&mut expected, stimulus.elapsed_ms);
            actual.scan_with(stimulus.elapsed_ms, |mem| jit.run(mem));
            let (a, b) = (bytemuck::bytes_of(&*expected), bytemuck::bytes_of(&*actual));
            if let Some(offset) = a.iter().zip(b).position(|(x, y)| x != y) {
                prop_assert!(
                    false,
                    "scan {}: images differ at {} (interp {} / jit {})\nprogram:\n{}\nIR:\n{}",
                    scan + 1, field_at(offset), a[offset], b[offset], text, ladderc::pipeline::ir(&program)
                );
            }
        }
    }
}
