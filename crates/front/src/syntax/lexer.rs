//! Lexer: source text to words, commas and line ends, each with its span.
//! Comments (`//` and `;` to the end of the line) are dropped here.

use crate::source::Span;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TokenKind {
    /// A run of characters without blanks, commas or comment starts:
    /// a mnemonic, a step number, an operand or a label.
    Word,
    /// `,` between operands.
    Comma,
    /// End of a line.
    Newline,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    pub kind: TokenKind,
    pub span: Span,
}

/// Splits `text` into tokens. Never fails: every byte is either part of a
/// token, a blank, or inside a comment.
pub fn tokenize(text: &str) -> Vec<Token> {
    let mut tokens = Vec::new();
    let mut chars = text.char_indices().peekable();
    while let Some((start, c)) = chars.next() {
        match c {
            '\n' => tokens.push(token(TokenKind::Newline, start, start + 1)),
            ',' => tokens.push(token(TokenKind::Comma, start, start + 1)),
            ';' => skip_to_line_end(&mut chars),
            '/' if text[start..].starts_with("//") => skip_to_line_end(&mut chars),
            c if c.is_whitespace() => {}
            _ => {
                let mut end = start + c.len_utf8();
                while let Some(&(i, next)) = chars.peek() {
                    if next.is_whitespace() || next == ',' || next == ';' || text[i..].starts_with("//") {
                        break;
                    }
                    end = i + next.len_utf8();
                    chars.next();
                }
                tokens.push(token(TokenKind::Word, start, end));
            }
        }
    }
    tokens
}

fn token(kind: TokenKind, start: usize, end: usize) -> Token {
    Token {
        kind,
        span: Span::new(start, end),
    }
}

fn skip_to_line_end(chars: &mut std::iter::Peekable<std::str::CharIndices<'_>>) {
    while let Some(&(_, c)) = chars.peek() {
        if c == '\n' {
            break;
        }
        chars.next();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<&str> {
        tokenize(text)
            .into_iter()
            .map(|t| match t.kind {
                TokenKind::Word => &text[t.span.range()],
                TokenKind::Comma => ",",
                TokenKind::Newline => "\\n",
            })
            .collect()
    }

    #[test]
    fn comments_are_dropped() {
        assert_eq!(words("LD X0 // start\nOUT Y0; done"), ["LD", "X0", "\\n", "OUT", "Y0"]);
        assert_eq!(words("SET S1 K1//x"), ["SET", "S1", "K1"]);
    }

    #[test]
    fn commas_and_comparison_mnemonics() {
        assert_eq!(words("LD>= D0,K10"), ["LD>=", "D0", ",", "K10"]);
        assert_eq!(words("MOV K4M0[D2]  D10.F"), ["MOV", "K4M0[D2]", "D10.F"]);
    }

    #[test]
    fn spans_point_into_the_text() {
        let text = "  LD\tX000\r\n";
        let tokens = tokenize(text);
        assert_eq!(tokens[0].span, Span::new(2, 4));
        assert_eq!(&text[tokens[1].span.range()], "X000");
        assert_eq!(tokens[2].kind, TokenKind::Newline);
    }
}
