//! Expressions of property files: bits, comparisons of words, `prev`,
//! `rose`, `fell`, and the logic between them; parsed with the place of
//! every part (for diagnostics) and evaluated on two device images (the one
//! after the previous scan and the one after this scan).

use crate::property::device;
use ladder_front::diagnostics::{Code, Diagnostic};
use ladder_front::host_device::{parse_number, HostDevice};
use ladder_front::source::Span;
use ladder_runtime::device::FIRST_WIDE_COUNTER;
use ladder_runtime::{BitArea, Device, Memory, Width, WordArea};

/// A comparison operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Compare {
    fn holds(self, a: i64, b: i64) -> bool {
        match self {
            Compare::Eq => a == b,
            Compare::Ne => a != b,
            Compare::Lt => a < b,
            Compare::Le => a <= b,
            Compare::Gt => a > b,
            Compare::Ge => a >= b,
        }
    }
}

/// A word's value in a comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Term {
    /// A device after this scan, or after the previous one (`prev`).
    Device {
        device: HostDevice,
        prev: bool,
    },
    Number(i64),
}

#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Bool(bool),
    /// A bit after this scan, or after the previous one (`prev`).
    Bit {
        device: HostDevice,
        prev: bool,
    },
    Compare {
        left: Term,
        op: Compare,
        right: Term,
    },
    Not(Box<Expr>),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
    Implies(Box<Expr>, Box<Expr>),
    Iff(Box<Expr>, Box<Expr>),
}

impl Expr {
    /// Its value with `now` the image after this scan and `before` the one
    /// after the previous scan (power-up, or `init`, before scan 1).
    pub fn holds(&self, before: &Memory, now: &Memory) -> bool {
        match self {
            Expr::Bool(b) => *b,
            Expr::Bit { device, prev } => read(if *prev { before } else { now }, *device) != 0,
            Expr::Compare { left, op, right } => op.holds(term(left, before, now), term(right, before, now)),
            Expr::Not(e) => !e.holds(before, now),
            Expr::And(a, b) => a.holds(before, now) && b.holds(before, now),
            Expr::Or(a, b) => a.holds(before, now) || b.holds(before, now),
            Expr::Implies(a, b) => !a.holds(before, now) || b.holds(before, now),
            Expr::Iff(a, b) => a.holds(before, now) == b.holds(before, now),
        }
    }

    /// The devices it names, and whether it reads any of them after the
    /// previous scan.
    pub fn devices(&self, out: &mut Vec<(HostDevice, bool)>) {
        match self {
            Expr::Bool(_) => {}
            Expr::Bit { device, prev } => out.push((*device, *prev)),
            Expr::Compare { left, right, .. } => {
                for t in [left, right] {
                    if let Term::Device { device, prev } = t {
                        out.push((*device, *prev));
                    }
                }
            }
            Expr::Not(e) => e.devices(out),
            Expr::And(a, b) | Expr::Or(a, b) | Expr::Implies(a, b) | Expr::Iff(a, b) => {
                a.devices(out);
                b.devices(out);
            }
        }
    }
}

/// A device's value as a signed number of its width, as a word holds it:
/// K4 and K8 digit groups are a signed word and pair, K1-K3 and K5-K7 the
/// non-negative numbers their bits make. 0 where the image cannot show it.
pub fn read(mem: &Memory, device: HostDevice) -> i64 {
    let value = mem.read_device(device.device, device.width).unwrap_or(0);
    match (device.device, device.bits()) {
        (Device::Digits(_, _, digits), _) if !signed_digits(digits) => {
            i64::from(value as u32 & ((1u32 << (4 * u32::from(digits))) - 1))
        }
        (_, 16) | (Device::Digits(_, _, 4), _) => i64::from(value as i16),
        (_, 1) => i64::from(value != 0),
        (_, _) => i64::from(value),
    }
}

/// K4 and K8 groups fill a word or a pair, whose top bit is the sign.
fn signed_digits(digits: u8) -> bool {
    digits == 4 || digits == 8
}

fn term(t: &Term, before: &Memory, now: &Memory) -> i64 {
    match t {
        Term::Number(n) => *n,
        Term::Device { device, prev } => read(if *prev { before } else { now }, *device),
    }
}

/// Where an expression stands: `assume` may not look at the previous scan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExprContext {
    Assume,
    Property,
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Word(String),
    Op(&'static str),
    LParen,
    RParen,
}

fn tokens(text: &str, start: usize) -> Result<Vec<(Token, Span)>, Diagnostic> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let span = |len: usize| Span::new(start + i, start + i + len);
        let op = ["<->", "->", "==", "!=", "<=", ">=", "<", ">", "!", "&", "|"]
            .into_iter()
            .find(|op| text[i..].starts_with(op));
        if let Some(op) = op {
            out.push((Token::Op(op), span(op.len())));
            i += op.len();
        } else if c == b'(' {
            out.push((Token::LParen, span(1)));
            i += 1;
        } else if c == b')' {
            out.push((Token::RParen, span(1)));
            i += 1;
        } else if c.is_ascii_alphanumeric() || c == b'-' || c == b'_' {
            let len = text[i..]
                .find(|ch: char| !(ch.is_ascii_alphanumeric() || "-_.:\\[]".contains(ch)))
                .unwrap_or(text.len() - i);
            // A `-` ends a word unless it starts a number (`-5`); `D0->Y0`
            // has no blanks around its arrow.
            let word_len = text[i..i + len]
                .char_indices()
                .skip(1)
                .find(|&(_, ch)| ch == '-')
                .map_or(len, |(at, _)| at);
            out.push((Token::Word(text[i..i + word_len].to_string()), span(word_len)));
            i += word_len;
        } else {
            let ch = text[i..].chars().next().unwrap_or('?');
            return Err(Diagnostic::new(
                Code::PropertySyntax,
                Span::new(start + i, start + i + ch.len_utf8()),
                format!("`{ch}` has no meaning in an expression"),
            ));
        }
    }
    Ok(out)
}

/// Parses an expression; `start` is its byte offset in the file.
pub fn parse_expr(text: &str, start: usize, context: ExprContext) -> Result<Expr, Diagnostic> {
    let tokens = tokens(text, start)?;
    let end = Span::new(start + text.len(), start + text.len());
    let whole = Span::new(start, start + text.len());
    if tokens.is_empty() {
        return Err(Diagnostic::new(
            Code::PropertySyntax,
            whole,
            "an expression is missing".to_string(),
        ));
    }
    let mut parser = Parser {
        tokens,
        at: 0,
        end,
        context,
    };
    let expr = parser.implication()?;
    match parser.tokens.get(parser.at) {
        None => Ok(expr),
        Some((token, span)) => Err(Diagnostic::new(
            Code::PropertySyntax,
            *span,
            format!("unexpected {} after a whole expression", describe(token)),
        )),
    }
}

fn describe(token: &Token) -> String {
    match token {
        Token::Word(w) => format!("`{w}`"),
        Token::Op(op) => format!("`{op}`"),
        Token::LParen => "`(`".to_string(),
        Token::RParen => "`)`".to_string(),
    }
}

struct Parser {
    tokens: Vec<(Token, Span)>,
    at: usize,
    end: Span,
    context: ExprContext,
}

/// A value in a comparison as parsed: a device (a bit when alone), or a
/// number with how it was written.
enum Operand {
    Device { device: HostDevice, prev: bool, span: Span },
    Number { value: i64, hex: bool, span: Span },
}

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.at).map(|(t, _)| t)
    }

    fn span(&self) -> Span {
        self.tokens.get(self.at).map_or(self.end, |(_, s)| *s)
    }

    fn error(&self, message: String) -> Diagnostic {
        Diagnostic::new(Code::PropertySyntax, self.span(), message)
    }

    fn implication(&mut self) -> Result<Expr, Diagnostic> {
        let left = self.disjunction()?;
        match self.peek() {
            Some(Token::Op("->")) => {
                self.at += 1;
                let right = self.implication()?;
                Ok(Expr::Implies(Box::new(left), Box::new(right)))
            }
            Some(Token::Op("<->")) => {
                self.at += 1;
                let right = self.implication()?;
                Ok(Expr::Iff(Box::new(left), Box::new(right)))
            }
            Some(_) | None => Ok(left),
        }
    }

    fn disjunction(&mut self) -> Result<Expr, Diagnostic> {
        let mut left = self.conjunction()?;
        while self.peek() == Some(&Token::Op("|")) {
            self.at += 1;
            left = Expr::Or(Box::new(left), Box::new(self.conjunction()?));
        }
        Ok(left)
    }

    fn conjunction(&mut self) -> Result<Expr, Diagnostic> {
        let mut left = self.unary()?;
        while self.peek() == Some(&Token::Op("&")) {
            self.at += 1;
            left = Expr::And(Box::new(left), Box::new(self.unary()?));
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Expr, Diagnostic> {
        if self.peek() == Some(&Token::Op("!")) {
            self.at += 1;
            return Ok(Expr::Not(Box::new(self.unary()?)));
        }
        self.atom()
    }

    fn atom(&mut self) -> Result<Expr, Diagnostic> {
        match self.peek() {
            Some(Token::LParen) => {
                self.at += 1;
                let inner = self.implication()?;
                if self.peek() != Some(&Token::RParen) {
                    return Err(self.error("`)` expected".to_string()));
                }
                self.at += 1;
                Ok(inner)
            }
            Some(Token::Word(w)) if w.eq_ignore_ascii_case("true") => {
                self.at += 1;
                Ok(Expr::Bool(true))
            }
            Some(Token::Word(w)) if w.eq_ignore_ascii_case("false") => {
                self.at += 1;
                Ok(Expr::Bool(false))
            }
            Some(Token::Word(w))
                if ["rose", "fell"].iter().any(|f| w.eq_ignore_ascii_case(f))
                    && self.tokens.get(self.at + 1).map(|(t, _)| t) == Some(&Token::LParen) =>
            {
                let rising = w.eq_ignore_ascii_case("rose");
                let span = self.span();
                self.no_previous_scan_here(span, w)?;
                self.at += 2;
                let device = self.device_inside()?;
                if !device.is_bit() {
                    return Err(Diagnostic::new(
                        Code::PropertyType,
                        span,
                        "`rose` and `fell` take a bit".to_string(),
                    ));
                }
                let now = Expr::Bit { device, prev: false };
                let before = Expr::Bit { device, prev: true };
                let (on, off) = if rising { (now, before) } else { (before, now) };
                Ok(Expr::And(Box::new(on), Box::new(Expr::Not(Box::new(off)))))
            }
            Some(_) => {
                let left = self.operand()?;
                let op = match self.peek() {
                    Some(Token::Op("==")) => Some(Compare::Eq),
                    Some(Token::Op("!=")) => Some(Compare::Ne),
                    Some(Token::Op("<")) => Some(Compare::Lt),
                    Some(Token::Op("<=")) => Some(Compare::Le),
                    Some(Token::Op(">")) => Some(Compare::Gt),
                    Some(Token::Op(">=")) => Some(Compare::Ge),
                    Some(_) | None => None,
                };
                match op {
                    None => match left {
                        Operand::Device { device, prev, span } => {
                            if !device.is_bit() {
                                return Err(Diagnostic::new(
                                    Code::PropertyType,
                                    span,
                                    "a word where a bit is needed: compare it (`D0 > 0`)".to_string(),
                                ));
                            }
                            Ok(Expr::Bit { device, prev })
                        }
                        Operand::Number { span, .. } => Err(Diagnostic::new(
                            Code::PropertyType,
                            span,
                            "a number where a bit is needed (true and false are the constant bits)".to_string(),
                        )),
                    },
                    Some(op) => {
                        self.at += 1;
                        let right = self.operand()?;
                        let (left, right) = comparison(left, right)?;
                        Ok(Expr::Compare { left, op, right })
                    }
                }
            }
            None => Err(self.error("an expression ends too early".to_string())),
        }
    }

    fn no_previous_scan_here(&self, span: Span, what: &str) -> Result<(), Diagnostic> {
        match self.context {
            ExprContext::Assume => Err(Diagnostic::new(
                Code::PropertyPrevInAssume,
                span,
                format!("`{what}` looks at the previous scan, which `assume` may not"),
            )),
            ExprContext::Property => Ok(()),
        }
    }

    /// `DEV)` after `prev(`, `rose(` or `fell(`.
    fn device_inside(&mut self) -> Result<HostDevice, Diagnostic> {
        let span = self.span();
        let Some(Token::Word(name)) = self.peek().cloned() else {
            return Err(self.error("a device expected".to_string()));
        };
        self.at += 1;
        let device = named_device(&name, span)?;
        if self.peek() != Some(&Token::RParen) {
            return Err(self.error("`)` expected".to_string()));
        }
        self.at += 1;
        Ok(device)
    }

    fn operand(&mut self) -> Result<Operand, Diagnostic> {
        let span = self.span();
        let Some(token) = self.peek().cloned() else {
            return Err(self.error("an expression ends too early".to_string()));
        };
        let Token::Word(word) = token else {
            return Err(self.error(format!("a device or a number expected, not {}", describe(&token))));
        };
        if word.eq_ignore_ascii_case("prev") && self.tokens.get(self.at + 1).map(|(t, _)| t) == Some(&Token::LParen) {
            self.no_previous_scan_here(span, "prev")?;
            self.at += 2;
            let device = self.device_inside()?;
            return Ok(Operand::Device {
                device,
                prev: true,
                span,
            });
        }
        self.at += 1;
        let first = word.as_bytes()[0];
        let numeric = first.is_ascii_digit()
            || first == b'-'
            || (matches!(first, b'K' | b'k') && word[1..].chars().all(|c| c.is_ascii_digit() || c == '-'))
            || (matches!(first, b'H' | b'h') && word.len() > 1 && word[1..].chars().all(|c| c.is_ascii_hexdigit()));
        if numeric {
            let value = parse_number(&word).map_err(|m| Diagnostic::new(Code::PropertySyntax, span, m))?;
            return Ok(Operand::Number {
                value,
                hex: matches!(first, b'H' | b'h') || word.ends_with(['H', 'h']),
                span,
            });
        }
        Ok(Operand::Device {
            device: named_device(&word, span)?,
            prev: false,
            span,
        })
    }
}

fn named_device(name: &str, span: Span) -> Result<HostDevice, Diagnostic> {
    device(name).map_err(|(code, message)| Diagnostic::new(code, span, message))
}

/// The value a device stands for in a comparison: `T0` and `C0` are the
/// current values there, as `TN0` and `CN0` are.
fn as_word(device: HostDevice, span: Span) -> Result<HostDevice, Diagnostic> {
    match device.device {
        Device::Bit(BitArea::TimerContact, n) => Ok(HostDevice {
            device: Device::Word(WordArea::TimerValue, n),
            width: Width::Single,
        }),
        Device::Bit(BitArea::CounterContact, n) if n >= FIRST_WIDE_COUNTER => Ok(HostDevice {
            device: Device::WideCounter(n),
            width: Width::Double,
        }),
        Device::Bit(BitArea::CounterContact, n) => Ok(HostDevice {
            device: Device::Word(WordArea::CounterValue, n),
            width: Width::Single,
        }),
        Device::Bit(..) | Device::WordBit(..) => Err(Diagnostic::new(
            Code::PropertyType,
            span,
            "a bit compared as a word: use the bit itself (`X0`, `!X0`)".to_string(),
        )),
        Device::Word(..) | Device::Digits(..) | Device::WideCounter(_) => Ok(device),
    }
}

/// A number as a word of `bits` compares it: decimal within the signed
/// range; `H` gives the bits.
fn number_for(value: i64, hex: bool, bits: u32, span: Span, digits: bool) -> Result<i64, Diagnostic> {
    let (low, high) = if digits {
        (0, (1i64 << bits) - 1)
    } else {
        (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
    };
    if hex && !digits {
        if !(0..(1i64 << bits)).contains(&value) {
            return Err(Diagnostic::new(
                Code::PropertyType,
                span,
                format!("a number of more than {bits} bits"),
            ));
        }
        // The bits of a signed word.
        return Ok(if value > high { value - (1i64 << bits) } else { value });
    }
    if !(low..=high).contains(&value) {
        return Err(Diagnostic::new(
            Code::PropertyType,
            span,
            format!("{value} is outside the word's range {low}..{high}"),
        ));
    }
    Ok(value)
}

fn comparison(left: Operand, right: Operand) -> Result<(Term, Term), Diagnostic> {
    let resolve = |operand: Operand, other_bits: Option<(u32, bool)>| -> Result<Term, Diagnostic> {
        match operand {
            Operand::Device { device, prev, span } => Ok(Term::Device {
                device: as_word(device, span)?,
                prev,
            }),
            Operand::Number { value, hex, span } => {
                let (bits, digits) = other_bits.unwrap_or((32, false));
                Ok(Term::Number(number_for(value, hex, bits, span, digits)?))
            }
        }
    };
    let width_of = |operand: &Operand| -> Result<Option<(u32, bool)>, Diagnostic> {
        match operand {
            Operand::Device { device, span, .. } => {
                let word = as_word(*device, *span)?;
                let unsigned = match word.device {
                    Device::Digits(_, _, digits) => !signed_digits(digits),
                    Device::Bit(..) | Device::Word(..) | Device::WordBit(..) | Device::WideCounter(_) => false,
                };
                let bits = match word.device {
                    Device::Digits(_, _, digits) => 4 * u32::from(digits),
                    Device::Bit(..) | Device::Word(..) | Device::WordBit(..) | Device::WideCounter(_) => word.bits(),
                };
                Ok(Some((bits, unsigned)))
            }
            Operand::Number { .. } => Ok(None),
        }
    };
    let left_bits = width_of(&left)?;
    let right_bits = width_of(&right)?;
    Ok((resolve(left, right_bits)?, resolve(right, left_bits)?))
}
