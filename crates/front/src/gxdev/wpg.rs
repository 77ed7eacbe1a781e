//! GX Developer's program file, `Pou/Body/MAIN.wpg`: decoded to the lines
//! of an IL listing (with their steps), and encoded from IL statements.
//!
//! After the header come four bytes (04 00 FF FF in the sample project and
//! in what public decoders write; what they mean is not known, and ladderc
//! writes them so) and the program's records: an instruction is a record
//! of its opcode followed by one record per operand device; a line statement (80) and a note (82) are
//! records of their text; a label is a record 3C followed by the pointer's
//! record; an empty record is a NOP. NOPs fill the program memory after END.
//!
//! The opcodes: a basic instruction is one byte, with its step count as a
//! second byte when it takes more than one step. An applied instruction is
//! a group byte, its step count and a byte that picks the instruction in the
//! group; a comparison contact is 40, its steps, the comparison and the
//! role. These codes are not the FNC numbers and no public source lists
//! them all: the table below holds the ones public decoders have seen in
//! real files (kernelbee/MitsubishiFX3, read for facts only), and ORI, ORP
//! and ANDF where the contact codes run in fours (LD LDI LDP LDF at 00-03,
//! OR ORI ORP ORF at 06-09, AND ANI ANDP ANDF at 0C-0F). An opcode not in
//! the table is a decode error naming its bytes; an instruction without a
//! code cannot be written.

use super::records::{self, code, Record};
use super::text::Encoding;
use super::DecodeError;
use crate::syntax::{InstructionSyntax, OperandSyntax, Prefix};

/// The four bytes after the header.
const SUBHEADER: [u8; 4] = [0x04, 0x00, 0xFF, 0xFF];

/// The largest program memory of an FX CPU (FX3U: 64000 steps).
const MOST_STEPS: u32 = 64_000;

const STATEMENT: u8 = 0x80;
const NOTE: u8 = 0x82;
const LABEL: u8 = 0x3C;
const OUT_WITH_PRESET: u8 = 0x21;
const COMPARE: u8 = 0x40;

/// Basic instructions: opcode and mnemonic.
const BASIC: &[(u8, &str)] = &[
    (0x00, "LD"),
    (0x01, "LDI"),
    (0x02, "LDP"),
    (0x03, "LDF"),
    (0x06, "OR"),
    (0x07, "ORI"),
    (0x08, "ORP"),
    (0x09, "ORF"),
    (0x0C, "AND"),
    (0x0D, "ANI"),
    (0x0E, "ANDP"),
    (0x0F, "ANDF"),
    (0x18, "ORB"),
    (0x19, "ANB"),
    (0x1A, "MPS"),
    (0x1B, "MRD"),
    (0x1C, "MPP"),
    (0x20, "OUT"),
    (OUT_WITH_PRESET, "OUT"),
    (0x23, "SET"),
    (0x24, "RST"),
    (0x2C, "MC"),
    (0x30, "MCR"),
    (0x33, "FEND"),
    (0x34, "END"),
];

/// Applied instructions: group, instruction in the group, mnemonic.
const APPLIED: &[(u8, u8, &str)] = &[
    (0x49, 0x28, "ADD"),
    (0x49, 0x2A, "SUB"),
    (0x49, 0x2B, "DSUB"),
    (0x49, 0x2C, "MUL"),
    (0x49, 0x2D, "DMUL"),
    (0x49, 0x30, "DEADD"),
    (0x49, 0x31, "DESUB"),
    (0x49, 0x32, "DEMUL"),
    (0x49, 0x33, "DEDIV"),
    (0x4A, 0x00, "INC"),
    (0x4A, 0x02, "DEC"),
    (0x4B, 0x05, "DINT"),
    (0x4B, 0x0F, "DNEG"),
    (0x4C, 0x00, "MOV"),
    (0x4C, 0x01, "DMOV"),
    (0x4C, 0x06, "BMOV"),
    (0x4C, 0x0F, "DEMOV"),
    (0x4D, 0x00, "CJ"),
    (0x4F, 0x01, "WAND"),
    (0x4F, 0x03, "WOR"),
    (0x4F, 0x09, "DAND"),
    (0x4F, 0x0B, "DOR"),
    (0x50, 0x06, "DROL"),
    (0x51, 0x00, "SFR"),
    (0x51, 0x01, "SFL"),
    (0x53, 0x19, "ZRST"),
    (0x53, 0x22, "FLT"),
    (0x53, 0x23, "DFLT"),
    (0x54, 0x01, "CALL"),
    (0x56, 0x00, "FROM"),
    (0x56, 0x02, "TO"),
    (0x5F, 0x1D, "RS2"),
    (0x69, 0x00, "DI"),
    (0x69, 0x01, "EI"),
    (0x69, 0x03, "IRET"),
    (0x6A, 0x00, "FOR"),
    (0x6A, 0x01, "NEXT"),
    (0x6A, 0x07, "SRET"),
];

/// Comparison contacts: the role byte and the mnemonic's start.
const COMPARE_ROLES: [(u8, &str); 3] = [(0x10, "LD"), (0x11, "AND"), (0x12, "OR")];
/// The comparisons in the order of their codes (32-bit forms add 6).
const COMPARISONS: [&str; 6] = ["=", "<>", ">", ">=", "<", "<="];

/// Every mnemonic that has a code, for the tests against the instruction
/// table.
pub fn mnemonics() -> Vec<String> {
    let mut names: Vec<String> = BASIC
        .iter()
        .map(|(_, n)| n.to_string())
        .chain(APPLIED.iter().map(|(_, _, n)| n.to_string()))
        .collect();
    for (_, role) in COMPARE_ROLES {
        for wide in ["", "D"] {
            names.extend(COMPARISONS.iter().map(|c| format!("{role}{wide}{c}")));
        }
    }
    names.sort();
    names.dedup();
    names
}

/// What a line of the listing holds.
#[derive(Clone, Debug, PartialEq)]
pub enum LineKind {
    Instruction {
        mnemonic: String,
        operands: Vec<String>,
    },
    /// `P12` (a label; interrupt pointers are decode errors).
    Label(u32),
    /// A line statement (its bytes), before the instruction it belongs to.
    Statement(Vec<u8>),
    /// A note (its bytes), after the instruction it belongs to.
    Note(Vec<u8>),
}

/// A line of the listing: its step (of the instruction or label; of the
/// next one for a statement), where its record starts, what it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    pub step: u32,
    pub at: usize,
    pub kind: LineKind,
}

/// A decoded program file.
#[derive(Clone, Debug)]
pub struct Program {
    pub cpu: u8,
    pub lines: Vec<Line>,
    /// Steps of program memory (the NOPs after the program included).
    pub capacity: u32,
}

/// Is `steps` a program memory GX Developer writes? The parameters set it
/// in thousands of steps; the FX0S has 800.
pub fn is_memory_size(steps: u32) -> bool {
    steps == 800 || (steps > 0 && steps.is_multiple_of(1000) && steps <= MOST_STEPS)
}

/// The most operand records one instruction has: five operands, each with
/// its modifiers, fit well within it.
const MOST_OPERAND_RECORDS: usize = 32;

/// Decodes a program file. Reading stops at the first record past the
/// largest program memory (`MOST_STEPS`), so a file of any size costs at
/// most a program's worth of memory.
pub fn decode(bytes: &[u8]) -> Result<Program, DecodeError> {
    let cpu = records::check_header(bytes)?;
    let body_at = records::HEADER_LEN + SUBHEADER.len();
    if bytes.len() < body_at {
        return Err(DecodeError::new(bytes.len(), "the four bytes after the header"));
    }
    let mut records = records::records(&bytes[body_at..], body_at).peekable();
    let mut lines = Vec::new();
    let mut step = 0u32;
    // Statements and notes take no steps: they are bounded on their own.
    let mut texts = 0u32;
    // NOPs not yet placed: written out only when something follows them.
    let mut nops: Vec<(u32, usize)> = Vec::new();
    while let Some(record) = records.next().transpose()? {
        let takes_steps = !matches!(record.payload.first(), Some(&(STATEMENT | NOTE)));
        if (takes_steps && step >= MOST_STEPS) || texts >= MOST_STEPS {
            return Err(DecodeError::new(
                record.at,
                format!(
                    "the end of the file: the program memory of an FX CPU holds at most {MOST_STEPS} steps \
                     (ladderc reads at most as many statements and notes)"
                ),
            ));
        }
        let Some(&opcode) = record.payload.first() else {
            nops.push((step, record.at));
            step += 1;
            continue;
        };
        for (nop_step, at) in nops.drain(..) {
            lines.push(Line {
                step: nop_step,
                at,
                kind: LineKind::Instruction {
                    mnemonic: "NOP".into(),
                    operands: Vec::new(),
                },
            });
        }
        let text = || {
            let bytes = record.payload.get(2..).unwrap_or_default();
            let end = bytes.iter().rposition(|&b| b != b' ' && b != 0).map_or(0, |i| i + 1);
            bytes[..end].to_vec()
        };
        let kind = match opcode {
            STATEMENT => {
                texts += 1;
                LineKind::Statement(text())
            }
            NOTE => {
                texts += 1;
                LineKind::Note(text())
            }
            LABEL => {
                let pointer = records
                    .next()
                    .transpose()?
                    .ok_or_else(|| DecodeError::new(record.at, "a pointer after a label mark"))?;
                match pointer.payload {
                    [code::P, value @ ..] if (1..=2).contains(&value.len()) => {
                        let number = value.iter().rev().fold(0u32, |a, &b| (a << 8) | u32::from(b));
                        let kind = LineKind::Label(number);
                        lines.push(Line {
                            step,
                            at: record.at,
                            kind,
                        });
                        step += value.len() as u32;
                        continue;
                    }
                    [code::I, ..] => {
                        return Err(DecodeError::new(
                            pointer.at,
                            "a P label (this is an interrupt pointer: ladderc runs no interrupt routines)",
                        ))
                    }
                    _ => return Err(DecodeError::new(pointer.at, "a P label after the label mark 3C")),
                }
            }
            code::FIRST_OPERAND.. => {
                return Err(DecodeError::new(
                    record.at,
                    format!("an instruction (found the operand code {opcode:02X} with no instruction before it)"),
                ))
            }
            _ => {
                let (mnemonic, steps) = instruction(&record)?;
                let mut own = Vec::new();
                while let Some(Ok(operand)) = records.peek() {
                    if operand.payload.first().is_none_or(|&c| c < code::FIRST_OPERAND) {
                        break;
                    }
                    if own.len() == MOST_OPERAND_RECORDS {
                        return Err(DecodeError::new(
                            operand.at,
                            format!("the next instruction (an instruction has at most {MOST_OPERAND_RECORDS} operand records)"),
                        ));
                    }
                    own.push(*operand);
                    records.next();
                }
                let operands = operands(&own, mnemonic_is_wide(&mnemonic) || long_counter(&mnemonic, &own))?;
                let line = Line {
                    step,
                    at: record.at,
                    kind: LineKind::Instruction { mnemonic, operands },
                };
                lines.push(line);
                step += steps;
                continue;
            }
        };
        lines.push(Line {
            step,
            at: record.at,
            kind,
        });
    }
    // GX Developer always writes END: a file without one was cut short at
    // a record's end, and its first part is not the program.
    let ends = lines
        .iter()
        .any(|line| matches!(&line.kind, LineKind::Instruction { mnemonic, .. } if mnemonic == "END"));
    if !ends {
        return Err(DecodeError::new(
            bytes.len(),
            format!("more of the program: the file ends after step {step} without END (cut short?)"),
        ));
    }
    // The NOPs after END fill the program memory: a file cut in them (or
    // padded) holds a size GX Developer does not write.
    if !is_memory_size(step) {
        return Err(DecodeError::new(
            bytes.len(),
            format!(
                "more NOPs: the file ends after {step} steps, and program memory is a whole number of \
                 thousands of steps (cut short?)"
            ),
        ));
    }
    Ok(Program {
        cpu,
        lines,
        capacity: step,
    })
}

/// An instruction's mnemonic and steps from its opcode record.
fn instruction(record: &Record) -> Result<(String, u32), DecodeError> {
    let unknown = |what: &str| {
        let bytes: Vec<String> = record.payload.iter().map(|b| format!("{b:02X}")).collect();
        DecodeError::new(
            record.at,
            format!(
                "an instruction code ladderc knows (found {} {what}); the codes ladderc reads are listed in docs/language.md",
                bytes.join(" ")
            ),
        )
    };
    match *record.payload {
        [opcode] | [opcode, _] => {
            let steps = record.payload.get(1).map_or(1, |&s| u32::from(s));
            let (_, name) = BASIC.iter().find(|(c, _)| *c == opcode).ok_or_else(|| unknown(""))?;
            Ok((name.to_string(), steps))
        }
        [group, steps, which] => {
            let (_, _, name) = APPLIED
                .iter()
                .find(|(g, w, _)| *g == group && *w == which)
                .ok_or_else(|| unknown("(an applied instruction)"))?;
            Ok((name.to_string(), u32::from(steps)))
        }
        [COMPARE, steps, comparison, role] => {
            let (_, start) = COMPARE_ROLES
                .iter()
                .find(|(r, _)| *r == role)
                .ok_or_else(|| unknown("(a comparison contact)"))?;
            let symbol = COMPARISONS
                .get(usize::from(comparison % 6))
                .filter(|_| comparison < 12)
                .ok_or_else(|| unknown("(a comparison contact)"))?;
            let wide = if comparison >= 6 { "D" } else { "" };
            Ok((format!("{start}{wide}{symbol}"), u32::from(steps)))
        }
        _ => Err(unknown("")),
    }
}

/// Is this a 32-bit instruction (its K constants are double words)?
fn mnemonic_is_wide(mnemonic: &str) -> bool {
    match crate::isa::lookup(mnemonic) {
        Some(crate::isa::Mnemonic::App(form)) => form.width == ladder_runtime::Width::Double,
        Some(crate::isa::Mnemonic::Bit(spec)) => spec.width == ladder_runtime::Width::Double,
        None => false,
    }
}

/// Is this the coil of a 32-bit counter (C200-C255), whose preset is a
/// 32-bit value?
fn long_counter(mnemonic: &str, operands: &[Record]) -> bool {
    let first = operands.first().map(|r| r.payload);
    let number = |bytes: &[u8]| bytes.iter().rev().fold(0u32, |a, &b| (a << 8) | u32::from(b));
    mnemonic == "OUT" && matches!(first, Some([code::C, value @ ..]) if number(value) >= 200)
}

/// The operands of an instruction from its operand records.
fn operands(records: &[Record], wide: bool) -> Result<Vec<String>, DecodeError> {
    const MODIFIERS: [u8; 5] = [code::INDEX_Z, code::DIGITS, code::BIT, code::INDEX_V, code::UNIT];
    let mut operands = Vec::new();
    let mut start = 0;
    for (i, record) in records.iter().enumerate() {
        let modifies = record.payload.first().is_some_and(|c| MODIFIERS.contains(c));
        if !modifies {
            operands.push(records::operand_text(&records[start..=i], wide)?);
            start = i + 1;
        }
    }
    if let Some(dangling) = records.get(start) {
        return Err(DecodeError::new(dangling.at, "a device after its modifier"));
    }
    Ok(operands)
}

/// What the encoder takes for one instruction: the statement, its line
/// statements (before it) and its note.
pub struct Item<'a> {
    pub instruction: Option<&'a InstructionSyntax>,
    pub label: Option<u32>,
    pub statements: Vec<String>,
    pub note: Option<String>,
}

/// Encodes a program for CPU type `cpu` with `capacity` steps of memory.
/// `Err` says which item cannot be written and why.
pub fn encode(items: &[Item], cpu: u8, capacity: u32, encoding: Encoding) -> Result<Vec<u8>, (usize, String)> {
    let mut out = records::header(cpu, &[0x03, 0x03, 0x01]);
    out.extend_from_slice(&SUBHEADER);
    let mut steps = 0u32;
    for (index, item) in items.iter().enumerate() {
        let fail = |message: String| (index, message);
        for statement in &item.statements {
            let mut payload = vec![STATEMENT, 0x00];
            payload.extend(encoding.encode(statement).map_err(fail)?);
            push_text(&mut out, &payload).map_err(fail)?;
        }
        if let Some(number) = item.label {
            let long = number > 0xFF;
            records::push(&mut out, if long { &[LABEL, 0x02] } else { &[LABEL] });
            let mut payload = vec![code::P];
            payload.extend(&number.to_le_bytes()[..if long { 2 } else { 1 }]);
            records::push(&mut out, &payload);
            steps += if long { 2 } else { 1 };
        }
        if let Some(instruction) = item.instruction {
            steps += encode_instruction(&mut out, instruction).map_err(fail)?;
        }
        if let Some(note) = &item.note {
            let mut payload = vec![NOTE, 0x00];
            payload.extend(encoding.encode(note).map_err(fail)?);
            push_text(&mut out, &payload).map_err(fail)?;
        }
    }
    if !is_memory_size(capacity) {
        return Err((
            items.len(),
            format!(
                "{capacity} steps of program memory: GX Developer sets it in thousands of steps \
                 (800 for an FX0S), at most {MOST_STEPS}"
            ),
        ));
    }
    if steps > capacity {
        return Err((
            items.len(),
            format!("the program takes {steps} steps, more than the {capacity} steps of program memory"),
        ));
    }
    for _ in steps..capacity {
        records::push(&mut out, &[]);
    }
    Ok(out)
}

fn push_text(out: &mut Vec<u8>, payload: &[u8]) -> Result<(), String> {
    if payload.len() > 250 {
        return Err("a comment longer than 248 bytes".into());
    }
    records::push(out, payload);
    Ok(())
}

/// Writes one instruction's records; returns its steps.
fn encode_instruction(out: &mut Vec<u8>, instruction: &InstructionSyntax) -> Result<u32, String> {
    let name = instruction.mnemonic.as_str();
    let operands: Vec<&OperandSyntax> = instruction.operands.iter().map(|o| &o.syntax).collect();
    let wide = mnemonic_is_wide(name);
    let steps = steps(name, &operands, wide);
    let long_counter = name == "OUT" && counted(operands.first()).counter.is_some_and(|n| n >= 200);
    let no_code =
        || format!("{name} has no known code in a GX Developer program (docs/language.md lists those ladderc writes)");
    let steps_byte = u8::try_from(steps).map_err(|_| format!("{name} takes too many steps"))?;
    // NOP is the empty record.
    let opcode: Vec<u8> = if name == "NOP" && operands.is_empty() {
        Vec::new()
    } else if let Some((_, group, which, _)) = APPLIED
        .iter()
        .map(|(g, w, n)| ((), *g, *w, *n))
        .find(|(_, _, _, n)| *n == name)
    {
        vec![group, steps_byte, which]
    } else if let Some(compare) = comparison_code(name) {
        let (comparison, role) = compare;
        vec![COMPARE, steps_byte, comparison, role]
    } else {
        let code = match (name, operands.len()) {
            ("OUT", 2) => OUT_WITH_PRESET,
            _ => BASIC
                .iter()
                .find(|(_, n)| *n == name)
                .map(|(c, _)| *c)
                .ok_or_else(no_code)?,
        };
        if steps > 1 {
            vec![code, steps_byte]
        } else {
            vec![code]
        }
    };
    records::push(out, &opcode);
    for operand in operands {
        records::encode_operand(out, operand, wide, wide || long_counter)?;
    }
    Ok(steps)
}

/// The comparison and role bytes of a comparison contact's mnemonic.
fn comparison_code(name: &str) -> Option<(u8, u8)> {
    COMPARE_ROLES.iter().find_map(|&(role, start)| {
        let rest = name.strip_prefix(start)?;
        let (wide, symbol) = match rest.strip_prefix('D') {
            Some(symbol) => (6, symbol),
            None => (0, rest),
        };
        let index = COMPARISONS.iter().position(|c| *c == symbol)?;
        Some((index as u8 + wide, role))
    })
}

/// What the step counts of the basic instructions depend on: the device
/// of an operand.
#[derive(Clone, Copy, Default)]
struct Counted {
    /// Indexed (Z, V) or a bit of a word.
    modified: bool,
    /// An M relay's number.
    m: Option<u32>,
    /// A state's number.
    s: Option<u32>,
    timer: bool,
    /// A counter's number.
    counter: Option<u32>,
    /// A data, file or index register.
    word: bool,
}

fn counted(operand: Option<&&OperandSyntax>) -> Counted {
    let mut counted = Counted::default();
    let Some(OperandSyntax::Device(device)) = operand.copied() else {
        return counted;
    };
    counted.modified = device.offset.is_some() || device.bit.is_some();
    let number = device.number;
    match device.prefix {
        Prefix::M => counted.m = Some(number),
        Prefix::S => counted.s = Some(number),
        Prefix::T | Prefix::Ts | Prefix::Tn => counted.timer = true,
        Prefix::C | Prefix::Cs | Prefix::Cn => counted.counter = Some(number),
        Prefix::D | Prefix::R | Prefix::V | Prefix::Z => counted.word = true,
        Prefix::X | Prefix::Y | Prefix::Sm | Prefix::Sd | Prefix::P | Prefix::N | Prefix::U => {}
    }
    counted
}

/// The steps an instruction takes in an FX program, as the FX programming
/// manuals count them.
fn steps(name: &str, operands: &[&OperandSyntax], wide: bool) -> u32 {
    let first = counted(operands.first());
    let m_in = |from: u32, to: u32| first.m.is_some_and(|n| (from..=to).contains(&n));
    let (mid_m, high_m) = (m_in(1536, 3583), m_in(3584, 7679));
    let out = name == "OUT";
    match name {
        "LD" | "LDI" | "AND" | "ANI" | "OR" | "ORI" => {
            if first.modified || high_m {
                3
            } else if mid_m || m_in(8256, 8511) || first.s.is_some_and(|n| n > 1023) {
                2
            } else {
                1
            }
        }
        "LDP" | "LDF" | "ANDP" | "ANDF" | "ORP" | "ORF" | "PLS" | "PLF" => {
            if first.modified || high_m {
                3
            } else {
                2
            }
        }
        "OUT" | "SET" | "RST" => {
            let counts = first.timer || first.counter.is_some();
            if first.modified {
                if out && counts {
                    4
                } else {
                    3
                }
            } else if mid_m || m_in(8000, 8511) || first.s.is_some() {
                2
            } else if high_m || first.word || (out && first.timer) {
                3
            } else if let (true, Some(n)) = (out, first.counter) {
                if (200..=255).contains(&n) {
                    5
                } else {
                    3
                }
            } else if counts {
                2
            } else {
                1
            }
        }
        "MC" => {
            if counted(operands.get(1)).m.is_some_and(|n| (3584..=7679).contains(&n)) {
                4
            } else {
                3
            }
        }
        "MCR" => 2,
        _ if BASIC.iter().any(|(_, n)| *n == name) => 1,
        // Applied instructions and comparison contacts: the instruction's
        // step, and two steps per 16-bit operand or four per 32-bit one.
        _ => 1 + operands.len() as u32 * if wide { 4 } else { 2 },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_names_an_instruction_of_the_table() {
        // Those ladderc does not implement read as themselves and are
        // reported by the checker at their step (E0032).
        let unsupported = |name: &str| {
            let base = name
                .strip_prefix('D')
                .filter(|b| crate::isa::fx::UNSUPPORTED_FX.contains(b));
            crate::isa::fx::UNSUPPORTED_FX.contains(&name) || base.is_some()
        };
        for name in mnemonics() {
            assert!(crate::isa::lookup(&name).is_some() || unsupported(&name), "{name}");
        }
    }

    #[test]
    fn comparison_codes_round_trip() {
        for name in ["LD=", "ANDD<>", "OR<=", "LDD>="] {
            let (comparison, role) = comparison_code(name).unwrap();
            let record = [COMPARE, 5, comparison, role];
            let (back, _) = instruction(&Record {
                at: 0,
                payload: &record,
            })
            .unwrap();
            assert_eq!(back, name);
        }
    }
}
