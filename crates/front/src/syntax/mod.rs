//! Front end, first stage: source text to a `ParsedProgram` of statements with
//! spans. Nothing here knows what an instruction means. `parse` tells plain
//! IL (`parser.rs`) from a vendor's export (`export/`) by content.

pub mod export;
pub mod lexer;
pub mod operand;
mod parser;

pub use operand::{Constant, DeviceSyntax, OffsetKind, OffsetSyntax, Operand, OperandSyntax, Prefix};

use crate::diagnostics::{Code, Diagnostic, Diagnostics, Severity};
use crate::source::{SourceFile, Span};

/// The program as written: one statement per non-empty line.
#[derive(Clone, Debug, Default)]
pub struct ParsedProgram {
    pub statements: Vec<Statement>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Statement {
    pub kind: StatementKind,
    /// From the mnemonic (or label) to the last operand.
    pub span: Span,
    /// 1-based source line.
    pub line: u32,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StatementKind {
    Instruction(InstructionSyntax),
    /// `P12` or `P12:` alone on a line.
    Label {
        number: u32,
    },
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InstructionSyntax {
    /// Upper-cased mnemonic.
    pub mnemonic: String,
    pub mnemonic_span: Span,
    pub operands: Vec<Operand>,
    /// Some operand could not be read (already reported); the checker still
    /// sees the instruction for the rung structure but skips its operands.
    pub malformed: bool,
}

/// Parses a whole source file, plain IL or a GX Works2 CSV export (told by
/// its content). Problems are reported, never fatal: the result holds every
/// statement that could be recognised.
pub fn parse(file: &SourceFile) -> (ParsedProgram, Diagnostics) {
    if export::is_export(&file.text) {
        return export::parse(file);
    }
    let (program, diagnostics) = parser::parse_il(file);
    // Rows of fields that are not an instruction list ladderc knows: one
    // error, not one per line.
    let errors = diagnostics.iter().filter(|d| d.severity() == Severity::Error).count();
    if errors >= 3 {
        if let Some(foreign) = export::tabular(&file.text).and(export::foreign_cpu_in(file)) {
            let mut one = Diagnostics::default();
            one.push(foreign);
            return (ParsedProgram::default(), one);
        }
        if let Some(line) = export::tabular(&file.text) {
            let start = file.line_starts().get(line).copied().unwrap_or(0);
            let end = file.text[start..].find('\n').map_or(file.text.len(), |n| start + n);
            let mut diagnostic = Diagnostic::new(
                Code::UnreadableExport,
                Span::new(start, end.max(start)),
                "this file looks like a CSV export, but not of an instruction list ladderc reads",
            )
            .with_label("fields separated by tabs or commas")
            .with_note(format!(
                "read as plain IL it gives {errors} errors; `ladderc explain E0048` says which exports are read"
            ));
            let row = &file.text[start..end];
            if row.matches(',').count().max(row.matches('\t').count()) == 2 {
                diagnostic = diagnostic.with_note(
                    "rows of a step, an instruction and an operand are how other vendors' editors list steps \
                     (Delta's WPLSoft writes `000000,LD,M1002`); their special devices are not FX's (Delta's \
                     M1002 is FX's M8002), so ladderc does not read them as FX programs",
                );
            }
            let mut one = Diagnostics::default();
            one.push(diagnostic);
            return (ParsedProgram::default(), one);
        }
    }
    (program, diagnostics)
}
