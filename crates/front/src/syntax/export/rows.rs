//! Splitting an export's lines into fields: separated by the layout's
//! separator, each field quoted (`""` inside is one quote) or not. Rows are
//! split here rather than with a CSV library: each field needs its span in
//! the file, and a quote left open must be an error at its own line instead
//! of swallowing the lines after it.

use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

/// One field of a row: its text (quotes removed, `""` unescaped) and the
/// span of that text in the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Field {
    pub text: String,
    pub span: Span,
}

/// One line of the export, split into fields.
pub struct Row {
    pub line: u32,
    pub fields: Vec<Field>,
}

impl Row {
    pub fn text(&self, index: usize) -> &str {
        self.fields.get(index).map_or("", |f| f.text.trim())
    }

    /// The text of an optional column.
    pub fn column(&self, index: Option<usize>) -> &str {
        index.map_or("", |i| self.text(i))
    }

    pub fn field(&self, index: usize) -> Option<&Field> {
        self.fields.get(index).filter(|f| !f.text.trim().is_empty())
    }
}

/// The fields of a line for telling what a text is: lenient (a quote left
/// open runs to the end of the line).
pub fn split_fields(line: &str, separator: char) -> Vec<String> {
    let mut fields = Vec::new();
    let mut rest = line.trim_end_matches(['\r', '\n']);
    loop {
        let (field, remainder) = match rest.strip_prefix('"') {
            Some(quoted) => {
                let mut text = String::new();
                let mut chars = quoted.char_indices().peekable();
                let mut end = quoted.len();
                while let Some((i, c)) = chars.next() {
                    if c == '"' {
                        if chars.peek().is_some_and(|&(_, next)| next == '"') {
                            text.push('"');
                            chars.next();
                            continue;
                        }
                        end = i + 1;
                        break;
                    }
                    text.push(c);
                }
                let after = &quoted[end.min(quoted.len())..];
                let next = after.find(separator).map_or("", |at| &after[at..]);
                (text, next)
            }
            None => {
                let at = rest.find(separator).unwrap_or(rest.len());
                (rest[..at].to_string(), &rest[at..])
            }
        };
        fields.push(field);
        match remainder.strip_prefix(separator) {
            Some(next) => rest = next,
            None => break,
        }
    }
    fields
}

/// Splits one line (starting at byte `start` of the file) into fields.
pub fn split_row(line: &str, start: usize, line_number: u32, separator: char) -> Result<Row, Diagnostic> {
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
            let end = rest.find(separator).unwrap_or(rest.len());
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
        match rest.strip_prefix(separator) {
            Some(next) => {
                rest = next;
                at += separator.len_utf8();
            }
            None if rest.trim().is_empty() => break,
            None => {
                let between = if separator == '\t' { "tabs" } else { "commas" };
                return Err(Diagnostic::new(
                    Code::MalformedCsvRow,
                    Span::new(at, at + rest.trim_end().len()),
                    "text after a closing quote",
                )
                .with_label(format!("fields are separated by {between}")));
            }
        }
    }
    Ok(Row {
        line: line_number,
        fields,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_and_bare_fields() {
        assert_eq!(split_fields("\"0\",\"\",\"LD\",\"X0\"", ','), ["0", "", "LD", "X0"]);
        assert_eq!(split_fields("0,,LD,M8002,,,,,", ',').len(), 9);
        assert_eq!(split_fields("\"a\"\"b\"\t\"c\td\"", '\t'), ["a\"b", "c\td"]);
        assert_eq!(split_fields("\"open", '\t'), ["open"]);
        let row = split_row(",,,K100,,,,,,", 10, 3, ',').unwrap();
        assert_eq!(row.text(3), "K100");
        assert_eq!(row.fields[3].span, Span::new(13, 17));
        assert!(split_row("\"a\"x,\"b\"", 0, 1, ',').is_err());
    }
}
