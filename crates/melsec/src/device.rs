//! The device families a MELSEC frame names, and how each frame kind names
//! them: the 1E frame's two-character names (`D `, `TN`), the 3E/4E
//! frame's one-byte binary codes and ASCII names (the family's name padded
//! with `*`: `D*`, `SM`), and the iQ-R forms of subcommands 0002/0003
//! (two-byte codes, names padded to four characters).

/// A family of devices, as the PLC numbers them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Inputs (octal numbers on an FX).
    X,
    /// Outputs (octal numbers on an FX).
    Y,
    /// Auxiliary relays; M8000 and up are an FX3's special relays.
    M,
    /// States.
    S,
    /// Special relays of an iQ-F.
    Sm,
    /// Special registers of an iQ-F.
    Sd,
    /// Data registers; D8000 and up are an FX3's special registers.
    D,
    /// File (extension) registers.
    R,
    /// Timer contacts.
    TimerContact,
    /// Timer coils.
    TimerCoil,
    /// Timer current values.
    TimerValue,
    /// Counter contacts.
    CounterContact,
    /// Counter coils.
    CounterCoil,
    /// Counter current values; on an FX, C200 and up are 32-bit.
    CounterValue,
    /// Current values of the 32-bit counters as an iQ-F names them (LCN);
    /// two words a point.
    LongCounterValue,
}

/// Every family, for tables and tests.
pub const FAMILIES: [Family; 15] = [
    Family::X,
    Family::Y,
    Family::M,
    Family::S,
    Family::Sm,
    Family::Sd,
    Family::D,
    Family::R,
    Family::TimerContact,
    Family::TimerCoil,
    Family::TimerValue,
    Family::CounterContact,
    Family::CounterCoil,
    Family::CounterValue,
    Family::LongCounterValue,
];

impl Family {
    /// Whether a point of the family is a bit (else a word or two).
    pub fn is_bit(self) -> bool {
        match self {
            Family::X
            | Family::Y
            | Family::M
            | Family::S
            | Family::Sm
            | Family::TimerContact
            | Family::TimerCoil
            | Family::CounterContact
            | Family::CounterCoil => true,
            Family::Sd
            | Family::D
            | Family::R
            | Family::TimerValue
            | Family::CounterValue
            | Family::LongCounterValue => false,
        }
    }

    /// The name the docs and messages use.
    pub fn name(self) -> &'static str {
        match self {
            Family::X => "X",
            Family::Y => "Y",
            Family::M => "M",
            Family::S => "S",
            Family::Sm => "SM",
            Family::Sd => "SD",
            Family::D => "D",
            Family::R => "R",
            Family::TimerContact => "TS",
            Family::TimerCoil => "TC",
            Family::TimerValue => "TN",
            Family::CounterContact => "CS",
            Family::CounterCoil => "CC",
            Family::CounterValue => "CN",
            Family::LongCounterValue => "LCN",
        }
    }

    /// Whether device numbers are octal (X and Y, as on an FX and an iQ-F).
    pub fn octal(self) -> bool {
        matches!(self, Family::X | Family::Y)
    }

    /// The 1E frame's name for the family: two characters, sent in binary
    /// as a 16-bit code (`D ` = 4420H). 1E frames name the FX3's devices
    /// only: no SM, SD, coils or LCN.
    pub fn code_1e(self) -> Option<u16> {
        let code = |name: &[u8; 2]| u16::from_be_bytes(*name);
        match self {
            Family::X => Some(code(b"X ")),
            Family::Y => Some(code(b"Y ")),
            Family::M => Some(code(b"M ")),
            Family::S => Some(code(b"S ")),
            Family::D => Some(code(b"D ")),
            Family::R => Some(code(b"R ")),
            Family::TimerContact => Some(code(b"TS")),
            Family::TimerValue => Some(code(b"TN")),
            Family::CounterContact => Some(code(b"CS")),
            Family::CounterValue => Some(code(b"CN")),
            Family::Sm | Family::Sd | Family::TimerCoil | Family::CounterCoil | Family::LongCounterValue => None,
        }
    }

    /// The 3E/4E frame's binary device code (the iQ-R subcommands send it
    /// as two bytes, the high one 00H).
    pub fn code_3e(self) -> u8 {
        match self {
            Family::X => 0x9C,
            Family::Y => 0x9D,
            Family::M => 0x90,
            Family::S => 0x98,
            Family::Sm => 0x91,
            Family::Sd => 0xA9,
            Family::D => 0xA8,
            Family::R => 0xAF,
            Family::TimerContact => 0xC1,
            Family::TimerCoil => 0xC0,
            Family::TimerValue => 0xC2,
            Family::CounterContact => 0xC4,
            Family::CounterCoil => 0xC3,
            Family::CounterValue => 0xC5,
            Family::LongCounterValue => 0x56,
        }
    }

    pub fn from_code_1e(code: u16) -> Option<Family> {
        FAMILIES.into_iter().find(|family| family.code_1e() == Some(code))
    }

    pub fn from_code_3e(code: u16) -> Option<Family> {
        FAMILIES.into_iter().find(|family| u16::from(family.code_3e()) == code)
    }

    /// A 3E/4E frame's ASCII device name: the family's name padded with `*`
    /// to two characters (`D*`, `SM`) or, in the iQ-R form, four (`D***`,
    /// `LCN*`).
    pub fn from_name_3e(name: &[u8]) -> Option<Family> {
        let end = name.iter().rposition(|&c| c != b'*').map_or(0, |last| last + 1);
        FAMILIES
            .into_iter()
            .find(|family| family.name().as_bytes() == &name[..end])
    }
}

/// One device: a family and a number (for octal families, the number's
/// value: X17 is 15).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Device {
    pub family: Family,
    pub number: u32,
}

impl std::fmt::Display for Device {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.family.octal() {
            write!(f, "{}{:o}", self.family.name(), self.number)
        } else {
            write!(f, "{}{}", self.family.name(), self.number)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_and_name_names_one_family() {
        for family in FAMILIES {
            assert_eq!(Family::from_code_3e(u16::from(family.code_3e())), Some(family));
            let short = format!("{:*<2}", family.name());
            assert_eq!(Family::from_name_3e(short.as_bytes()), Some(family), "{short}");
            let padded = format!("{:*<4}", family.name());
            assert_eq!(Family::from_name_3e(padded.as_bytes()), Some(family), "{padded}");
            if let Some(code) = family.code_1e() {
                assert_eq!(Family::from_code_1e(code), Some(family));
            }
        }
        assert_eq!(Family::D.code_1e(), Some(0x4420));
        assert_eq!(Family::TimerValue.code_1e(), Some(0x544E));
        assert_eq!(Family::from_name_3e(b"Z*"), None);
        assert_eq!(
            Device {
                family: Family::X,
                number: 15
            }
            .to_string(),
            "X17"
        );
    }
}
