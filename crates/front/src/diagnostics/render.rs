//! Rendering with codespan-reporting: `file:line:col`, the source line and the
//! span underlined, plus the code.
//!
//! The source file is its own file database: its line starts are computed
//! once when it is read, so rendering N diagnostics costs O(N log lines), not
//! O(N × file size) as building a codespan `SimpleFile` per diagnostic would.

use super::{Code, Diagnostic, Severity};
use crate::source::SourceFile;
use codespan_reporting::diagnostic::{Diagnostic as Report, Label};
use codespan_reporting::files::{Error as FilesError, Files};
use codespan_reporting::term::{self, Config};
use std::collections::BTreeMap;
use std::ops::Range;

impl<'a> Files<'a> for SourceFile {
    type FileId = ();
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, (): ()) -> Result<&'a str, FilesError> {
        Ok(&self.name)
    }

    fn source(&'a self, (): ()) -> Result<&'a str, FilesError> {
        Ok(&self.text)
    }

    fn line_index(&'a self, (): (), byte_index: usize) -> Result<usize, FilesError> {
        Ok(self.line_of(byte_index.min(u32::MAX as usize) as u32) as usize - 1)
    }

    fn line_range(&'a self, (): (), line_index: usize) -> Result<Range<usize>, FilesError> {
        let starts = self.line_starts();
        let start = *starts.get(line_index).ok_or(FilesError::LineTooLarge {
            given: line_index,
            max: starts.len() - 1,
        })?;
        let end = starts.get(line_index + 1).copied().unwrap_or(self.text.len());
        Ok(start..end)
    }
}

/// Renders one diagnostic as plain text.
pub fn render(file: &SourceFile, diagnostic: &Diagnostic) -> String {
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
    term::emit_into_string(&Config::default(), file, &report).unwrap_or_else(|_| {
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

/// How many diagnostics of one code are printed before the rest are only
/// counted: thousands of identical warnings help nobody, and a corrupt file
/// can produce an error per line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shown {
    All,
    PerCode { warnings: usize, errors: usize },
}

impl Default for Shown {
    fn default() -> Shown {
        Shown::PerCode {
            warnings: 20,
            errors: 200,
        }
    }
}

/// Renders diagnostics in source order, then a line per code cut short
/// ("and 17,412 more W0002 warnings"), then a count line when there are
/// errors.
pub fn render_all(file: &SourceFile, diagnostics: &[Diagnostic], shown: Shown) -> String {
    let mut out = String::new();
    let mut printed: BTreeMap<Code, usize> = BTreeMap::new();
    let mut hidden: BTreeMap<Code, usize> = BTreeMap::new();
    for diagnostic in diagnostics {
        let count = printed.entry(diagnostic.code).or_default();
        let show = match shown {
            Shown::All => true,
            Shown::PerCode { warnings, errors } => *count < if diagnostic.is_error() { errors } else { warnings },
        };
        if show {
            *count += 1;
            out.push_str(&render(file, diagnostic));
        } else {
            *hidden.entry(diagnostic.code).or_default() += 1;
        }
    }
    for (code, count) in &hidden {
        let kind = match code.severity() {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        out.push_str(&format!(
            "{}: and {} more {code} {kind}{} (`--all-diagnostics` prints every one)\n",
            file.name,
            thousands(*count),
            if *count == 1 { "" } else { "s" },
        ));
    }
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    let warnings = diagnostics.len() - errors;
    if errors > 0 {
        out.push_str(&format!(
            "{}: {} error{}{}\n",
            file.name,
            thousands(errors),
            if errors == 1 { "" } else { "s" },
            match warnings {
                0 => String::new(),
                1 => ", 1 warning".to_string(),
                n => format!(", {} warnings", thousands(n)),
            }
        ));
    }
    out
}

/// 17412 → "17,412".
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, digit) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(digit);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::compile_source;

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(thousands(7), "7");
        assert_eq!(thousands(17412), "17,412");
        assert_eq!(thousands(1_000_000), "1,000,000");
    }

    #[test]
    fn repeated_warnings_are_counted_after_the_first_ones() {
        // 30 double coils: W0002 on every OUT after the first.
        let text: String = (0..31).map(|i| format!("LD X{}\nOUT Y0\n", i % 8)).collect();
        let file = SourceFile::new("w.il", text);
        let (program, diagnostics) = compile_source(&file);
        assert!(program.is_some());
        let code = diagnostics[0].code;
        assert_eq!(diagnostics.len(), 30, "{diagnostics:?}");
        let limited = render_all(
            &file,
            &diagnostics,
            Shown::PerCode {
                warnings: 20,
                errors: 200,
            },
        );
        assert_eq!(limited.matches(&format!("warning[{code}]")).count(), 20, "{limited}");
        assert!(
            limited.contains(&format!("w.il: and 10 more {code} warnings")),
            "{limited}"
        );
        let all = render_all(&file, &diagnostics, Shown::All);
        assert_eq!(all.matches(&format!("warning[{code}]")).count(), 30);
        assert!(!all.contains("more"), "{all}");
    }

    #[test]
    fn rendering_points_at_the_line_and_column_from_the_shared_line_table() {
        let file = SourceFile::new("e.il", "LD X0\nOUT Y0\n  FOO X1\n");
        let (_, diagnostics) = compile_source(&file);
        let text = render_all(&file, &diagnostics, Shown::default());
        assert!(text.contains("e.il:3:3"), "{text}");
        assert!(text.contains("  FOO X1\n"), "{text}");
    }
}
