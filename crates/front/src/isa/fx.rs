//! Mnemonics of Mitsubishi FX (FX3U) instructions that ladderc does not
//! implement, so that a program written for an FX PLC gets "not supported"
//! instead of "unknown", and suggestions for mistyped mnemonics.

use super::table::{lookup, mnemonics};
use std::sync::OnceLock;

/// FX3U instructions (base names, without the D prefix and P suffix of
/// their forms) that ladderc does not implement.
#[rustfmt::skip]
pub const UNSUPPORTED_FX: &[&str] = &[
    // Interrupts and the watchdog: no interrupts in the model.
    "IRET", "EI", "DI", "WDT",
    // Digit shifts, rotations with carry, word shifts and FIFO tables.
    "SMOV", "RCR", "RCL", "WSFR", "WSFL", "SFWR", "SFRD",
    // I/O refresh and hardware timing: no hardware behind the program.
    "REF", "REFF", "MTR", "HSCT", "DUTY", "HCMOV",
    // Handy instructions for particular machines.
    "IST", "ROTC",
    // External I/O devices (keypads, switches, printers).
    "TKY", "HKY", "DSW", "ARWS", "ASC", "PR",
    // Serial communication and the volume/analog expansion boards.
    "RS", "RS2", "VRRD", "VRSC", "RD3A", "WR3A",
    // Floating point to and from character strings.
    "ESTR", "EVAL",
    // Index register stack.
    "ZPUSH", "ZPOP",
    // Positioning beyond the pulse outputs: absolute encoder, tables.
    "DVIT", "TBL", "ABS",
    // Gray code, extended ROM, communication, random numbers.
    "GRY", "GBIN", "EXTR", "COMRD", "RND",
    // Character strings.
    "BINDA", "DABIN", "STR", "VAL", "LEN", "RIGHT", "LEFT", "MIDR", "MIDW", "INSTR",
    // Data operation and data tables.
    "FDEL", "FINS", "SFR", "SFL", "BAND", "ZONE", "SCL", "SCL2",
    // Inverter communication, buffer memory blocks, file registers.
    "IVCK", "IVDR", "IVRD", "IVWR", "IVBWR", "ADPRW", "RBFM", "WBFM",
    "LOADR", "SAVER", "INITR", "LOGR", "RWER", "INITER",
];

/// Is `mnemonic` (any case) a form of an FX instruction ladderc does not
/// implement? (`DECMP` is ECMP in 32 bits, `REFP` the pulse form of REF.)
pub fn unsupported_fx(mnemonic: &str) -> bool {
    let upper = mnemonic.to_ascii_uppercase();
    let without_pulse = upper.strip_suffix('P');
    let candidates = [
        Some(upper.as_str()),
        without_pulse,
        upper.strip_prefix('D'),
        without_pulse.and_then(|m| m.strip_prefix('D')),
    ];
    lookup(&upper).is_none()
        && candidates
            .into_iter()
            .flatten()
            .any(|base| UNSUPPORTED_FX.contains(&base))
}

/// What an instruction of another dialect (IEC 61131-3 IL, other vendors'
/// timer and counter boxes) is written as in FX: a note for an unknown
/// mnemonic, given before any guess by spelling (`TMR` is not a typo of
/// `TTMR`).
pub fn idiom(mnemonic: &str) -> Option<&'static str> {
    Some(match mnemonic.to_ascii_uppercase().as_str() {
        "TMR" | "TON" | "TIM" | "TIMER" | "TMRA" | "TONR" => {
            "an FX timer is its coil with a preset: `OUT T0 K100` (T0 ON after 100 x 100 ms while the rung is ON)"
        }
        "CNT" | "CTU" | "CTR" | "COUNTER" => {
            "an FX counter is its coil with a preset: `OUT C0 K10` (C0 ON after 10 rising edges of the rung);              `RST C0` clears it"
        }
        "LDN" => "FX writes a normally closed contact at the start of a rung as `LDI`",
        "ANDN" => "FX writes a normally closed contact in series as `ANI`",
        "ORN" => "FX writes a normally closed contact in parallel as `ORI`",
        "ST" | "STO" | "=" => "FX writes a coil as `OUT`",
        "S" => "FX writes a latching coil as `SET`",
        "R" => "FX writes an unlatching coil as `RST`",
        "NOT" => "FX inverts the rung result with `INV`",
        "JMP" | "JP" => "FX jumps with `CJ Pn` to a label `Pn`",
        _ => return None,
    })
}

/// The supported mnemonic closest to a mistyped one, if one is close.
pub fn suggestion(mnemonic: &str) -> Option<&'static str> {
    static SORTED: OnceLock<Vec<&'static str>> = OnceLock::new();
    // No mnemonic is longer than this; a long word is no typo of one.
    const LONGEST: usize = 8;
    let upper = mnemonic.to_ascii_uppercase();
    let length = upper.chars().count();
    // A quoted CSV field (`"Step`) or other punctuation is no typo of a
    // mnemonic.
    let word_like = upper
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || matches!(c, '<' | '>' | '='));
    if length > LONGEST + 2 || !word_like {
        return None;
    }
    // `EADD` for `DEADD`: an instruction with only a 32-bit form.
    let wide = format!("D{upper}");
    if let Some(&known) = SORTED.get_or_init(mnemonics).iter().find(|m| **m == wide) {
        return Some(known);
    }
    // Two edits for long words, one for short ones: `LDD` -> `LD`, but no
    // wild guess for `Q`.
    let most = if length > 4 { 2 } else { 1 };
    let first = upper.chars().next();
    SORTED
        .get_or_init(mnemonics)
        .iter()
        .filter(|candidate| candidate.chars().count().abs_diff(length) <= most)
        .map(|&candidate| {
            let distance = strsim::damerau_levenshtein(&upper, candidate);
            // Among equally close ones, a mnemonic with the same first
            // letter is the likelier typo.
            (distance, candidate.chars().next() != first, candidate)
        })
        .filter(|&(distance, _, _)| distance <= most)
        .min()
        .map(|(_, _, candidate)| candidate)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fx_instructions_are_known_as_unsupported() {
        for mnemonic in ["REF", "refp", "DSW", "RS", "ZPUSH"] {
            assert!(unsupported_fx(mnemonic), "{mnemonic}");
        }
        for mnemonic in ["MOV", "DMOVP", "LD", "QQQ", "SORT", "DECMP", "EADD", "DPLSY", "TRD"] {
            assert!(!unsupported_fx(mnemonic), "{mnemonic}");
        }
    }

    #[test]
    fn other_dialects_get_the_fx_spelling() {
        assert!(idiom("TMR").is_some_and(|hint| hint.contains("OUT T0 K100")));
        assert!(idiom("ctu").is_some_and(|hint| hint.contains("OUT C0")));
        assert!(idiom("LDN").is_some_and(|hint| hint.contains("LDI")));
        assert_eq!(idiom("TTMR"), None);
        assert_eq!(idiom("MOV"), None);
    }

    #[test]
    fn close_mnemonics_are_suggested() {
        assert_eq!(suggestion("LDD"), Some("LD"));
        assert_eq!(suggestion("OTU"), Some("OUT"));
        assert_eq!(suggestion("MOOV"), Some("MOV"));
        assert_eq!(suggestion("XYZZY"), None);
        assert_eq!(suggestion("EADD"), Some("DEADD"));
        assert_eq!(suggestion("\"STEP"), None, "a quoted CSV header is no typo of ZSETP");
        assert_eq!(suggestion(&"A".repeat(100_000)), None);
        assert!(
            mnemonics().iter().all(|m| m.chars().count() <= 8),
            "LONGEST in `suggestion` is the longest mnemonic"
        );
    }
}
