//! Front end, first stage: source text to a `ParsedProgram` of statements with
//! spans. Nothing here knows what an instruction means.

pub mod export;
pub mod lexer;
pub mod operand;
mod parser;

pub use operand::{Constant, DeviceSyntax, OffsetKind, OffsetSyntax, Operand, OperandSyntax, Prefix};
pub use parser::parse;

use crate::source::Span;

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
