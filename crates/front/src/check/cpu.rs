//! The program checked against the CPU its `//@ cpu` line names (a GX
//! Developer project's parameters give it): an FX2N or FX1N has no file
//! registers (R), no buffer-memory operands (`Un\Gm`), no bits of words
//! (`D0.1`) and none of the instructions the FX3U series added.

use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::syntax::{OperandSyntax, ParsedProgram, Prefix, StatementKind};

/// Instructions of the FX3U/FX3UC/FX3G that the earlier series lack (base
/// names; their D and P forms follow them).
pub const FX3_ONLY: &[&str] = &[
    "MEP", "MEF", "EMOV", "EXP", "LOGE", "LOG10", "ASIN", "ACOS", "ATAN", "RAD", "DEG", "WSUM", "WTOB", "BTOW", "UNI",
    "DIS", "SORT2", "DSZR", "HTOS", "STOH", "LIMIT", "BAND", "ZONE", "SCL", "SCL2", "DABIN", "BINDA", "CRC", "HCMOV",
    "TBL", "DVIT",
];

/// The CPUs of the FX3 series (the others are earlier).
const FX3: [&str; 5] = ["FX3U", "FX3UC", "FX3G", "FX3GC", "FX3S"];

/// The errors of instructions and operands `cpu` does not have.
pub fn check(parsed: &ParsedProgram, cpu: &str) -> Diagnostics {
    let mut diagnostics = Diagnostics::default();
    let cpu = cpu.trim().to_ascii_uppercase();
    if FX3.contains(&cpu.as_str()) {
        return diagnostics;
    }
    let note = format!("the program's CPU is an {cpu} (its `//@ cpu` line, from the project's parameters)");
    for statement in &parsed.statements {
        let StatementKind::Instruction(instruction) = &statement.kind else {
            continue;
        };
        let name = instruction.mnemonic.as_str();
        let base = name.strip_suffix('P').filter(|b| is_fx3_only(b)).unwrap_or(name);
        if is_fx3_only(base) {
            diagnostics.push(
                Diagnostic::new(
                    Code::NotOnThisCpu,
                    instruction.mnemonic_span,
                    format!("`{name}` is an instruction of the FX3 series; an {cpu} does not have it"),
                )
                .with_label("not on this CPU")
                .with_note(note.clone()),
            );
        }
        for operand in &instruction.operands {
            let OperandSyntax::Device(device) = operand.syntax else {
                continue;
            };
            let what = if device.prefix == Prefix::R {
                Some("file registers (R)")
            } else if device.prefix == Prefix::U {
                Some("buffer-memory operands (Un\\Gm)")
            } else if device.bit.is_some() {
                Some("bits of words (D0.1)")
            } else {
                None
            };
            if let Some(what) = what {
                diagnostics.push(
                    Diagnostic::new(
                        Code::NotOnThisCpu,
                        operand.span,
                        format!("{what} are FX3-series devices; an {cpu} does not have them"),
                    )
                    .with_label("not on this CPU")
                    .with_note(note.clone()),
                );
            }
        }
    }
    diagnostics
}

/// Is `name` (or its 32-bit form's base) an FX3-only instruction?
fn is_fx3_only(name: &str) -> bool {
    FX3_ONLY.contains(&name) || name.strip_prefix('D').is_some_and(|b| FX3_ONLY.contains(&b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::SourceFile;

    fn errors(text: &str, cpu: &str) -> usize {
        let (parsed, _) = crate::syntax::parse(&SourceFile::new("t.il", text));
        check(&parsed, cpu).len()
    }

    #[test]
    fn an_fx2n_has_no_fx3_devices_or_instructions() {
        let program = "LD X0\nMEP\nMOV K1 R0\nDEMOVP E1.5 D0\nOUT D0.1\nMOV K1 D0\n";
        assert_eq!(errors(program, "FX2N"), 4);
        assert_eq!(errors(program, "FX3U"), 0);
    }

    #[test]
    fn the_list_names_instructions_of_the_table() {
        for name in FX3_ONLY {
            let known = crate::isa::lookup(name).is_some()
                || crate::isa::lookup(&format!("D{name}")).is_some()
                || crate::isa::fx::UNSUPPORTED_FX.contains(name);
            assert!(known, "{name}");
        }
    }
}
