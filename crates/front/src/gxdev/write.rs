//! An IL program written as a GX Developer project's MAIN.wpg and
//! COMMENT.wcd: `//` comment lines right above an instruction become its
//! line statements, the comment after it its note, the `//@` lines the CPU,
//! program memory, code page and device comments; a program without END
//! gets one at its end.

use super::records::code;
use super::text::Encoding;
use super::wpg::Item;
use super::{listing, wcd, wpa, wpg};
use crate::source::SourceFile;
use crate::syntax::{OperandSyntax, Prefix, StatementKind};

/// What a project that already exists says, for what the IL does not.
#[derive(Clone, Debug, Default)]
pub struct Defaults {
    pub cpu: Option<u8>,
    pub memory: Option<u32>,
}

/// The GX Developer default: an FX3U with 8000 steps of program memory.
const CPU: u8 = 0x08;
pub const DEFAULT_CPU: &str = "FX3U";
const MEMORY: u32 = 8000;

/// The two files: MAIN.wpg's and COMMENT.wcd's bytes. `Err` says what
/// cannot be written (at which line of the IL).
pub fn encode(file: &SourceFile, defaults: &Defaults) -> Result<(Vec<u8>, Vec<u8>), String> {
    let directives = listing::directives(&file.text);
    let cpu = match &directives.cpu {
        Some(name) => {
            wpa::cpu_code(name).ok_or_else(|| format!("`//@ cpu {name}` is not an FX CPU GX Developer knows"))?
        }
        None => defaults.cpu.unwrap_or(CPU),
    };
    // GX Developer reads a MAIN.wpg only at the size the parameters
    // declare (and so does ladderc).
    if let (Some(memory), Some(declared)) = (directives.memory, defaults.memory) {
        if memory != declared {
            return Err(format!(
                "`//@ memory {memory}`, but the project's param.wpa declares {declared} steps of program memory: \
                 MAIN.wpg must be that size (change the line, or the parameters in GX Developer)"
            ));
        }
    }
    let memory = directives.memory.or(defaults.memory).unwrap_or(MEMORY);
    let encoding = directives.encoding.unwrap_or(Encoding::ShiftJis);
    let (parsed, _) = crate::syntax::parse(file);
    let lines: Vec<&str> = file.text.split('\n').collect();
    let mut items = Vec::new();
    let mut previous_line = 0usize;
    for statement in &parsed.statements {
        let line = statement.line as usize;
        // Comment lines right above (no blank line between).
        let mut statements = Vec::new();
        for above in (previous_line + 1..line).rev() {
            let text = lines.get(above - 1).map_or("", |l| l.trim());
            match text.strip_prefix("//") {
                Some(comment) if !listing::is_directive(text) => statements.push(comment.trim().to_string()),
                Some(_) | None => break,
            }
        }
        statements.reverse();
        previous_line = line;
        let note = lines
            .get(line - 1)
            .and_then(|l| trailing_comment(l))
            .map(str::to_string);
        let item = match &statement.kind {
            StatementKind::Instruction(instruction) => Item {
                instruction: Some(instruction),
                label: None,
                statements,
                note,
            },
            StatementKind::Label { number } => Item {
                instruction: None,
                label: Some(*number),
                statements,
                note,
            },
        };
        items.push(item);
    }
    // GX Developer's programs end with END (ladderc's need not): one is
    // added after the last instruction when the program has none.
    let end = crate::syntax::InstructionSyntax {
        mnemonic: "END".into(),
        mnemonic_span: crate::source::Span::default(),
        operands: Vec::new(),
        malformed: false,
    };
    let has_end = parsed
        .statements
        .iter()
        .any(|s| matches!(&s.kind, StatementKind::Instruction(i) if i.mnemonic == "END"));
    if !has_end {
        items.push(Item {
            instruction: Some(&end),
            label: None,
            statements: Vec::new(),
            note: None,
        });
    }
    let program =
        wpg::encode(&items, cpu, memory, encoding).map_err(|(index, message)| match parsed.statements.get(index) {
            Some(statement) => format!("{}:{}: {message}", file.name, statement.line),
            None => format!("{}: {message}", file.name),
        })?;
    let mut comments = Vec::new();
    for (device, comment) in &directives.comments {
        let (device_code, number) = comment_device(device).ok_or_else(|| {
            format!("`//@ comment {device}`: GX Developer keeps comments of X, Y, M, S, T, C, D, R and P devices")
        })?;
        comments.push((device_code, number, comment.clone()));
    }
    let comments = wcd::encode(cpu, &comments, encoding)?;
    Ok((program, comments))
}

/// The comment after an instruction on its line (`;` or `//`).
fn trailing_comment(line: &str) -> Option<&str> {
    let at = [line.find(';'), line.find("//")].into_iter().flatten().min()?;
    let before = line[..at].trim();
    let comment = line[at..].trim_start_matches([';', '/']).trim();
    (!before.is_empty() && !comment.is_empty()).then_some(comment)
}

/// The device code and number of a device a comment is for.
fn comment_device(name: &str) -> Option<(u8, u32)> {
    let operand = crate::syntax::operand::parse_operand(name, 0).ok()?;
    let OperandSyntax::Device(device) = operand.syntax else {
        return None;
    };
    if device.digits.is_some() || device.bit.is_some() || device.offset.is_some() {
        return None;
    }
    let device_code = match device.prefix {
        Prefix::X => code::X,
        Prefix::Y => code::Y,
        Prefix::M => code::M,
        Prefix::S => code::S,
        Prefix::T | Prefix::Ts | Prefix::Tn => code::T,
        Prefix::C | Prefix::Cs | Prefix::Cn => code::C,
        Prefix::D => code::D,
        Prefix::R => code::R,
        Prefix::P => code::P,
        Prefix::Sm | Prefix::Sd | Prefix::N | Prefix::V | Prefix::Z | Prefix::U => return None,
    };
    Some((device_code, device.number))
}
