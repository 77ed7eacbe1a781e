//! Parser of plain IL: tokens of each line to a statement. Whether a file
//! is plain IL or an export is decided in `mod.rs`.

use super::lexer::{tokenize, Token, TokenKind};
use super::operand::parse_operand;
use super::{InstructionSyntax, ParsedProgram, Statement, StatementKind};
use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::source::{SourceFile, Span};

/// Parses plain IL.
pub(super) fn parse_il(file: &SourceFile) -> (ParsedProgram, Diagnostics) {
    let mut diagnostics = Diagnostics::default();
    let tokens = tokenize(&file.text);
    let statements = tokens
        .split(|t| t.kind == TokenKind::Newline)
        .filter(|line| !line.is_empty())
        .filter_map(|line| parse_line(file, line, &mut diagnostics))
        .collect();
    (ParsedProgram { statements }, diagnostics)
}

fn parse_line(file: &SourceFile, line: &[Token], diagnostics: &mut Diagnostics) -> Option<Statement> {
    let text = |t: &Token| file.slice(t.span);
    let line_number = file.line_of(line[0].span.start);
    let mut rest = line;

    // An optional step number, as vendor listings export it.
    if rest[0].kind == TokenKind::Word && text(&rest[0]).bytes().all(|b| b.is_ascii_digit()) {
        if rest.len() == 1 {
            diagnostics.push(
                Diagnostic::new(Code::MalformedLine, rest[0].span, "step number without an instruction")
                    .with_label("expected an instruction after the step number"),
            );
            return None;
        }
        rest = &rest[1..];
    }
    let head = rest[0];
    if head.kind == TokenKind::Comma {
        diagnostics.push(stray_comma(head.span));
        return None;
    }
    let head_text = text(&head);
    if let Some(number) = label_number(head_text) {
        if rest.len() > 1 {
            let span = rest[1].span.to(rest[rest.len() - 1].span);
            diagnostics.push(
                Diagnostic::new(
                    Code::MalformedLine,
                    span,
                    format!("label `{head_text}` must be alone on its line"),
                )
                .with_label("nothing may follow a label"),
            );
        }
        return Some(Statement {
            kind: StatementKind::Label { number },
            span: head.span,
            line: line_number,
        });
    }

    let mnemonic = head_text.to_ascii_uppercase();
    let mut operands = Vec::new();
    let mut malformed = false;
    let mut expect_operand = true;
    // A line reports a few problems, not one per character: a run of stray
    // commas is one diagnostic, and past `MOST_PER_LINE` the line is only
    // marked malformed (each diagnostic shows the whole line, so thousands
    // of them on one long line would print gigabytes).
    const MOST_PER_LINE: usize = 8;
    let first_of_line = diagnostics.len();
    let mut previous_stray: Option<usize> = None;
    for (i, token) in rest.iter().enumerate().skip(1) {
        if diagnostics.len() - first_of_line >= MOST_PER_LINE {
            malformed = true;
            break;
        }
        let stray = previous_stray.take();
        match token.kind {
            TokenKind::Comma if expect_operand || i == rest.len() - 1 || i == 1 => {
                match stray {
                    Some(index) => diagnostics.extend_span(index, token.span),
                    None => diagnostics.push(stray_comma(token.span)),
                }
                previous_stray = Some(stray.unwrap_or(diagnostics.len() - 1));
                malformed = true;
            }
            TokenKind::Comma => expect_operand = true,
            TokenKind::Word if mnemonic == "NETWORK" => {
                // NETWORK takes a bare number, not an operand.
                if !text(token).bytes().all(|b| b.is_ascii_digit()) || i > 1 {
                    diagnostics.push(
                        Diagnostic::new(
                            Code::MalformedLine,
                            token.span,
                            format!("`{}` after NETWORK", text(token)),
                        )
                        .with_label("NETWORK takes an optional network number"),
                    );
                }
            }
            TokenKind::Word => {
                match parse_operand(text(token), token.span.start as usize) {
                    Ok(operand) => operands.push(operand),
                    Err(diagnostic) => {
                        diagnostics.push(diagnostic);
                        malformed = true;
                    }
                }
                expect_operand = false;
            }
            TokenKind::Newline => {}
        }
    }
    let span = head.span.to(rest[rest.len() - 1].span);
    Some(Statement {
        kind: StatementKind::Instruction(InstructionSyntax {
            mnemonic,
            mnemonic_span: head.span,
            operands,
            malformed,
        }),
        span,
        line: line_number,
    })
}

/// `P12` or `P12:` (case-insensitive) is a label; returns its number.
pub(super) fn label_number(word: &str) -> Option<u32> {
    let body = word.strip_suffix(':').unwrap_or(word);
    let digits = body.strip_prefix(['P', 'p'])?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some(digits.parse().unwrap_or(u32::MAX))
}

fn stray_comma(span: Span) -> Diagnostic {
    Diagnostic::new(Code::MalformedLine, span, "unexpected `,`").with_label("commas only separate operands")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parse;

    fn parse_text(text: &str) -> (ParsedProgram, Vec<Code>) {
        let (program, diagnostics) = parse(&SourceFile::new("t.il", text));
        (program, diagnostics.iter().map(|d| d.code).collect())
    }

    fn mnemonics(program: &ParsedProgram) -> Vec<&str> {
        program
            .statements
            .iter()
            .map(|s| match &s.kind {
                StatementKind::Instruction(i) => i.mnemonic.as_str(),
                StatementKind::Label { .. } => "<label>",
            })
            .collect()
    }

    #[test]
    fn step_numbers_comments_and_labels() {
        let (program, errors) = parse_text("0 LD X000 // go\n\n1 out y0\nP3:\nP4\nNETWORK 001\n");
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(mnemonics(&program), ["LD", "OUT", "<label>", "<label>", "NETWORK"]);
        assert_eq!(program.statements[1].line, 3);
        assert_eq!(program.statements[3].kind, StatementKind::Label { number: 4 });
    }

    #[test]
    fn commas_between_operands() {
        let (program, errors) = parse_text("MOV K1, D0\nMOV ,K1 D0\nMOV K1 D0,\nMOV K1,,D0");
        assert_eq!(errors, [Code::MalformedLine; 3]);
        let StatementKind::Instruction(first) = &program.statements[0].kind else {
            panic!()
        };
        assert_eq!(first.operands.len(), 2);
        assert!(!first.malformed);
    }

    #[test]
    fn bad_lines_are_reported_and_parsing_goes_on() {
        let (program, errors) = parse_text("12\nP1 LD X0\nLD X9\nOUT Y0");
        assert_eq!(
            errors,
            [Code::MalformedLine, Code::MalformedLine, Code::MalformedOperand]
        );
        assert_eq!(mnemonics(&program), ["<label>", "LD", "OUT"]);
        let StatementKind::Instruction(ld) = &program.statements[1].kind else {
            panic!()
        };
        assert!(ld.malformed);
    }

    /// Found by AFL: a line of 26,000 commas gave a diagnostic per comma,
    /// each printing the whole line (16 s and 700 MB of output).
    #[test]
    fn a_run_of_stray_commas_is_one_diagnostic_and_a_line_reports_a_few() {
        let commas = ",".repeat(20_000);
        let (_, codes) = parse_text(&format!("LD X0{commas}\n"));
        assert_eq!(codes, vec![Code::MalformedLine], "{codes:?}");
        let words = " ?".repeat(5_000);
        let (_, codes) = parse_text(&format!("LD{words}\nLD X0 ,,, X1 ,, X2\n"));
        assert!(codes.len() <= 8 + 2, "{} diagnostics", codes.len());
        assert!(codes.len() >= 2, "{codes:?}");
    }
}
