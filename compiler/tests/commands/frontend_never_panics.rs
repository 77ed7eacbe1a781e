//! The front end never panics, whatever it is given: random bytes, and random
//! sequences of real mnemonics and operand-like words. Programs that happen to
//! compile are also run for a few scans on the interpreter with random
//! register contents (offsets out of range and all), which must not panic.

use ladder_front::check::compile_source;
use ladder_front::diagnostics::render_all;
use ladder_front::source::SourceFile;
use ladder_interp::Interpreter;
use ladder_runtime::Memory;
use proptest::prelude::*;

use crate::common;

fn compile_and_render(text: &str) {
    let file = SourceFile::new("fuzz.il", text);
    let (program, diagnostics) = compile_source(&file);
    // Rendering must cope with every span the front end produces.
    let _ = render_all(&file, &diagnostics, ladder_front::diagnostics::Shown::All);
    if let Some(program) = program {
        let mut mem = Memory::new_boxed();
        for (i, value) in (0..16).zip([-1i16, 3, 8511, -32768, 32767, 200, 7, 0].iter().cycle()) {
            mem.d[i] = *value;
        }
        let interpreter = Interpreter::new(&program);
        for _ in 0..3 {
            interpreter.scan(&mut mem, 10);
            mem.input_image.iter_mut().for_each(|b| *b ^= 1);
        }
    }
}

fn operand() -> impl Strategy<Value = String> {
    prop_oneof![
        "[XY][0-7]{1,3}",
        "(M|S|SM|T|C|TS|CS|TN|CN|D|SD|R)[0-9]{1,5}",
        "K-?[0-9]{1,11}",
        "H[0-9A-F]{1,9}",
        "K[1-9](X|Y|M|S)[0-9]{1,4}",
        "D[0-9]{1,4}\\.[0-9A-G]",
        "(D|M|K4M|Y)[0-9]{1,4}\\[D[0-9]{1,5}\\]",
        "(P|N)[0-9]{1,5}",
        "[ -~]{1,6}",
    ]
}

fn line() -> impl Strategy<Value = String> {
    let mnemonics: Vec<String> = ladder_front::isa::mnemonics().into_iter().map(str::to_string).collect();
    let mnemonic = prop_oneof![
        4 => proptest::sample::select(mnemonics),
        1 => "[A-Z]{1,5}",
    ];
    (
        proptest::option::of("[0-9]{1,4} "),
        mnemonic,
        proptest::collection::vec(operand(), 0..4),
        "( |,|// x|;y)?",
    )
        .prop_map(|(step, mnemonic, operands, tail)| {
            format!("{}{mnemonic} {}{tail}", step.unwrap_or_default(), operands.join(" "))
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        compile_and_render(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn random_token_sequences(lines in proptest::collection::vec(line(), 0..40)) {
        compile_and_render(&lines.join("\n"));
    }

    #[test]
    fn random_valid_programs(text in common::program()) {
        let file = SourceFile::new("gen.il", text.as_str());
        let (program, diagnostics) = compile_source(&file);
        prop_assert!(program.is_some(), "generated program rejected:\n{}\n{}", text, render_all(&file, &diagnostics, ladder_front::diagnostics::Shown::All));
        compile_and_render(&text);
    }
}
