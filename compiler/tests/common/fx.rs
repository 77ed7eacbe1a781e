//! Random FX-structured programs for the differential test: index-register
//! devices (`M3Z0`, `D2V1`, `K2M0Z1`, `DMOV ... Z1`), FOR/NEXT loops (nested,
//! with counts below 1 and from a register, now and then one past the
//! watchdog), subroutines after FEND called by CALL and CALLP (one calling
//! the other, one holding a loop), and an FX-style STL sequence closed by
//! RET with outputs on the state's power and OUT transfers.

use super::{condition, emit_rung, Condition, Rung};
use proptest::prelude::*;

/// Contacts and outputs on index-modified devices.
fn index_rung() -> impl Strategy<Value = Rung> {
    let contact = prop_oneof![
        "(M[0-9]|X[0-7]|Y[0-7])(Z0|V1|Z1)".prop_map(|d| Condition::Contact(String::new(), d)),
        "D[0-3](Z0|V1) K[0-3]".prop_map(|d| Condition::Contact("=".to_string(), d)),
        "(Z0|V0|Z1|V1) K[0-3]".prop_map(|d| Condition::Contact(">".to_string(), d)),
    ];
    let condition = prop_oneof![
        1 => contact.clone(),
        1 => proptest::collection::vec(contact, 2..3).prop_map(Condition::Series),
    ];
    let output = prop_oneof![
        "OUT (M[0-9]|Y[0-7])(Z0|V1)",
        "SET M[0-9]Z1",
        "RST Y[0-7]V1",
        "MOV K-?[0-9] (Z0|Z1|V0|V1)",
        "MOV (D[0-3]Z0|Z1|V1|K2M0Z1) D[4-6]",
        "MOV (D[0-3]|K[0-9]) (D[4-6]V1|K1Y0Z0|D8510Z0)",
        "INC (Z0|Z1|V1)",
        "DEC Z0",
        "DMOV (K[0-9]{1,6}|D0) Z1",
        "DMOV Z1 D4",
        "ADD Z0 V0 D[4-6]",
        "PLS M[0-9]Z0",
        // Helper instructions with an index register as a single word.
        "MEAN D[0-3] (Z0|V1) K2",
        "ENCO (D0|X0) K[1-4] (Z0|V1)",
        "SUM (Z1|V0) D[4-6]",
        "MAX D0 D3 Z0",
        "BMOV D0Z0 D10V1 K2",
        "RST (Z0|V1)",
    ];
    (condition, proptest::collection::vec((Just(None), output), 1..3))
        .prop_map(|(condition, outputs)| Rung { condition, outputs })
}

fn any_rung() -> impl Strategy<Value = Rung> {
    prop_oneof![
        2 => super::rung(),
        2 => index_rung(),
    ]
}

fn rungs(range: std::ops::Range<usize>) -> impl Strategy<Value = Vec<Rung>> {
    proptest::collection::vec(any_rung(), range)
}

fn emit(rungs: &[Rung], out: &mut Vec<String>) {
    for rung in rungs {
        emit_rung(rung, out);
    }
}

/// FOR ... NEXT around `body`, maybe around an inner loop.
fn emit_loop(count: &str, body: &[Rung], inner: Option<(&str, &[Rung])>, out: &mut Vec<String>) {
    out.push(format!("FOR {count}"));
    emit(body, out);
    if let Some((count, body)) = inner {
        emit_loop(count, body, None, out);
    }
    out.push("NEXT".to_string());
}

fn loop_count() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => "K[0-4]",
        1 => Just("K-2".to_string()),
        1 => "(D[0-3]|Z0|D0Z1)",
    ]
}

/// A call: CALL or CALLP under a condition, or right on an STL state's power.
fn call() -> impl Strategy<Value = (Condition, String)> {
    (condition(), "CALLP? P1[01]")
}

pub fn fx_program() -> impl Strategy<Value = String> {
    (
        (
            rungs(1..4),
            loop_count(),
            rungs(1..3),
            proptest::option::of((loop_count(), rungs(1..2))),
        ),
        (call(), call(), rungs(0..3)),
        (rungs(0..2), rungs(0..2), any_rung()),
        (rungs(1..3), rungs(0..2), proptest::option::of(loop_count()), 0..10u8),
    )
        .prop_map(|(main, calls, stl, subroutines)| {
            let (plain, count, body, inner) = main;
            let ((call_condition, call_a), (_, call_b), after_calls) = calls;
            let (in_s20, in_s21, s21_exit) = stl;
            let (p10, p11, p10_loop, watchdog) = subroutines;
            let mut out: Vec<String> = ["LD M8002", "SET S0", "MOV K1 D1", "LD M8013", "OUT M40"]
                .map(str::to_string)
                .to_vec();
            emit(&plain, &mut out);
            let inner = inner.as_ref().map(|(count, body)| (count.as_str(), body.as_slice()));
            emit_loop(&count, &body, inner, &mut out);
            super::emit_block(&call_condition, &mut out);
            out.push(call_a);
            out.push("OUT M41".to_string());
            emit(&after_calls, &mut out);
            if watchdog == 0 {
                // Past the watchdog (400 x 400 repetitions) when X3 and X4 are ON.
                out.extend(
                    [
                        "LDI X3", "ORI X4", "CJ P5", "FOR K400", "FOR K400", "LD SM0", "INC D7", "NEXT", "NEXT", "P5",
                    ]
                    .map(str::to_string),
                );
            }
            // An FX-style sequence: S0 -> S20 -> S21 -> S0.
            out.extend(["STL S0", "OUT Y0", "LD X0", "OUT S20"].map(str::to_string));
            out.extend(["STL S20", "OUT Y1", "OUT T3 K2"].map(str::to_string));
            emit(&in_s20, &mut out);
            out.extend(["LD T3", "SET S21"].map(str::to_string));
            out.extend(["STL S21", "OUT Y2", &call_b].map(str::to_string));
            emit(&in_s21, &mut out);
            super::emit_block(&s21_exit.condition, &mut out);
            out.push("OUT S0".to_string());
            out.extend(["RET", "FEND", "P10"].map(str::to_string));
            emit(&p10, &mut out);
            if let Some(count) = p10_loop {
                out.push(format!("FOR {count}"));
                out.extend(["LD SM0", "INC Z1", "MOV Z1 D20Z1"].map(str::to_string));
                out.push("NEXT".to_string());
            }
            out.extend(["LD X2", "CALL P11", "SRET", "P11"].map(str::to_string));
            emit(&p11, &mut out);
            out.extend(["LD SM0", "INC D9", "SRET", "END"].map(str::to_string));
            out.join("\n") + "\n"
        })
}
