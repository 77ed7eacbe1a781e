//! Rendering with codespan-reporting: `file:line:col`, the source line and the
//! span underlined, plus the code.

use super::{Diagnostic, Severity};
use crate::source::SourceFile;
use codespan_reporting::diagnostic::{Diagnostic as Report, Label};
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term::{self, Config};

/// Renders one diagnostic as plain text.
pub fn render(file: &SourceFile, diagnostic: &Diagnostic) -> String {
    let files = SimpleFile::new(file.name.as_str(), file.text.as_str());
    let report = match diagnostic.severity() {
        Severity::Error => Report::error(),
        Severity::Warning => Report::warning(),
    };
    let primary = Label::primary((), diagnostic.span.range()).with_message(&diagnostic.label);
    let labels = std::iter::once(primary).chain(
        diagnostic
            .related
            .iter()
            .map(|(span, text)| Label::secondary((), span.range()).with_message(text)),
    );
    let report = report
        .with_code(diagnostic.code.as_str())
        .with_message(&diagnostic.message)
        .with_labels(labels.collect())
        .with_notes(diagnostic.notes.clone());
    term::emit_into_string(&Config::default(), &files, &report).unwrap_or_else(|_| {
        // Only reachable with a span outside the text; never lose the message.
        let (line, col) = file.line_col(diagnostic.span.start);
        format!(
            "{}[{}]: {}\n  --> {}:{line}:{col}\n",
            if diagnostic.is_error() { "error" } else { "warning" },
            diagnostic.code,
            diagnostic.message,
            file.name
        )
    })
}

/// Renders diagnostics in source order, followed by a count line.
pub fn render_all(file: &SourceFile, diagnostics: &[Diagnostic]) -> String {
    let mut out: String = diagnostics.iter().map(|d| render(file, d)).collect();
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    let warnings = diagnostics.len() - errors;
    if errors > 0 {
        out.push_str(&format!(
            "{}: {} error{}{}\n",
            file.name,
            errors,
            if errors == 1 { "" } else { "s" },
            match warnings {
                0 => String::new(),
                1 => ", 1 warning".to_string(),
                n => format!(", {n} warnings"),
            }
        ));
    }
    out
}
