//! `ladderc import`: an export as plain IL.

use super::{detect, lines, parse, Lines};
use crate::diagnostics::Diagnostics;
use crate::source::SourceFile;

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
    let Some(layout) = detect(&file.text) else {
        return Err(parse_diagnostics);
    };
    let Lines { header, rows } = lines(file, &layout, &mut diagnostics);
    let mut lines: Vec<IlLine> = Vec::new();
    // The program-name and PLC-information lines.
    for row in header.iter().take(2) {
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
    for row in rows {
        let instruction = row.text(layout.instruction);
        let operand = row.text(layout.operand);
        let notes = [layout.pi_statement, layout.note]
            .into_iter()
            .map(|i| row.text(i))
            .filter(|t| !t.is_empty())
            .map(one_line);
        match (instruction.is_empty(), operand.is_empty()) {
            (false, _) => {
                let statement = row.column(layout.statement);
                if !statement.is_empty() {
                    lines.push(IlLine::Comment(one_line(statement)));
                }
                let step = row.column(layout.step);
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
                let statement = Some(row.column(layout.statement))
                    .filter(|t| !t.is_empty())
                    .map(one_line);
                if let Some(IlLine::Instruction {
                    operands, notes: kept, ..
                }) = instruction_line.and_then(|i| lines.get_mut(i))
                {
                    operands.push(operand.to_string());
                    kept.extend(statement.into_iter().chain(notes));
                }
            }
            (true, true) => lines.extend(layout.comments(&row).map(|c| IlLine::Comment(one_line(c)))),
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
