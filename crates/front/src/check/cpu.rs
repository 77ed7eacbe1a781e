//! The program checked against the CPU its `//@ cpu` line names (a GX
//! Developer project's parameters give it): an FX2N or FX1N has no file
//! registers (R), no buffer-memory operands (`Un\Gm`), no bits of words
//! (`D0.1`) and none of the instructions the FX3U series added.

use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::syntax::{OperandSyntax, ParsedProgram, Prefix, StatementKind};

/// Instructions of the FX3U/FX3UC/FX3G that the FX2N and FX1N lack (base
/// names; their D and P forms follow them), by FNC number as the FX3U
/// programming manual lists them. The instruction table knows no CPU
/// families, so they are listed here; the names the table does not know
/// are left out (they are unknown instructions on any CPU). Left out too
/// where the FX2N manual lists the instruction for later FX2N versions
/// (ABS 155, HOUR 169, RD3A/WR3A 176-177, the logic contacts 215-223).
/// (BK+ to BKCMP 192-199, $+ 202, $MOV 209 and IVMC 275 are not in the
/// table.)
#[rustfmt::skip]
pub const FX3_ONLY: &[&str] = &[
    // Basic: operation-result edges.
    "MEP", "MEF",
    // 87, 102-103: serial communication 2, index register stack.
    "RS2", "ZPUSH", "ZPOP",
    // 112-137: floating point beyond the FX2N's.
    "EMOV", "ESTR", "EVAL", "EXP", "LOGE", "LOG10", "ENEG", "ASIN", "ACOS", "ATAN", "RAD", "DEG",
    // 140-149: data operation.
    "WSUM", "WTOB", "BTOW", "UNI", "DIS", "SORT2",
    // 150-159: positioning.
    "DSZR", "DVIT", "TBL", "ZRN", "PLSV", "DRVI", "DRVA",
    // 164-165: time conversion.
    "HTOS", "STOH",
    // 182-189: comments, random numbers, timing pulses, CRC, high-speed counter move.
    "COMRD", "RND", "DUTY", "CRC", "HCMOV",
    // 200-209: character strings.
    "STR", "VAL", "LEN", "RIGHT", "LEFT", "MIDR", "MIDW", "INSTR",
    // 210-214: data tables and shifts.
    "FDEL", "FINS", "POP", "SFR", "SFL",
    // 256-262: data operation 3.
    "LIMIT", "BAND", "ZONE", "SCL", "DABIN", "BINDA", "SCL2",
    // 270-280: inverter communication, buffer memory, high-speed counters.
    "IVCK", "IVDR", "IVRD", "IVWR", "IVBWR", "ADPRW", "RBFM", "WBFM", "HSCT",
    // 290-295: extension file registers.
    "LOADR", "SAVER", "INITR", "LOGR", "RWER", "INITER",
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
    let note = format!("the program's CPU is an {cpu} (its `//@ cpu` line, or the parameters of its project)");
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
    fn the_fx3_float_and_data_instructions_are_not_on_an_fx2n() {
        // ENEG is FNC128, WSUM FNC140, SORT2 FNC149: FX3U only.
        for line in ["DENEG D0", "ENEGP D0", "WSUM D0 D10 K2", "DZRN K1 K2 X0 Y0"] {
            assert_eq!(errors(&format!("LD X0\n{line}\n"), "FX2N"), 1, "{line}");
        }
        // FX2N instructions: none.
        assert_eq!(errors("LD X0\nDNEG D0\nDEADD D0 D2 D4\nSWAP D0\n", "FX2N"), 0);
    }

    #[test]
    fn the_list_names_instructions_of_the_table() {
        let unknown: Vec<&&str> = FX3_ONLY
            .iter()
            .filter(|name| {
                crate::isa::lookup(name).is_none()
                    && crate::isa::lookup(&format!("D{name}")).is_none()
                    && !crate::isa::fx::UNSUPPORTED_FX.contains(name)
            })
            .collect();
        assert!(unknown.is_empty(), "{unknown:?}");
    }
}
