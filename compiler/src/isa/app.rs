//! Application instructions: one declaration each, from which everything
//! else that lists them is derived — the `AppOp` enum, the typed operands of
//! the checked program (`AppArgs`), the mnemonic table with the D (32-bit)
//! and P (pulse) forms, the documentation checks and the differential
//! test's vocabulary.
//!
//! A declaration reads
//!
//! ```text
//! Variant: "NAME" "DNAME" pulse Family (operand: Kind(device table), ...)
//!     reads [special bits] writes [special bits] "summary";
//! ```
//!
//! with `_` where there is no 32-bit form and `no_pulse` where there is no P
//! form. Operands are in the order of the seed's instruction format line.
//! The semantics are written twice on purpose: once in `interp::app` (the
//! specification) and once in `lower::app`, in files named after the family.

use super::operand::{tables::*, Devices, OperandKind};
use crate::program::{AppOperand, BitRef, Element, WordRef};
use ladder_runtime::special::{self, SpecialBit};

/// Groups instructions in the language reference and the engines' kernel
/// files (`interp/app/<family>.rs`, `lower/app/<family>.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// MOV, BMOV, FMOV and other transfers.
    Move,
    /// ADD, SUB, MUL, DIV, INC, DEC and other arithmetic.
    Arithmetic,
    /// CMP, ZCP.
    Compare,
}

impl Family {
    pub fn title(self) -> &'static str {
        match self {
            Family::Move => "Transfers",
            Family::Arithmetic => "Arithmetic",
            Family::Compare => "Comparisons",
        }
    }
}

/// One operand position of an instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OperandDecl {
    /// The seed's name in lower case: `s1`, `d`, `n`.
    pub name: &'static str,
    pub kind: OperandKind,
    /// The devices the position accepts.
    pub devices: Devices,
}

/// Everything the declaration says about an instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AppSpec {
    pub op: AppOp,
    /// The 16-bit mnemonic.
    pub name: &'static str,
    /// The 32-bit mnemonic, if there is a 32-bit form.
    pub wide_name: Option<&'static str>,
    /// There are P (pulse) forms: `NAMEP`, `DNAMEP`.
    pub pulse: bool,
    pub family: Family,
    pub summary: &'static str,
    pub operands: &'static [OperandDecl],
    /// Special relays the instruction reads (modes).
    pub reads: &'static [SpecialBit],
    /// Special relays every execution writes (flags): ON when the condition
    /// holds, OFF otherwise.
    pub writes: &'static [SpecialBit],
}

impl AppSpec {
    /// Every mnemonic of the instruction: 16/32-bit, plain/pulse.
    pub fn mnemonics(&self) -> Vec<(String, ladder_runtime::Width, bool)> {
        use ladder_runtime::Width;
        let mut names = vec![(self.name.to_string(), Width::Single, false)];
        if let Some(wide) = self.wide_name {
            names.push((wide.to_string(), Width::Double, false));
        }
        if self.pulse {
            names.push((format!("{}P", self.name), Width::Single, true));
            if let Some(wide) = self.wide_name {
                names.push((format!("{wide}P"), Width::Double, true));
            }
        }
        names
    }

    /// Writes bit devices through some operand (not only words).
    pub fn writes_bits(&self) -> bool {
        self.operands.iter().any(|o| o.kind.writes_bits())
    }

    /// The format line as the reference shows it: `MOV S D`.
    pub fn format(&self) -> String {
        let mut text = self.name.to_string();
        for operand in self.operands {
            text.push(' ');
            text.push_str(&operand.name.to_ascii_uppercase());
        }
        text
    }
}

/// Converts a checked operand to the typed field of `AppArgs`; `None` when
/// the resolver produced the wrong shape (it never does for a declared kind).
pub trait FromOperand: Sized {
    fn from_operand(operand: AppOperand) -> Option<Self>;
}

impl FromOperand for WordRef {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Word(word) => Some(word),
            AppOperand::Bit(_) | AppOperand::Element(_) => None,
        }
    }
}

impl FromOperand for BitRef {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Bit(bit) => Some(bit),
            AppOperand::Word(_) | AppOperand::Element(_) => None,
        }
    }
}

impl FromOperand for Element {
    fn from_operand(operand: AppOperand) -> Option<Self> {
        match operand {
            AppOperand::Element(element) => Some(element),
            AppOperand::Word(_) | AppOperand::Bit(_) => None,
        }
    }
}

/// What the checker implements to resolve the operands of an instruction,
/// in declaration order. A `None` has been reported already.
pub trait ResolveOperand {
    fn resolve(&mut self, name: &'static str, kind: OperandKind, devices: Devices) -> Option<AppOperand>;
}

/// The Rust type of a checked operand of each kind.
macro_rules! operand_type {
    (Source) => {
        WordRef
    };
    (Count) => {
        WordRef
    };
    (Destination) => {
        WordRef
    };
    (Modified) => {
        WordRef
    };
    (DoubleDestination) => {
        WordRef
    };
    (BlockSource) => {
        WordRef
    };
    (BlockDestination) => {
        WordRef
    };
    (BitDestination) => {
        BitRef
    };
    (BitTriple) => {
        BitRef
    };
    (ElementSource) => {
        Element
    };
    (ElementDestination) => {
        Element
    };
    (RangeEnd) => {
        Element
    };
}

macro_rules! wide_name {
    (_) => {
        None
    };
    ($name:literal) => {
        Some($name)
    };
}

macro_rules! pulse_form {
    (pulse) => {
        true
    };
    (no_pulse) => {
        false
    };
}

macro_rules! app_instructions {
    ($(
        $(#[doc = $doc:literal])*
        $variant:ident: $name:literal $wide:tt $pulse:ident $family:ident
            ($($field:ident: $kind:ident($devices:expr)),* $(,)?)
            reads [$($read:ident),* $(,)?] writes [$($flag:ident),* $(,)?]
            $summary:literal;
    )*) => {
        /// Every application instruction (its 16/32-bit and pulse forms are
        /// properties of the mnemonic, not of the operation).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum AppOp {
            $( $(#[doc = $doc])* $variant, )*
        }

        impl AppOp {
            pub const ALL: &'static [AppOp] = &[$(AppOp::$variant),*];

            pub fn spec(self) -> &'static AppSpec {
                match self {
                    $(AppOp::$variant => {
                        const SPEC: AppSpec = AppSpec {
                            op: AppOp::$variant,
                            name: $name,
                            wide_name: wide_name!($wide),
                            pulse: pulse_form!($pulse),
                            family: Family::$family,
                            summary: $summary,
                            operands: &[$(OperandDecl {
                                name: stringify!($field),
                                kind: OperandKind::$kind,
                                devices: $devices,
                            }),*],
                            reads: &[$(special::$read),*],
                            writes: &[$(special::$flag),*],
                        };
                        &SPEC
                    })*
                }
            }
        }

        /// The checked operands of an application instruction, by name, with
        /// the type their kind gives them.
        #[derive(Clone, Debug, PartialEq, Eq)]
        pub enum AppArgs {
            $( $variant { $($field: operand_type!($kind)),* }, )*
        }

        impl AppArgs {
            pub fn op(&self) -> AppOp {
                match self {
                    $(AppArgs::$variant { .. } => AppOp::$variant,)*
                }
            }

            /// The operands in declaration order (see `spec().operands`).
            pub fn operands(&self) -> Vec<AppOperand> {
                match self {
                    $(AppArgs::$variant { $($field),* } => vec![$(AppOperand::from(*$field)),*],)*
                }
            }

            /// Resolves every operand of `op` in declaration order (all of
            /// them, so that each bad operand is reported), then builds the
            /// typed operands if none failed.
            pub fn resolve(op: AppOp, resolver: &mut impl ResolveOperand) -> Option<AppArgs> {
                match op {
                    $(AppOp::$variant => {
                        $(
                            let $field = resolver
                                .resolve(stringify!($field), OperandKind::$kind, $devices)
                                .and_then(<operand_type!($kind) as FromOperand>::from_operand);
                        )*
                        Some(AppArgs::$variant { $($field: $field?),* })
                    })*
                }
            }
        }
    };
}

/// Word destinations of multiple units: registers and digit groups.
const MULTI_WORD_DESTINATION: Devices = REGISTERS.with(WRITABLE_DIGITS);

app_instructions! {
    /// MOV S D: D = S.
    Mov: "MOV" "DMOV" pulse Move
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "copies S to D";
    /// BMOV S D n: n words from S to D; overlapping blocks move as a whole.
    BlockMov: "BMOV" _ pulse Move
        (s: BlockSource(ANY_WORD), d: BlockDestination(WRITABLE_WORD), n: Count(COUNT))
        reads [] writes []
        "copies n words from S to D";
    /// FMOV S D n: S into n units from D.
    FillMov: "FMOV" "DFMOV" pulse Move
        (s: Source(ANY_VALUE), d: BlockDestination(WRITABLE_WORD), n: Count(COUNT))
        reads [] writes []
        "writes S into n units from D";
    /// ADD S1 S2 D: D = S1 + S2, wrapping.
    Add: "ADD" "DADD" pulse Arithmetic
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 + S2";
    /// SUB S1 S2 D: D = S1 - S2, wrapping.
    Sub: "SUB" "DSUB" pulse Arithmetic
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 - S2";
    /// MUL S1 S2 D: the double-width product to D.
    Mul: "MUL" "DMUL" pulse Arithmetic
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: DoubleDestination(MULTI_WORD_DESTINATION))
        reads [] writes []
        "the double-width product S1 × S2 to D";
    /// DIV S1 S2 D: quotient to D, remainder to the next unit.
    Div: "DIV" "DDIV" pulse Arithmetic
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: DoubleDestination(MULTI_WORD_DESTINATION))
        reads [] writes []
        "quotient of S1 / S2 to D, remainder to the next unit";
    /// INC D: D + 1, wrapping.
    Inc: "INC" "DINC" pulse Arithmetic
        (d: Modified(WRITABLE_WORD))
        reads [] writes []
        "D = D + 1";
    /// DEC D: D - 1, wrapping.
    Dec: "DEC" "DDEC" pulse Arithmetic
        (d: Modified(WRITABLE_WORD))
        reads [] writes []
        "D = D - 1";
    /// CMP S1 S2 D: D, D+1, D+2 = S1>S2, S1=S2, S1<S2.
    Cmp: "CMP" "DCMP" pulse Compare
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = S1 > S2, S1 = S2, S1 < S2";
    /// ZCP S1 S2 S D: D, D+1, D+2 = S<S1, S1<=S<=S2, S>S2.
    ZoneCmp: "ZCP" "DZCP" pulse Compare
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), s: Source(ANY_VALUE), d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = S < S1, S1 ≤ S ≤ S2, S > S2";
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declarations_are_consistent() {
        for &op in AppOp::ALL {
            let spec = op.spec();
            assert_eq!(spec.op, op);
            assert!(!spec.summary.is_empty(), "{op:?}");
            for operand in spec.operands {
                assert_ne!(operand.devices, Devices::NONE, "{op:?} {}", operand.name);
                // Destinations never take constants.
                if !operand.kind.is_read() {
                    assert!(
                        !operand.devices.contains(super::super::operand::DeviceClass::Constant),
                        "{op:?} {}",
                        operand.name
                    );
                }
            }
        }
    }
}
