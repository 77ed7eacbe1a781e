//! How far an operand reaches from its device, where its kind alone does
//! not say: BMOV's source and destination reach n units, TRD's destination
//! seven words, SFTL's destination n1 bits.
//!
//! Declared beside the operand in `app.rs` (`d: BlockDestination(...) [n
//! units]`) and read by the compact image's footprint, which then holds the
//! run instead of the operand's whole area. The length is the largest the
//! instruction can use in any mode (CRC's source is n words: one byte per
//! word under M8161), never less: a device the image lacks reads 0.

/// What an operand's run is counted in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReachUnit {
    /// Units of the instruction's width (a word, or a pair of words for the
    /// 32-bit form; a digit group; a 32-bit counter).
    Units,
    /// 16-bit words whatever the instruction's width (a digit group or a
    /// 32-bit counter still counts as one).
    Words,
    /// Bit devices (for a word operand of a bit-or-word position: the word).
    Bits,
}

/// How many units an operand's run holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReachLength {
    Fixed(u32),
    /// The value of a constant count operand, by name.
    Count(&'static str),
    /// A factor times a constant count operand.
    Scaled(u32, &'static str),
    /// The product of two constant count operands (a table's rows and columns).
    Product(&'static str, &'static str),
    /// Two to the power of a constant count operand (ENCO's and DECO's bits).
    PowerOfTwo(&'static str),
}

/// An operand's declared run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reach {
    pub length: ReachLength,
    pub unit: ReachUnit,
}

impl Reach {
    /// The count operands the length reads.
    pub fn counts(self) -> Vec<&'static str> {
        match self.length {
            ReachLength::Fixed(_) => vec![],
            ReachLength::Count(name) | ReachLength::Scaled(_, name) | ReachLength::PowerOfTwo(name) => vec![name],
            ReachLength::Product(rows, columns) => vec![rows, columns],
        }
    }

    /// The run's length when every count it reads is known (`count` gives
    /// an operand's constant value, `None` for a device or an unknown
    /// name); `None` when one is not. A negative count makes the
    /// instruction fail before it touches anything, so its run is 0 long.
    pub fn length(self, count: impl Fn(&str) -> Option<i64>) -> Option<u32> {
        let value = |name: &str| count(name).map(|v| u32::try_from(v.max(0)).unwrap_or(u32::MAX));
        Some(match self.length {
            ReachLength::Fixed(units) => units,
            ReachLength::Count(name) => value(name)?,
            ReachLength::Scaled(factor, name) => value(name)?.saturating_mul(factor),
            ReachLength::Product(rows, columns) => value(rows)?.saturating_mul(value(columns)?),
            ReachLength::PowerOfTwo(name) => 1u32.checked_shl(value(name)?).unwrap_or(u32::MAX),
        })
    }
}

/// `[n units]`, `[7 words]`, `[2 * n units]`, `[n1 * n2 units]`,
/// `[2 ^ n bits]`, or nothing.
macro_rules! reach {
    () => {
        None
    };
    ($units:literal $unit:ident) => {
        Some($crate::isa::reach::Reach {
            length: $crate::isa::reach::ReachLength::Fixed($units),
            unit: reach_unit!($unit),
        })
    };
    ($factor:literal * $count:ident $unit:ident) => {
        Some($crate::isa::reach::Reach {
            length: $crate::isa::reach::ReachLength::Scaled($factor, stringify!($count)),
            unit: reach_unit!($unit),
        })
    };
    (2 ^ $count:ident $unit:ident) => {
        Some($crate::isa::reach::Reach {
            length: $crate::isa::reach::ReachLength::PowerOfTwo(stringify!($count)),
            unit: reach_unit!($unit),
        })
    };
    ($rows:ident * $columns:ident $unit:ident) => {
        Some($crate::isa::reach::Reach {
            length: $crate::isa::reach::ReachLength::Product(stringify!($rows), stringify!($columns)),
            unit: reach_unit!($unit),
        })
    };
    ($count:ident $unit:ident) => {
        Some($crate::isa::reach::Reach {
            length: $crate::isa::reach::ReachLength::Count(stringify!($count)),
            unit: reach_unit!($unit),
        })
    };
}

macro_rules! reach_unit {
    (units) => {
        $crate::isa::reach::ReachUnit::Units
    };
    (words) => {
        $crate::isa::reach::ReachUnit::Words
    };
    (word) => {
        $crate::isa::reach::ReachUnit::Words
    };
    (bit) => {
        $crate::isa::reach::ReachUnit::Bits
    };
    (bits) => {
        $crate::isa::reach::ReachUnit::Bits
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_from_counts() {
        let count = |name: &str| match name {
            "n" => Some(10),
            "n1" => Some(3),
            "n2" => Some(4),
            "negative" => Some(-5),
            "huge" => Some(1 << 40),
            _ => None,
        };
        let length = |length| {
            Reach {
                length,
                unit: ReachUnit::Words,
            }
            .length(count)
        };
        assert_eq!(length(ReachLength::Fixed(7)), Some(7));
        assert_eq!(length(ReachLength::Count("n")), Some(10));
        assert_eq!(length(ReachLength::Scaled(2, "n")), Some(20));
        assert_eq!(length(ReachLength::Product("n1", "n2")), Some(12));
        assert_eq!(length(ReachLength::PowerOfTwo("n1")), Some(8));
        assert_eq!(length(ReachLength::Count("negative")), Some(0));
        assert_eq!(length(ReachLength::Count("huge")), Some(u32::MAX));
        assert_eq!(length(ReachLength::PowerOfTwo("n")), Some(1024));
        assert_eq!(length(ReachLength::PowerOfTwo("huge")), Some(u32::MAX));
        assert_eq!(length(ReachLength::Count("register")), None);
        assert_eq!(length(ReachLength::Product("n1", "register")), None);
    }

    #[test]
    fn the_macro_reads_every_form() {
        let unit = ReachUnit::Units;
        assert_eq!(reach!(), None::<Reach>);
        assert_eq!(reach!(3 words).map(|r| r.length), Some(ReachLength::Fixed(3)));
        assert_eq!(reach!(n bits).map(|r| r.unit), Some(ReachUnit::Bits));
        assert_eq!(
            reach!(2 * n units),
            Some(Reach {
                length: ReachLength::Scaled(2, "n"),
                unit
            })
        );
        assert_eq!(
            reach!(n1 * n2 units).map(|r| r.length),
            Some(ReachLength::Product("n1", "n2"))
        );
        assert_eq!(reach!(2 ^ n bits).map(|r| r.length), Some(ReachLength::PowerOfTwo("n")));
        assert_eq!(reach!(n units).map(|r| r.length), Some(ReachLength::Count("n")));
    }
}
