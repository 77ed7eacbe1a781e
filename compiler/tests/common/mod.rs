//! Random, structurally valid ladder programs for property tests: rungs are
//! series/parallel trees of contacts emitted as LD/AND/OR/ANB/ORB, with
//! branch points (MPS/MRD/MPP), outputs, data instructions, jumps, MC regions
//! and STL blocks drawn from a small device vocabulary so that instructions
//! interact.

#![allow(dead_code)]

pub mod browser;
pub mod differential;
pub mod fx;
pub mod image;
pub mod server;
pub mod stimulus;
pub mod tools;
pub mod vocabulary;

use proptest::prelude::*;

/// A rung's condition: a contact, or blocks in series or in parallel.
#[derive(Clone, Debug)]
pub enum Condition {
    Contact(String, String),
    Series(Vec<Condition>),
    Parallel(Vec<Condition>),
}

fn contact() -> impl Strategy<Value = Condition> {
    let device = prop_oneof![
        "X[0-7]",
        "M[0-9]",
        "Y[0-7]",
        "S[0-3]",
        "T[0-3]",
        "T(200|246|250)",
        "C[0-2]",
        "C20[0-1]",
        "M8002",
        "D0\\.[0-3]",
        "M[0-9]\\[D1\\]",
    ];
    let kind = prop_oneof![
        4 => Just(""), 2 => Just("I"), 1 => Just("P"), 1 => Just("F"),
    ];
    prop_oneof![
        8 => (kind, device).prop_map(|(k, d)| Condition::Contact(k.to_string(), d)),
        1 => (prop_oneof![Just("="), Just("<>"), Just(">"), Just("<"), Just(">="), Just("<=")],
              prop_oneof![Just("D0"), Just("D2"), Just("TN0"), Just("K4M0"), Just("D8511[D1]"), Just("K2M0[D2]")],
              prop_oneof![Just("K3"), Just("D3"), Just("K-1"), Just("CN1")])
            .prop_map(|(op, a, b)| Condition::Contact(op.to_string(), format!("{a} {b}"))),
        1 => (prop_oneof![Just("="), Just(">"), Just("<")], prop_oneof![Just("D10"), Just("CN200"), Just("CN255[D1]")])
            .prop_map(|(op, a)| Condition::Contact(format!("D{op}"), format!("{a} K2"))),
    ]
}

pub fn condition() -> impl Strategy<Value = Condition> {
    contact().prop_recursive(3, 12, 3, |inner| {
        prop_oneof![
            proptest::collection::vec(inner.clone(), 2..4).prop_map(Condition::Series),
            proptest::collection::vec(inner, 2..4).prop_map(Condition::Parallel),
        ]
    })
}

/// Emits `condition` as a block: starting with an LD-type instruction.
pub fn emit_block(condition: &Condition, out: &mut Vec<String>) {
    match condition {
        Condition::Contact(kind, device) => out.push(contact_line("LD", kind, device)),
        Condition::Series(parts) | Condition::Parallel(parts) => {
            let series = matches!(condition, Condition::Series(_));
            emit_block(&parts[0], out);
            for part in &parts[1..] {
                match part {
                    Condition::Contact(kind, device) => {
                        out.push(contact_line(if series { "AND" } else { "OR" }, kind, device))
                    }
                    Condition::Series(_) | Condition::Parallel(_) => {
                        emit_block(part, out);
                        out.push(if series { "ANB" } else { "ORB" }.to_string());
                    }
                }
            }
        }
    }
}

fn contact_line(role: &str, kind: &str, device: &str) -> String {
    let comparison = kind.contains(['=', '<', '>']);
    match (role, kind) {
        (_, _) if comparison => format!("{role}{kind} {device}"),
        ("AND", "I") => format!("ANI {device}"),
        (role, kind) => format!("{role}{kind} {device}"),
    }
}

pub fn output() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => prop_oneof![
            "OUT (Y[0-7]|M[0-9])", "SET (Y[0-7]|M[0-9])", "RST (Y[0-7]|M[0-9])", "PLS M[0-9]", "PLF Y[0-7]",
            "OUT T[0-3] K[0-5]", "OUT T[0-3] D[0-3]", "OUT T20[0-1] K[0-9]{1,2}", "OUT T24[6-7] K[0-9]{1,3}",
            "OUT T25[0-1] K3", "OUT C[0-2] K[0-3]", "OUT C20[0-1] K[0-2]", "OUT C[0-2] D[0-3]",
            "RST (T|C)[0-3]", "RST T(200|246|250)", "RST C20[0-1]", "OUT M[0-9]\\[D1\\]", "SET S[1-3]", "OUT D0\\.[0-3]", "OUT M820[0-1]",
            "SET M[0-9]\\[D2\\] K[1-4]", "RST Y[0-7]\\[D1\\] K[2-3]", "RST D[4-6]\\[D2\\] K2", "PLS M[0-9]\\[D3\\]",
            "OUT Y37[0-7]\\[D1\\]", "RST M8510\\[D1\\] K2", "SET D0\\.[0-3]\\[D3\\]",
        ],
        3 => vocabulary::app_instruction(),
    ]
}

/// A whole rung: its condition, then outputs, possibly on MPS branches.
#[derive(Clone, Debug)]
pub struct Rung {
    pub condition: Condition,
    pub outputs: Vec<(Option<Condition>, String)>,
}

pub fn rung() -> impl Strategy<Value = Rung> {
    (
        condition(),
        proptest::collection::vec((proptest::option::of(contact()), output()), 1..4),
    )
        .prop_map(|(condition, outputs)| Rung { condition, outputs })
}

pub fn emit_rung(rung: &Rung, out: &mut Vec<String>) {
    emit_block(&rung.condition, out);
    let branches = rung.outputs.iter().any(|(c, _)| c.is_some()) && rung.outputs.len() > 1;
    for (i, (branch, output)) in rung.outputs.iter().enumerate() {
        if branches {
            let last = i + 1 == rung.outputs.len();
            out.push(
                match (i, last) {
                    (0, _) => "MPS",
                    (_, true) => "MPP",
                    _ => "MRD",
                }
                .to_string(),
            );
        }
        if let Some(Condition::Contact(kind, device)) = branch.as_ref().filter(|_| branches) {
            out.push(contact_line("AND", kind, device));
        }
        out.push(output.clone());
    }
}

/// A program: plain rungs, some in an MC region, some behind a jump, and a
/// small STL sequence whose transitions depend on inputs.
pub fn program() -> impl Strategy<Value = String> {
    program_of(rung().boxed())
}

/// Rungs that keep coming back to four relays, a word and its bits, so the
/// compiler's memory forwarding is exercised: a relay written, read and
/// overwritten by later rungs, with dynamic (`M0[D1]`) accesses, helper
/// calls (BMOV, digit groups), timer coils and index changes in between.
pub fn memory_rung() -> impl Strategy<Value = Rung> {
    let contact = prop_oneof![
        6 => (prop_oneof![4 => Just(""), 2 => Just("I"), 1 => Just("P")], "(M[0-3]|Y[0-1]|D0\\.[0-2])")
            .prop_map(|(k, d)| Condition::Contact(k.to_string(), d)),
        1 => "(M0\\[D1\\]|T0|X[0-2]|M8067)".prop_map(|d| Condition::Contact(String::new(), d)),
        1 => "D[0-1] K[0-3]".prop_map(|d| Condition::Contact("=".to_string(), d)),
    ];
    let condition = contact.clone().prop_recursive(2, 6, 3, |inner| {
        prop_oneof![
            proptest::collection::vec(inner.clone(), 2..3).prop_map(Condition::Series),
            proptest::collection::vec(inner, 2..3).prop_map(Condition::Parallel),
        ]
    });
    let output = prop_oneof![
        "(OUT|SET|RST) M[0-3]",
        "OUT Y[0-1]",
        "OUT D0\\.[0-2]",
        "SET M[0-2] K2",
        "(SET|RST) M0 K6",
        "RST D0 K2",
        "MOV K600 D[0-1]",
        "MOV D0 D[0-1]",
        "OUT M0\\[D1\\]",
        "SET M1\\[D1\\]",
        "MOV K[0-3] D1",
        "INCP D1",
        "BMOV K1M0 D4 K1",
        "MOV D4 K1M0",
        "MOV K[0-9] D0",
        "PLS M[0-3]",
        "OUT T0 K2",
        "RST T0",
    ];
    (
        condition,
        proptest::collection::vec((proptest::option::of(contact), output), 1..3),
    )
        .prop_map(|(condition, outputs)| Rung { condition, outputs })
}

/// `program` made of memory rungs.
pub fn memory_program() -> impl Strategy<Value = String> {
    program_of(memory_rung().boxed())
}

fn program_of(rung: BoxedStrategy<Rung>) -> impl Strategy<Value = String> {
    (
        proptest::collection::vec(rung.clone(), 1..8),
        proptest::collection::vec(rung.clone(), 0..3),
        proptest::collection::vec(rung.clone(), 0..3),
        proptest::collection::vec(rung, 0..3),
    )
        .prop_map(|(plain, in_mc, jumped, in_stl)| {
            let mut out = vec!["LD M8002".to_string(), "SET S1".to_string(), "MOV K1 D1".to_string()];
            for rung in &plain {
                emit_rung(rung, &mut out);
            }
            out.extend(["LD X6", "MC N0 M50"].map(str::to_string));
            for rung in &in_mc {
                emit_rung(rung, &mut out);
            }
            out.extend(["MCR N0", "LD X7", "CJ P1"].map(str::to_string));
            for rung in &jumped {
                emit_rung(rung, &mut out);
            }
            out.push("P1".to_string());
            out.extend(["STL S1", "LD X5", "SET S2", "LD T2", "OUT Y6"].map(str::to_string));
            for rung in &in_stl {
                emit_rung(rung, &mut out);
            }
            out.extend(
                [
                    "STLE",
                    "STL S2",
                    "LD SM0",
                    "OUT T2 K2",
                    "LDP X4",
                    "SET S1",
                    "PLS M30",
                    "STLE",
                ]
                .map(str::to_string),
            );
            out.join("\n") + "\n"
        })
}
