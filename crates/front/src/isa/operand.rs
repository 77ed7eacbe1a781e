//! What an operand position of an instruction accepts: its kind (how the
//! instruction uses it, and the typed operand it gives: `FromOperand`) and
//! its device table (which devices may stand there).
//!
//! The device table is the "Device used" table of the seed for that
//! parameter; a device outside it is a compile error (E0003), as a vendor
//! editor refuses it.

use crate::program::{Address, AppOperand, BitRef, CounterRef, DigitGroup, Element, RangeEnd, WordRef};
use std::fmt;

/// Converts a checked operand to the typed field of `AppArgs`; `None` when
/// the resolver produced the wrong shape (it never does for a declared kind).
pub trait FromOperand: Sized {
    fn from_operand(operand: AppOperand) -> Option<Self>;
}

impl FromOperand for WordRef {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Word(word) => Some(word),
            AppOperand::Bit(_)
            | AppOperand::Element(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Digits(_)
            | AppOperand::Timer(_)
            | AppOperand::Counter(_) => None,
        }
    }
}

impl FromOperand for DigitGroup {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Digits(group) => Some(group),
            AppOperand::Word(_)
            | AppOperand::Bit(_)
            | AppOperand::Element(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Timer(_)
            | AppOperand::Counter(_) => None,
        }
    }
}

impl FromOperand for BitRef {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Bit(bit) => Some(bit),
            AppOperand::Word(_)
            | AppOperand::Element(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Digits(_)
            | AppOperand::Timer(_)
            | AppOperand::Counter(_) => None,
        }
    }
}

impl FromOperand for Element {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Element(element) => Some(element),
            AppOperand::Word(_)
            | AppOperand::Bit(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Digits(_)
            | AppOperand::Timer(_)
            | AppOperand::Counter(_) => None,
        }
    }
}

impl FromOperand for Address {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Timer(timer) => Some(timer),
            AppOperand::Counter(_)
            | AppOperand::Word(_)
            | AppOperand::Bit(_)
            | AppOperand::Element(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Digits(_) => None,
        }
    }
}

impl FromOperand for RangeEnd {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::RangeEnd(end) => Some(end),
            AppOperand::Word(_)
            | AppOperand::Bit(_)
            | AppOperand::Element(_)
            | AppOperand::Digits(_)
            | AppOperand::Timer(_)
            | AppOperand::Counter(_) => None,
        }
    }
}

impl FromOperand for CounterRef {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Counter(counter) => Some(counter),
            AppOperand::Word(_)
            | AppOperand::Bit(_)
            | AppOperand::Element(_)
            | AppOperand::RangeEnd(_)
            | AppOperand::Digits(_)
            | AppOperand::Timer(_) => None,
        }
    }
}

/// Declares the operand kinds: each with the Rust type its checked operand
/// has in `AppArgs`, whether the instruction reads it (out of range: 4085H,
/// else 4086H) and whether it writes bit devices through it.
macro_rules! operand_kinds {
    ($(
        $(#[doc = $doc:literal])*
        $kind:ident => $ty:ident, read: $read:literal, writes_bits: $bits:literal;
    )*) => {
        /// How an application instruction uses one of its operands: the kind
        /// decides the Rust type of the checked operand, whether it is read or
        /// written, and how many units it covers.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum OperandKind {
            $( $(#[doc = $doc])* $kind, )*
        }

        impl OperandKind {
            pub const ALL: &'static [OperandKind] = &[$(OperandKind::$kind),*];

            /// The instruction reads the operand's value (or address) first;
            /// out of range, it records 4085H.
            pub fn is_read(self) -> bool {
                match self {
                    $(OperandKind::$kind => $read,)*
                }
            }

            /// The instruction writes bit devices through this operand.
            pub fn writes_bits(self) -> bool {
                match self {
                    $(OperandKind::$kind => $bits,)*
                }
            }
        }

        /// The Rust type of a checked operand of each kind (for the
        /// instruction declarations).
        macro_rules! operand_type {
            $( ($kind) => { $ty }; )*
        }
        pub(crate) use operand_type;

        /// Whether a checked operand has the type its kind gives it in
        /// `AppArgs` (the checker asserts it for every operand it resolves).
        pub fn fits(kind: OperandKind, operand: AppOperand) -> bool {
            match kind {
                $(OperandKind::$kind => <$ty as FromOperand>::from_operand(operand).is_some(),)*
            }
        }
    };
}

operand_kinds! {
    /// A value read at the instruction's width (16 or 32 bits).
    Source => WordRef, read: true, writes_bits: false;
    /// A 16-bit value read whatever the instruction's width: a count, a
    /// mode, a bit position of a 16-bit instruction.
    Count => WordRef, read: true, writes_bits: false;
    /// A value written at the instruction's width.
    Destination => WordRef, read: false, writes_bits: false;
    /// A value read and then written at the instruction's width (NEG D).
    Modified => WordRef, read: true, writes_bits: false;
    /// A value written at twice the instruction's width: two units from the
    /// device (MUL and DIV results, WSUM sums). A digit group holds only its
    /// own bits.
    DoubleDestination => WordRef, read: false, writes_bits: false;
    /// The first of a run of values read at the instruction's width; how many
    /// is known only at run time (BMOV S, MEAN S).
    BlockSource => WordRef, read: true, writes_bits: false;
    /// The first of a run of values written (BMOV D, FMOV D, DIS D).
    BlockDestination => WordRef, read: false, writes_bits: false;
    /// One bit written (BON D).
    BitDestination => BitRef, read: false, writes_bits: true;
    /// The first of a run of bits read (SFTR S).
    BitSource => BitRef, read: true, writes_bits: false;
    /// One bit, or the first of a run of bits, read and then written (ALT D,
    /// SFTR D).
    BitModified => BitRef, read: true, writes_bits: true;
    /// The first of three consecutive bits written (CMP, ZCP results).
    BitTriple => BitRef, read: false, writes_bits: true;
    /// The first of a run of bits, or a word, read (ENCO S): a bit device is
    /// one bit per unit, a word 16 bits.
    ElementSource => Element, read: true, writes_bits: false;
    /// The same, written (DECO D).
    ElementDestination => Element, read: false, writes_bits: true;
    /// One end of a device range that is written (ZRST d1, d2; ZSET d1, d2):
    /// a bit, a word, a timer or a counter.
    RangeEnd => RangeEnd, read: false, writes_bits: true;
    /// A digit group read bit by bit (PRUN S).
    DigitSource => DigitGroup, read: true, writes_bits: false;
    /// A digit group written bit by bit (PRUN D).
    DigitDestination => DigitGroup, read: false, writes_bits: true;
    /// One end of a run of words whose values are read (MAX S1, S2): the
    /// device, not its value, is the operand.
    TableEnd => WordRef, read: true, writes_bits: false;
    /// The first of a run of words whose bytes are read (BCC, CRC); a digit
    /// group must be a whole word (K4).
    ByteSource => WordRef, read: true, writes_bits: false;
    /// A timer the instruction drives (ANS S).
    Timer => Address, read: true, writes_bits: false;
    /// A real number read (IEEE-754 binary32 in a word pair, whatever the
    /// instruction's width): K and H constants are converted, E constants
    /// taken as they are.
    RealSource => WordRef, read: true, writes_bits: false;
    /// A real number written (a word pair).
    RealDestination => WordRef, read: false, writes_bits: false;
    /// A real number read and then written (DENEG D).
    RealModified => WordRef, read: true, writes_bits: false;
    /// A high-speed counter C235-C255 by number (DHSCS S2).
    HighSpeedCounter => CounterRef, read: true, writes_bits: false;
    /// A 16-bit counter by number that the instruction drives with the next
    /// one (INCD S2: C and C+1).
    CounterPair => CounterRef, read: true, writes_bits: false;
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
    /// E constants (real numbers).
    Real,
    /// Buffer memory of a special-function unit, `Un\Gm` (FX3U takes it
    /// wherever it takes D).
    Buffer,
}

impl DeviceClass {
    pub const ALL: [DeviceClass; 19] = [
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
        DeviceClass::Real,
        DeviceClass::Buffer,
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
            DeviceClass::Real => "E",
            DeviceClass::Buffer => "U\\G",
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
    /// D, R, SD, and the buffer memory of units (`U0\G10`).
    pub const REGISTERS: Devices = of(C::D).with(of(C::R)).with(of(C::Sd)).with(of(C::Buffer));
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
    /// E constants.
    pub const REAL: Devices = of(C::Real);
    /// Where real numbers are read from: registers and E constants.
    pub const REAL_VALUE: Devices = REGISTERS.with(REAL);
    /// Real numbers from registers or any constant (K and H converted).
    pub const ANY_REAL: Devices = REAL_VALUE.with(CONSTANT);
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
        assert_eq!(REGISTERS.to_string(), "D R SD U\\G");
        assert!(!Devices::NONE.contains(DeviceClass::X));
    }
}
