//! The generator's vocabulary of application instructions, built from the
//! instruction table: every instruction, every form (16/32-bit, pulse), and
//! for each operand a device drawn from its device table, sometimes with an
//! index register. A new instruction is generated as soon as it is declared;
//! a new operand kind or device class does not compile here until it has a
//! vocabulary.

use ladder_front::isa::{AppOp, DeviceClass, OperandKind};
use ladder_runtime::Width;
use proptest::prelude::*;

/// Devices of a class, valid for an operand of `kind` at `width` wherever
/// the generator puts them (low numbers, so runs of units stay in range).
fn class_operand(class: DeviceClass, kind: OperandKind, width: Width) -> BoxedStrategy<String> {
    let wide = width == Width::Double;
    // Counts draw values that exercise the range checks; other operands
    // draw ordinary values and addresses.
    let counting = kind == OperandKind::Count;
    let digits = match (kind, wide) {
        // Bytes are read from whole words.
        (OperandKind::ByteSource, _) => "4",
        (_, true) => "[1-8]",
        (_, false) => "[1-4]",
    };
    let regex = |pattern: String| -> BoxedStrategy<String> {
        proptest::string::string_regex(&pattern)
            .expect("a valid pattern")
            .boxed()
    };
    let indexed = |base: String| -> BoxedStrategy<String> {
        prop_oneof![
            4 => Just(base.clone()),
            1 => prop_oneof![Just("[D1]"), Just("[D2]"), Just("[D3]")].prop_map(move |r| format!("{base}{r}")),
        ]
        .boxed()
    };
    match class {
        DeviceClass::X => "X[0-7]".boxed(),
        DeviceClass::Y => "Y[0-7]".boxed(),
        DeviceClass::M => prop_oneof!["M[0-9]", "M2[0-9]", Just("M8509[D1]".to_string())].boxed(),
        DeviceClass::S => prop_oneof!["S[1-3]", "S90[0-3]"].boxed(),
        DeviceClass::Sm => "SM1[0-9]".boxed(),
        DeviceClass::WordBit => "D0\\.[0-9A-F]".boxed(),
        DeviceClass::KnX => regex(format!("K{digits}X0")),
        // Groups start at a few nearby devices, so that a source and a
        // destination of one instruction overlap in every way (K1M0 into
        // K1M1 as well as the same group).
        DeviceClass::KnY => regex(format!("K{digits}Y[0-3]")),
        DeviceClass::KnM => prop_oneof![
            regex(format!("K{digits}M[0-6]")),
            regex(format!("K{digits}M40\\[D2\\]"))
        ]
        .boxed(),
        DeviceClass::KnS => regex(format!("K{digits}S[0-3]")),
        // Now and then a timer beyond T199, named directly: STMR's range
        // (T0-T199) leaves it out, and it compiles and fails when it runs,
        // on every engine alike. (INCD's counter pair and the high-speed
        // counters refuse such devices when they compile.)
        DeviceClass::T => prop_oneof![6 => "T[0-3]", 1 => "T2[0-1][0-9]"].boxed(),
        DeviceClass::C if kind == OperandKind::HighSpeedCounter => {
            prop_oneof!["C23[5-9]", "C24[0-9]", "C25[0-5]"].boxed()
        }
        DeviceClass::C if kind == OperandKind::CounterPair => "C[0-2]".boxed(),
        DeviceClass::C if wide => "C20[0-3]".boxed(),
        DeviceClass::C => "C[0-2]".boxed(),
        DeviceClass::WideCounter => "C20[0-3]".boxed(),
        DeviceClass::D if counting => prop_oneof!["D[1-3]", Just("D8511[D1]".to_string())].boxed(),
        // The scan-time registers D8010-D8012 now and then (the host
        // varies the scan time from step to step).
        DeviceClass::D => prop_oneof![
            6 => "D[0-3]".prop_flat_map(indexed),
            6 => "D[1-4]0".prop_flat_map(indexed),
            2 => Just("D8508[D2]".to_string()),
            1 => "D801[0-2]",
        ]
        .boxed(),
        DeviceClass::R => "R[0-9]".prop_flat_map(indexed).boxed(),
        DeviceClass::Sd => "SD1[0-9]".boxed(),
        DeviceClass::Constant if counting => {
            prop_oneof![4 => "K[0-9]", 1 => Just("K600".to_string()), 1 => Just("K-1".to_string())].boxed()
        }
        DeviceClass::Constant => prop_oneof![
            "K-?[0-9]{1,3}",
            "H[0-9A-F]{1,4}",
            if wide { "K[0-9]{6,9}" } else { "K3276[0-7]" },
        ]
        .boxed(),
        DeviceClass::Real => prop_oneof![
            "E-?[0-9]\\.[0-9]{1,3}",
            "E[1-9]\\.[0-9]{1,2}[+-][0-3]?[0-7]",
            Just("E0".to_string()),
        ]
        .boxed(),
        DeviceClass::Buffer => prop_oneof![
            "U[0-1]\\\\G[0-9]{1,2}",
            Just("U7\\G32760".to_string()),
            Just("U0\\G10[D1]".to_string()),
        ]
        .boxed(),
    }
}

/// One operand of `kind` from the device table `classes`.
fn operand(classes: Vec<DeviceClass>, kind: OperandKind, width: Width) -> BoxedStrategy<String> {
    // Counts are 16-bit whatever the instruction; timer values are 16-bit
    // only, the 32-bit counters 32-bit only.
    let width = if kind == OperandKind::Count {
        Width::Single
    } else {
        width
    };
    let classes: Vec<DeviceClass> = classes
        .into_iter()
        .filter(|class| match class {
            DeviceClass::T => width == Width::Single,
            DeviceClass::WideCounter => width == Width::Double,
            DeviceClass::X
            | DeviceClass::Y
            | DeviceClass::M
            | DeviceClass::S
            | DeviceClass::Sm
            | DeviceClass::WordBit
            | DeviceClass::KnX
            | DeviceClass::KnY
            | DeviceClass::KnM
            | DeviceClass::KnS
            | DeviceClass::C
            | DeviceClass::D
            | DeviceClass::R
            | DeviceClass::Sd
            | DeviceClass::Constant
            | DeviceClass::Real
            | DeviceClass::Buffer => true,
        })
        .collect();
    proptest::sample::select(classes)
        .prop_flat_map(move |class| class_operand(class, kind, width))
        .boxed()
}

/// Every mnemonic of every application instruction, with its operation,
/// width and whether it is a P form.
pub fn app_forms() -> Vec<(String, AppOp, Width)> {
    AppOp::ALL
        .iter()
        .flat_map(|&op| {
            op.spec()
                .mnemonics()
                .into_iter()
                .map(move |(name, width, _pulse)| (name, op, width))
        })
        .collect()
}

/// A random application instruction with valid operands.
pub fn app_instruction() -> BoxedStrategy<String> {
    proptest::sample::select(app_forms())
        .prop_flat_map(|(name, op, width)| {
            let operands: Vec<BoxedStrategy<String>> = op
                .spec()
                .operands
                .iter()
                .map(|decl| operand(decl.devices.classes().collect(), decl.kind, width))
                .collect();
            operands.prop_map(move |operands| {
                std::iter::once(name.clone())
                    .chain(operands)
                    .collect::<Vec<_>>()
                    .join(" ")
            })
        })
        .boxed()
}
