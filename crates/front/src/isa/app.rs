//! Application instructions: one declaration each, from which everything
//! else that lists them is derived — the `AppOp` enum, the typed operands of
//! the checked program (`AppArgs`), the mnemonic table with the D (32-bit)
//! and P (pulse) forms, the documentation checks and the differential
//! test's vocabulary.
//!
//! A declaration reads
//!
//! ```text
//! Variant: "NAME" "DNAME" pulse Family on (operand: Kind(device table), ...)
//!     reads [special bits] writes [special bits] "summary";
//! ```
//!
//! with `_` where there is no 32-bit form, `no_pulse` where there is no P
//! form, and `always` (or `job`) instead of `on` for instructions that run
//! every scan with their rung's power (see `Runs`). Operands are in the order of the seed's instruction format line.
//! An operand whose run its kind does not bound says how far it reaches
//! after its device table: `s: BlockSource(ANY_WORD) [n units]`, `d:
//! BlockDestination(REGISTERS) [7 words]` (see `reach`); the compact image
//! holds that run instead of the operand's whole area.
//! The semantics are written twice on purpose: once in `interp::app` (the
//! specification) and once in `lower::app`, in files named after the family.

pub use super::operand::fits;
use super::operand::{operand_type, tables::*, DeviceClass, Devices, FromOperand, OperandKind};
use super::reach::Reach;
use crate::program::{Address, AppOperand, BitRef, CounterRef, DigitGroup, Element, RangeEnd, WordRef};
use ladder_runtime::special::{self, SpecialBit};

/// Groups instructions in the language reference and the engines' kernel
/// files (`interp/app/<family>.rs`, `lower/app/<family>.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// MOV, BMOV, FMOV, PRUN, XCH.
    Move,
    /// ADD, SUB, MUL, DIV, INC, DEC, NEG, SQR.
    Arithmetic,
    /// WAND, WOR, WXOR, CML, BON, SUM, ALT.
    Logic,
    /// SWAP, ENCO, DECO, BTOW, WTOB, DIS, UNI, BCD, BIN.
    Convert,
    /// CMP, ZCP.
    Compare,
    /// ZRST, ZSET.
    Zone,
    /// MAX, MIN, MEAN, WSUM, SORT, SORT2.
    Table,
    /// BCC, CRC.
    Check,
    /// ANS, ANR.
    Alarm,
    /// ROR, ROL, SFTR, SFTL.
    Shift,
    /// DEADD, DECMP, FLT, INT, DSIN, ... (real numbers).
    Float,
    /// TRD, TWR, TCMP, TZCP, TADD, TSUB, HTOS, STOH, HOUR.
    Clock,
    /// SER, ABSD, INCD, TTMR, STMR, RAMP, SEGD, SEGL, ASCI, HEX, CCD.
    Handy,
    /// DHSCS, DHSCR, DHSZ, SPD, PLSY, PLSR, PLSV, DRVI, DRVA, ZRN, DSZR, PWM.
    HighSpeed,
    /// FROM, TO.
    Module,
    /// PID.
    Control,
}

impl Family {
    pub const ALL: [Family; 16] = [
        Family::Move,
        Family::Arithmetic,
        Family::Logic,
        Family::Shift,
        Family::Convert,
        Family::Compare,
        Family::Table,
        Family::Zone,
        Family::Check,
        Family::Alarm,
        Family::Float,
        Family::Clock,
        Family::Handy,
        Family::HighSpeed,
        Family::Module,
        Family::Control,
    ];

    pub fn title(self) -> &'static str {
        match self {
            Family::Move => "Transfers",
            Family::Arithmetic => "Arithmetic",
            Family::Logic => "Logic and bits",
            Family::Convert => "Conversions",
            Family::Compare => "Comparisons",
            Family::Zone => "Zones",
            Family::Table => "Tables and sorting",
            Family::Check => "Check codes",
            Family::Alarm => "Alarms",
            Family::Shift => "Rotation and shift",
            Family::Float => "Floating point",
            Family::Clock => "Clock",
            Family::Handy => "Handy and display instructions",
            Family::HighSpeed => "High-speed counters and pulse outputs",
            Family::Module => "Special-function modules",
            Family::Control => "Process control",
        }
    }
}

/// When an instruction runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Runs {
    /// While its rung is ON (once per rising edge for the P form).
    WhenOn,
    /// Every scan, with its rung's power (the P form: ON only in the scan
    /// the rung rose): it keeps state across scans, like a timer.
    EveryScan,
}

/// What an instruction keeps in the image between scans, besides its
/// operands; the checker numbers each instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Keeps {
    Nothing,
    /// A sort job (SORT, SORT2, DSORT2): `Memory::sort_state`.
    SortJob,
    /// An instance state (`Memory::instance`): pulse outputs, high-speed
    /// compares, HOUR, ...
    State,
}

/// One operand position of an instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OperandDecl {
    /// The seed's name in lower case: `s1`, `d`, `n`.
    pub name: &'static str,
    pub kind: OperandKind,
    /// The devices the position accepts.
    pub devices: Devices,
    /// How far its run reaches from the device, when the kind does not say
    /// (`None`: one unit, or the whole area for the kinds of runs).
    pub reach: Option<Reach>,
}

/// Everything the declaration says about an instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AppSpec {
    pub op: AppOp,
    /// The 16-bit mnemonic, or the 32-bit one of an instruction that has
    /// only a 32-bit form (`narrow` false).
    pub name: &'static str,
    /// There is a 16-bit form (`name`).
    pub narrow: bool,
    /// The 32-bit mnemonic, if there is a 32-bit form.
    pub wide_name: Option<&'static str>,
    /// There are P (pulse) forms: `NAMEP`, `DNAMEP`.
    pub pulse: bool,
    pub family: Family,
    pub runs: Runs,
    pub keeps: Keeps,
    pub summary: &'static str,
    pub operands: &'static [OperandDecl],
    /// Special relays the instruction reads (modes).
    pub reads: &'static [SpecialBit],
    /// Special relays every execution writes (flags): ON when the condition
    /// holds, OFF otherwise.
    pub writes: &'static [SpecialBit],
    /// The parts of the machine model it works on beyond its operands and
    /// special relays.
    pub machine: &'static [MachinePart],
}

/// A part of the machine model an instruction works on beyond its operands
/// and the special relays it declares: what a compact image must hold for
/// it, and what the scan must keep up to date.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MachinePart {
    /// The clock's registers D8013-D8019 and relays M8015-M8019.
    Clock,
    /// Counting X0-X7 at the input refresh (high-speed counters and their
    /// comparisons, SPD).
    InputCounting,
    /// The pulse outputs Y0-Y3: which instruction drives each, their
    /// pulse, speed and position registers and relays, M8029.
    PulseOutputs,
    /// The annunciator states S900-S999.
    AlarmStates,
    /// The special-function units' buffer memory, as far as the operands
    /// reach.
    BufferMemory,
}

impl AppSpec {
    /// Every mnemonic of the instruction: 16/32-bit, plain/pulse.
    pub fn mnemonics(&self) -> Vec<(String, ladder_runtime::Width, bool)> {
        use ladder_runtime::Width;
        let mut names = Vec::new();
        if self.narrow {
            names.push((self.name.to_string(), Width::Single, false));
        }
        if let Some(wide) = self.wide_name {
            names.push((wide.to_string(), Width::Double, false));
        }
        if self.pulse {
            if self.narrow {
                names.push((format!("{}P", self.name), Width::Single, true));
            }
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

/// What the checker implements to resolve the operands of an instruction,
/// in declaration order. A `None` has been reported already.
pub trait ResolveOperand {
    fn resolve(&mut self, name: &'static str, kind: OperandKind, devices: Devices) -> Option<AppOperand>;
}

macro_rules! wide_name {
    (_) => {
        None
    };
    ($name:literal) => {
        Some($name)
    };
}

/// (the name, whether there is a 16-bit form) of `NAME DNAME` or `_ DNAME`.
macro_rules! narrow_name {
    (_ $wide:literal) => {
        ($wide, false)
    };
    ($name:literal $wide:tt) => {
        ($name, true)
    };
}

macro_rules! runs {
    (on) => {
        (Runs::WhenOn, Keeps::Nothing)
    };
    (always) => {
        (Runs::EveryScan, Keeps::Nothing)
    };
    (job) => {
        (Runs::EveryScan, Keeps::SortJob)
    };
    (state) => {
        (Runs::EveryScan, Keeps::State)
    };
    (on_state) => {
        (Runs::WhenOn, Keeps::State)
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
        $variant:ident: $name:tt $wide:tt $pulse:ident $family:ident $runs:ident
            ($($field:ident: $kind:ident($devices:expr) $([$($reach:tt)+])?),* $(,)?)
            reads [$($read:ident),* $(,)?] writes [$($flag:ident),* $(,)?]
            $(machine [$($part:ident),* $(,)?])?
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
                            name: narrow_name!($name $wide).0,
                            narrow: narrow_name!($name $wide).1,
                            wide_name: wide_name!($wide),
                            pulse: pulse_form!($pulse),
                            family: Family::$family,
                            runs: runs!($runs).0,
                            keeps: runs!($runs).1,
                            summary: $summary,
                            operands: &[$(OperandDecl {
                                name: stringify!($field),
                                kind: OperandKind::$kind,
                                devices: $devices,
                                reach: reach!($($($reach)+)?),
                            }),*],
                            reads: &[$(special::$read),*],
                            writes: &[$(special::$flag),*],
                            machine: &[$($(MachinePart::$part),*)?],
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
/// Bits and values: where ENCO reads and DECO writes.
const BITS_OR_VALUES: Devices = ANY_BIT.with(ANY_VALUE);
const BITS_OR_WORDS: Devices = WRITABLE_BITS.with(WRITABLE_WORD);
/// Word registers and timer/counter values, no digit groups (BTOW, WTOB).
const WORD_REGISTERS: Devices = WORDS;
const OCTAL_SOURCE: Devices = Devices::of(DeviceClass::KnX).with(Devices::of(DeviceClass::KnM));
const OCTAL_DESTINATION: Devices = Devices::of(DeviceClass::KnY).with(Devices::of(DeviceClass::KnM));
/// What ZRST resets: bits, timers, counters, registers.
const RESET_ZONE: Devices = Devices::of(DeviceClass::Y)
    .with(Devices::of(DeviceClass::M))
    .with(Devices::of(DeviceClass::S))
    .with(Devices::of(DeviceClass::Sm))
    .with(Devices::of(DeviceClass::T))
    .with(Devices::of(DeviceClass::C))
    .with(REGISTERS);

app_instructions! {
    /// MOV S D: D = S.
    Mov: "MOV" "DMOV" pulse Move on
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "copies S to D";
    /// BMOV S D n: n words from S to D; overlapping blocks move as a whole.
    BlockMov: "BMOV" _ pulse Move on
        (s: BlockSource(ANY_WORD) [n units], d: BlockDestination(WRITABLE_WORD) [n units], n: Count(COUNT))
        reads [] writes []
        "copies n words from S to D";
    /// FMOV S D n: S into n units from D.
    FillMov: "FMOV" "DFMOV" pulse Move on
        (s: Source(ANY_VALUE), d: BlockDestination(WRITABLE_WORD) [n units], n: Count(COUNT))
        reads [] writes []
        "writes S into n units from D";
    /// ADD S1 S2 D: D = S1 + S2, wrapping.
    Add: "ADD" "DADD" pulse Arithmetic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 + S2";
    /// SUB S1 S2 D: D = S1 - S2, wrapping.
    Sub: "SUB" "DSUB" pulse Arithmetic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 - S2";
    /// MUL S1 S2 D: the double-width product to D.
    Mul: "MUL" "DMUL" pulse Arithmetic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: DoubleDestination(MULTI_WORD_DESTINATION))
        reads [] writes []
        "the double-width product S1 × S2 to D";
    /// DIV S1 S2 D: quotient to D, remainder to the next unit.
    Div: "DIV" "DDIV" pulse Arithmetic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: DoubleDestination(MULTI_WORD_DESTINATION))
        reads [] writes []
        "quotient of S1 / S2 to D, remainder to the next unit";
    /// INC D: D + 1, wrapping.
    Inc: "INC" "DINC" pulse Arithmetic on
        (d: Modified(WRITABLE_WORD))
        reads [] writes []
        "D = D + 1";
    /// DEC D: D - 1, wrapping.
    Dec: "DEC" "DDEC" pulse Arithmetic on
        (d: Modified(WRITABLE_WORD))
        reads [] writes []
        "D = D - 1";
    /// CMP S1 S2 D: D, D+1, D+2 = S1>S2, S1=S2, S1<S2.
    Cmp: "CMP" "DCMP" pulse Compare on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = S1 > S2, S1 = S2, S1 < S2";
    /// ZCP S1 S2 S D: D, D+1, D+2 = S<S1, S1<=S<=S2, S>S2.
    ZoneCmp: "ZCP" "DZCP" pulse Compare on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), s: Source(ANY_VALUE), d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = S < S1, S1 ≤ S ≤ S2, S > S2";
    /// NEG D: D = -D (two's complement; the smallest value stays).
    Neg: "NEG" "DNEG" pulse Arithmetic on
        (d: Modified(WRITABLE_WORD))
        reads [] writes []
        "D = −D";
    /// SQR S D: D = the square root of S, rounded down.
    Sqr: "SQR" "DSQR" pulse Arithmetic on
        (s: Source(REGISTERS.with(CONSTANT)), d: Destination(REGISTERS))
        reads [] writes [SM_BORROW_FLAG, SM_ZERO_FLAG]
        "D = √S rounded down; SM152 when a fraction was dropped, SM153 when D is 0; S < 0 is 4084H";
    /// WAND S1 S2 D: bitwise AND.
    Wand: "WAND" "DAND" pulse Logic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = S1 AND S2, bit by bit";
    /// WOR S1 S2 D: bitwise OR.
    Wor: "WOR" "DOR" pulse Logic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = S1 OR S2, bit by bit";
    /// WXOR S1 S2 D: bitwise exclusive OR.
    Wxor: "WXOR" "DXOR" pulse Logic on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = S1 XOR S2, bit by bit";
    /// CML S D: D = NOT S.
    Cml: "CML" "DCML" pulse Logic on
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = NOT S, bit by bit";
    /// BON S N D: D = bit N of S.
    Bon: "BON" "DBON" pulse Logic on
        (s: Source(ANY_VALUE), n: Source(ANY_VALUE), d: BitDestination(WRITABLE_BITS))
        reads [] writes []
        "D = bit N of S (N 0-15, 0-31 for DBON; else 4084H)";
    /// SUM S D: the number of ON bits of S.
    Sum: "SUM" "DSUM" pulse Logic on
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes [SM_ZERO_FLAG]
        "D = the number of ON bits of S; SM153 when S is 0";
    /// SWAP D: the high and low byte of each word of D change places.
    Swap: "SWAP" "DSWAP" pulse Convert on
        (d: Modified(WRITABLE_WORD))
        reads [] writes []
        "swaps the high and low byte of each word of D";
    /// ENCO S N D: D = the number of the highest ON bit among 2^N bits of S.
    Encode: "ENCO" _ pulse Convert on
        (s: ElementSource(BITS_OR_VALUES) [2 ^ n bits], n: Count(COUNT), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = the position of the highest ON bit among 2^N bits from S";
    /// DECO S N D: turns ON bit (low N bits of S) of 2^N bits from D, the rest OFF.
    Decode: "DECO" _ pulse Convert on
        (s: ElementSource(BITS_OR_VALUES) [n bits], n: Count(COUNT), d: ElementDestination(BITS_OR_WORDS) [2 ^ n bits])
        reads [] writes []
        "of 2^N bits from D, turns ON the one numbered by the low N bits of S";
    /// BTOW S D N: the low bytes of N words packed into words.
    BytesToWords: "BTOW" _ pulse Convert on
        (s: BlockSource(WORD_REGISTERS) [n words], d: BlockDestination(WORD_REGISTERS) [n words], n: Count(COUNT))
        reads [] writes []
        "packs the low bytes of N words from S into words from D";
    /// WTOB S D N: N bytes of words split into words.
    WordsToBytes: "WTOB" _ pulse Convert on
        (s: BlockSource(WORD_REGISTERS) [n words], d: BlockDestination(WORD_REGISTERS) [n words], n: Count(COUNT))
        reads [] writes []
        "splits N bytes of words from S into N words from D";
    /// DIS S D N: the low N nibbles of S into N words.
    Distribute: "DIS" _ pulse Convert on
        (s: Source(ANY_VALUE), d: BlockDestination(WRITABLE_WORD) [n words], n: Count(COUNT))
        reads [] writes []
        "the low N 4-bit digits of S into N words from D";
    /// UNI S D N: the low nibbles of N words combined.
    Unite: "UNI" _ pulse Convert on
        (s: BlockSource(ANY_WORD) [n words], d: Destination(WRITABLE_WORD), n: Count(COUNT))
        reads [] writes []
        "the low 4 bits of N words from S combined into D";
    /// PRUN S D: digit groups transferred with octal device numbering.
    OctalMove: "PRUN" _ pulse Move on
        (s: DigitSource(OCTAL_SOURCE), d: DigitDestination(OCTAL_DESTINATION))
        reads [] writes []
        "copies a digit group, numbering M in octal steps (M0-M7, M10-M17, ...)";
    /// ZRST D1 D2: resets every device from D1 to D2.
    ZoneReset: "ZRST" _ pulse Zone on
        (d1: RangeEnd(RESET_ZONE), d2: RangeEnd(RESET_ZONE))
        reads [] writes []
        "resets D1 to D2 (bits OFF, words 0, timers and counters cleared)";
    /// ZSET D1 D2: sets every bit from D1 to D2.
    ZoneSet: "ZSET" _ pulse Zone on
        (d1: RangeEnd(WRITABLE_BITS), d2: RangeEnd(WRITABLE_BITS))
        reads [] writes []
        "turns ON every bit from D1 to D2";
    /// MAX S1 S2 D: the largest value from device S1 to device S2.
    Max: "MAX" "DMAX" pulse Table on
        (s1: TableEnd(WORDS), s2: TableEnd(WORDS), d: Destination(WORDS))
        reads [] writes []
        "D = the largest value from device S1 to device S2 (4093H: not the same device; 4094H: S1 after S2)";
    /// MIN S1 S2 D: the smallest value from device S1 to device S2.
    Min: "MIN" "DMIN" pulse Table on
        (s1: TableEnd(WORDS), s2: TableEnd(WORDS), d: Destination(WORDS))
        reads [] writes []
        "D = the smallest value from device S1 to device S2 (4093H, 4094H as MAX)";
    /// LIMIT S1 S2 S3 D: S3 kept within the lower limit S1 and the upper
    /// limit S2.
    Limit: "LIMIT" "DLIMIT" pulse Table on
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), s3: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = S1 when S3 < S1, S2 when S3 > S2, else S3 (S1 > S2: 4084H, D unchanged)";
    /// MEAN S D N: the mean of N values from S.
    Mean: "MEAN" "DMEAN" pulse Table on
        (s: BlockSource(ANY_WORD) [n units], d: Destination(WRITABLE_WORD), n: Source(COUNT))
        reads [] writes []
        "D = the mean of N values from S, truncated toward 0 (N ≤ 0: 4084H)";
    /// WSUM S D N: the sum of N values from S, at twice the width.
    Wsum: "WSUM" "DWSUM" pulse Table on
        (s: BlockSource(ANY_WORD) [n units], d: DoubleDestination(MULTI_WORD_DESTINATION), n: Source(COUNT))
        reads [] writes []
        "D (twice the width) = the sum of N values from S (N < 0: 4084H)";
    /// SORT S N1 N2 D N3: the column-major table sorted by column N3.
    Sort: "SORT" _ no_pulse Table job
        (s: BlockSource(WORDS) [n1 * n2 units], n1: Count(COUNT), n2: Count(COUNT), d: BlockDestination(WORDS) [n1 * n2 units], n3: Count(COUNT))
        reads [] writes [SM_SORT_DONE]
        "sorts the rows of an N1 × N2 table stored column by column, ascending by column N3, in N1 scans";
    /// SORT2 S N1 N2 D N3: the row-major table sorted by column N3.
    Sort2: "SORT2" "DSORT2" pulse Table job
        (s: BlockSource(WORDS) [n1 * n2 units], n1: Source(COUNT), n2: Source(COUNT), d: BlockDestination(WORDS) [n1 * n2 units], n3: Source(COUNT))
        reads [SM_DESCENDING] writes [SM_SORT_DONE]
        "sorts the rows of an N1 × N2 table stored row by row by column N3 (SM165: descending), in N1 scans";
    /// BCC S1 S2 S3 D: the block check code of S3 bytes from S2.
    Bcc: "BCC" _ pulse Check on
        (s1: Count(COUNT), s2: ByteSource(ANY_WORD) [s3 words], s3: Count(COUNT), d: Destination(WRITABLE_WORD))
        reads [SM_EIGHT_BIT_MODE] writes []
        "the low byte of D = the check code of S3 bytes from S2: S1 = 0 add, 1 subtract, 2 XOR";
    /// CRC S D N: the CRC-16 of N bytes from S.
    Crc: "CRC" _ pulse Check on
        (s: ByteSource(ANY_WORD) [n words], d: Destination(WRITABLE_WORD) [2 words], n: Count(COUNT))
        reads [SM_EIGHT_BIT_MODE] writes []
        "D = the CRC-16/MODBUS of N bytes from S (N 1-256)";
    /// XCH D1 D2: the two values change places.
    Xch: "XCH" "DXCH" pulse Move on
        (d1: Modified(WRITABLE_WORD), d2: Modified(WRITABLE_WORD))
        reads [] writes []
        "exchanges D1 and D2";
    /// ALT D: toggles bit D.
    Alt: "ALT" _ pulse Logic on
        (d: BitModified(WRITABLE_BITS) [1 bit])
        reads [] writes []
        "toggles bit D at every execution with power (ALTP: once per rising edge)";
    /// BCD S D: binary to BCD.
    Bcd: "BCD" "DBCD" pulse Convert on
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = S in BCD (S 0-9999, 0-99999999 for DBCD; else 4084H)";
    /// BIN S D: BCD to binary.
    Bin: "BIN" "DBIN" pulse Convert on
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = the BCD value S in binary (a digit above 9: 4084H)";
    /// ROR D n: rotate right, M8022 the last bit out.
    Ror: "ROR" "DROR" pulse Shift on
        (d: Modified(WRITABLE_WORD), n: Count(COUNT))
        reads [] writes [CARRY_FLAG]
        "rotates D right by n bits (0-16, 0-32 for DROR; else 4084H); M8022 = the last bit rotated out";
    /// ROL D n: rotate left, M8022 the last bit out.
    Rol: "ROL" "DROL" pulse Shift on
        (d: Modified(WRITABLE_WORD), n: Count(COUNT))
        reads [] writes [CARRY_FLAG]
        "rotates D left by n bits (0-16, 0-32 for DROL; else 4084H); M8022 = the last bit rotated out";
    /// SFTR S D n1 n2: the n1 bits from D shift n2 toward D.
    ShiftRight: "SFTR" _ pulse Shift on
        (s: BitSource(ANY_BIT) [n2 bits], d: BitModified(WRITABLE_BITS) [n1 bits], n1: Count(CONSTANT), n2: Count(COUNT))
        reads [] writes []
        "shifts the n1 bits from D by n2 toward D; the n2 bits from S fill the top (1 ≤ n2 ≤ n1 ≤ 1024, else 4084H)";
    /// SFTL S D n1 n2: the n1 bits from D shift n2 away from D.
    ShiftLeft: "SFTL" _ pulse Shift on
        (s: BitSource(ANY_BIT) [n2 bits], d: BitModified(WRITABLE_BITS) [n1 bits], n1: Count(CONSTANT), n2: Count(COUNT))
        reads [] writes []
        "shifts the n1 bits from D by n2 away from D; the n2 bits from S fill the bottom (1 ≤ n2 ≤ n1 ≤ 1024, else 4084H)";
    /// ANS S N D: sets alarm D after the rung was ON for N × 100 ms on timer S.
    Ans: "ANS" _ pulse Alarm always
        (s: Timer(Devices::of(DeviceClass::T)), n: Count(COUNT), d: BitDestination(Devices::of(DeviceClass::S)))
        reads [] writes []
        machine [AlarmStates]
        "sets the alarm state D (S900-S999) once the rung has been ON for N × 100 ms, timed by T0-T199 S";
    /// ANR: resets the lowest alarm state that is ON.
    Anr: "ANR" _ pulse Alarm on
        ()
        reads [] writes []
        machine [AlarmStates]
        "turns OFF the lowest alarm state S900-S999 that is ON";
    /// DECMP S1 S2 D: real comparison.
    RealCmp: "DECMP" _ pulse Float on
        (s1: RealSource(ANY_REAL), s2: RealSource(ANY_REAL), d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = S1 > S2, S1 = S2, S1 < S2 (real numbers)";
    /// DEZCP S1 S2 S D: real zone comparison.
    RealZoneCmp: "DEZCP" _ pulse Float on
        (s1: RealSource(ANY_REAL), s2: RealSource(ANY_REAL), s: RealSource(ANY_REAL), d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = S < S1, S1 ≤ S ≤ S2, S > S2 (real numbers)";
    /// DEMOV S D: a real number moved.
    RealMov: "DEMOV" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "copies the real number S to D";
    /// DEADD S1 S2 D: real addition.
    RealAdd: "DEADD" _ pulse Float on
        (s1: RealSource(ANY_REAL), s2: RealSource(ANY_REAL), d: RealDestination(REGISTERS))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 + S2 (real numbers)";
    /// DESUB S1 S2 D: real subtraction.
    RealSub: "DESUB" _ pulse Float on
        (s1: RealSource(ANY_REAL), s2: RealSource(ANY_REAL), d: RealDestination(REGISTERS))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 − S2 (real numbers)";
    /// DEMUL S1 S2 D: real multiplication.
    RealMul: "DEMUL" _ pulse Float on
        (s1: RealSource(ANY_REAL), s2: RealSource(ANY_REAL), d: RealDestination(REGISTERS))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 × S2 (real numbers)";
    /// DEDIV S1 S2 D: real division.
    RealDiv: "DEDIV" _ pulse Float on
        (s1: RealSource(ANY_REAL), s2: RealSource(ANY_REAL), d: RealDestination(REGISTERS))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = S1 / S2 (real numbers; S2 = 0 is 4084H)";
    /// DESQR S D: real square root.
    RealSqr: "DESQR" _ pulse Float on
        (s: RealSource(ANY_REAL), d: RealDestination(REGISTERS))
        reads [] writes [ZERO_FLAG]
        "D = √S (real numbers; S < 0 is 4084H)";
    /// DENEG D: the sign of a real number changes.
    RealNeg: "DENEG" _ pulse Float on
        (d: RealModified(REGISTERS))
        reads [] writes []
        "D = −D (real numbers)";
    /// FLT S D: integer to real.
    Flt: "FLT" "DFLT" pulse Float on
        (s: Source(REGISTERS), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = the integer S as a real number";
    /// INT S D: real to integer.
    Int: "INT" "DINT" pulse Float on
        (s: RealSource(REGISTERS), d: Destination(REGISTERS))
        reads [] writes [ZERO_FLAG, BORROW_FLAG, CARRY_FLAG]
        "D = the real number S without its fraction (4084H if it does not fit)";
    /// DEBCD S D: real to scientific notation.
    RealToDecimal: "DEBCD" _ pulse Float on
        (s: RealSource(REGISTERS), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = the 4-digit mantissa and D+1 the decimal exponent of the real number S";
    /// DEBIN S D: scientific notation to real.
    DecimalToReal: "DEBIN" _ pulse Float on
        (s: RealSource(REGISTERS), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = the real number of mantissa S and decimal exponent S+1";
    /// DSIN S D.
    Sin: "DSIN" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = sin S (radians)";
    /// DCOS S D.
    Cos: "DCOS" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = cos S (radians)";
    /// DTAN S D.
    Tan: "DTAN" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = tan S (radians)";
    /// DASIN S D.
    Asin: "DASIN" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = arcsin S in radians (S outside −1..1 is 4084H)";
    /// DACOS S D.
    Acos: "DACOS" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = arccos S in radians (S outside −1..1 is 4084H)";
    /// DATAN S D.
    Atan: "DATAN" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = arctan S in radians";
    /// DRAD S D.
    Rad: "DRAD" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = S degrees in radians";
    /// DDEG S D.
    Deg: "DDEG" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = S radians in degrees";
    /// DEXP S D.
    Exp: "DEXP" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = e^S (a result out of range is 4084H)";
    /// DLOGE S D.
    Loge: "DLOGE" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = the natural logarithm of S (S ≤ 0 is 4084H)";
    /// DLOG10 S D.
    Log10: "DLOG10" _ pulse Float on
        (s: RealSource(REAL_VALUE), d: RealDestination(REGISTERS))
        reads [] writes []
        "D = the common logarithm of S (S ≤ 0 is 4084H)";
    /// TRD D: reads the clock.
    Trd: "TRD" _ pulse Clock on
        (d: BlockDestination(REGISTERS) [7 words])
        reads [] writes []
        machine [Clock]
        "D..D+6 = year, month, day, hour, minute, second, day of week of the clock (D8018, D8017, ..., D8013, D8019)";
    /// TWR S: sets the clock.
    Twr: "TWR" _ pulse Clock on
        (s: BlockSource(REGISTERS) [7 words])
        reads [] writes []
        machine [Clock]
        "sets the clock to year, month, day, hour, minute, second, day of week S..S+6 (out of range: 4084H)";
    /// TCMP S1 S2 S3 S D: time comparison.
    Tcmp: "TCMP" _ pulse Clock on
        (s1: Count(ANY_VALUE), s2: Count(ANY_VALUE), s3: Count(ANY_VALUE), s: BlockSource(WORDS) [3 words], d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = the time S1:S2:S3 is later than, the same as, earlier than the time S..S+2";
    /// TZCP S1 S2 S D: time zone comparison.
    Tzcp: "TZCP" _ pulse Clock on
        (s1: BlockSource(WORDS) [3 words], s2: BlockSource(WORDS) [3 words], s: BlockSource(WORDS) [3 words], d: BitTriple(RESULT_BITS))
        reads [] writes []
        "D, D+1, D+2 = the time S is before S1, from S1 to S2, after S2 (times in 3 words)";
    /// TADD S1 S2 D: time addition.
    Tadd: "TADD" _ pulse Clock on
        (s1: BlockSource(WORDS) [3 words], s2: BlockSource(WORDS) [3 words], d: BlockDestination(WORDS) [3 words])
        reads [] writes [ZERO_FLAG, CARRY_FLAG]
        "D = the time S1 + S2, wrapped to 24 hours (M8022 when it wrapped)";
    /// TSUB S1 S2 D: time subtraction.
    Tsub: "TSUB" _ pulse Clock on
        (s1: BlockSource(WORDS) [3 words], s2: BlockSource(WORDS) [3 words], d: BlockDestination(WORDS) [3 words])
        reads [] writes [ZERO_FLAG, BORROW_FLAG]
        "D = the time S1 − S2, wrapped to 24 hours (M8021 when it wrapped)";
    /// HTOS S D: hours, minutes, seconds to seconds.
    Htos: "HTOS" "DHTOS" pulse Clock on
        (s: BlockSource(WORDS) [3 words], d: Destination(WRITABLE_WORD))
        reads [] writes []
        "D = the hours S, minutes S+1, seconds S+2 in seconds";
    /// STOH S D: seconds to hours, minutes, seconds.
    Stoh: "STOH" "DSTOH" pulse Clock on
        (s: Source(ANY_VALUE), d: BlockDestination(WORDS) [3 words])
        reads [] writes []
        "D, D+1, D+2 = the seconds S in hours, minutes, seconds";
    /// HOUR S D1 D2: hour meter.
    Hour: "HOUR" "DHOUR" no_pulse Clock on_state
        (s: Source(ANY_VALUE), d1: BlockDestination(REGISTERS) [3 words], d2: BitDestination(RESULT_BITS))
        reads [] writes []
        "while ON, counts hours in D1 and seconds in the next word; D2 turns ON at S hours";
    /// SER S1 S2 D n: data search.
    Ser: "SER" "DSER" pulse Handy on
        (s1: BlockSource(WORDS) [n units], s2: Source(ANY_VALUE), d: BlockDestination(WRITABLE_WORD) [5 units], n: Source(COUNT))
        reads [] writes []
        "searches n values from S1 for S2: D = matches, D+1 first, D+2 last, D+3 smallest, D+4 largest position";
    /// ABSD S1 S2 D n: absolute drum.
    Absd: "ABSD" "DABSD" no_pulse Handy on
        (s1: BlockSource(WORDS) [2 * n units], s2: Source(Devices::of(DeviceClass::C).with(Devices::of(DeviceClass::WideCounter))), d: BitDestination(RESULT_BITS) [n bits], n: Count(CONSTANT))
        reads [] writes []
        "output k of n from D is ON while counter S2 is from S1+2k to S1+2k+1";
    /// INCD S1 S2 D n: incremental drum.
    Incd: "INCD" _ no_pulse Handy always
        (s1: BlockSource(WORDS) [n words], s2: CounterPair(Devices::of(DeviceClass::C)), d: BitDestination(RESULT_BITS) [n bits], n: Count(CONSTANT))
        reads [] writes [EXECUTION_COMPLETE]
        "step k (counter S2+1) lasts until counter S2 reaches S1+k; output D+k ON during step k; M8029 after the last";
    /// TTMR D n: teaching timer.
    Ttmr: "TTMR" _ no_pulse Handy state
        (d: BlockDestination(REGISTERS) [2 words], n: Count(CONSTANT))
        reads [] writes []
        "D+1 = the rung's ON time in 100 ms; when it turns OFF, D = D+1 × 10^n / 10";
    /// STMR S m D: special timer.
    Stmr: "STMR" _ no_pulse Handy state
        (s: Timer(Devices::of(DeviceClass::T)), m: Count(COUNT), d: BitDestination(RESULT_BITS) [4 bits])
        reads [] writes []
        "D OFF-delay, D+1 one-shot after OFF, D+2 one-shot after ON, D+3 ON- and OFF-delay, of m × 100 ms";
    /// RAMP S1 S2 D n: ramp.
    Ramp: "RAMP" _ no_pulse Handy state
        (s1: Count(REGISTERS), s2: Count(REGISTERS), d: BlockDestination(REGISTERS) [2 words], n: Count(COUNT))
        reads [RAMP_HOLD] writes [EXECUTION_COMPLETE]
        "D moves from S1 to S2 in n scans (D+1 counts them); M8029 at the end, M8026 holds it there";
    /// SEGD S D: seven-segment decode.
    Segd: "SEGD" _ pulse Handy on
        (s: Source(ANY_VALUE), d: Destination(WRITABLE_WORD))
        reads [] writes []
        "the low byte of D = the seven segments of the hex digit in the low 4 bits of S";
    /// SEGL S D n: seven-segment with latch.
    Segl: "SEGL" _ no_pulse Handy state
        (s: Source(ANY_VALUE) [2 words], d: BitDestination(Devices::of(DeviceClass::Y)) [12 bits], n: Count(CONSTANT))
        reads [] writes [EXECUTION_COMPLETE]
        "shows S (and S+1 for n 4-7) as 4 BCD digits on D..D+3 with strobes D+4..D+7, a cycle of 12 scans";
    /// ASCI S D n: hex to ASCII.
    Asci: "ASCI" _ pulse Handy on
        (s: BlockSource(ANY_WORD) [n words], d: BlockDestination(WRITABLE_WORD) [n words], n: Count(COUNT))
        reads [EIGHT_BIT_MODE_FX] writes []
        "the n lowest hex digits of S as ASCII characters from D (M8161: one per word)";
    /// HEX S D n: ASCII to hex.
    Hex: "HEX" _ pulse Handy on
        (s: BlockSource(ANY_WORD) [n words], d: BlockDestination(WRITABLE_WORD) [n words], n: Count(COUNT))
        reads [EIGHT_BIT_MODE_FX] writes []
        "n ASCII hex characters from S as a number in D, D+1, ... (M8161: one per word)";
    /// CCD S D n: check code.
    Ccd: "CCD" _ pulse Handy on
        (s: BlockSource(ANY_WORD) [n words], d: BlockDestination(WRITABLE_WORD) [2 words], n: Count(COUNT))
        reads [EIGHT_BIT_MODE_FX] writes []
        "D = the sum and D+1 the exclusive OR of n bytes from S (M8161: low bytes only)";
    /// DHSCS S1 S2 D: high-speed counter set.
    Hscs: _ "DHSCS" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: HighSpeedCounter(Devices::of(DeviceClass::C)), d: BitDestination(RESULT_BITS))
        reads [] writes []
        machine [InputCounting]
        "D turns ON when counting at the input refresh brings counter S2 to S1";
    /// DHSCR S1 S2 D: high-speed counter reset.
    Hscr: _ "DHSCR" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: HighSpeedCounter(Devices::of(DeviceClass::C)), d: BitDestination(RESULT_BITS))
        reads [] writes []
        machine [InputCounting]
        "D turns OFF when counting at the input refresh brings counter S2 to S1";
    /// DHSZ S1 S2 S D: high-speed zone compare.
    Hsz: _ "DHSZ" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), s: HighSpeedCounter(Devices::of(DeviceClass::C)), d: BitTriple(RESULT_BITS))
        reads [] writes []
        machine [InputCounting]
        "D, D+1, D+2 = counter S below S1, from S1 to S2, above S2, as it counts";
    /// SPD S1 S2 D: pulse speed.
    Spd: "SPD" "DSPD" no_pulse HighSpeed on
        (s1: BitSource(Devices::of(DeviceClass::X)), s2: Source(ANY_VALUE), d: BlockDestination(REGISTERS) [3 units])
        reads [] writes []
        machine [InputCounting]
        "D = the rising edges of S1 (X0-X5) in the last S2 ms, D+1 so far, D+2 the time left";
    /// PLSY S1 S2 D: pulse output.
    Plsy: "PLSY" "DPLSY" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: BitDestination(Devices::of(DeviceClass::Y)))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "S2 pulses (0: without end) at S1 Hz on D (Y0-Y3)";
    /// PLSR S1 S2 S3 D: pulse output with ramps.
    Plsr: "PLSR" "DPLSR" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), s3: Source(ANY_VALUE), d: BitDestination(Devices::of(DeviceClass::Y)))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "S2 pulses up to S1 Hz on D (Y0-Y3), accelerating and decelerating in S3 ms";
    /// PLSV S D1 D2: variable speed output.
    Plsv: "PLSV" "DPLSV" no_pulse HighSpeed state
        (s: Source(ANY_VALUE), d1: BitDestination(Devices::of(DeviceClass::Y)), d2: BitDestination(RESULT_BITS))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "pulses at the signed frequency S on D1 (Y0-Y3) while driven; D2 the direction";
    /// DRVI S1 S2 D1 D2: relative positioning.
    Drvi: "DRVI" "DDRVI" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d1: BitDestination(Devices::of(DeviceClass::Y)), d2: BitDestination(RESULT_BITS))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "moves S1 pulses from where it starts at S2 Hz on D1 (Y0-Y3); D2 the direction";
    /// DRVA S1 S2 D1 D2: absolute positioning.
    Drva: "DRVA" "DDRVA" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d1: BitDestination(Devices::of(DeviceClass::Y)), d2: BitDestination(RESULT_BITS))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "moves to the address S1 at S2 Hz on D1 (Y0-Y3); D2 the direction";
    /// ZRN S1 S2 S3 D: zero return.
    Zrn: "ZRN" "DZRN" no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), s3: BitSource(ANY_BIT), d: BitDestination(Devices::of(DeviceClass::Y)))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "returns to zero at S1 Hz until the near point S3, then at S2 Hz until it is released (address 0)";
    /// DSZR S1 S2 D1 D2: zero return with the near point and zero signal.
    Dszr: "DSZR" _ no_pulse HighSpeed state
        (s1: BitSource(ANY_BIT), s2: BitSource(Devices::of(DeviceClass::X)), d1: BitDestination(Devices::of(DeviceClass::Y)), d2: BitDestination(RESULT_BITS))
        reads [] writes [EXECUTION_COMPLETE]
        machine [PulseOutputs]
        "returns to zero at the speeds of its output (Y0: D8346, D8345; Y1: D8356, D8355; ...) until the near point S1 is released (address 0)";
    /// PWM S1 S2 D: pulse width modulation.
    Pwm: "PWM" _ no_pulse HighSpeed state
        (s1: Source(ANY_VALUE), s2: Source(ANY_VALUE), d: BitDestination(Devices::of(DeviceClass::Y)))
        reads [] writes []
        machine [PulseOutputs]
        "D (Y0-Y3) is ON for S1 ms of every S2 ms while driven";
    /// FROM m1 m2 D n: reads buffer memory.
    From: "FROM" "DFROM" pulse Module on
        (m1: Source(COUNT), m2: Source(COUNT), d: BlockDestination(WRITABLE_WORD) [n units], n: Source(COUNT))
        reads [] writes []
        machine [BufferMemory]
        "n units from buffer word m2 of unit m1 (U0-U7) to D";
    /// TO m1 m2 S n: writes buffer memory.
    To: "TO" "DTO" pulse Module on
        (m1: Source(COUNT), m2: Source(COUNT), s: Source(ANY_VALUE) [n units], n: Source(COUNT))
        reads [] writes []
        machine [BufferMemory]
        "n units from S (a constant: n times) to buffer word m2 of unit m1 (U0-U7)";
    /// PID S1 S2 S3 D: PID control.
    Pid: "PID" _ no_pulse Control state
        (s1: Count(REGISTERS), s2: Count(REGISTERS), s3: BlockSource(REGISTERS) [25 words], d: Destination(REGISTERS))
        reads [] writes []
        "MV D from the set value S1 and the process value S2, with the parameter block S3..S3+24, every Ts ms";
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
                // Runs of devices never start at a constant.
                if matches!(
                    operand.kind,
                    OperandKind::BlockSource | OperandKind::TableEnd | OperandKind::ByteSource
                ) {
                    assert!(
                        !operand.devices.contains(super::super::operand::DeviceClass::Constant),
                        "{op:?} {}",
                        operand.name
                    );
                }
                // Destinations never take constants.
                if !operand.kind.is_read() {
                    assert!(
                        !operand.devices.contains(super::super::operand::DeviceClass::Constant),
                        "{op:?} {}",
                        operand.name
                    );
                }
                // A reach counts by operands of the same instruction that
                // hold counts, and bits only from bit positions.
                if let Some(reach) = operand.reach {
                    for count in reach.counts() {
                        let counted = spec.operands.iter().find(|o| o.name == count);
                        assert!(
                            counted.is_some_and(|o| matches!(o.kind, OperandKind::Count | OperandKind::Source)),
                            "{op:?} {} counts by {count}",
                            operand.name
                        );
                    }
                }
            }
        }
    }
}
