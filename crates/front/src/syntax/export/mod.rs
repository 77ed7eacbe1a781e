//! Instruction-list exports of the vendor editors, read as programs with
//! every statement's span in the export itself (so diagnostics show its own
//! lines), and written out as plain IL (`ladderc import`).
//!
//! An export has one row per step: step number, line statement,
//! instruction, operand, blank, PI statement, note (`layout.rs` tells the
//! separator and the columns by content). A row with neither a step nor an
//! instruction holds the next operand of the instruction above; one with
//! only a line statement (or a note) is a comment. Labels and END/FEND/SRET
//! are rows of their own. Header lines (program name, PLC information,
//! column titles) come before the first row; a PLC-information line that
//! names another CPU family than FX makes the whole export one error.

mod il;
mod layout;
mod rows;

pub use il::to_il;
pub use layout::{cpu_family, detect, tabular, Cpu, Layout};

use super::operand::parse_operand;
use super::parser::label_number;
use super::{InstructionSyntax, ParsedProgram, Statement, StatementKind};
use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::source::{SourceFile, Span};
use rows::{split_row, Field, Row};

/// Is `text` an instruction-list export (of any editor)?
pub fn is_export(text: &str) -> bool {
    detect(text).is_some()
}

/// The lines of an export: header rows (before the first row of the
/// program) and program rows, or the diagnostics of rows that cannot be
/// read.
struct Lines {
    header: Vec<Row>,
    rows: Vec<Row>,
}

impl Layout {
    /// A row of the program: the columns up to the operand, and a step
    /// number or nothing in the step column. Header lines have fewer
    /// fields (program name, PLC information) or words in the step column
    /// (the column titles).
    fn is_data(&self, row: &Row) -> bool {
        row.fields.len() > self.operand && row.column(self.step).bytes().all(|b| b.is_ascii_digit())
    }

    /// The row's comments: its line statement, PI statement and note.
    fn comments<'r>(&self, row: &'r Row) -> impl Iterator<Item = &'r str> {
        [
            row.column(self.statement),
            row.text(self.pi_statement),
            row.text(self.note),
        ]
        .into_iter()
        .filter(|t| !t.is_empty())
    }
}

fn lines(file: &SourceFile, layout: &Layout, diagnostics: &mut Diagnostics) -> Lines {
    let starts = file.line_starts();
    let mut header = Vec::new();
    let mut rows = Vec::new();
    let mut in_data = false;
    for (index, &start) in starts.iter().enumerate() {
        let end = starts.get(index + 1).copied().unwrap_or(file.text.len());
        let raw = file.text[start..end].trim_end_matches(['\n', '\r']);
        // A byte-order mark saved twice (an editor re-saving an export).
        let line = raw.trim_start_matches('\u{feff}');
        let start = start + (raw.len() - line.len());
        if line.trim().is_empty() {
            continue;
        }
        match split_row(line, start, index as u32 + 1, layout.separator) {
            Ok(row) => {
                in_data = in_data || layout.is_data(&row);
                if in_data {
                    rows.push(row);
                } else {
                    header.push(row);
                }
            }
            Err(diagnostic) => {
                // A line that does not split is a broken row once the rows
                // have begun, or when it reads as one; before that, a title.
                let fields = rows::split_fields(line, layout.separator);
                let looks_like_row = fields.len() > layout.operand
                    && layout
                        .step
                        .is_none_or(|step| fields[step].trim().bytes().all(|b| b.is_ascii_digit()));
                in_data = in_data || looks_like_row;
                if in_data {
                    diagnostics.push(diagnostic);
                }
            }
        }
    }
    Lines { header, rows }
}

/// The error for an export whose header names another CPU family.
fn foreign_cpu(header: &[Row]) -> Option<Diagnostic> {
    // The PLC-information line comes after the program name; the name is
    // looked at last (a program may be called anything).
    let rows = header.iter().skip(1).chain(header.first());
    rows.flat_map(|row| &row.fields)
        .find_map(|field| match cpu_family(&field.text)? {
            Cpu::Fx => None,
            Cpu::Other(family) => Some(not_fx(field.span, family)),
        })
}

fn not_fx(span: Span, family: &str) -> Diagnostic {
    Diagnostic::new(
        Code::NotAnFxProgram,
        span,
        format!("this is an export of a {family} program, not of an FX program"),
    )
    .with_label(format!("the PLC information names a {family} CPU"))
    .with_note("ladderc compiles programs of Mitsubishi FX PLCs (FX1S, FX1N, FX2N, FX3U, FX3G and compatibles)")
}

/// For a file of fields that is no export ladderc reads: the error that
/// its first lines name another CPU family (`PLC Information:` of a
/// MELSEC-L export re-saved without quotes), if they do.
pub fn foreign_cpu_in(file: &SourceFile) -> Option<Diagnostic> {
    let mut lines = Vec::new();
    let mut at = 0;
    for line in file.text.split_inclusive('\n').take(4) {
        lines.push((at, line));
        at += line.len();
    }
    // The PLC information after the program's name, the name last (as in
    // a quoted export).
    let order = lines.iter().skip(1).chain(lines.first());
    order.into_iter().find_map(|&(line_start, line)| {
        let mut start = line_start;
        for field in line.split(['\t', ',']) {
            let text = field.trim_matches(|c: char| c.is_whitespace() || c == '"' || c == '\u{feff}');
            if let Some(Cpu::Other(family)) = cpu_family(text) {
                let begin = start + field.find(text).unwrap_or(0);
                return Some(not_fx(Span::new(begin, begin + text.len()), family));
            }
            start += field.len() + 1;
        }
        None
    })
}

/// Reads an export as a program.
pub fn parse(file: &SourceFile) -> (ParsedProgram, Diagnostics) {
    let mut diagnostics = Diagnostics::default();
    let mut statements: Vec<Statement> = Vec::new();
    let Some(layout) = detect(&file.text) else {
        return (ParsedProgram { statements }, diagnostics);
    };
    let Lines { header, rows } = lines(file, &layout, &mut diagnostics);
    if let Some(foreign) = foreign_cpu(&header) {
        let mut only = Diagnostics::default();
        only.push(foreign);
        return (ParsedProgram { statements }, only);
    }
    for row in rows {
        let operand = row.field(layout.operand);
        if let Some(problem) = row_problem(&layout, &row) {
            diagnostics.push(problem);
            continue;
        }
        match row.field(layout.instruction) {
            Some(instruction) => {
                let word = instruction.text.trim();
                if let Some(number) = label_number(word) {
                    statements.push(Statement {
                        kind: StatementKind::Label { number },
                        span: instruction.span,
                        line: row.line,
                    });
                    continue;
                }
                let mut syntax = InstructionSyntax {
                    mnemonic: word.to_ascii_uppercase(),
                    mnemonic_span: instruction.span,
                    operands: Vec::new(),
                    malformed: false,
                };
                let mut span = instruction.span;
                if let Some(operand) = operand {
                    add_operand(&mut syntax, &mut span, operand, &mut diagnostics);
                }
                statements.push(Statement {
                    kind: StatementKind::Instruction(syntax),
                    span,
                    line: row.line,
                });
            }
            None => {
                let Some(operand) = operand else {
                    continue; // a comment row
                };
                let step_empty = row.column(layout.step).is_empty();
                let previous = statements.last_mut().filter(|_| step_empty);
                match previous {
                    Some(Statement {
                        kind: StatementKind::Instruction(syntax),
                        span,
                        ..
                    }) => add_operand(syntax, span, operand, &mut diagnostics),
                    Some(Statement {
                        kind: StatementKind::Label { .. },
                        ..
                    })
                    | None => diagnostics.push(
                        Diagnostic::new(
                            Code::MalformedCsvRow,
                            operand.span,
                            "an operand row with no instruction above it",
                        )
                        .with_label("operand rows continue the instruction of the row above")
                        .with_note(if step_empty {
                            "the rows above hold no instruction that takes operands"
                        } else {
                            "a row with a step number needs an instruction"
                        }),
                    ),
                }
            }
        }
    }
    (ParsedProgram { statements }, diagnostics)
}

/// The comment rows of an export (no instruction, no operand): their line
/// and their line statement, PI statement and note, for the ladder.
pub fn comment_rows(file: &SourceFile) -> Vec<(u32, String)> {
    let Some(layout) = detect(&file.text) else {
        return Vec::new();
    };
    let mut ignored = Diagnostics::default();
    let Lines { rows, .. } = lines(file, &layout, &mut ignored);
    rows.iter()
        .filter(|row| row.text(layout.instruction).is_empty() && row.text(layout.operand).is_empty())
        .flat_map(|row| {
            layout
                .comments(row)
                .map(|text| (row.line, text.to_string()))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// What makes a row that splits into fields still unreadable: a step that
/// is not a number, an instruction field that is not one word, an operand
/// on a label's row. (Such rows would also not survive `to_il`.)
fn row_problem(layout: &Layout, row: &Row) -> Option<Diagnostic> {
    let problem = |field: usize, message: &str, label: &str| {
        let span = row.fields.get(field).map_or_else(Span::default, |f| f.span);
        Some(Diagnostic::new(Code::MalformedCsvRow, span, message.to_string()).with_label(label.to_string()))
    };
    if let Some(step) = layout.step {
        if !row.text(step).bytes().all(|b| b.is_ascii_digit()) {
            return problem(step, "the step column holds a step number", "not a number");
        }
    }
    let instruction = row.text(layout.instruction);
    if instruction.contains(|c: char| c.is_whitespace() || c == ';' || c == ',') || instruction.contains("//") {
        return problem(
            layout.instruction,
            "the instruction column holds one word",
            "more than an instruction",
        );
    }
    let operand = row.text(layout.operand);
    if operand.contains(|c: char| c.is_whitespace() || c == ';' || c == ',') || operand.contains("//") {
        return problem(
            layout.operand,
            "the operand column holds one operand",
            "more than one operand",
        );
    }
    if label_number(instruction).is_some() && !operand.is_empty() {
        return problem(
            layout.operand,
            "a label's row holds no operand",
            "labels are rows of their own",
        );
    }
    if instruction.contains('\0') || layout.comments(row).any(|c| c.contains('\0')) {
        return problem(layout.instruction, "a NUL character in the row", "not text");
    }
    None
}

fn add_operand(syntax: &mut InstructionSyntax, span: &mut Span, field: &Field, diagnostics: &mut Diagnostics) {
    let text = field.text.trim();
    let offset = field.text.find(text).unwrap_or(0);
    match parse_operand(text, field.span.start as usize + offset) {
        Ok(operand) => {
            *span = span.to(operand.span);
            syntax.operands.push(operand);
        }
        Err(diagnostic) => {
            diagnostics.push(diagnostic);
            syntax.malformed = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn export(rows: &[&str]) -> SourceFile {
        let mut text = String::from("\"MAIN\"\r\n\"PLC:\"\t\"FX3U\"\r\n\"Step\"\t\"Line Statement\"\t\"Instruction\"\t\"I/O(Device)\"\t\"Blank\"\t\"PI Statement\"\t\"Note\"\r\n");
        for row in rows {
            text.push_str(row);
            text.push_str("\r\n");
        }
        SourceFile::new("t.csv", text)
    }

    fn row(fields: [&str; 7]) -> String {
        fields.map(|f| format!("\"{f}\"")).join("\t")
    }

    #[test]
    fn rows_become_statements_with_their_own_lines() {
        let file = export(&[
            &row(["", "start the motor", "", "", "", "", ""]),
            &row(["0", "", "LD", "X000", "", "", "start button"]),
            &row(["1", "", "OUT", "T0", "", "", ""]),
            &row(["", "", "", "K10", "", "", ""]),
            &row(["4", "", "P1", "", "", "", ""]),
            &row(["5", "", "END", "", "", "", ""]),
        ]);
        assert!(is_export(&file.text));
        let (parsed, diagnostics) = parse(&file);
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        let shapes: Vec<(u32, String)> = parsed
            .statements
            .iter()
            .map(|s| match &s.kind {
                StatementKind::Instruction(i) => (s.line, format!("{} {}", i.mnemonic, i.operands.len())),
                StatementKind::Label { number } => (s.line, format!("P{number}")),
            })
            .collect();
        assert_eq!(
            shapes,
            [
                (5, "LD 1".into()),
                (6, "OUT 2".into()),
                (8, "P1".into()),
                (9, "END 0".into())
            ]
        );
        let preset = match &parsed.statements[1].kind {
            StatementKind::Instruction(i) => i.operands[1].span,
            StatementKind::Label { .. } => panic!("an instruction"),
        };
        assert_eq!(file.slice(preset), "K10");
        assert_eq!(file.line_of(preset.start), 7);
    }

    #[test]
    fn unreadable_rows_are_errors_at_their_line() {
        let file = export(&[
            &row(["", "", "", "K1", "", "", ""]),
            "\"0\"\t\"\"\t\"LD\t\"X0\"",
            &row(["1", "", "OUT", "Y0", "", "", ""]),
        ]);
        let (_, diagnostics) = parse(&file);
        let mut found: Vec<(Code, u32)> = diagnostics
            .iter()
            .map(|d| (d.code, file.line_of(d.span.start)))
            .collect();
        found.sort();
        assert_eq!(found, [(Code::MalformedCsvRow, 4), (Code::MalformedCsvRow, 5)]);
    }

    #[test]
    fn rows_that_would_not_survive_import_are_errors() {
        for bad in [
            row(["6", "", "P1", "K5", "", "", ""]),
            row(["1", "", "LD X0", "", "", "", ""]),
            row(["x", "", "OUT", "Y0", "", "", ""]),
            row(["1", "", "LD", "X0 X1", "", "", ""]),
        ] {
            let first = row(["0", "", "LD", "X0", "", "", ""]);
            let (_, diagnostics) = parse(&export(&[&first, &bad]));
            assert_eq!(
                diagnostics.iter().map(|d| d.code).collect::<Vec<_>>(),
                [Code::MalformedCsvRow],
                "{bad}"
            );
        }
    }

    #[test]
    fn import_is_linear_in_operand_rows() {
        let operands: Vec<String> = (0..200_000).map(|_| row(["", "", "", "K1", "", "", "n"])).collect();
        let mut rows: Vec<&str> = vec!["\"0\"\t\"\"\t\"LD\"\t\"X0\"\t\"\"\t\"\"\t\"\""];
        rows.extend(operands.iter().map(String::as_str));
        let il = to_il(&export(&rows)).unwrap();
        assert_eq!(il.matches("K1").count(), 200_000);
    }

    #[test]
    fn plain_il_is_not_an_export() {
        assert!(!is_export("LD X0\nOUT Y0\n"));
        assert!(!is_export("\"LD X0\nOUT Y0\n"));
    }

    #[test]
    fn import_keeps_steps_comments_and_notes() {
        let file = export(&[
            &row(["", "start the motor", "", "", "", "", ""]),
            &row(["0", "", "LD", "X000", "", "", "start button"]),
            &row(["1", "", "MOV", "K5", "", "", ""]),
            &row(["", "", "", "D0", "", "", "speed"]),
            &row(["6", "", "END", "", "", "", ""]),
        ]);
        let il = to_il(&file).unwrap();
        assert_eq!(
            il,
            "// MAIN\n// PLC: FX3U\n// imported from t.csv by ladderc import\n// start the motor\n0\tLD\tX000 ; start button\n1\tMOV\tK5 D0 ; speed\n6\tEND\n"
        );
    }
}
