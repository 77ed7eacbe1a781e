//! Checker tests that scenarios cannot express: how many diagnostics, which
//! codes, and the shape of the checked program. (They match only the
//! variants they look for.)
#![allow(clippy::wildcard_enum_match_arm)]

use super::compile_source;
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{CheckedProgram, Contact, Line, Logic, Op, Output};
use crate::source::SourceFile;

fn compile(text: &str) -> (Option<CheckedProgram>, Vec<Diagnostic>) {
    compile_source(&SourceFile::new("t.il", text))
}

fn codes(text: &str) -> Vec<(Code, u32)> {
    let file = SourceFile::new("t.il", text);
    compile_source(&file)
        .1
        .iter()
        .map(|d| (d.code, file.line_of(d.span.start)))
        .collect()
}

#[test]
fn independent_errors_are_all_reported_once() {
    let text = "LD X0\nOUT X1\nLD D0\nOUT Y0\nLD X2\nANB\nOUT Y1\nMOV K1 K2\nSTLE\nLD X3\nCJ P9\n";
    assert_eq!(
        codes(text),
        [
            (Code::OperandKind, 2),
            (Code::OperandKind, 3),
            (Code::BlockUnderflow, 6),
            (Code::OperandKind, 8),
            (Code::StrayStle, 9),
            (Code::MissingLabel, 11),
        ]
    );
}

#[test]
fn bad_operands_do_not_cascade_into_structure_errors() {
    // The LD with a bad operand still starts the rung: no "output without a
    // condition" for the OUT, no "no rung" for the AND.
    assert_eq!(codes("LD X9\nAND X1\nOUT Y0\n"), [(Code::MalformedOperand, 1)]);
    assert_eq!(codes("LD Q7\nOUT Y0\n"), [(Code::MalformedOperand, 1)]);
    // A wrong operand count keeps the instruction's role too.
    assert_eq!(codes("LD X0 X1\nOUT Y0\n"), [(Code::OperandCount, 1)]);
}

#[test]
fn unknown_instructions_do_not_cascade() {
    assert_eq!(codes("LDX X0\nOUT Y0\n"), [(Code::UnknownMnemonic, 1)]);
    assert_eq!(codes("LD X0\nOUTT Y0\nLD X1\nOUT Y1\n"), [(Code::UnknownMnemonic, 2)]);
}

#[test]
fn an_stl_closes_the_open_block() {
    let text = "STL S0\nOUT Y0\nSTL S1\nLD X1\nOUT S2\nRET\nLD X2\nOUT Y2\n";
    let (program, diagnostics) = compile(text);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("compiles");
    let blocks: Vec<(u32, Op, Op)> = program
        .stl_blocks
        .iter()
        .map(|b| {
            let op = |i: usize| program.instructions[i].op.clone();
            (b.state, op(b.begin), op(b.end))
        })
        .collect();
    assert!(matches!(
        blocks[..],
        [
            (0, Op::Line(Line::StlBegin { .. }), Op::Line(Line::StlEnd)),
            (1, Op::Line(Line::StlBegin { .. }), Op::Line(Line::StlEnd))
        ]
    ));
    // OUT Y0 right after STL takes the state's power; OUT S2 is a transfer.
    assert!(matches!(
        program.instructions[1].op,
        Op::Load {
            contact: Contact::Constant(true),
            new_rung: true,
            ..
        }
    ));
    assert!(program.instructions.iter().any(|i| matches!(
        i.op,
        Op::Output(Output::Set {
            transfer_from: Some(1),
            ..
        })
    )));
}

#[test]
fn other_dialects_get_the_fx_spelling_rather_than_a_near_mnemonic() {
    let (_, diagnostics) = compile("LD X0\nTMR T0 K100\n");
    assert_eq!(diagnostics[0].code, Code::UnknownMnemonic);
    assert!(
        diagnostics[0].notes.iter().any(|n| n.contains("OUT T0 K100")),
        "{:?}",
        diagnostics[0].notes
    );
    assert!(!diagnostics[0].notes.iter().any(|n| n.contains("TTMR")));
}

#[test]
fn unknown_mnemonics_get_a_suggestion() {
    let (_, diagnostics) = compile("LDD X0\nOUT Y0\n");
    assert_eq!(diagnostics[0].code, Code::UnknownMnemonic);
    assert!(
        diagnostics[0].notes.iter().any(|n| n.contains("did you mean `LD`")),
        "{:?}",
        diagnostics[0]
    );
}

#[test]
fn warnings_do_not_block_compilation() {
    let (program, diagnostics) = compile("LD X0\nOUT Y0\nLD X1\nOUT Y0\nLD X2\nOUT M8000\nEND\nLD X3\nOUT Y3\n");
    let found: Vec<Code> = diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(found, [Code::DoubleCoil, Code::SystemRelayWrite, Code::CodeAfterEnd]);
    let program = program.expect("warnings only");
    assert_eq!(program.instructions.len(), 6, "nothing after END is executable");
}

#[test]
fn double_coils_inside_stl_blocks_are_normal() {
    let text = "STL S0\nLD X0\nOUT Y0\nSTLE\nSTL S1\nLD X1\nOUT Y0\nSTLE\n";
    assert_eq!(codes(text), []);
}

#[test]
fn edge_instructions_get_their_own_slots() {
    let (program, _) = compile("LDP X0\nANDF X1\nMEP\nPLS M0\nLD X2\nMOVP K1 D0\n");
    let program = program.unwrap();
    assert_eq!(program.edge_slots, 5);
    let slots: Vec<u32> = program
        .instructions
        .iter()
        .filter_map(|i| match &i.op {
            Op::Load {
                contact: Contact::Edge { slot, .. },
                ..
            }
            | Op::And(Contact::Edge { slot, .. }) => Some(*slot),
            Op::Logic(Logic::ResultEdge { slot, .. }) | Op::Output(Output::Pulse { slot, .. }) => Some(*slot),
            Op::Output(Output::App(app)) => app.pulse_slot,
            _ => None,
        })
        .collect();
    assert_eq!(slots, [0, 1, 2, 3, 4]);
}

#[test]
fn too_many_edge_instructions() {
    let mut text = "LD X0\n".to_string();
    for _ in 0..16385 {
        text.push_str("ANDP X1\n");
    }
    text.push_str("OUT Y0\n");
    assert_eq!(codes(&text), [(Code::TooManyEdges, 16386)]);
    assert!(
        compile(&text.replacen("ANDP X1\n", "", 1)).0.is_some(),
        "16384 slots fit"
    );
}

#[test]
fn new_rungs_and_blocks_are_told_apart() {
    let (program, _) = compile("LD X0\nOUT Y0\nLD X1\nMPS\nAND X2\nOUT Y1\nMPP\nLD X3\nANB\nOUT Y2\n");
    let loads: Vec<bool> = program
        .unwrap()
        .instructions
        .iter()
        .filter_map(|i| match i.op {
            Op::Load { new_rung, .. } => Some(new_rung),
            _ => None,
        })
        .collect();
    assert_eq!(loads, [true, true, false]);
}

#[test]
fn stl_blocks_know_what_to_reset() {
    let text = "STL S0\nLD X0\nOUT Y0\nOUT T0 K5\nPLS M0\nSET Y1\nMOVP K1 D0\nSET S1\nSTLE\n";
    let program = compile(text).0.unwrap();
    let block = &program.stl_blocks[0];
    assert_eq!((block.state, block.begin, block.end), (0, 0, 8));
    let reset_ops: Vec<&Op> = block
        .reset_outputs
        .iter()
        .map(|&i| &program.instructions[i].op)
        .collect();
    assert!(matches!(
        reset_ops[..],
        [
            Op::Output(Output::Coil(_)),
            Op::Output(Output::Timer { .. }),
            Op::Output(Output::Pulse { .. })
        ]
    ));
    assert_eq!(block.reset_slots, [0, 1]);
    let transfer = program.instructions.iter().find_map(|i| match i.op {
        Op::Output(Output::Set { transfer_from, .. }) if transfer_from.is_some() => transfer_from,
        _ => None,
    });
    assert_eq!(transfer, Some(0));
}

#[test]
fn mc_levels_reach_the_loads_of_their_region() {
    let text = "LD X0\nMC N0 M0\nLD X1\nMC N2 M1\nLD X2\nOUT Y0\nMCR N0\nLD X3\nOUT Y1\n";
    let masks: Vec<u8> = compile(text)
        .0
        .unwrap()
        .instructions
        .iter()
        .filter_map(|i| match i.op {
            Op::Load { mc_levels, .. } => Some(mc_levels),
            _ => None,
        })
        .collect();
    assert_eq!(masks, [0, 1, 0b101, 0]);
}
