//! A source file compiled: the files that are one error whatever they
//! hold (a GX Developer project that cannot be decoded, a NUL byte, bytes
//! that are not text), parsing, the program against its CPU, the checker,
//! and for a project's listing its steps in D8069 and in diagnostics.

use super::{check, cpu};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::CheckedProgram;
use crate::source::{SourceFile, Span};
use crate::syntax;

/// Parses and checks a source file. The program is returned only when there
/// are no errors; the diagnostics may hold warnings either way.
pub fn compile_source(file: &SourceFile) -> (Option<CheckedProgram>, Vec<Diagnostic>) {
    compile_source_on(file, None)
}

/// `compile_source` for a program that will run on (or be written for)
/// CPU `cpu` where its own `//@ cpu` line names none.
pub fn compile_source_on(file: &SourceFile, cpu: Option<&str>) -> (Option<CheckedProgram>, Vec<Diagnostic>) {
    // A binary project file that cannot be decoded: its one error.
    if let Some(message) = &file.decode_error {
        let diagnostic = Diagnostic::new(Code::UndecodableProject, Span::new(0, 0), message.clone())
            .with_label("this file")
            .with_note("nothing of the project is compiled; `ladderc explain E0053` says what is read");
        return (None, vec![diagnostic]);
    }
    let (program, diagnostics) = compile_text(file, cpu);
    match &file.listing_of {
        None => (program, diagnostics),
        Some(name) => {
            // D8069 records the instruction's step, as on the PLC.
            let program = program.map(|mut program| {
                for instruction in &mut program.instructions {
                    instruction.step = listed_step(file, instruction.line);
                }
                program
            });
            (
                program,
                diagnostics.into_iter().map(|d| with_step(file, name, d)).collect(),
            )
        }
    }
}

/// The step number a listing's line starts with.
fn listed_step(file: &SourceFile, line: u32) -> Option<u32> {
    let start = *file.line_starts().get((line as usize).checked_sub(1)?)?;
    let digits: String = file.text[start..].chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// A diagnostic on a project's listing names the step as GX Developer
/// shows it (`MAIN.wpg step 125`): the step number starts the line.
fn with_step(file: &SourceFile, name: &str, diagnostic: Diagnostic) -> Diagnostic {
    match listed_step(file, file.line_of(diagnostic.span.start)) {
        Some(step) => diagnostic.with_note(format!("at {name} step {step}")),
        None => diagnostic,
    }
}

fn compile_text(file: &SourceFile, cpu: Option<&str>) -> (Option<CheckedProgram>, Vec<Diagnostic>) {
    // A NUL byte means this is not a program text: one error, not a cascade.
    if let Some(nul) = file.text.find('\0') {
        let diagnostic = Diagnostic::new(Code::BinaryInput, Span::new(nul, nul + 1), "this is not a text file")
            .with_label("a NUL byte")
            .with_note("program files are text: UTF-8, UTF-16 with a byte-order mark, or a GX Works2 CSV export");
        return (None, vec![diagnostic]);
    }
    // Bytes that are not text in the file's encoding: one error, before the
    // garbage they decode to makes a cascade.
    if let Some(at) = file.undecodable_at {
        let end = at + char::REPLACEMENT_CHARACTER.len_utf8();
        let diagnostic = Diagnostic::new(
            Code::UnknownEncoding,
            Span::new(at, end),
            "text encoding not recognised",
        )
        .with_label("not valid UTF-8 (or UTF-16) here")
        .with_note(
            "program files are UTF-8 (with or without the byte-order mark EF BB BF) or UTF-16 with \
                 a byte-order mark (FF FE or FE FF); save the file in one of these",
        );
        return (None, vec![diagnostic]);
    }
    let (parsed, mut diagnostics) = syntax::parse(file);
    // A file the parser refused as a whole (an export of another PLC
    // family, one it cannot read) has nothing to check: its one error is all
    // there is to say (no "the program is empty" beside it).
    if diagnostics.has_errors() && parsed.statements.is_empty() {
        return (None, diagnostics.into_sorted());
    }
    // The CPU a GX Developer project's parameters name (or any IL's
    // `//@ cpu` line): what it does not have is an error.
    let named = crate::gxdev::listing::directives(&file.text).cpu;
    if let Some(cpu) = named.as_deref().or(cpu) {
        for diagnostic in cpu::check(&parsed, cpu).iter() {
            diagnostics.push(diagnostic.clone());
        }
    }
    let parse_failed = diagnostics.has_errors();
    let (program, check_diagnostics) = check(&parsed, &file.name, file.text.len());
    for diagnostic in check_diagnostics.iter() {
        // After an error the program is not complete: whether it drives
        // anything is not worth a word (as the checker's own lints hold).
        if !(parse_failed && diagnostic.code == Code::DrivesNothing) {
            diagnostics.push(diagnostic.clone());
        }
    }
    let program = if diagnostics.has_errors() { None } else { Some(program) };
    (program, diagnostics.into_sorted())
}
