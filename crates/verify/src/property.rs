//! Property files (docs/verify.md): their directives, expressions and the
//! diagnostics of a file that cannot be read. One directive per line; `#`
//! to the end of the line is a comment outside the program block; names
//! are case-insensitive.

use crate::expr::{parse_expr, Expr, ExprContext};
use ladder_engine::scenario::ProgramSource;
use ladder_front::diagnostics::{Code, Diagnostic};
use ladder_front::host_device::{parse_device, parse_number, parse_value, HostDevice};
use ladder_front::source::{SourceFile, Span};
use ladder_runtime::{BitArea, Device};
use std::path::Path;

/// The elapsed time each scan reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScanTime {
    /// `scan-ms N`: every scan N ms (timers exact).
    Fixed(u32),
    /// `scan-ms A..B`: each scan any whole number of ms from A to B.
    Range(u32, u32),
}

impl ScanTime {
    /// The times a scan may report.
    pub fn choices(self) -> std::ops::RangeInclusive<u32> {
        match self {
            ScanTime::Fixed(ms) => ms..=ms,
            ScanTime::Range(low, high) => low..=high,
        }
    }
}

/// A free input: chosen before every scan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// A bit, ON or OFF.
    Bit(BitArea, u32),
    /// A word (or pair) written with any value from `low` to `high`.
    Word { device: HostDevice, low: i64, high: i64 },
}

/// What a property claims.
#[derive(Clone, Debug, PartialEq)]
pub enum Claim {
    Never(Expr),
    Always(Expr),
    Reach(Expr),
    /// Whenever `trigger` holds after a scan, `response` holds after that
    /// scan or one of the `within` scans after it.
    Respond {
        trigger: Expr,
        response: Expr,
        within: u32,
    },
}

impl Claim {
    /// The expressions the claim is made of.
    pub fn exprs(&self) -> Vec<&Expr> {
        match self {
            Claim::Never(e) | Claim::Always(e) | Claim::Reach(e) => vec![e],
            Claim::Respond { trigger, response, .. } => vec![trigger, response],
        }
    }
}

/// One property: its line in the file and its claim.
#[derive(Clone, Debug, PartialEq)]
pub struct Property {
    pub line: u32,
    pub claim: Claim,
}

/// A property file, read.
#[derive(Clone, Debug)]
pub struct PropertyFile {
    pub program: ProgramSource,
    pub scan_time: ScanTime,
    /// `None`: no `input` line (every X the program reads is free).
    pub inputs: Option<Vec<Input>>,
    pub inits: Vec<(HostDevice, i32)>,
    pub forces: Vec<(BitArea, u32, bool)>,
    pub assumes: Vec<Expr>,
    pub properties: Vec<Property>,
}

/// Reads a property file; `Err` holds one diagnostic per line that cannot
/// be read (with the file's text, for rendering).
pub fn parse_file(path: &Path, source: &SourceFile) -> Result<PropertyFile, Vec<Diagnostic>> {
    let text = source.text.as_str();
    let mut errors = Vec::new();
    let mut program = None;
    let mut scan_time = ScanTime::Fixed(10);
    let mut inputs: Option<Vec<Input>> = None;
    let mut inits = Vec::new();
    let mut forces = Vec::new();
    let mut assumes = Vec::new();
    let mut properties = Vec::new();
    let mut offset = 0usize;
    let mut lines = text.split_inclusive('\n').enumerate();
    while let Some((index, raw)) = lines.next() {
        let line_start = offset;
        offset += raw.len();
        let line_number = index as u32 + 1;
        let content_end = raw.find('#').unwrap_or(raw.len());
        let content = raw[..content_end].trim_end();
        let leading = content.len() - content.trim_start().len();
        let content = content.trim_start();
        if content.is_empty() {
            continue;
        }
        let start = line_start + leading;
        let keyword_len = content.find(char::is_whitespace).unwrap_or(content.len());
        let keyword = content[..keyword_len].to_ascii_lowercase();
        let rest_offset = keyword_len + (content.len() - keyword_len - content[keyword_len..].trim_start().len());
        let rest = content[keyword_len..].trim();
        let rest_start = start + rest_offset;
        let whole = Span::new(start, start + content.len());
        let at_rest = Span::new(rest_start, rest_start + rest.len());
        let fail = |code: Code, span: Span, message: String| Diagnostic::new(code, span, message);
        let result: Result<(), Diagnostic> = (|| {
            match keyword.as_str() {
                "program" if program.is_some() => Err(fail(
                    Code::PropertySyntax,
                    whole,
                    "a property file has one program".into(),
                )),
                "program" if rest == "<<" => {
                    let first_line = line_number + 1;
                    let mut body = String::new();
                    loop {
                        let Some((_, program_line)) = lines.next() else {
                            return Err(fail(
                                Code::PropertySyntax,
                                whole,
                                "`program <<` without a closing `>>` line".into(),
                            ));
                        };
                        offset += program_line.len();
                        if program_line.trim() == ">>" {
                            break;
                        }
                        body.push_str(program_line.trim_end_matches(['\n', '\r']));
                        body.push('\n');
                    }
                    program = Some(ProgramSource::Inline { text: body, first_line });
                    Ok(())
                }
                "program" if !rest.is_empty() => {
                    let base = path.parent().unwrap_or(Path::new("."));
                    program = Some(ProgramSource::File(base.join(rest)));
                    Ok(())
                }
                "scan-ms" => {
                    scan_time = scan_ms(rest).map_err(|m| fail(Code::PropertySyntax, at_rest, m))?;
                    Ok(())
                }
                "input" => {
                    let list = inputs.get_or_insert_with(Vec::new);
                    list.extend(input(rest).map_err(|(code, m)| fail(code, at_rest, m))?);
                    Ok(())
                }
                "init" => {
                    let (device, value) = device_value(rest).map_err(|(code, m)| fail(code, at_rest, m))?;
                    inits.push((device, value));
                    Ok(())
                }
                "force" => {
                    forces.push(force(rest).map_err(|(code, m)| fail(code, at_rest, m))?);
                    Ok(())
                }
                "assume" => {
                    assumes.push(parse_expr(rest, rest_start, ExprContext::Assume)?);
                    Ok(())
                }
                "never" | "always" | "reach" => {
                    let expr = parse_expr(rest, rest_start, ExprContext::Property)?;
                    let claim = match keyword.as_str() {
                        "never" => Claim::Never(expr),
                        "always" => Claim::Always(expr),
                        _ => Claim::Reach(expr),
                    };
                    properties.push(Property {
                        line: line_number,
                        claim,
                    });
                    Ok(())
                }
                "respond" => {
                    let claim = respond(rest, rest_start)?;
                    properties.push(Property {
                        line: line_number,
                        claim,
                    });
                    Ok(())
                }
                "program" => Err(fail(
                    Code::PropertySyntax,
                    whole,
                    "`program` takes a file name or `<<` (then the program, then `>>`)".into(),
                )),
                _ => Err(fail(
                    Code::PropertySyntax,
                    Span::new(start, start + keyword_len),
                    format!(
                        "unknown directive `{}` (program, scan-ms, input, init, force, assume, never, always, reach, respond)",
                        &content[..keyword_len]
                    ),
                )),
            }
        })();
        if let Err(diagnostic) = result {
            errors.push(diagnostic);
        }
    }
    if program.is_none() && errors.is_empty() {
        errors.push(Diagnostic::new(
            Code::PropertySyntax,
            Span::new(0, text.find('\n').unwrap_or(text.len())),
            "no `program` directive".to_string(),
        ));
    }
    match (program, errors.is_empty()) {
        (Some(program), true) => Ok(PropertyFile {
            program,
            scan_time,
            inputs,
            inits,
            forces,
            assumes,
            properties,
        }),
        (Some(_) | None, _) => Err(errors),
    }
}

fn whole_number(text: &str, what: &str) -> Result<u32, String> {
    match parse_number(text) {
        Ok(n) if (0..=i64::from(u32::MAX)).contains(&n) => Ok(n as u32),
        Ok(_) | Err(_) => Err(format!("`{text}` is not a {what}")),
    }
}

fn scan_ms(text: &str) -> Result<ScanTime, String> {
    match text.split_once("..") {
        Some((low, high)) => {
            let low = whole_number(low.trim(), "number of milliseconds")?;
            let high = whole_number(high.trim(), "number of milliseconds")?;
            if low > high {
                return Err(format!("`{text}`: the range is empty"));
            }
            Ok(ScanTime::Range(low, high))
        }
        None if text.is_empty() => Err("`scan-ms` takes a number of milliseconds or a range A..B".into()),
        None => Ok(ScanTime::Fixed(whole_number(text, "number of milliseconds")?)),
    }
}

/// A device name, `:32` asking for the pair.
pub(crate) fn device(text: &str) -> Result<HostDevice, (Code, String)> {
    let (bare, double) = match text.strip_suffix(":32") {
        Some(bare) => (bare, true),
        None => (text, false),
    };
    parse_device(bare, double).map_err(|m| (Code::PropertyDevice, m))
}

fn input(text: &str) -> Result<Vec<Input>, (Code, String)> {
    let words: Vec<&str> = text.split_whitespace().collect();
    match words.as_slice() {
        [word, "in" | "IN", range] => {
            let device = device(word)?;
            if device.is_bit() {
                return Err((
                    Code::PropertyType,
                    format!("`{word}` is a bit: name it without a range (`input {word}`)"),
                ));
            }
            let (low, high) = range
                .split_once("..")
                .ok_or((Code::PropertySyntax, format!("`{range}` is not a range LO..HI")))?;
            let low = parse_value(low, device).map_err(|m| (Code::PropertySyntax, m))?;
            let high = parse_value(high, device).map_err(|m| (Code::PropertySyntax, m))?;
            if low > high {
                return Err((Code::PropertySyntax, format!("`{range}`: the range is empty")));
            }
            Ok(vec![Input::Word {
                device,
                low: i64::from(low),
                high: i64::from(high),
            }])
        }
        [single] => {
            let (first, last) = match single.split_once("..") {
                Some((first, last)) => (device(first)?, device(last)?),
                None => {
                    let d = device(single)?;
                    (d, d)
                }
            };
            match (first.device, last.device) {
                (Device::Bit(area, a), Device::Bit(other, b)) if area == other && a <= b => {
                    Ok((a..=b).map(|n| Input::Bit(area, n)).collect())
                }
                (Device::Bit(..), Device::Bit(..)) => {
                    Err((Code::PropertySyntax, format!("`{single}` is not a range of one area")))
                }
                (Device::Word(..) | Device::WordBit(..) | Device::Digits(..) | Device::WideCounter(_), _)
                | (
                    Device::Bit(..),
                    Device::Word(..) | Device::WordBit(..) | Device::Digits(..) | Device::WideCounter(_),
                ) => Err((
                    Code::PropertyType,
                    format!("`{single}` is not a bit: a word input takes a range (`input D0 in 0..100`)"),
                )),
            }
        }
        _ => Err((
            Code::PropertySyntax,
            "`input` takes a bit (X0), a range of bits (X0..X7) or a word with its values (D0 in 0..100)".into(),
        )),
    }
}

fn device_value(text: &str) -> Result<(HostDevice, i32), (Code, String)> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let [name, value] = words.as_slice() else {
        return Err((Code::PropertySyntax, "`init` takes a device and its value".into()));
    };
    let device = device(name)?;
    let value = parse_value(value, device).map_err(|m| (Code::PropertySyntax, m))?;
    Ok((device, value))
}

fn force(text: &str) -> Result<(BitArea, u32, bool), (Code, String)> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let [name, value] = words.as_slice() else {
        return Err((Code::PropertySyntax, "`force` takes a device and 0 or 1".into()));
    };
    let (area, index) = match device(name)?.device {
        Device::Bit(
            area @ (BitArea::X | BitArea::Y | BitArea::M | BitArea::TimerContact | BitArea::CounterContact),
            index,
        ) => (area, index),
        Device::Bit(BitArea::S | BitArea::Sm, _)
        | Device::Word(..)
        | Device::WordBit(..)
        | Device::Digits(..)
        | Device::WideCounter(_) => {
            return Err((
                Code::PropertyType,
                format!("`{name}` cannot be forced: X, Y, M and timer and counter contacts can"),
            ))
        }
    };
    let on = match value.to_ascii_lowercase().as_str() {
        "1" | "on" => true,
        "0" | "off" => false,
        _ => {
            return Err((
                Code::PropertySyntax,
                format!("`{value}` is not a bit value (0, 1, on, off)"),
            ))
        }
    };
    Ok((area, index, on))
}

/// `EXPR1 -> EXPR2 within N`: the first `->` outside parentheses
/// separates the two.
fn respond(text: &str, start: usize) -> Result<Claim, Diagnostic> {
    let whole = Span::new(start, start + text.len());
    let lower = text.to_ascii_lowercase();
    let Some(within_at) = lower.rfind("within") else {
        return Err(Diagnostic::new(
            Code::PropertySyntax,
            whole,
            "`respond` needs `within N` at its end".to_string(),
        ));
    };
    let count_text = text[within_at + "within".len()..].trim();
    let count_span = Span::new(start + within_at, start + text.len());
    let within = if count_text.is_empty() {
        return Err(Diagnostic::new(
            Code::PropertySyntax,
            count_span,
            "`within` without a number of scans".to_string(),
        ));
    } else {
        whole_number(count_text, "number of scans").map_err(|m| Diagnostic::new(Code::PropertySyntax, count_span, m))?
    };
    let body = &text[..within_at];
    let mut depth = 0i32;
    let mut arrow = None;
    let bytes = body.as_bytes();
    for (i, &c) in bytes.iter().enumerate() {
        match c {
            b'(' => depth += 1,
            b')' => depth -= 1,
            b'-' if depth == 0 && bytes.get(i + 1) == Some(&b'>') && (i == 0 || bytes[i - 1] != b'<') => {
                arrow = Some(i);
                break;
            }
            _ => {}
        }
    }
    let Some(arrow) = arrow else {
        return Err(Diagnostic::new(
            Code::PropertySyntax,
            whole,
            "`respond` needs `EXPR1 -> EXPR2` before `within`".to_string(),
        ));
    };
    let trigger = parse_expr(&body[..arrow], start, ExprContext::Property)?;
    let response = parse_expr(&body[arrow + 2..], start + arrow + 2, ExprContext::Property)?;
    Ok(Claim::Respond {
        trigger,
        response,
        within,
    })
}
