//! What an operand position of an instruction accepts: its kind (how the
//! instruction uses it) and its device table (which devices may stand there).
//!
//! The device table is the "Device used" table of the seed for that
//! parameter; a device outside it is a compile error (E0003), as a vendor
//! editor refuses it.

use std::fmt;

/// How an application instruction uses one of its operands. The kind decides
/// the Rust type of the checked operand (see `program::AppOperand`), whether
/// the operand is read or written, and how many units it covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OperandKind {
    /// A value read at the instruction's width (16 or 32 bits).
    Source,
    /// A 16-bit value read whatever the instruction's width: a count, a
    /// mode, a bit position of a 16-bit instruction.
    Count,
    /// A value written at the instruction's width.
    Destination,
    /// A value read and then written at the instruction's width (NEG D).
    Modified,
    /// A value written at twice the instruction's width: two units from the
    /// device (MUL and DIV results, WSUM sums). A digit group holds only its
    /// own bits.
    DoubleDestination,
    /// The first of a run of values read at the instruction's width; how many
    /// is known only at run time (BMOV S, MEAN S).
    BlockSource,
    /// The first of a run of values written (BMOV D, FMOV D, DIS D).
    BlockDestination,
    /// One bit written (BON D).
    BitDestination,
    /// The first of three consecutive bits written (CMP, ZCP results).
    BitTriple,
    /// The first of a run of bits or the first of a run of words, read
    /// (ENCO S): a bit device is one bit per unit, a word device 16.
    ElementSource,
    /// The same, written (DECO D).
    ElementDestination,
    /// One end of a device range that is written (ZRST d1, d2; ZSET d1, d2):
    /// a bit, a word, a timer or a counter.
    RangeEnd,
    /// A digit group read bit by bit (PRUN S).
    DigitSource,
    /// One end of a run of words whose values are read (MAX S1, S2): the
    /// device, not its value, is the operand.
    TableEnd,
    /// The first of a run of words whose bytes are read (BCC, CRC); a digit
    /// group must be a whole word (K4).
    ByteSource,
    /// A timer the instruction drives (ANS S).
    Timer,
    /// A digit group written bit by bit (PRUN D).
    DigitDestination,
}

impl OperandKind {
    /// The instruction reads the operand's value (before writing it, for
    /// `Modified`). Out of range, it records 4085H.
    pub fn is_read(self) -> bool {
        match self {
            OperandKind::Source
            | OperandKind::Count
            | OperandKind::Modified
            | OperandKind::BlockSource
            | OperandKind::ElementSource
            | OperandKind::DigitSource
            | OperandKind::TableEnd
            | OperandKind::ByteSource
            | OperandKind::Timer => true,
            OperandKind::Destination
            | OperandKind::DoubleDestination
            | OperandKind::BlockDestination
            | OperandKind::BitDestination
            | OperandKind::BitTriple
            | OperandKind::ElementDestination
            | OperandKind::RangeEnd
            | OperandKind::DigitDestination => false,
        }
    }

    /// The instruction writes bit devices through this operand.
    pub fn writes_bits(self) -> bool {
        match self {
            OperandKind::BitDestination
            | OperandKind::BitTriple
            | OperandKind::ElementDestination
            | OperandKind::RangeEnd
            | OperandKind::DigitDestination => true,
            OperandKind::Source
            | OperandKind::Count
            | OperandKind::Destination
            | OperandKind::Modified
            | OperandKind::DoubleDestination
            | OperandKind::BlockSource
            | OperandKind::BlockDestination
            | OperandKind::ElementSource
            | OperandKind::DigitSource
            | OperandKind::TableEnd
            | OperandKind::ByteSource
            | OperandKind::Timer => false,
        }
    }

    pub const ALL: [OperandKind; 17] = [
        OperandKind::Source,
        OperandKind::Count,
        OperandKind::Destination,
        OperandKind::Modified,
        OperandKind::DoubleDestination,
        OperandKind::BlockSource,
        OperandKind::BlockDestination,
        OperandKind::BitDestination,
        OperandKind::BitTriple,
        OperandKind::ElementSource,
        OperandKind::ElementDestination,
        OperandKind::RangeEnd,
        OperandKind::DigitSource,
        OperandKind::DigitDestination,
        OperandKind::TableEnd,
        OperandKind::ByteSource,
        OperandKind::Timer,
    ];
}

/// The classes of device a device table names, as the seed's tables do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum DeviceClass {
    X,
    Y,
    M,
    S,
    Sm,
    /// A bit of a data register, `D0.F`.
    WordBit,
    KnX,
    KnY,
    KnM,
    KnS,
    /// Timer current values (T, TN) — or timers as a whole for ZRST.
    T,
    /// 16-bit counter current values (C, CN) — or counters for ZRST.
    C,
    D,
    R,
    Sd,
    /// 32-bit counter current values C200-C255 (the seed's LC and HSC).
    WideCounter,
    /// K and H constants.
    Constant,
}

impl DeviceClass {
    pub const ALL: [DeviceClass; 17] = [
        DeviceClass::X,
        DeviceClass::Y,
        DeviceClass::M,
        DeviceClass::S,
        DeviceClass::Sm,
        DeviceClass::WordBit,
        DeviceClass::KnX,
        DeviceClass::KnY,
        DeviceClass::KnM,
        DeviceClass::KnS,
        DeviceClass::T,
        DeviceClass::C,
        DeviceClass::D,
        DeviceClass::R,
        DeviceClass::Sd,
        DeviceClass::WideCounter,
        DeviceClass::Constant,
    ];

    /// How the seed's tables spell the class.
    pub fn name(self) -> &'static str {
        match self {
            DeviceClass::X => "X",
            DeviceClass::Y => "Y",
            DeviceClass::M => "M",
            DeviceClass::S => "S",
            DeviceClass::Sm => "SM",
            DeviceClass::WordBit => "D.b",
            DeviceClass::KnX => "KnX",
            DeviceClass::KnY => "KnY",
            DeviceClass::KnM => "KnM",
            DeviceClass::KnS => "KnS",
            DeviceClass::T => "T",
            DeviceClass::C => "C",
            DeviceClass::D => "D",
            DeviceClass::R => "R",
            DeviceClass::Sd => "SD",
            DeviceClass::WideCounter => "C200-C255",
            DeviceClass::Constant => "K/H",
        }
    }
}

/// A device table: a set of device classes.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Devices(u32);

impl Devices {
    pub const NONE: Devices = Devices(0);

    pub const fn of(class: DeviceClass) -> Devices {
        Devices(1 << class as u8)
    }

    pub const fn with(self, other: Devices) -> Devices {
        Devices(self.0 | other.0)
    }

    pub const fn contains(self, class: DeviceClass) -> bool {
        self.0 & (1 << class as u8) != 0
    }

    pub fn classes(self) -> impl Iterator<Item = DeviceClass> {
        DeviceClass::ALL.into_iter().filter(move |&c| self.contains(c))
    }
}

impl fmt::Debug for Devices {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_set().entries(self.classes().map(DeviceClass::name)).finish()
    }
}

impl fmt::Display for Devices {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.classes().map(DeviceClass::name).collect();
        f.write_str(&names.join(" "))
    }
}

/// Device tables used by the declarations, named the way the seed groups its
/// columns.
pub mod tables {
    use super::{DeviceClass as C, Devices};

    const fn of(class: C) -> Devices {
        Devices::of(class)
    }

    /// K and H.
    pub const CONSTANT: Devices = of(C::Constant);
    /// D, R, SD.
    pub const REGISTERS: Devices = of(C::D).with(of(C::R)).with(of(C::Sd));
    /// T, C, D, R, SD (and the 32-bit counters in 32-bit instructions).
    pub const WORDS: Devices = REGISTERS.with(of(C::T)).with(of(C::C)).with(of(C::WideCounter));
    /// Digit groups that can be written: KnY, KnM, KnS.
    pub const WRITABLE_DIGITS: Devices = of(C::KnY).with(of(C::KnM)).with(of(C::KnS));
    /// Every digit group.
    pub const DIGITS: Devices = WRITABLE_DIGITS.with(of(C::KnX));
    /// Everything a word value can be read from, constants included.
    pub const ANY_VALUE: Devices = DIGITS.with(WORDS).with(CONSTANT);
    /// Every word device (no constants).
    pub const ANY_WORD: Devices = DIGITS.with(WORDS);
    /// Everything a word value can be written to.
    pub const WRITABLE_WORD: Devices = WRITABLE_DIGITS.with(WORDS);
    /// Bits a program can write: Y, M, S, SM and bits of data registers.
    pub const WRITABLE_BITS: Devices = of(C::Y)
        .with(of(C::M))
        .with(of(C::S))
        .with(of(C::Sm))
        .with(of(C::WordBit));
    /// Bits a program can read.
    pub const ANY_BIT: Devices = WRITABLE_BITS.with(of(C::X));
    /// Y, M, S: the results of CMP and ZCP.
    pub const RESULT_BITS: Devices = of(C::Y).with(of(C::M)).with(of(C::S));
    /// Constants, registers: counts and modes.
    pub const COUNT: Devices = CONSTANT.with(REGISTERS);
}

#[cfg(test)]
mod tests {
    use super::tables::*;
    use super::*;

    #[test]
    fn tables_are_sets() {
        assert!(ANY_VALUE.contains(DeviceClass::KnX) && ANY_VALUE.contains(DeviceClass::Constant));
        assert!(!WRITABLE_WORD.contains(DeviceClass::KnX));
        assert!(!WRITABLE_WORD.contains(DeviceClass::Constant));
        assert_eq!(REGISTERS.to_string(), "D R SD");
        assert!(!Devices::NONE.contains(DeviceClass::X));
    }
}
