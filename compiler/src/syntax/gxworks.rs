//! GX Works2 instruction-list CSV exports: reading them as programs, with
//! every statement's span in the export itself (so diagnostics show its own
//! lines), and writing them out as plain IL (`ladderc import`).
//!
//! An export is tab-separated with every field in double quotes: the program
//! name, the PLC information and a header line (words in the editor's
//! language), then one row per step: step number, line statement,
//! instruction, operand, blank, PI statement, note. A row with neither a
//! step nor an instruction holds the next operand of the instruction above;
//! one with only a line statement (or a note) is a comment. Labels and
//! END/FEND/SRET are rows of their own.
//!
//! Rows are split here rather than with a CSV library: each field needs its
//! span in the file, and a quote left open must be an error at its own line
//! instead of swallowing the lines after it.

use super::operand::parse_operand;
use super::parser::label_number;
use super::{InstructionSyntax, ParsedProgram, Statement, StatementKind};
use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::source::{SourceFile, Span};

/// Field positions of a row.
const STEP: usize = 0;
const LINE_STATEMENT: usize = 1;
const INSTRUCTION: usize = 2;
const OPERAND: usize = 3;
const PI_STATEMENT: usize = 5;
const NOTE: usize = 6;

/// Is `text` a GX Works2 CSV export? Told by content, not by file name:
/// its first line is a quoted field, and a tab-separated row of quoted
/// fields follows within the first lines. (Plain IL never starts with a
/// quote.)
pub fn is_export(text: &str) -> bool {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let starts_quoted = lines.next().is_some_and(|first| first.trim_start().starts_with('"'));
    starts_quoted
        && text
            .lines()
            .filter(|l| !l.trim().is_empty())
            .take(8)
            .any(|line| line.contains("\"\t\""))
}

/// One field of a row: its text (quotes removed, `""` unescaped) and the
/// span of that text in the file.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Field {
    text: String,
    span: Span,
}

/// One line of the export, split into fields.
struct Row {
    line: u32,
    fields: Vec<Field>,
}

impl Row {
    fn text(&self, index: usize) -> &str {
        self.fields.get(index).map_or("", |f| f.text.trim())
    }

    fn field(&self, index: usize) -> Option<&Field> {
        self.fields.get(index).filter(|f| !f.text.trim().is_empty())
    }

    /// A row of the program: at least the four first fields, the first a
    /// step number or empty. The header lines before the first one have
    /// fewer fields (program name, PLC information) or words in the step
    /// column (the column titles).
    fn is_data(&self) -> bool {
        let step = self.text(STEP);
        self.fields.len() > OPERAND && step.bytes().all(|b| b.is_ascii_digit())
    }

    /// The row's comments: its line statement, PI statement and note.
    fn comments(&self) -> impl Iterator<Item = &str> {
        [LINE_STATEMENT, PI_STATEMENT, NOTE]
            .into_iter()
            .map(|i| self.text(i))
            .filter(|t| !t.is_empty())
    }
}

/// Splits one line (starting at byte `start` of the file) into fields.
fn split_row(line: &str, start: usize, line_number: u32) -> Result<Row, Diagnostic> {
    let mut fields = Vec::new();
    let mut rest = line;
    let mut at = start;
    loop {
        let (field, used) = if let Some(quoted) = rest.strip_prefix('"') {
            let mut text = String::new();
            let mut chars = quoted.char_indices();
            let close = loop {
                match chars.next() {
                    None => {
                        return Err(Diagnostic::new(
                            Code::MalformedCsvRow,
                            Span::new(at, start + line.len()),
                            "a quote is not closed",
                        )
                        .with_label("this field has no closing `\"` on its line"));
                    }
                    Some((i, '"')) if quoted[i + 1..].starts_with('"') => {
                        text.push('"');
                        chars.next();
                    }
                    Some((i, '"')) => break i,
                    Some((_, c)) => text.push(c),
                }
            };
            let span = Span::new(at + 1, at + 1 + close);
            (Field { text, span }, close + 2)
        } else {
            let end = rest.find('\t').unwrap_or(rest.len());
            let text = rest[..end].to_string();
            (
                Field {
                    text,
                    span: Span::new(at, at + end),
                },
                end,
            )
        };
        fields.push(field);
        rest = &rest[used..];
        at += used;
        match rest.strip_prefix('\t') {
            Some(next) => {
                rest = next;
                at += 1;
            }
            None if rest.trim().is_empty() => break,
            None => {
                return Err(Diagnostic::new(
                    Code::MalformedCsvRow,
                    Span::new(at, at + rest.trim_end().len()),
                    "text after a closing quote",
                )
                .with_label("fields are separated by tabs"));
            }
        }
    }
    Ok(Row {
        line: line_number,
        fields,
    })
}

/// Every row of the export after its header, or the diagnostic of a row
/// that cannot be read.
fn rows(file: &SourceFile, diagnostics: &mut Diagnostics) -> Vec<Row> {
    let starts = file.line_starts();
    let mut rows = Vec::new();
    let mut in_data = false;
    for (index, &start) in starts.iter().enumerate() {
        let end = starts.get(index + 1).copied().unwrap_or(file.text.len());
        let line = file.text[start..end].trim_end_matches(['\n', '\r']);
        if line.trim().is_empty() {
            continue;
        }
        match split_row(line, start, index as u32 + 1) {
            Ok(row) => {
                in_data = in_data || row.is_data();
                if in_data {
                    rows.push(row);
                }
            }
            Err(diagnostic) => diagnostics.push(diagnostic),
        }
    }
    rows
}

/// Reads an export as a program.
pub fn parse(file: &SourceFile) -> (ParsedProgram, Diagnostics) {
    let mut diagnostics = Diagnostics::default();
    let mut statements: Vec<Statement> = Vec::new();
    for row in rows(file, &mut diagnostics) {
        let operand = row.field(OPERAND);
        if let Some(problem) = row_problem(&row) {
            diagnostics.push(problem);
            continue;
        }
        match row.field(INSTRUCTION) {
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
                let previous = statements.last_mut().filter(|_| row.text(STEP).is_empty());
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
                        .with_note(if row.text(STEP).is_empty() {
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

/// What makes a row that splits into fields still unreadable: a step that
/// is not a number, an instruction field that is not one word, an operand
/// on a label's row. (Such rows would also not survive `to_il`.)
fn row_problem(row: &Row) -> Option<Diagnostic> {
    let problem = |field: usize, message: &str, label: &str| {
        let span = row.fields.get(field).map_or_else(Span::default, |f| f.span);
        Some(Diagnostic::new(Code::MalformedCsvRow, span, message.to_string()).with_label(label.to_string()))
    };
    if !row.text(STEP).bytes().all(|b| b.is_ascii_digit()) {
        return problem(STEP, "the step column holds a step number", "not a number");
    }
    let instruction = row.text(INSTRUCTION);
    if instruction.contains(|c: char| c.is_whitespace() || c == ';' || c == ',') || instruction.contains("//") {
        return problem(
            INSTRUCTION,
            "the instruction column holds one word",
            "more than an instruction",
        );
    }
    let operand = row.text(OPERAND);
    if operand.contains(|c: char| c.is_whitespace() || c == ';' || c == ',') || operand.contains("//") {
        return problem(OPERAND, "the operand column holds one operand", "more than one operand");
    }
    if label_number(instruction).is_some() && !operand.is_empty() {
        return problem(
            OPERAND,
            "a label's row holds no operand",
            "labels are rows of their own",
        );
    }
    if instruction.contains('\0') || row.comments().any(|c| c.contains('\0')) {
        return problem(INSTRUCTION, "a NUL character in the row", "not text");
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

/// One line of the IL `to_il` writes.
enum IlLine {
    Comment(String),
    /// An instruction or label: its step and mnemonic, its operands, and the
    /// notes of its rows.
    Instruction {
        head: String,
        operands: Vec<String>,
        notes: Vec<String>,
    },
}

/// The export as plain IL: a line per instruction or label with its step
/// number first, its operands after it, line statements as `//` comment
/// lines before it and notes as a `;` comment after it; the export's header
/// lines (program name, PLC information) as comments at the top. Reading
/// the IL gives the same program as reading the export (its instructions;
/// the lines D8069 records are the IL's).
pub fn to_il(file: &SourceFile) -> Result<String, Diagnostics> {
    // What `parse` reports is what makes the export unreadable here too.
    let (_, parse_diagnostics) = parse(file);
    if parse_diagnostics.has_errors() {
        return Err(parse_diagnostics);
    }
    let mut diagnostics = Diagnostics::default();
    let mut lines: Vec<IlLine> = Vec::new();
    // The program-name and PLC-information lines.
    let starts = file.line_starts();
    let header_rows = starts.iter().enumerate().filter_map(|(index, &start)| {
        let end = starts.get(index + 1).copied().unwrap_or(file.text.len());
        let line = file.text[start..end].trim_end_matches(['\n', '\r']);
        (!line.trim().is_empty())
            .then(|| split_row(line, start, 0).ok())
            .flatten()
    });
    for row in header_rows.take(2).filter(|row| !row.is_data()) {
        let words: Vec<&str> = row
            .fields
            .iter()
            .map(|f| f.text.trim())
            .filter(|t| !t.is_empty())
            .collect();
        lines.push(IlLine::Comment(one_line(&words.join(" "))));
    }
    let name = std::path::Path::new(&file.name)
        .file_name()
        .map_or(file.name.clone(), |n| n.to_string_lossy().into_owned());
    lines.push(IlLine::Comment(format!("imported from {name} by ladderc import")));
    // The line of the instruction that operand rows continue.
    let mut instruction_line = None;
    for row in rows(file, &mut diagnostics) {
        let instruction = row.text(INSTRUCTION);
        let operand = row.text(OPERAND);
        let notes = [PI_STATEMENT, NOTE]
            .into_iter()
            .map(|i| row.text(i))
            .filter(|t| !t.is_empty())
            .map(one_line);
        match (instruction.is_empty(), operand.is_empty()) {
            (false, _) => {
                let statement = row.text(LINE_STATEMENT);
                if !statement.is_empty() {
                    lines.push(IlLine::Comment(one_line(statement)));
                }
                let step = row.text(STEP);
                let head = if step.is_empty() {
                    instruction.to_string()
                } else {
                    format!("{step}\t{instruction}")
                };
                lines.push(IlLine::Instruction {
                    head,
                    operands: (!operand.is_empty()).then(|| operand.to_string()).into_iter().collect(),
                    notes: notes.collect(),
                });
                instruction_line = Some(lines.len() - 1);
            }
            (true, false) => {
                // A line statement on an operand row stays with its
                // instruction, as a note.
                let statement = Some(row.text(LINE_STATEMENT)).filter(|t| !t.is_empty()).map(one_line);
                if let Some(IlLine::Instruction {
                    operands, notes: kept, ..
                }) = instruction_line.and_then(|i| lines.get_mut(i))
                {
                    operands.push(operand.to_string());
                    kept.extend(statement.into_iter().chain(notes));
                }
            }
            (true, true) => lines.extend(row.comments().map(|c| IlLine::Comment(one_line(c)))),
        }
    }
    let mut il = String::new();
    for line in lines {
        match line {
            IlLine::Comment(text) => il.push_str(format!("// {text}").trim_end()),
            IlLine::Instruction { head, operands, notes } => {
                il.push_str(&head);
                if !operands.is_empty() {
                    il.push('\t');
                    il.push_str(&operands.join(" "));
                }
                if !notes.is_empty() {
                    il.push_str(" ; ");
                    il.push_str(&notes.join(" / "));
                }
            }
        }
        il.push('\n');
    }
    Ok(il)
}

/// A comment on one line: line breaks inside a field become blanks.
fn one_line(text: &str) -> String {
    text.split(['\r', '\n']).collect::<Vec<_>>().join(" ")
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
