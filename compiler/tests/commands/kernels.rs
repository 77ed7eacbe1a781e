//! Golden vectors for the application-instruction kernels, taken from the
//! seed's examples where it gives values: each is run on the interpreter's
//! kernel and on the native (JIT) kernel, which must both give the expected
//! outputs. The full rules (P forms, flags, errors, offsets) are in the
//! scenarios under testsuite/scenarios/app/.

use ladder_engine::scenario::{parse_scenario, run_scenario, EngineKind};
use ladder_front::source::SourceFile;
use std::path::Path;

/// (instruction, inputs, expected outputs); inputs and outputs are scenario
/// lines (`set`/`set32` and `expect`/`expect32`).
struct Vector {
    instruction: &'static str,
    inputs: &'static [&'static str],
    outputs: &'static [&'static str],
}

const VECTORS: &[Vector] = &[
    // NEG: "if D2=K4 and D4=K8 ... the result of D10 is K4" is the ABS idiom;
    // plain negation and the wrap of the smallest value:
    Vector {
        instruction: "NEG D0",
        inputs: &["set D0 4"],
        outputs: &["expect D0 -4"],
    },
    Vector {
        instruction: "NEG D0",
        inputs: &["set D0 -32768"],
        outputs: &["expect D0 -32768"],
    },
    Vector {
        instruction: "DNEG D0",
        inputs: &["set32 D0 70000"],
        outputs: &["expect32 D0 -70000"],
    },
    Vector {
        instruction: "WAND D0 D2 D4",
        inputs: &["set D0 H0F0F", "set D2 H00FF"],
        outputs: &["expect D4 H000F"],
    },
    Vector {
        instruction: "WOR D0 D2 D4",
        inputs: &["set D0 H0F0F", "set D2 H00FF"],
        outputs: &["expect D4 H0FFF"],
    },
    Vector {
        instruction: "WXOR D0 D2 D4",
        inputs: &["set D0 H0F0F", "set D2 H00FF"],
        outputs: &["expect D4 H0FF0"],
    },
    Vector {
        instruction: "DAND D0 D2 D4",
        inputs: &["set32 D0 H12345678", "set32 D2 HFFFF0000"],
        outputs: &["expect32 D4 H12340000"],
    },
    // BON: "When n in D0 = the third bit is 1 (ON), M0 is set to 1 (ON)."
    Vector {
        instruction: "BON D0 K3 M0",
        inputs: &["set D0 H0008"],
        outputs: &["expect M0 1"],
    },
    Vector {
        instruction: "BON D0 K2 M0",
        inputs: &["set D0 H0008"],
        outputs: &["expect M0 0"],
    },
    Vector {
        instruction: "DBON D0 K31 M0",
        inputs: &["set32 D0 H80000000"],
        outputs: &["expect M0 1"],
    },
    // SUM: "There are 8 in the example"; DSUM: 16.
    Vector {
        instruction: "SUM D0 D1",
        inputs: &["set D0 H0FF0"],
        outputs: &["expect D1 8", "expect SM153 0"],
    },
    Vector {
        instruction: "SUM D0 D1",
        inputs: &["set D0 0"],
        outputs: &["expect D1 0", "expect SM153 1"],
    },
    Vector {
        instruction: "DSUM D0 D10",
        inputs: &["set32 D0 HFF00FF00"],
        outputs: &["expect32 D10 16"],
    },
    // SQR: "the value of D0 is 100, so the value of D2 is 10"; DSQR: "D0 is
    // 110 ... D2 is 10 ... SM152 is turned ON".
    Vector {
        instruction: "SQR D0 D2",
        inputs: &["set D0 100"],
        outputs: &["expect D2 10", "expect SM152 0"],
    },
    Vector {
        instruction: "DSQR D0 D2",
        inputs: &["set32 D0 110"],
        outputs: &["expect32 D2 10", "expect SM152 1", "expect SM153 0"],
    },
    // SWAP: "swap the low 8 bits and high 8 bits of D0 to get H8F2A";
    // DSWAP: "D0=H8F2A, D1=H3412 are obtained".
    Vector {
        instruction: "SWAP D0",
        inputs: &["set D0 H2A8F"],
        outputs: &["expect D0 H8F2A"],
    },
    Vector {
        instruction: "DSWAP D0",
        inputs: &["set D0 H2A8F", "set D1 H1234"],
        outputs: &["expect D0 H8F2A", "expect D1 H3412"],
    },
    // DIS: "The result is D10 = HF, D11 = H8, D12 = HA."
    Vector {
        instruction: "DIS D0 D10 K3",
        inputs: &["set D0 H0A8F"],
        outputs: &["expect D10 HF", "expect D11 H8", "expect D12 HA"],
    },
    // UNI: "the low 4 bits of D0 to D3 are combined and stored in D10, the
    // value is H236F."
    Vector {
        instruction: "UNI D0 D10 K4",
        inputs: &["set D0 H00FF", "set D1 H0016", "set D2 H0123", "set D3 HF002"],
        outputs: &["expect D10 H236F"],
    },
    // DECO: "When M20 is ON, M3 will be turned ON."
    Vector {
        instruction: "DECO D0 K3 M0",
        inputs: &["set D0 3"],
        outputs: &["expect K2M0 H08"],
    },
    Vector {
        instruction: "DECO D0 K4 D1",
        inputs: &["set D0 15"],
        outputs: &["expect D1 H8000"],
    },
    Vector {
        instruction: "ENCO D0 K4 D1",
        inputs: &["set D0 H0480"],
        outputs: &["expect D1 10"],
    },
    Vector {
        instruction: "ENCO M0 K3 D1",
        inputs: &["set M2 1", "set M6 1"],
        outputs: &["expect D1 6"],
    },
    // BTOW: "When (N)=5, the data up to the lower 8 bits of (S)+(S)+4 is
    // stored in (D)+(D)+2" with the last high byte 00H.
    Vector {
        instruction: "BTOW D20 D10 K5",
        inputs: &[
            "set D20 H1201",
            "set D21 H3402",
            "set D22 H5603",
            "set D23 H7804",
            "set D24 H9A05",
        ],
        outputs: &["expect D10 H0201", "expect D11 H0403", "expect D12 H0005"],
    },
    Vector {
        instruction: "WTOB D10 D20 K5",
        inputs: &["set D10 H0201", "set D11 H0403", "set D12 H0605"],
        outputs: &[
            "expect D20 1",
            "expect D21 2",
            "expect D22 3",
            "expect D23 4",
            "expect D24 5",
            "expect D25 0",
        ],
    },
    // PRUN: "X0 to X17 take the value of octal digits and pass it to the
    // Devices corresponding to M."
    Vector {
        instruction: "PRUN K4X0 K4M0",
        inputs: &["set X10 1", "set X7 1", "set M8 1"],
        outputs: &["expect M10 1", "expect M7 1", "expect M8 1", "expect M9 0"],
    },
    // ZRST: "set the value of the D0 to D100 device to 0"; ZSET: "set the
    // value of the M1 to M4 device to ON".
    Vector {
        instruction: "ZRST D0 D100",
        inputs: &["set D0 5", "set D100 7", "set D101 9"],
        outputs: &["expect D0 0", "expect D100 0", "expect D101 9"],
    },
    Vector {
        instruction: "ZSET M1 M4",
        inputs: &[],
        outputs: &["expect K2M0 H1E"],
    },
];

#[test]
fn kernels_give_the_golden_outputs_on_both_engines() {
    let mut failures = Vec::new();
    for vector in VECTORS {
        let text = format!(
            "program <<\nLD SM0\n{}\n>>\n{}\nscan\n{}\n",
            vector.instruction,
            vector.inputs.join("\n"),
            vector.outputs.join("\n")
        );
        let path = Path::new("kernels.scn");
        let scenario = parse_scenario(path, &text).unwrap_or_else(|e| panic!("{}: {e:?}", vector.instruction));
        let source = SourceFile::new("kernels.il", format!("LD SM0\n{}\n", vector.instruction));
        let outcome = run_scenario(
            &scenario,
            &source,
            &[EngineKind::Interp, EngineKind::Jit],
            Default::default(),
        );
        assert_eq!(outcome.ran.len(), 2, "{}", vector.instruction);
        failures.extend(
            outcome
                .failures
                .iter()
                .map(|f| format!("{}: {}", vector.instruction, f)),
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
