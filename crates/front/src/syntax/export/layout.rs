//! What kind of export a text is, told by its content: the field separator
//! (tab or comma), where the columns are, and the CPU its header names.
//!
//! The editors write the same columns (step, line statement, instruction,
//! operand, blank, PI statement, note) in several dresses: GX Works2
//! tab-separated with every field quoted and three header lines; GX
//! Developer comma-separated and quoted with a `"PLC Type:..."` line;
//! a headerless step CSV (`0,,LD,M8002,,,,,`, operand rows
//! `,,,D300,,,,,`); tab-separated without quotes or step numbers.

use super::rows::split_fields;

/// The columns of an export's rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub separator: char,
    pub step: Option<usize>,
    pub statement: Option<usize>,
    pub instruction: usize,
    pub operand: usize,
    pub pi_statement: usize,
    pub note: usize,
}

impl Layout {
    /// The GX Works2 layout with `separator`: step, line statement,
    /// instruction, operand, blank, PI statement, note.
    pub const fn standard(separator: char) -> Layout {
        Layout::with_instruction_at(separator, 2)
    }

    const fn with_instruction_at(separator: char, instruction: usize) -> Layout {
        Layout {
            separator,
            step: instruction.checked_sub(2),
            statement: instruction.checked_sub(1),
            instruction,
            operand: instruction + 1,
            pi_statement: instruction + 3,
            note: instruction + 4,
        }
    }
}

/// How many lines detection looks at.
const SAMPLE: usize = 40;

/// Looks like a mnemonic: a letter, then letters, digits and comparison
/// signs (`LD`, `LDD>=`, `DMOVP`, `LOG10`), at most 10 long, and not a
/// device (`X000`, `T0`: a device prefix and digits), so that a list of
/// device comments is not taken for a program.
pub fn mnemonic_like(word: &str) -> bool {
    const DEVICE_PREFIXES: [&str; 16] = [
        "X", "Y", "M", "S", "T", "C", "D", "R", "SM", "SD", "TS", "TN", "CS", "CN", "V", "Z",
    ];
    let word = word.trim();
    let letters = word.trim_end_matches(|c: char| c.is_ascii_digit());
    let device = letters.len() < word.len() && DEVICE_PREFIXES.iter().any(|p| letters.eq_ignore_ascii_case(p));
    word.len() <= 10
        && !device
        && word.starts_with(|c: char| c.is_ascii_alphabetic())
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '<' | '>' | '='))
}

/// A step column entry: empty or a number.
fn step_like(field: &str) -> bool {
    field.trim().bytes().all(|b| b.is_ascii_digit())
}

/// The export layout of `text`, if it is an export: most rows of four or
/// more fields hold a mnemonic in one column with only step numbers or
/// nothing before it (plain IL has one instruction and its operands per
/// line, separated by blanks).
pub fn detect(text: &str) -> Option<Layout> {
    let lines: Vec<&str> = text
        .lines()
        .map(|l| l.trim_start_matches('\u{feff}'))
        .filter(|l| !l.trim().is_empty())
        .take(SAMPLE)
        .collect();
    let first_quoted = lines.first().is_some_and(|l| l.trim_start().starts_with('"'));
    let mut best: Option<(usize, Layout)> = None;
    for separator in ['\t', ','] {
        let rows: Vec<Vec<String>> = lines
            .iter()
            .map(|line| split_fields(line, separator))
            .filter(|fields| fields.len() >= 4)
            .collect();
        if rows.is_empty() {
            continue;
        }
        // Votes for the column that holds the instruction.
        let mut votes = [0usize; 3];
        for fields in &rows {
            // The operand beside the instruction is one word or nothing
            // (column titles are not: "Line Statement", "I/O (Device)").
            let column = (0..3).find(|&c| {
                mnemonic_like(&fields[c])
                    && !fields[c + 1].trim().contains(char::is_whitespace)
                    && fields[..c]
                        .iter()
                        .enumerate()
                        .all(|(i, f)| f.trim().is_empty() || (i == 0 && step_like(f)))
            });
            if let Some(column) = column {
                votes[column] += 1;
            }
        }
        // Ties go to the editors' own layout (the instruction third).
        let (column, &count) = votes
            .iter()
            .enumerate()
            .max_by_key(|&(column, votes)| (*votes, column == 2))
            .unwrap_or((2, &0));
        let enough =
            count > 0 && (2 * count >= rows.len() || first_quoted) && (2 * rows.len() >= lines.len() || first_quoted);
        if enough && best.is_none_or(|(c, _)| count > c) {
            best = Some((count, Layout::with_instruction_at(separator, column)));
        }
    }
    best.map(|(_, layout)| layout)
}

/// Does `text` look like rows of fields (most lines hold three or more tabs
/// or commas, or two after a step number), whether or not `detect` found an
/// instruction list in them? The line of the first such row.
pub fn tabular(text: &str) -> Option<usize> {
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .take(SAMPLE)
        .collect();
    let rows: Vec<usize> = lines
        .iter()
        .filter(|(_, l)| {
            let separators = l.matches('\t').count().max(l.matches(',').count());
            // Three fields are a row too when the first is a step number
            // (`000000,LD,M1002`, as Delta's WPLSoft lists steps).
            let numbered = l
                .split(['\t', ','])
                .next()
                .is_some_and(|step| !step.trim().is_empty() && step.trim().bytes().all(|b| b.is_ascii_digit()));
            separators >= 3 || (separators >= 2 && numbered)
        })
        .map(|&(i, _)| i)
        .collect();
    (rows.len() >= 2 && 2 * rows.len() >= lines.len()).then(|| rows[0])
}

/// The CPU family an export's header names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cpu {
    Fx,
    /// Another family: its name and the field that says so.
    Other(&'static str),
}

/// The family a PLC-information field names, if it names one.
pub fn cpu_family(field: &str) -> Option<Cpu> {
    let upper = field.to_ascii_uppercase();
    if upper.contains("FX5") || upper.contains("IQ-F") {
        Some(Cpu::Other("MELSEC iQ-F (FX5)"))
    } else if upper.contains("FX") {
        Some(Cpu::Fx)
    } else if upper.contains("RCPU") || upper.contains("IQ-R") {
        Some(Cpu::Other("MELSEC iQ-R"))
    } else if upper.contains("LCPU") {
        Some(Cpu::Other("MELSEC-L"))
    } else if upper.contains("QCPU") || upper.contains("QNA") {
        Some(Cpu::Other("MELSEC-Q"))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_are_told_by_content() {
        let works2 = "\"MAIN\"\n\"PLC Information:\"\t\"FXCPU FX3U/FX3UC\"\n\"Step No.\"\t\"Line Statement\"\t\"Instruction\"\t\"I/O(Device)\"\n\"0\"\t\"\"\t\"LD\"\t\"X000\"\t\"\"\t\"\"\t\"\"\n";
        assert_eq!(detect(works2), Some(Layout::standard('\t')));
        let developer = "\"MAIN\"\n\"PLC Type:FX2N\"\n\"Step No.\",\"Line Statement\",\"Instruction\",\"I/O(Device)\",\"Blank\",\"PI Statement\",\"Note\"\n\"0\",\"\",\"LD\",\"X000\",\"\",\"\",\"\"\n\"1\",\"\",\"OUT\",\"Y000\",\"\",\"\",\"\"\n";
        assert_eq!(detect(developer), Some(Layout::standard(',')));
        let steps = "0,,LD,M8002,,,,,\n1,,MOV,K0,,,,,\n,,,D320,,,,,,\n6,,END,,,,,,\n";
        assert_eq!(detect(steps), Some(Layout::standard(',')));
        let unquoted = "\u{feff}\u{feff}\t\tLD\tX0\t\t\t\n\t\tOUT\tT0\t\t\t\n\t\t\tK10\t\t\t\n";
        assert_eq!(detect(unquoted), Some(Layout::standard('\t')));
        let no_step_column = "\tLD\tX0\t\t\t\n\tOUT\tY0\t\t\t\n\tEND\t\t\t\t\n";
        assert_eq!(detect(no_step_column).map(|l| l.instruction), Some(1));
    }

    #[test]
    fn plain_il_is_not_an_export() {
        for il in [
            "LD X0\nOUT Y0\n",
            "0 LD X000\n1 OUT Y000\n",
            "LD X0 // a, b, c, d\nOUT Y0 ; x, y, z, w\n",
            "MOV K1, D0\nADD D0, D1, D2\n",
            "\"LD X0\nOUT Y0\n",
        ] {
            assert_eq!(detect(il), None, "{il}");
        }
    }

    #[test]
    fn device_lists_are_not_programs() {
        assert!(!mnemonic_like("X000") && !mnemonic_like("T0") && !mnemonic_like("SM400"));
        assert!(mnemonic_like("LOG10") && mnemonic_like("SORT2") && mnemonic_like("LDD>="));
        let comments = "Device,Comment,Comment 2,Comment 3\nX000,Start button,green,panel\nY000,Motor,K1,MCC\n";
        assert_eq!(detect(comments), None);
        assert!(tabular(comments).is_some());
    }

    #[test]
    fn cpu_families() {
        assert_eq!(cpu_family("FXCPU FX3U/FX3UC"), Some(Cpu::Fx));
        assert_eq!(cpu_family("PLC Type:FX2N"), Some(Cpu::Fx));
        assert_eq!(cpu_family("LCPU L26-BT"), Some(Cpu::Other("MELSEC-L")));
        assert_eq!(cpu_family("QCPU (Q mode) Q26UDV"), Some(Cpu::Other("MELSEC-Q")));
        assert_eq!(cpu_family("RCPU R04"), Some(Cpu::Other("MELSEC iQ-R")));
        assert_eq!(cpu_family("FX5U"), Some(Cpu::Other("MELSEC iQ-F (FX5)")));
        assert_eq!(cpu_family("Step No."), None);
    }
}
