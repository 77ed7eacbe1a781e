//! A GX Developer project as IL text (the listing the front end reads, and
//! what `ladderc import` writes), and the `//@` lines of IL that carry what
//! is not instructions: the CPU, the program memory, the latched ranges,
//! the code page and the device comments.
//!
//! ```text
//! //@ cpu FX2N
//! //@ memory 2000
//! //@ latch M500-M1023,D200-D511
//! //@ encoding Big5
//! //@ comment X000 start button
//! 0 LD X000
//! ```
//!
//! To the IL parser they are comments; any IL file may carry them.

use super::text::Encoding;
use super::wpg::{Line, LineKind};

/// What the `//@` lines of an IL text say.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Directives {
    /// `//@ cpu FX2N`: the CPU model.
    pub cpu: Option<String>,
    /// `//@ memory 8000`: steps of program memory.
    pub memory: Option<u32>,
    /// `//@ latch M500-M1023,...`: latched ranges (as `serve --latch`).
    pub latch: Option<String>,
    /// `//@ encoding Shift_JIS`: the code page of the project's texts.
    pub encoding: Option<Encoding>,
    /// `//@ comment DEV text`: device comments, devices as written.
    pub comments: Vec<(String, String)>,
    /// `//@ comments FILE`: a GX Works2 device-comment CSV export to read
    /// the comments from (beside the program).
    pub comment_file: Option<String>,
}

const MARK: &str = "//@";

/// Is this line a `//@` line?
pub fn is_directive(line: &str) -> bool {
    line.trim_start().starts_with(MARK)
}

/// The `//@` lines of `text` (others, and unknown words, are left alone).
pub fn directives(text: &str) -> Directives {
    let mut found = Directives::default();
    for line in text.lines() {
        let Some(rest) = line.trim_start().strip_prefix(MARK) else {
            continue;
        };
        let rest = rest.trim();
        let (word, value) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
        let value = value.trim();
        match word {
            "cpu" => found.cpu = Some(value.to_string()),
            "memory" => found.memory = value.parse().ok(),
            "latch" => found.latch = Some(value.to_string()),
            "encoding" => found.encoding = Encoding::from_name(value),
            "comments" if !value.is_empty() => found.comment_file = Some(value.to_string()),
            "comment" => {
                let (device, comment) = value.split_once(char::is_whitespace).unwrap_or((value, ""));
                if !device.is_empty() {
                    found
                        .comments
                        .push((device.to_ascii_uppercase(), comment.trim().to_string()));
                }
            }
            _ => {}
        }
    }
    found
}

/// The `//@ comment` lines of a GX Works2 device-comment CSV export (the
/// device in the first field, its comment in the second; fields separated
/// by commas or tabs, quoted or not; rows whose first field is not a device,
/// such as the column titles, are skipped).
pub fn comments_from_csv(text: &str) -> String {
    let mut lines = String::new();
    for row in text.lines() {
        let row = row.trim_start_matches('\u{feff}');
        let separator = if row.contains('\t') { '\t' } else { ',' };
        let mut fields = row.split(separator).map(|f| f.trim().trim_matches('"').trim());
        let (Some(device), Some(comment)) = (fields.next(), fields.next()) else {
            continue;
        };
        let Some(device) = canonical_device(device) else {
            continue;
        };
        if !comment.is_empty() {
            lines.push_str(&format!("{MARK} comment {device} {comment}\n"));
        }
    }
    lines
}

/// The device comments of an IL text (`//@ comment` lines), keyed by the
/// device's name as the vendor editors show it (`X000`, `M100`, `D10`), so
/// that `X0` and `X000` find the same comment.
pub fn device_comments(text: &str) -> std::collections::BTreeMap<String, String> {
    directives(text)
        .comments
        .into_iter()
        .filter(|(_, comment)| !comment.is_empty())
        .map(|(device, comment)| (canonical_device(&device).unwrap_or(device), comment))
        .collect()
}

/// A device's name as the vendor editors show it: X and Y in three octal
/// digits, the others in decimal.
pub fn canonical_device(name: &str) -> Option<String> {
    use crate::syntax::{OperandSyntax, Prefix};
    let operand = crate::syntax::operand::parse_operand(name, 0).ok()?;
    let OperandSyntax::Device(device) = operand.syntax else {
        return None;
    };
    if device.digits.is_some() || device.bit.is_some() || device.offset.is_some() {
        return None;
    }
    let prefix = match device.prefix {
        Prefix::X | Prefix::Y => return Some(format!("{}{:03o}", device.prefix.as_str(), device.number)),
        Prefix::Ts | Prefix::Tn => "T",
        Prefix::Cs | Prefix::Cn => "C",
        Prefix::M
        | Prefix::S
        | Prefix::Sm
        | Prefix::T
        | Prefix::C
        | Prefix::D
        | Prefix::Sd
        | Prefix::R
        | Prefix::P
        | Prefix::N
        | Prefix::V
        | Prefix::Z
        | Prefix::U => device.prefix.as_str(),
    };
    Some(format!("{prefix}{}", device.number))
}

/// The listing of a decoded project.
pub fn write(directives: &Directives, lines: &[Line], encoding: Encoding) -> String {
    let mut text = String::new();
    let mut directive = |word: &str, value: &str| text.push_str(&format!("{MARK} {word} {value}\n"));
    if let Some(cpu) = &directives.cpu {
        directive("cpu", cpu);
    }
    if let Some(memory) = directives.memory {
        directive("memory", &memory.to_string());
    }
    if let Some(latch) = &directives.latch {
        directive("latch", latch);
    }
    if let Some(encoding) = directives.encoding {
        directive("encoding", encoding.name());
    }
    for (device, comment) in &directives.comments {
        directive("comment", &format!("{device} {comment}"));
    }
    // Whether the last line written is an instruction or a label: a note
    // is put on it, and on no other line.
    let mut after_code = false;
    for line in lines {
        let code = matches!(line.kind, LineKind::Instruction { .. } | LineKind::Label(_));
        match &line.kind {
            LineKind::Instruction { mnemonic, operands } => {
                text.push_str(&format!("{}\t{mnemonic}", line.step));
                if !operands.is_empty() {
                    text.push('\t');
                    text.push_str(&operands.join(" "));
                }
                text.push('\n');
            }
            LineKind::Label(number) => text.push_str(&format!("{}\tP{number}\n", line.step)),
            LineKind::Statement(statement) => text.push_str(&format!("// {}\n", encoding.decode(statement))),
            LineKind::Note(note) if after_code => {
                // A note belongs to the instruction above: on its line.
                text.pop();
                text.push_str(&format!(" ; {}\n", encoding.decode(note)));
            }
            // With no instruction above (the first line, after a statement
            // or another note): a comment line of its own, which a `//@`
            // line or a statement must not take in.
            LineKind::Note(note) => text.push_str(&format!("// {}\n", encoding.decode(note))),
        }
        after_code = code;
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_note_with_no_instruction_above_is_a_line_of_its_own() {
        let line = |step, kind| Line { step, at: 0, kind };
        let note = |text: &str| LineKind::Note(text.as_bytes().to_vec());
        let lines = [
            line(0, note("first")),
            line(0, LineKind::Statement(b"rung".to_vec())),
            line(0, note("after statement")),
            line(
                0,
                LineKind::Instruction {
                    mnemonic: "LD".into(),
                    operands: vec!["X0".into()],
                },
            ),
            line(1, note("of LD")),
            line(1, note("second")),
        ];
        let found = Directives {
            cpu: Some("FX3U".into()),
            ..Directives::default()
        };
        let text = write(&found, &lines, Encoding::ShiftJis);
        assert_eq!(
            text,
            "//@ cpu FX3U\n// first\n// rung\n// after statement\n0\tLD\tX0 ; of LD\n// second\n"
        );
        assert_eq!(directives(&text).cpu.as_deref(), Some("FX3U"));
    }

    #[test]
    fn directives_read_back() {
        let text =
            "//@ cpu FX2N\n//@ memory 2000\n//@ encoding Big5\n//@ comment x000 start  button\n// plain\nLD X0\n";
        let found = directives(text);
        assert_eq!(found.cpu.as_deref(), Some("FX2N"));
        assert_eq!(found.memory, Some(2000));
        assert_eq!(found.encoding, Some(Encoding::Big5));
        assert_eq!(found.comments, [("X000".to_string(), "start  button".to_string())]);
        assert_eq!(
            device_comments("//@ comment X10 ten\n//@ comment TS3 t")
                .get("X010")
                .unwrap(),
            "ten"
        );
        assert_eq!(canonical_device("TS3").as_deref(), Some("T3"));
        let csv = "Device,Comment,Comment 2\r\nX000,Start button,green\r\n\"Y0\"\t\"Motor\"\r\nD1,\r\n";
        assert_eq!(
            comments_from_csv(csv),
            "//@ comment X000 Start button\n//@ comment Y000 Motor\n"
        );
        assert_eq!(
            directives("//@ comments names.csv").comment_file.as_deref(),
            Some("names.csv")
        );
        assert_eq!(
            write(&found, &[], Encoding::ShiftJis),
            "//@ cpu FX2N\n//@ memory 2000\n//@ encoding Big5\n//@ comment X000 start  button\n"
        );
    }
}
