//! Operand syntax: one operand word (`X17`, `K4M0[D2]`, `D0.F`, `H1F`, `K-5`)
//! to its parts, with spans. Ranges and kinds are the checker's business.

use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use ladder_runtime::device::{buffer_word, BUFFER_UNITS, BUFFER_WORDS_PER_UNIT};

/// Device-name prefixes as written in source.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Prefix {
    X,
    Y,
    M,
    S,
    Sm,
    /// `T`: timer contact or current value, by position.
    T,
    /// `TS`: timer contact.
    Ts,
    /// `TN`: timer current value.
    Tn,
    C,
    Cs,
    Cn,
    D,
    Sd,
    R,
    /// `P`: jump label.
    P,
    /// `N`: master-control nesting level.
    N,
    /// `V`: index register V0-V7.
    V,
    /// `Z`: index register Z0-Z7.
    Z,
    /// `Un\Gm`: word m of the buffer memory of special-function unit n
    /// (the number is the word of the buffer area, `buffer_word(n, m)`).
    U,
}

impl Prefix {
    /// Longest spellings first so `SM0` is not read as `S` + `M0`.
    const SPELLINGS: [(&'static str, Prefix); 19] = [
        ("SM", Prefix::Sm),
        ("SD", Prefix::Sd),
        ("TS", Prefix::Ts),
        ("TN", Prefix::Tn),
        ("CS", Prefix::Cs),
        ("CN", Prefix::Cn),
        ("X", Prefix::X),
        ("Y", Prefix::Y),
        ("M", Prefix::M),
        ("S", Prefix::S),
        ("T", Prefix::T),
        ("C", Prefix::C),
        ("D", Prefix::D),
        ("R", Prefix::R),
        ("P", Prefix::P),
        ("N", Prefix::N),
        ("V", Prefix::V),
        ("Z", Prefix::Z),
        ("U", Prefix::U),
    ];

    pub fn as_str(self) -> &'static str {
        Prefix::SPELLINGS
            .iter()
            .find(|(_, p)| *p == self)
            .map_or("?", |(s, _)| s)
    }

    /// Device numbers of X and Y are octal.
    pub fn is_octal(self) -> bool {
        matches!(self, Prefix::X | Prefix::Y)
    }
}

/// A K or H constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Constant {
    /// K: the signed value; H: the unsigned bit pattern (0..=FFFFFFFF).
    pub value: i64,
    pub hex: bool,
}

/// The register that modifies a device number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OffsetKind {
    /// `DEV[Dk]`.
    D,
    /// `DEVZn` (FX index modification).
    Z,
    /// `DEVVn`.
    V,
}

/// `[Dk]`, `Zn` or `Vn` after a device: the device number is offset by the
/// register's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OffsetSyntax {
    pub kind: OffsetKind,
    pub register: u32,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceSyntax {
    pub prefix: Prefix,
    /// The device number, octal already converted for X/Y. Numbers too large
    /// to represent are `u32::MAX` (the checker reports them as out of range).
    pub number: u32,
    /// `Kn` in front: a group of n·4 bits.
    pub digits: Option<u8>,
    /// `.b` behind a data register: one bit of the word.
    pub bit: Option<u8>,
    pub offset: Option<OffsetSyntax>,
}

/// An E constant: a real number (IEEE-754 binary32), `E1.5`, `E-0.25`,
/// `E1.234+3` (mantissa and decimal exponent: 1234.0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealConstant {
    pub value: f32,
}

// The value is finite (the parser refuses others), so equality is total.
impl Eq for RealConstant {}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperandSyntax {
    Constant(Constant),
    Real(RealConstant),
    Device(DeviceSyntax),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Operand {
    pub syntax: OperandSyntax,
    pub span: Span,
}

/// Parses one operand word that starts at byte `base` of the source.
pub fn parse_operand(text: &str, base: usize) -> Result<Operand, Diagnostic> {
    let span = Span::new(base, base + text.len());
    let mut cursor = Cursor { text, pos: 0, base };
    let syntax = cursor.operand()?;
    if cursor.pos < text.len() {
        return Err(cursor.error_here(
            format!("unexpected `{}` in operand `{text}`", &text[cursor.pos..]),
            "not part of a device or constant",
        ));
    }
    Ok(Operand { syntax, span })
}

struct Cursor<'a> {
    text: &'a str,
    pos: usize,
    base: usize,
}

impl Cursor<'_> {
    fn rest(&self) -> &str {
        &self.text[self.pos..]
    }

    fn peek(&self) -> Option<char> {
        self.rest().chars().next()
    }

    fn eat(&mut self, c: char) -> bool {
        let matched = self.peek().is_some_and(|p| p.eq_ignore_ascii_case(&c));
        if matched {
            self.pos += c.len_utf8();
        }
        matched
    }

    fn span_from(&self, start: usize) -> Span {
        Span::new(
            self.base + start,
            self.base + self.pos.max(start + 1).min(self.text.len()),
        )
    }

    /// A malformed operand from `start` to the end of the operand word, so
    /// the underline covers what cannot be read (`Q110`, not only `Q`).
    fn error(&self, start: usize, message: String, label: &str) -> Diagnostic {
        let span = Span::new(self.base + start, self.base + self.text.len().max(start + 1));
        Diagnostic::new(Code::MalformedOperand, span, message).with_label(label)
    }

    fn error_here(&self, message: String, label: &str) -> Diagnostic {
        let span = Span::new(self.base + self.pos, self.base + self.text.len());
        Diagnostic::new(Code::MalformedOperand, span, message).with_label(label)
    }

    fn operand(&mut self) -> Result<OperandSyntax, Diagnostic> {
        let first = self.peek().map(|c| c.to_ascii_uppercase());
        match first {
            Some('K') => {
                self.pos += 1;
                let digits_start = self.pos;
                let negative = self.eat('-');
                if !negative {
                    self.eat('+');
                }
                let (magnitude, count) = self.decimal_digits();
                if count == 0 {
                    return Err(self.error(
                        0,
                        format!("`{}` is not a constant", self.text),
                        "expected K followed by a number",
                    ));
                }
                self.refuse_modified_constant()?;
                if self.peek().is_some_and(|c| c.is_ascii_alphabetic()) && !negative {
                    return self.digit_group(digits_start, magnitude);
                }
                let value = if negative {
                    -(magnitude as i64)
                } else {
                    magnitude as i64
                };
                if !(i64::from(i32::MIN)..=i64::from(i32::MAX)).contains(&value) {
                    return Err(Diagnostic::new(
                        Code::ConstantRange,
                        self.span_from(0),
                        format!("constant `{}` is out of range", self.text),
                    )
                    .with_label("K constants are K-2147483648..K2147483647"));
                }
                Ok(OperandSyntax::Constant(Constant { value, hex: false }))
            }
            Some('H') => {
                self.pos += 1;
                let start = self.pos;
                while self.peek().is_some_and(|c| c.is_ascii_hexdigit()) {
                    self.pos += 1;
                }
                let digits = &self.text[start..self.pos];
                self.refuse_modified_constant()?;
                if digits.is_empty() {
                    return Err(self.error(
                        0,
                        format!("`{}` is not a hex constant", self.text),
                        "expected H followed by hex digits",
                    ));
                }
                let trimmed = digits.trim_start_matches('0');
                if trimmed.len() > 8 {
                    return Err(Diagnostic::new(
                        Code::ConstantRange,
                        self.span_from(0),
                        format!("constant `{}` is out of range", self.text),
                    )
                    .with_label("H constants are H0..HFFFFFFFF"));
                }
                let value = i64::from_str_radix(if trimmed.is_empty() { "0" } else { trimmed }, 16).unwrap_or(0);
                Ok(OperandSyntax::Constant(Constant { value, hex: true }))
            }
            Some('E') => self.real().map(OperandSyntax::Real),
            _ => self.device(None).map(OperandSyntax::Device),
        }
    }

    /// `E` followed by a decimal number and an optional exponent, written
    /// as GX Developer does (`E1.234+3`) or as in C (`E1.234E+3`, `E1e-3`).
    fn real(&mut self) -> Result<RealConstant, Diagnostic> {
        self.pos += 1;
        let number_start = self.pos;
        if !self.eat('-') {
            self.eat('+');
        }
        let (_, whole) = self.decimal_digits();
        let fraction = if self.eat('.') { self.decimal_digits().1 } else { 0 };
        if whole + fraction == 0 {
            return Err(self.error(
                0,
                format!("`{}` is not a real constant", self.text),
                "expected E followed by a number, as in E1.5 or E1.234+3",
            ));
        }
        let mantissa = &self.text[number_start..self.pos];
        let exponent_start = self.pos;
        let written_e = self.eat('E');
        let exponent = match self.peek() {
            Some(sign @ ('+' | '-')) => {
                self.pos += 1;
                let (value, count) = self.decimal_digits();
                if count == 0 {
                    return Err(self.error(
                        exponent_start,
                        format!("`{}`: the exponent has no digits", self.text),
                        "expected digits",
                    ));
                }
                let value = i64::try_from(value).unwrap_or(i64::MAX);
                if sign == '-' {
                    -value
                } else {
                    value
                }
            }
            Some(c) if written_e && c.is_ascii_digit() => {
                let (value, _) = self.decimal_digits();
                i64::try_from(value).unwrap_or(i64::MAX)
            }
            _ if written_e => {
                return Err(self.error(
                    exponent_start,
                    format!("`{}`: the exponent has no digits", self.text),
                    "expected digits",
                ));
            }
            _ => 0,
        };
        self.refuse_modified_constant()?;
        if self.pos < self.text.len() {
            return Err(self.error_here(
                format!("unexpected `{}` in real constant `{}`", self.rest(), self.text),
                "not part of the number",
            ));
        }
        let out_of_range = || {
            Diagnostic::new(
                Code::ConstantRange,
                Span::new(self.base, self.base + self.text.len()),
                format!("real constant `{}` is out of range", self.text),
            )
            .with_label("real numbers are 0 or ±1.175494E-38 to ±3.402823E+38")
        };
        let text = format!("{mantissa}e{}", exponent.clamp(-1000, 1000));
        let value: f64 = text.parse().map_err(|_| out_of_range())?;
        let single = value as f32;
        if !single.is_finite() || (value != 0.0 && (single.abs() < f32::MIN_POSITIVE)) {
            return Err(out_of_range());
        }
        Ok(RealConstant { value: single })
    }

    /// `K5Z0`: FX programs may modify constants, ladderc does not.
    fn refuse_modified_constant(&self) -> Result<(), Diagnostic> {
        if self.index_register_ahead().is_some() {
            let span = Span::new(self.base + self.pos, self.base + self.text.len());
            return Err(Diagnostic::new(
                Code::OperandKind,
                span,
                format!("`{}`: a constant cannot be modified by an index register", self.text),
            )
            .with_label("index register on a constant")
            .with_note("compute the value into a register first, e.g. `ADD K5 Z0 D0`"));
        }
        Ok(())
    }

    /// `Zn`/`Vn` at the cursor (a letter and a digit).
    fn index_register_ahead(&self) -> Option<OffsetKind> {
        let mut chars = self.rest().chars();
        let kind = match chars.next()?.to_ascii_uppercase() {
            'Z' => OffsetKind::Z,
            'V' => OffsetKind::V,
            _ => return None,
        };
        chars.next().is_some_and(|c| c.is_ascii_digit()).then_some(kind)
    }

    /// `Kn` followed by a bit device: a digit group.
    fn digit_group(&mut self, start: usize, n: u64) -> Result<OperandSyntax, Diagnostic> {
        if !(1..=8).contains(&n) {
            return Err(self.error(start, format!("`K{n}` is not a digit count"), "digit groups are K1..K8"));
        }
        let device = self.device(Some(n as u8))?;
        if !matches!(device.prefix, Prefix::X | Prefix::Y | Prefix::M | Prefix::S) {
            return Err(self.error(
                0,
                format!("`{}`: digit groups are made of X, Y, M or S", self.text),
                "not a bit device",
            ));
        }
        Ok(OperandSyntax::Device(device))
    }

    fn device(&mut self, digits: Option<u8>) -> Result<DeviceSyntax, Diagnostic> {
        let start = self.pos;
        let prefix = Prefix::SPELLINGS
            .iter()
            .find(|(spelling, _)| {
                self.rest()
                    .get(..spelling.len())
                    .is_some_and(|head| head.eq_ignore_ascii_case(spelling))
                    && self.rest()[spelling.len()..].starts_with(|c: char| c.is_ascii_digit())
            })
            .map(|&(spelling, prefix)| (spelling.len(), prefix));
        let Some((prefix_len, prefix)) = prefix else {
            return Err(self.error(
                start,
                format!("`{}` is not a device or constant", self.text),
                "expected a device such as X0, M10, D100 or a constant such as K5",
            ));
        };
        self.pos += prefix_len;
        let number = if prefix == Prefix::U {
            self.buffer_number(start)?
        } else {
            self.device_number(prefix)?
        };
        let bit = if self.eat('.') {
            let bit_start = self.pos - 1;
            let digit = self.peek().and_then(|c| c.to_digit(16));
            match (digit, prefix) {
                (Some(b), Prefix::D) => {
                    self.pos += 1;
                    Some(b as u8)
                }
                (Some(_), _) => {
                    return Err(self.error(
                        bit_start,
                        format!("`{}`: bit numbers apply to data registers (D) only", self.text),
                        "bit of a non-D device",
                    ))
                }
                (None, _) => {
                    return Err(self.error(
                        bit_start,
                        format!("`{}`: a bit number is one hex digit 0-F", self.text),
                        "expected 0-F",
                    ))
                }
            }
        } else {
            None
        };
        let offset = if self.peek() == Some('[') {
            Some(self.offset()?)
        } else if let Some(kind) = self.index_register_ahead() {
            let start = self.pos;
            self.pos += 1;
            let (register, _) = self.decimal_digits();
            Some(OffsetSyntax {
                kind,
                register: u32::try_from(register).unwrap_or(u32::MAX),
                span: Span::new(self.base + start, self.base + self.pos),
            })
        } else {
            None
        };
        Ok(DeviceSyntax {
            prefix,
            number,
            digits,
            bit,
            offset,
        })
    }

    /// `n\Gm` after `U`: the word of the buffer area.
    fn buffer_number(&mut self, start: usize) -> Result<u32, Diagnostic> {
        let (unit, _) = self.decimal_digits();
        if !(self.eat('\\') && self.eat('G') && self.peek().is_some_and(|c| c.is_ascii_digit())) {
            return Err(self.error(
                start,
                format!("`{}` is not a buffer-memory device", self.text),
                "expected Un\\Gm, as in U0\\G10",
            ));
        }
        let word_start = self.pos;
        let (word, _) = self.decimal_digits();
        let range = |label: &str, from: usize, to: usize| {
            Diagnostic::new(
                Code::DeviceRange,
                Span::new(self.base + from, self.base + to),
                format!("`{}` is out of range", self.text),
            )
            .with_label(label.to_string())
        };
        if unit >= u64::from(BUFFER_UNITS) {
            return Err(range("units are U0..U7", start, word_start));
        }
        if word >= u64::from(BUFFER_WORDS_PER_UNIT) {
            return Err(range("buffer memory words are G0..G32766", word_start, self.pos));
        }
        Ok(buffer_word(unit as u32, word as u32))
    }

    fn device_number(&mut self, prefix: Prefix) -> Result<u32, Diagnostic> {
        let start = self.pos;
        let (value, count) = self.decimal_digits();
        debug_assert!(count > 0, "prefix match requires a digit");
        let digits = &self.text[start..self.pos];
        if prefix.is_octal() {
            let hex_letter = self
                .peek()
                .is_some_and(|c| c.is_ascii_hexdigit() && !c.is_ascii_digit());
            if digits.contains(['8', '9']) || hex_letter {
                return Err(self.error(
                    start,
                    format!("`{}`: {} numbers are octal (0-7)", self.text, prefix.as_str()),
                    "octal digits are 0-7 (X10 follows X7)",
                ));
            }
            return Ok(u32::from_str_radix(digits.trim_start_matches('0'), 8).unwrap_or(
                if digits.trim_start_matches('0').is_empty() {
                    0
                } else {
                    u32::MAX
                },
            ));
        }
        Ok(u32::try_from(value).unwrap_or(u32::MAX))
    }

    fn offset(&mut self) -> Result<OffsetSyntax, Diagnostic> {
        let open = self.pos;
        self.pos += 1; // '['
        let register_start = self.pos;
        let is_d = self.rest().get(..1).is_some_and(|p| p.eq_ignore_ascii_case("D"))
            && self.rest()[1..].starts_with(|c: char| c.is_ascii_digit());
        if !is_d {
            return Err(self.error(
                open,
                format!("`{}`: an offset is a data register, as in D10[D0]", self.text),
                "expected [Dk]",
            ));
        }
        self.pos += 1;
        let (register, _) = self.decimal_digits();
        let register_span = Span::new(self.base + register_start, self.base + self.pos);
        if !self.eat(']') {
            return Err(self.error(open, format!("`{}`: unclosed offset", self.text), "expected `]`"));
        }
        Ok(OffsetSyntax {
            kind: OffsetKind::D,
            register: u32::try_from(register).unwrap_or(u32::MAX),
            span: register_span,
        })
    }

    /// Decimal digits at the cursor: (value saturated at u64::MAX, digit count).
    fn decimal_digits(&mut self) -> (u64, usize) {
        let mut value: u64 = 0;
        let mut count = 0;
        while let Some(d) = self.peek().and_then(|c| c.to_digit(10)) {
            value = value.saturating_mul(10).saturating_add(u64::from(d));
            self.pos += 1;
            count += 1;
        }
        (value, count)
    }
}

#[cfg(test)]
mod tests {
    // The helpers below take the one variant they expect and panic on any other.
    #![allow(clippy::wildcard_enum_match_arm)]

    use super::*;

    fn device(text: &str) -> DeviceSyntax {
        match parse_operand(text, 0).unwrap().syntax {
            OperandSyntax::Device(d) => d,
            other => panic!("{text}: {other:?}"),
        }
    }

    fn constant(text: &str) -> Constant {
        match parse_operand(text, 0).unwrap().syntax {
            OperandSyntax::Constant(c) => c,
            other => panic!("{text}: {other:?}"),
        }
    }

    fn error_code(text: &str) -> Code {
        parse_operand(text, 0).unwrap_err().code
    }

    #[test]
    fn octal_io_numbers() {
        assert_eq!(device("X000").number, 0);
        assert_eq!(device("X17").number, 15);
        assert_eq!(device("y377").number, 255);
        assert_eq!(error_code("X8"), Code::MalformedOperand);
        assert_eq!(device("M19").number, 19, "M is decimal");
    }

    #[test]
    fn longest_prefix_wins() {
        assert_eq!(device("SM0").prefix, Prefix::Sm);
        assert_eq!(device("S10").prefix, Prefix::S);
        assert_eq!(device("SD5").prefix, Prefix::Sd);
        assert_eq!(device("TN3").prefix, Prefix::Tn);
        assert_eq!(device("cs4").prefix, Prefix::Cs);
    }

    #[test]
    fn constants() {
        assert_eq!(constant("K10"), Constant { value: 10, hex: false });
        assert_eq!(constant("k-5").value, -5);
        assert_eq!(
            constant("HFFFF"),
            Constant {
                value: 0xFFFF,
                hex: true
            }
        );
        assert_eq!(constant("H0000FFFFFFFF").value, 0xFFFF_FFFF);
        assert_eq!(error_code("K2147483648"), Code::ConstantRange);
        assert_eq!(constant("K-2147483648").value, i64::from(i32::MIN));
        assert_eq!(error_code("H100000000"), Code::ConstantRange);
        assert_eq!(error_code("H1G"), Code::MalformedOperand);
    }

    #[test]
    fn digit_groups_bits_and_offsets() {
        let group = device("K4M0");
        assert_eq!((group.prefix, group.digits, group.number), (Prefix::M, Some(4), 0));
        assert_eq!(device("K2X10").number, 8);
        assert_eq!(error_code("K9M0"), Code::MalformedOperand);
        assert_eq!(error_code("K4D0"), Code::MalformedOperand);
        assert_eq!(device("D0.F").bit, Some(15));
        assert_eq!(error_code("D0.G"), Code::MalformedOperand);
        assert_eq!(error_code("M0.1"), Code::MalformedOperand);
        assert_eq!(
            parse_operand("Q110", 7).unwrap_err().span,
            Span::new(7, 11),
            "the whole word is underlined"
        );
        let offset = device("D10[D2]").offset.unwrap();
        assert_eq!((offset.register, offset.span), (2, Span::new(4, 6)));
        assert_eq!(device("K4M0[D2]").offset.unwrap().register, 2);
        assert_eq!(error_code("D10[D2"), Code::MalformedOperand);
        assert_eq!(error_code("D10[M2]"), Code::MalformedOperand);
    }

    #[test]
    fn index_registers_and_modifiers() {
        assert_eq!((device("V3").prefix, device("z7").number), (Prefix::V, 7));
        let modified = device("D100Z2").offset.unwrap();
        assert_eq!(
            (modified.kind, modified.register, modified.span),
            (OffsetKind::Z, 2, Span::new(4, 6))
        );
        assert_eq!(device("X10v1").offset.unwrap().kind, OffsetKind::V);
        assert_eq!(
            device("X10v1").number,
            8,
            "the octal number is read before the modifier"
        );
        let group = device("K4M0Z2");
        assert_eq!((group.digits, group.offset.unwrap().register), (Some(4), 2));
        assert_eq!(error_code("K5Z0"), Code::OperandKind);
        assert_eq!(error_code("H1FV2"), Code::OperandKind);
        assert_eq!(error_code("D0Z1Z2"), Code::MalformedOperand);
        assert_eq!(error_code("D0Z"), Code::MalformedOperand);
    }

    fn real(text: &str) -> f32 {
        match parse_operand(text, 0).unwrap().syntax {
            OperandSyntax::Real(r) => r.value,
            other => panic!("{text}: {other:?}"),
        }
    }

    #[test]
    fn real_constants() {
        assert_eq!(real("E1.5"), 1.5);
        assert_eq!(real("e-0.25"), -0.25);
        assert_eq!(real("E1.234+3"), 1234.0);
        assert_eq!(real("E1.234E+3"), 1234.0);
        assert_eq!(real("E5e-1"), 0.5);
        assert_eq!(real("E3"), 3.0);
        assert_eq!(real("E0"), 0.0);
        assert_eq!(error_code("E1.2.3"), Code::MalformedOperand);
        assert_eq!(error_code("E"), Code::MalformedOperand);
        assert_eq!(error_code("E1.0+39"), Code::ConstantRange);
        assert_eq!(error_code("E1.0-40"), Code::ConstantRange);
        assert_eq!(error_code("E1.5Z0"), Code::OperandKind);
        assert_eq!(error_code("E1+"), Code::MalformedOperand);
    }

    #[test]
    fn buffer_memory_devices() {
        let d = device("U3\\G10");
        assert_eq!((d.prefix, d.number), (Prefix::U, buffer_word(3, 10)));
        let d = device("u0\\g32766Z1");
        assert_eq!(d.number, 32766);
        assert!(d.offset.is_some());
        assert_eq!(error_code("U8\\G0"), Code::DeviceRange);
        assert_eq!(error_code("U0\\G32767"), Code::DeviceRange);
        assert_eq!(error_code("U0G1"), Code::MalformedOperand);
        assert_eq!(error_code("U0\\"), Code::MalformedOperand);
    }

    #[test]
    fn octal_numbers_refuse_hex_letters() {
        let message = parse_operand("X5A", 0).unwrap_err().message;
        assert!(message.contains("octal"), "{message}");
        assert!(parse_operand("X59", 0).unwrap_err().message.contains("octal"));
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        for text in [
            "", "Q1", "X", "K", "H", "D0..1", "[", "M1x", "é", "K-4M0", "K4M", "D0[D1]x",
        ] {
            assert!(parse_operand(text, 0).is_err(), "{text:?}");
        }
        assert_eq!(device("M99999999999999999999").number, u32::MAX);
    }
}
