//! Device areas: what kinds of devices exist, how many of each, how they
//! are numbered, and the widths of their values. The compiler's checker,
//! the interpreter, the native code and the C API all take their ranges
//! from here.

/// Areas whose elements are single bits (stored one byte per bit, 0 or 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum BitArea {
    /// Inputs X0–X377 (octal numbering).
    X,
    /// Outputs Y0–Y377 (octal numbering).
    Y,
    /// Auxiliary relays M0–M8511; M8000 and up are special relays.
    M,
    /// States S0–S4095.
    S,
    /// Special relays SM0–SM1023.
    Sm,
    /// Timer contacts T0–T511 (`T`/`TS`).
    TimerContact,
    /// Counter contacts C0–C255 (`C`/`CS`).
    CounterContact,
}

/// Areas whose elements are signed 16-bit words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum WordArea {
    /// Data registers D0–D8511; D8000 and up are special registers.
    D,
    /// Special registers SD0–SD1023.
    Sd,
    /// File registers R0–R32767.
    R,
    /// Timer current values T0–T511 (`T`/`TN` in word position).
    TimerValue,
    /// 16-bit counter current values C0–C199 (`C`/`CN`).
    CounterValue,
    /// Index registers, interleaved so that a 32-bit access at Zn is the
    /// pair (Vn, Zn) as on an FX: word 2n is Zn, word 2n+1 is Vn.
    Index,
    /// Buffer memories of special-function units 0-7 (`Un\Gm`): unit after
    /// unit, `BUFFER_WORDS_PER_UNIT` words each, so word `u * 32767 + m` is
    /// `Uu\Gm`.
    Buffer,
}

/// Special-function units whose buffer memory the image keeps (U0-U7).
pub const BUFFER_UNITS: u32 = 8;
/// Words of one unit's buffer memory (G0-G32766).
pub const BUFFER_WORDS_PER_UNIT: u32 = 32767;

/// The word of the buffer-memory area that holds `Uunit\Gword`.
pub const fn buffer_word(unit: u32, word: u32) -> u32 {
    unit * BUFFER_WORDS_PER_UNIT + word
}

/// Number of Z (and of V) index registers: Z0–Z7, V0–V7.
pub const INDEX_REGISTER_COUNT: u32 = 8;

/// The word of the index-register area that holds Zn (`v` false) or Vn.
pub const fn index_register_word(number: u32, v: bool) -> u32 {
    2 * number + v as u32
}

/// First 32-bit counter; C200–C255 hold 32-bit current values.
pub const FIRST_WIDE_COUNTER: u32 = 200;
/// Number of counters, 16-bit and 32-bit together.
pub const COUNTER_COUNT: u32 = 256;
/// Number of 32-bit counters (C200–C255).
pub const WIDE_COUNTER_COUNT: u32 = COUNTER_COUNT - FIRST_WIDE_COUNTER;
/// Number of timers.
pub const TIMER_COUNT: u32 = 512;
/// Number of STL states.
pub const STATE_COUNT: u32 = 4096;
/// SORT, SORT2 and DSORT2 instructions one program may hold (each keeps its
/// progress in the image).
pub const SORT_INSTANCES: u32 = 64;
/// Instructions that keep state between scans (pulse outputs, high-speed
/// compares, HOUR, ...) one program may hold.
pub const STATE_INSTANCES: u32 = 256;
/// Inputs X0-X7 that feed the high-speed counters.
pub const HSC_INPUTS: u32 = 8;
/// Pulse outputs Y0-Y3.
pub const PULSE_OUTPUTS: u32 = 4;
/// Largest unit count of BMOV/FMOV (more is operation error 4084H).
pub const MAX_BLOCK_UNITS: u32 = 512;
/// The most units FROM and TO move at once (a unit's whole buffer memory).
pub const MAX_TRANSFER_UNITS: u32 = 32_767;
/// Most bits SFTR/SFTL shift (n1 above is operation error 4084H).
pub const MAX_SHIFT_BITS: u32 = 1024;
/// Number of previous-scan slots available to edge instructions of one program.
pub const EDGE_SLOT_COUNT: u32 = 16384;

impl BitArea {
    pub const ALL: [BitArea; 7] = [
        BitArea::X,
        BitArea::Y,
        BitArea::M,
        BitArea::S,
        BitArea::Sm,
        BitArea::TimerContact,
        BitArea::CounterContact,
    ];

    /// Number of devices in the area.
    pub const fn count(self) -> u32 {
        match self {
            BitArea::X | BitArea::Y => 256,
            BitArea::M => 8512,
            BitArea::S => STATE_COUNT,
            BitArea::Sm => 1024,
            BitArea::TimerContact => TIMER_COUNT,
            BitArea::CounterContact => COUNTER_COUNT,
        }
    }

    /// Device numbers of X and Y are written in octal (X17 is followed by X20).
    pub const fn is_octal(self) -> bool {
        matches!(self, BitArea::X | BitArea::Y)
    }

    /// The canonical prefix used when printing a device of this area.
    pub const fn prefix(self) -> &'static str {
        match self {
            BitArea::X => "X",
            BitArea::Y => "Y",
            BitArea::M => "M",
            BitArea::S => "S",
            BitArea::Sm => "SM",
            BitArea::TimerContact => "T",
            BitArea::CounterContact => "C",
        }
    }

    /// Formats device `index` the way a programmer writes it (`X17`, `M100`).
    #[cfg(feature = "std")]
    pub fn device_name(self, index: u32) -> String {
        if self.is_octal() {
            format!("{}{:o}", self.prefix(), index)
        } else {
            format!("{}{}", self.prefix(), index)
        }
    }
}

impl WordArea {
    pub const ALL: [WordArea; 7] = [
        WordArea::D,
        WordArea::Sd,
        WordArea::R,
        WordArea::TimerValue,
        WordArea::CounterValue,
        WordArea::Index,
        WordArea::Buffer,
    ];

    /// Number of words in the area.
    pub const fn count(self) -> u32 {
        match self {
            WordArea::D => 8512,
            WordArea::Sd => 1024,
            WordArea::R => 32768,
            WordArea::TimerValue => TIMER_COUNT,
            WordArea::CounterValue => FIRST_WIDE_COUNTER,
            WordArea::Index => 2 * INDEX_REGISTER_COUNT,
            WordArea::Buffer => BUFFER_UNITS * BUFFER_WORDS_PER_UNIT,
        }
    }

    /// The words that a device written as word `index` of the area may
    /// reach with an offset or a run: (first, end), `end` excluded. The
    /// whole area, except for buffer memory: one unit's words.
    pub const fn reach(self, index: u32) -> (u32, u32) {
        match self {
            WordArea::Buffer => {
                let unit = index / BUFFER_WORDS_PER_UNIT;
                (unit * BUFFER_WORDS_PER_UNIT, (unit + 1) * BUFFER_WORDS_PER_UNIT)
            }
            WordArea::D
            | WordArea::Sd
            | WordArea::R
            | WordArea::TimerValue
            | WordArea::CounterValue
            | WordArea::Index => (0, self.count()),
        }
    }

    /// The prefix of the area's devices (for the index registers, of Zn).
    pub const fn prefix(self) -> &'static str {
        match self {
            WordArea::D => "D",
            WordArea::Sd => "SD",
            WordArea::R => "R",
            WordArea::TimerValue => "T",
            WordArea::CounterValue => "C",
            WordArea::Index => "Z",
            WordArea::Buffer => "U",
        }
    }

    /// Formats word `index` the way a programmer writes it (`D100`, `V3`).
    #[cfg(feature = "std")]
    pub fn device_name(self, index: u32) -> String {
        match self {
            WordArea::Index if index % 2 == 1 => format!("V{}", index / 2),
            WordArea::Index => format!("Z{}", index / 2),
            WordArea::Buffer => format!("U{}\\G{}", index / BUFFER_WORDS_PER_UNIT, index % BUFFER_WORDS_PER_UNIT),
            WordArea::D | WordArea::Sd | WordArea::R | WordArea::TimerValue | WordArea::CounterValue => {
                format!("{}{}", self.prefix(), index)
            }
        }
    }
}

/// How many bits a value covers: an instruction's form (16 or 32 bits),
/// a host access, a counter's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Width {
    /// One bit, or one 16-bit word.
    Single,
    /// A 32-bit pair (n+1, n) of words, or a 32-bit device.
    Double,
}

impl Width {
    /// 16-bit words in a value of this width.
    pub const fn words(self) -> u32 {
        match self {
            Width::Single => 1,
            Width::Double => 2,
        }
    }

    /// Bits in a word value of this width.
    pub const fn bits(self) -> u32 {
        16 * self.words()
    }
}

/// Timer behaviour fixed by its number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimerClass {
    /// Milliseconds per count of the current value.
    pub resolution_ms: u32,
    /// Retentive timers keep their value while the coil is OFF, until RST.
    pub retentive: bool,
}

impl TimerClass {
    /// T0–T199 100 ms, T200–T245 10 ms, T246–T249 1 ms retentive,
    /// T250–T255 100 ms retentive, T256–T511 1 ms.
    pub const fn of(timer: u32) -> TimerClass {
        let (resolution_ms, retentive) = match timer {
            0..=199 => (100, false),
            200..=245 => (10, false),
            246..=249 => (1, true),
            250..=255 => (100, true),
            _ => (1, false),
        };
        TimerClass {
            resolution_ms,
            retentive,
        }
    }
}

/// Is counter `n` one of the 32-bit up/down counters?
pub const fn is_wide_counter(counter: u32) -> bool {
    counter >= FIRST_WIDE_COUNTER
}

/// The width of a counter's value and preset: 32 bits from C200 on.
pub const fn counter_width(counter: u32) -> Width {
    if is_wide_counter(counter) {
        Width::Double
    } else {
        Width::Single
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octal_names() {
        assert_eq!(BitArea::X.device_name(0o17), "X17");
        assert_eq!(BitArea::Y.device_name(255), "Y377");
        assert_eq!(BitArea::M.device_name(17), "M17");
        assert_eq!(WordArea::Index.device_name(index_register_word(3, false)), "Z3");
        assert_eq!(WordArea::Index.device_name(index_register_word(7, true)), "V7");
        assert_eq!(WordArea::Buffer.device_name(buffer_word(3, 10)), "U3\\G10");
        assert_eq!(WordArea::Buffer.device_name(buffer_word(7, 32766)), "U7\\G32766");
    }

    #[test]
    fn timer_classes_follow_numbering() {
        assert_eq!(TimerClass::of(0).resolution_ms, 100);
        assert_eq!(TimerClass::of(199).resolution_ms, 100);
        assert_eq!(TimerClass::of(200).resolution_ms, 10);
        assert!(!TimerClass::of(245).retentive);
        assert_eq!(
            TimerClass::of(246),
            TimerClass {
                resolution_ms: 1,
                retentive: true
            }
        );
        assert_eq!(
            TimerClass::of(250),
            TimerClass {
                resolution_ms: 100,
                retentive: true
            }
        );
        assert_eq!(
            TimerClass::of(256),
            TimerClass {
                resolution_ms: 1,
                retentive: false
            }
        );
    }
}
