//! Operand resolution: operand syntax, checked against what its position
//! accepts, to the devices of the runtime's areas.

use super::index_registers::{index_register, index_register_value};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{Address, BitRef, CounterRef, DigitGroup, Element, RangeEnd, WordRef};
use crate::syntax::{Constant, DeviceSyntax, Operand, OperandSyntax, Prefix};
use ladder_runtime::device::{FIRST_WIDE_COUNTER, TIMER_COUNT};
use ladder_runtime::{BitArea, Width, WordArea};

pub type Resolved<T> = Result<T, Diagnostic>;

/// Largest jump label number.
pub const LAST_LABEL: u32 = 4095;
/// Master-control levels N0..N7.
pub const MC_LEVELS: u32 = 8;

/// An OUT coil: a bit, or a timer/counter that needs a preset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coil {
    Bit(BitRef),
    Timer(u32),
    Counter(u32),
}

pub(super) fn kind_error(operand: &Operand, message: impl Into<String>, label: &str) -> Diagnostic {
    Diagnostic::new(Code::OperandKind, operand.span, message).with_label(label)
}

fn range_error(operand: &Operand, message: impl Into<String>, label: impl Into<String>) -> Diagnostic {
    Diagnostic::new(Code::DeviceRange, operand.span, message).with_label(label)
}

fn device(operand: &Operand) -> Option<&DeviceSyntax> {
    match &operand.syntax {
        OperandSyntax::Device(d) => Some(d),
        OperandSyntax::Constant(_) | OperandSyntax::Real(_) => None,
    }
}

pub(super) fn text_of(d: &DeviceSyntax) -> String {
    if d.prefix == Prefix::U {
        return WordArea::Buffer.device_name(d.number);
    }
    let number = if d.prefix.is_octal() {
        format!("{:o}", d.number)
    } else {
        d.number.to_string()
    };
    format!("{}{}", d.prefix.as_str(), number)
}

fn bit_area(prefix: Prefix) -> Option<BitArea> {
    Some(match prefix {
        Prefix::X => BitArea::X,
        Prefix::Y => BitArea::Y,
        Prefix::M => BitArea::M,
        Prefix::S => BitArea::S,
        Prefix::Sm => BitArea::Sm,
        Prefix::T | Prefix::Ts => BitArea::TimerContact,
        Prefix::C | Prefix::Cs => BitArea::CounterContact,
        Prefix::Tn
        | Prefix::Cn
        | Prefix::D
        | Prefix::Sd
        | Prefix::R
        | Prefix::P
        | Prefix::N
        | Prefix::V
        | Prefix::Z
        | Prefix::U => return None,
    })
}

/// Checks that `count` units from `index` lie in an area of `len` units.
/// Checks that `count` devices from `index` lie in an area of `len`; the
/// device's name and the area's text are only made for a diagnostic.
pub(super) fn check_extent(
    operand: &Operand,
    name: impl FnOnce() -> String,
    index: u32,
    count: u32,
    len: u32,
    area_text: impl FnOnce() -> String,
) -> Resolved<()> {
    if index >= len {
        return Err(range_error(
            operand,
            format!("device `{}` is out of range", name()),
            area_text(),
        ));
    }
    if u64::from(index) + u64::from(count) > u64::from(len) {
        return Err(range_error(
            operand,
            format!(
                "`{}` needs {count} consecutive devices, which run past the end of the area",
                name()
            ),
            area_text(),
        ));
    }
    Ok(())
}

fn area_text_bits(area: BitArea) -> String {
    format!(
        "{} is {}..{}",
        area.prefix(),
        area.device_name(0),
        area.device_name(area.count() - 1)
    )
}

pub(super) fn area_text_words(area: WordArea) -> String {
    format!(
        "{} is {}..{}",
        area.prefix(),
        area.device_name(0),
        area.device_name(area.count() - 1)
    )
}

/// A bit a contact reads: X Y M S SM T C, or Dn.b.
pub fn bit_source(operand: &Operand) -> Resolved<BitRef> {
    let Some(d) = device(operand) else {
        return Err(kind_error(
            operand,
            "this operand is a bit device, not a constant",
            "constant here",
        ));
    };
    if d.digits.is_some() {
        return Err(kind_error(
            operand,
            "a digit group is a word; this operand is one bit",
            "digit group here",
        ));
    }
    let address = Address {
        index: d.number,
        index_register: index_register(d)?,
    };
    if let Some(bit) = d.bit {
        check_extent(
            operand,
            || text_of(d),
            d.number,
            1,
            WordArea::D.count(),
            || area_text_words(WordArea::D),
        )?;
        return Ok(BitRef::WordBit(WordArea::D, address, bit));
    }
    match d.prefix {
        Prefix::Tn | Prefix::Cn => Err(kind_error(
            operand,
            format!(
                "`{}` is a current value; the contact is {}S{}",
                text_of(d),
                &d.prefix.as_str()[..1],
                d.number
            ),
            "word, not bit",
        )),
        Prefix::V | Prefix::Z => Err(kind_error(
            operand,
            format!(
                "`{}` is an index register (a word); this operand is one bit",
                text_of(d)
            ),
            "word, not bit",
        )),
        Prefix::U => Err(kind_error(
            operand,
            format!("`{}` is a buffer-memory word; this operand is one bit", text_of(d)),
            "word, not bit",
        )),
        Prefix::D | Prefix::Sd | Prefix::R => Err(kind_error(
            operand,
            format!(
                "`{}` is a word; this operand is one bit, such as {}.0",
                text_of(d),
                text_of(d)
            ),
            "word, not bit",
        )),
        Prefix::P | Prefix::N => Err(kind_error(
            operand,
            format!("`{}` is not a device", text_of(d)),
            "not a bit device",
        )),
        Prefix::X
        | Prefix::Y
        | Prefix::M
        | Prefix::S
        | Prefix::Sm
        | Prefix::T
        | Prefix::Ts
        | Prefix::C
        | Prefix::Cs => match bit_area(d.prefix) {
            Some(area) => {
                check_extent(
                    operand,
                    || text_of(d),
                    d.number,
                    1,
                    area.count(),
                    || area_text_bits(area),
                )?;
                Ok(BitRef::Device(area, address))
            }
            None => Err(kind_error(
                operand,
                format!("`{}` is not a bit device", text_of(d)),
                "not a bit device",
            )),
        },
    }
}

/// A bit SET, RST, PLS, PLF or MC writes: not X (an input), not T/C.
pub fn bit_target(operand: &Operand) -> Resolved<BitRef> {
    let bit = bit_source(operand)?;
    match bit {
        BitRef::Device(BitArea::X, _) => Err(kind_error(
            operand,
            "X is an input; the program cannot write it",
            "input",
        )),
        BitRef::Device(BitArea::TimerContact | BitArea::CounterContact, _) => Err(kind_error(
            operand,
            "timer and counter contacts are driven by their coils (OUT Tn/Cn with a preset)",
            "timer/counter contact",
        )),
        BitRef::Device(BitArea::Y | BitArea::M | BitArea::S | BitArea::Sm, _) | BitRef::WordBit(..) => Ok(bit),
    }
}

/// The coil of OUT.
pub fn coil(operand: &Operand) -> Resolved<Coil> {
    if let Some(d) = device(operand) {
        let counter_or_timer = matches!(d.prefix, Prefix::T | Prefix::Ts | Prefix::C | Prefix::Cs);
        if counter_or_timer && d.digits.is_none() && d.bit.is_none() {
            if d.offset.is_some() {
                return Err(kind_error(
                    operand,
                    "a timer or counter coil cannot be offset",
                    "offset coil",
                ));
            }
            let is_timer = matches!(d.prefix, Prefix::T | Prefix::Ts);
            let area = if is_timer {
                BitArea::TimerContact
            } else {
                BitArea::CounterContact
            };
            check_extent(
                operand,
                || text_of(d),
                d.number,
                1,
                area.count(),
                || area_text_bits(area),
            )?;
            return Ok(if is_timer {
                Coil::Timer(d.number)
            } else {
                Coil::Counter(d.number)
            });
        }
    }
    bit_target(operand).map(Coil::Bit)
}

/// The preset of `OUT Tn`/`OUT Cn`: a K constant or a D register (a pair for
/// the 32-bit counters).
pub fn preset(operand: &Operand, width: Width) -> Resolved<WordRef> {
    match &operand.syntax {
        OperandSyntax::Constant(c) => {
            let value = constant(operand, c, width)?;
            if width == Width::Single && value < 0 {
                return Err(
                    Diagnostic::new(Code::ConstantRange, operand.span, "a preset cannot be negative")
                        .with_label("presets are K0..K32767"),
                );
            }
            Ok(WordRef::Constant(value))
        }
        OperandSyntax::Device(d)
            if d.prefix == Prefix::D && d.digits.is_none() && d.bit.is_none() && d.offset.is_none() =>
        {
            check_extent(
                operand,
                || text_of(d),
                d.number,
                width.words(),
                WordArea::D.count(),
                || area_text_words(WordArea::D),
            )?;
            Ok(WordRef::Word(WordArea::D, Address::fixed(d.number)))
        }
        OperandSyntax::Real(_) | OperandSyntax::Device(_) => Err(kind_error(
            operand,
            "a preset is a K constant or a D register (without offset)",
            "not K or D",
        )),
    }
}

/// A constant at the instruction's width: K must fit signed, H unsigned.
pub fn constant(operand: &Operand, c: &Constant, width: Width) -> Resolved<i32> {
    let fits = match (width, c.hex) {
        (Width::Single, false) => (-32768..=32767).contains(&c.value),
        (Width::Single, true) => (0..=0xFFFF).contains(&c.value),
        (Width::Double, false) => (i64::from(i32::MIN)..=i64::from(i32::MAX)).contains(&c.value),
        (Width::Double, true) => (0..=0xFFFF_FFFF).contains(&c.value),
    };
    if !fits {
        let range = match width {
            Width::Double => "K-2147483648..K2147483647 or H0..HFFFFFFFF",
            Width::Single => "K-32768..K32767 or H0..HFFFF",
        };
        return Err(Diagnostic::new(
            Code::ConstantRange,
            operand.span,
            "constant out of range for this instruction",
        )
        .with_label(format!("{}-bit operands take {range}", width.bits())));
    }
    Ok(match width {
        Width::Double => c.value as u32 as i32,
        Width::Single => i32::from(c.value as u16 as i16),
    })
}

/// `K1`.. — how many consecutive devices SET/RST act on, from `first`.
pub fn device_count(operand: &Operand, first: u32, area_len: u32) -> Resolved<u32> {
    let OperandSyntax::Constant(c) = &operand.syntax else {
        return Err(kind_error(
            operand,
            "the device count is a K constant",
            "not a constant",
        ));
    };
    if c.value < 1 || c.value > i64::from(area_len) {
        return Err(
            Diagnostic::new(Code::ConstantRange, operand.span, "device count out of range")
                .with_label(format!("count is K1..K{area_len}")),
        );
    }
    let count = c.value as u32;
    if u64::from(first) + u64::from(count) > u64::from(area_len) {
        return Err(range_error(
            operand,
            format!("{count} devices from number {first} run past the end of the area"),
            "count too large",
        ));
    }
    Ok(count)
}

/// A plain numbered operand of one prefix (no offset, digits or bit), at
/// most `last`: states, nesting levels, labels.
fn numbered(operand: &Operand, prefix: Prefix, last: u32, what: &str) -> Resolved<u32> {
    let name = prefix.as_str();
    match device(operand) {
        Some(d) if d.prefix == prefix && d.digits.is_none() && d.bit.is_none() && d.offset.is_none() => {
            if d.number > last {
                return Err(range_error(
                    operand,
                    format!("{what} {name}{} is out of range", d.number),
                    format!("{what}s are {name}0..{name}{last}"),
                ));
            }
            Ok(d.number)
        }
        _ => Err(kind_error(
            operand,
            format!("expected a {what} such as {name}1"),
            &format!("not a {what}"),
        )),
    }
}

/// A state Sn.
pub fn state(operand: &Operand) -> Resolved<u32> {
    numbered(operand, Prefix::S, BitArea::S.count() - 1, "state")
}

/// `N0`..`N7`.
pub fn nest_level(operand: &Operand) -> Resolved<u8> {
    numbered(operand, Prefix::N, MC_LEVELS - 1, "nesting level").map(|n| n as u8)
}

/// `P0`..`P4095`.
pub fn label(operand: &Operand) -> Resolved<u32> {
    numbered(operand, Prefix::P, LAST_LABEL, "label")
}

/// A value the instruction reads at `width`: a constant or a word device.
/// An E constant where an integer is read.
fn real_here(operand: &Operand) -> Diagnostic {
    kind_error(
        operand,
        "a real (E) constant is read only by the floating-point instructions (DEMOV, DEADD, DECMP, ...)",
        "real constant",
    )
    .with_note("for an integer write K or H; to make a real number of an integer, use FLT")
}

pub fn word_source(operand: &Operand, width: Width) -> Resolved<WordRef> {
    match &operand.syntax {
        OperandSyntax::Constant(c) => Ok(WordRef::Constant(constant(operand, c, width)?)),
        OperandSyntax::Real(_) => Err(real_here(operand)),
        OperandSyntax::Device(d) => word_device(operand, d, width, 1),
    }
}

/// A word device the instruction reads (no constant): the start of a block.
pub fn word_device_source(operand: &Operand, width: Width) -> Resolved<WordRef> {
    match &operand.syntax {
        OperandSyntax::Constant(_) | OperandSyntax::Real(_) => Err(kind_error(
            operand,
            "this operand is a device, not a constant",
            "constant here",
        )),
        OperandSyntax::Device(d) => word_device(operand, d, width, 1),
    }
}

/// One end of a run of words (MAX S1, S2): the device itself must exist;
/// how far the run reaches is checked when the instruction runs.
pub fn table_end(operand: &Operand, width: Width) -> Resolved<WordRef> {
    let OperandSyntax::Device(d) = &operand.syntax else {
        return Err(kind_error(
            operand,
            "this operand is a device, not a constant",
            "constant here",
        ));
    };
    match (width, d.prefix) {
        // 32-bit counters are 32-bit devices; other words are resolved as
        // their first word.
        (Width::Double, Prefix::C | Prefix::Cn | Prefix::T | Prefix::Tn) => word_device(operand, d, width, 1),
        (Width::Single, _)
        | (
            Width::Double,
            Prefix::X
            | Prefix::Y
            | Prefix::M
            | Prefix::S
            | Prefix::Sm
            | Prefix::Ts
            | Prefix::Cs
            | Prefix::D
            | Prefix::Sd
            | Prefix::R
            | Prefix::P
            | Prefix::N
            | Prefix::V
            | Prefix::Z
            | Prefix::U,
        ) => word_device(operand, d, Width::Single, 1),
    }
}

/// A real number read: an E constant's bits, a K or H constant converted
/// to the nearest real number, or a word pair.
pub fn real_source(operand: &Operand) -> Resolved<WordRef> {
    match &operand.syntax {
        OperandSyntax::Real(r) => Ok(WordRef::Constant(r.value.to_bits() as i32)),
        OperandSyntax::Constant(c) => {
            let value = constant(operand, c, Width::Double)?;
            // H constants are bit patterns read as unsigned numbers.
            let number = if c.hex {
                f64::from(value as u32)
            } else {
                f64::from(value)
            };
            Ok(WordRef::Constant((number as f32).to_bits() as i32))
        }
        OperandSyntax::Device(d) => word_device(operand, d, Width::Double, 1),
    }
}

/// A counter by number: `C` or `CS` (`CN` too), with an index register if any.
fn counter_number(operand: &Operand, what: &str) -> Resolved<(u32, Address)> {
    match device(operand) {
        Some(d) if matches!(d.prefix, Prefix::C | Prefix::Cs | Prefix::Cn) && d.digits.is_none() && d.bit.is_none() => {
            Ok((
                d.number,
                Address {
                    index: d.number,
                    index_register: index_register(d)?,
                },
            ))
        }
        Some(_) | None => Err(kind_error(operand, format!("expected {what}"), "not a counter")),
    }
}

/// A high-speed counter C235-C255 (DHSCS S2).
pub fn high_speed_counter(operand: &Operand) -> Resolved<CounterRef> {
    let (number, address) = counter_number(operand, "a high-speed counter C235..C255")?;
    if !(ladder_runtime::hsc::FIRST_HSC..=ladder_runtime::hsc::LAST_HSC).contains(&number) {
        return Err(kind_error(
            operand,
            "high-speed counters are C235..C255",
            "not a high-speed counter",
        ));
    }
    Ok(CounterRef(address))
}

/// A 16-bit counter that the instruction drives together with the next one
/// (INCD S2): C0..C198.
pub fn counter_pair(operand: &Operand) -> Resolved<CounterRef> {
    let (number, address) = counter_number(operand, "a counter such as C0")?;
    if number >= FIRST_WIDE_COUNTER {
        // A 32-bit counter where 16-bit ones are driven: the operand's kind
        // (E0003), as anywhere a 16-bit counter is asked for.
        return Err(kind_error(
            operand,
            format!("C{number} is a 32-bit counter; this instruction drives two 16-bit counters (C0..C198)"),
            "32-bit counter",
        ));
    }
    check_extent(
        operand,
        || format!("C{number}"),
        number,
        2,
        FIRST_WIDE_COUNTER,
        || "16-bit counters are C0..C199".to_string(),
    )?;
    Ok(CounterRef(address))
}

/// A word the instruction writes; `multiple` = 2 for MUL/DIV results.
pub fn word_destination(operand: &Operand, width: Width, multiple: u32) -> Resolved<WordRef> {
    let OperandSyntax::Device(d) = &operand.syntax else {
        return Err(kind_error(
            operand,
            "a constant cannot be a destination",
            "constant as destination",
        ));
    };
    let word = word_device(operand, d, width, multiple)?;
    if let WordRef::Digits(BitArea::X, ..) = word {
        return Err(kind_error(
            operand,
            "X is an input; the program cannot write it",
            "input",
        ));
    }
    if multiple > 1
        && !matches!(
            word,
            WordRef::Word(WordArea::D | WordArea::R | WordArea::Sd | WordArea::Buffer, _) | WordRef::Digits(..)
        )
    {
        return Err(kind_error(
            operand,
            "this result is several words long; use D, R, SD, U\\G or a digit group",
            "not a register",
        ));
    }
    Ok(word)
}

fn word_device(operand: &Operand, d: &DeviceSyntax, width: Width, multiple: u32) -> Resolved<WordRef> {
    let address = Address {
        index: d.number,
        index_register: index_register(d)?,
    };
    let name = text_of(d);
    let wide = width == Width::Double;
    let words = width.words() * multiple;
    if let Some(n) = d.digits {
        // A digit group has at most 8 digits; a result twice the width (a
        // MUL product, a WSUM sum) takes up to K8 and keeps its own bits.
        let limit = (4 * words).min(8);
        if u32::from(n) > limit {
            return Err(kind_error(
                operand,
                format!(
                    "K{n}{name} has {} bits; this operand is {} bits (K1..K{limit})",
                    4 * u32::from(n),
                    16 * words,
                ),
                "too many digits",
            ));
        }
        let Some(area) = bit_area(d.prefix) else {
            return Err(kind_error(
                operand,
                format!("`K{n}{name}`: digit groups are made of X, Y, M or S"),
                "not a bit device",
            ));
        };
        check_extent(
            operand,
            || format!("K{n}{name}"),
            d.number,
            4 * u32::from(n),
            area.count(),
            || area_text_bits(area),
        )?;
        return Ok(WordRef::Digits(area, address, n));
    }
    if d.bit.is_some() {
        return Err(kind_error(
            operand,
            format!("`{name}.{:X}` is a bit; this operand is a word", d.bit.unwrap_or(0)),
            "bit, not word",
        ));
    }
    let area = match d.prefix {
        Prefix::D => WordArea::D,
        Prefix::U => WordArea::Buffer,
        Prefix::Sd => WordArea::Sd,
        Prefix::R => WordArea::R,
        Prefix::T | Prefix::Tn if wide => {
            return Err(kind_error(
                operand,
                "timer values are 16-bit; 32-bit instructions cannot use them",
                "16-bit device",
            ));
        }
        Prefix::T | Prefix::Tn => {
            check_extent(
                operand,
                || name.to_string(),
                d.number,
                multiple,
                TIMER_COUNT,
                || area_text_words(WordArea::TimerValue),
            )?;
            return Ok(WordRef::Word(WordArea::TimerValue, address));
        }
        Prefix::C | Prefix::Cn => return counter_value(operand, &name, d.number, address, wide, multiple),
        Prefix::V | Prefix::Z => return index_register_value(operand, d, wide, multiple),
        Prefix::X
        | Prefix::Y
        | Prefix::M
        | Prefix::S
        | Prefix::Sm
        | Prefix::Ts
        | Prefix::Cs
        | Prefix::P
        | Prefix::N => {
            return Err(kind_error(
                operand,
                format!("`{name}` is a bit device; this operand is a word (use a digit group such as K4{name})"),
                "bit, not word",
            ));
        }
    };
    let (first, end) = area.reach(d.number);
    if area == WordArea::Buffer {
        // Within one unit's buffer memory (the number is already in range).
        check_extent(
            operand,
            || name.to_string(),
            d.number - first,
            words,
            end - first,
            || "buffer memory words are G0..G32766".to_string(),
        )?;
    } else {
        check_extent(
            operand,
            || name.to_string(),
            d.number,
            words,
            area.count(),
            || area_text_words(area),
        )?;
    }
    Ok(WordRef::Word(area, address))
}

fn counter_value(
    operand: &Operand,
    name: &str,
    number: u32,
    address: Address,
    wide: bool,
    multiple: u32,
) -> Resolved<WordRef> {
    if multiple > 1 {
        return Err(kind_error(
            operand,
            "this result is several words long; use D, R, SD or a digit group",
            "counter",
        ));
    }
    match (wide, number >= FIRST_WIDE_COUNTER) {
        (false, false) => {
            check_extent(
                operand,
                || name.to_string(),
                number,
                1,
                FIRST_WIDE_COUNTER,
                || "16-bit counters are C0..C199".to_string(),
            )?;
            Ok(WordRef::Word(WordArea::CounterValue, address))
        }
        (true, true) => {
            check_extent(
                operand,
                || name.to_string(),
                number,
                1,
                ladder_runtime::device::COUNTER_COUNT,
                || "32-bit counters are C200..C255".to_string(),
            )?;
            Ok(WordRef::WideCounter(address))
        }
        (false, true) => Err(kind_error(
            operand,
            format!("`{name}` is a 32-bit counter; use the D (32-bit) form of the instruction"),
            "32-bit counter",
        )),
        (true, false) => Err(kind_error(
            operand,
            format!("`{name}` is a 16-bit counter; 32-bit instructions take C200..C255"),
            "16-bit counter",
        )),
    }
}

/// The first of three result bits (CMP, ZCP): Y, M or S.
pub fn bit_triple(operand: &Operand) -> Resolved<BitRef> {
    let bit = bit_target(operand)?;
    match bit {
        BitRef::Device(area @ (BitArea::Y | BitArea::M | BitArea::S), address) => {
            check_extent(
                operand,
                || area.device_name(address.index),
                address.index,
                3,
                area.count(),
                || area_text_bits(area),
            )?;
            Ok(bit)
        }
        BitRef::Device(BitArea::X | BitArea::Sm | BitArea::TimerContact | BitArea::CounterContact, _)
        | BitRef::WordBit(..) => Err(kind_error(
            operand,
            "the result is three consecutive bits of Y, M or S",
            "not Y, M or S",
        )),
    }
}

/// The start of a run of bits or words (ENCO S, DECO D): a bit device is
/// bits, a word device or digit group words (16 bits each), and for a
/// source a constant is one word.
pub fn element(operand: &Operand, written: bool) -> Resolved<Element> {
    let d = match &operand.syntax {
        OperandSyntax::Constant(_) | OperandSyntax::Real(_) if written => {
            return Err(kind_error(
                operand,
                "a constant cannot be a destination",
                "constant as destination",
            ))
        }
        OperandSyntax::Constant(_) => return Ok(Element::Word(word_source(operand, Width::Single)?)),
        OperandSyntax::Real(_) => return Err(real_here(operand)),
        OperandSyntax::Device(d) => d,
    };
    let is_bit = d.digits.is_none()
        && (d.bit.is_some()
            || matches!(
                d.prefix,
                Prefix::X | Prefix::Y | Prefix::M | Prefix::S | Prefix::Sm | Prefix::Ts | Prefix::Cs
            ));
    match (is_bit, written) {
        (true, true) => Ok(Element::Bits(bit_target(operand)?)),
        (true, false) => Ok(Element::Bits(bit_source(operand)?)),
        (false, true) => Ok(Element::Word(word_destination(operand, Width::Single, 1)?)),
        (false, false) => Ok(Element::Word(word_device(operand, d, Width::Single, 1)?)),
    }
}

/// One end of a device range that ZRST/ZSET write: Y M S SM bits, timers,
/// counters, or D R SD words.
pub fn range_end(operand: &Operand) -> Resolved<RangeEnd> {
    let Some(d) = device(operand) else {
        return Err(kind_error(
            operand,
            "a range end is a device, not a constant",
            "constant here",
        ));
    };
    if d.digits.is_some() {
        return Err(kind_error(
            operand,
            "a range end is one device, not a digit group",
            "digit group here",
        ));
    }
    let address = Address {
        index: d.number,
        index_register: index_register(d)?,
    };
    let numbered = |area: BitArea| -> Resolved<Address> {
        check_extent(
            operand,
            || text_of(d),
            d.number,
            1,
            area.count(),
            || area_text_bits(area),
        )?;
        Ok(address)
    };
    match d.prefix {
        Prefix::T | Prefix::Ts | Prefix::Tn if d.bit.is_none() => Ok(RangeEnd::Timer(numbered(BitArea::TimerContact)?)),
        Prefix::C | Prefix::Cs | Prefix::Cn if d.bit.is_none() => {
            Ok(RangeEnd::Counter(numbered(BitArea::CounterContact)?))
        }
        Prefix::D | Prefix::Sd | Prefix::R | Prefix::U if d.bit.is_none() => {
            match word_destination(operand, Width::Single, 1)? {
                WordRef::Word(area, address) => Ok(RangeEnd::Word(area, address)),
                WordRef::Constant(_) | WordRef::WideCounter(_) | WordRef::Digits(..) => Err(kind_error(
                    operand,
                    "a range end is a device such as D0",
                    "not a register",
                )),
            }
        }
        Prefix::X
        | Prefix::Y
        | Prefix::M
        | Prefix::S
        | Prefix::Sm
        | Prefix::T
        | Prefix::Ts
        | Prefix::Tn
        | Prefix::C
        | Prefix::Cs
        | Prefix::Cn
        | Prefix::D
        | Prefix::Sd
        | Prefix::R
        | Prefix::P
        | Prefix::N
        | Prefix::V
        | Prefix::Z
        | Prefix::U => Ok(RangeEnd::Bit(bit_target(operand)?)),
    }
}

/// A word operand that must be a digit group (PRUN).
pub fn digit_group(word: WordRef, operand: &Operand) -> Resolved<DigitGroup> {
    match word {
        WordRef::Digits(area, address, digits) => Ok(DigitGroup { area, address, digits }),
        WordRef::Constant(_) | WordRef::Word(..) | WordRef::WideCounter(_) => Err(kind_error(
            operand,
            "this operand is a digit group such as K4M0",
            "not a digit group",
        )),
    }
}

/// The first of a run of words whose bytes an instruction reads (BCC,
/// CRC): a word device, or a digit group of a whole word (K4).
pub fn byte_source(operand: &Operand) -> Resolved<WordRef> {
    let word = word_device_source(operand, Width::Single)?;
    if let WordRef::Digits(_, _, digits) = word {
        if digits != 4 {
            return Err(kind_error(
                operand,
                format!("a digit group read as bytes is a whole word: K4, not K{digits}"),
                "not K4",
            ));
        }
    }
    Ok(word)
}

/// A timer by number: `T3`, `T0[D1]`.
pub fn timer(operand: &Operand) -> Resolved<Address> {
    match device(operand) {
        Some(d) if matches!(d.prefix, Prefix::T | Prefix::Ts | Prefix::Tn) && d.digits.is_none() && d.bit.is_none() => {
            check_extent(
                operand,
                || text_of(d),
                d.number,
                1,
                TIMER_COUNT,
                || area_text_bits(BitArea::TimerContact),
            )?;
            Ok(Address {
                index: d.number,
                index_register: index_register(d)?,
            })
        }
        Some(_) | None => Err(kind_error(operand, "expected a timer such as T0", "not a timer")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::operand::parse_operand;

    fn op(text: &str) -> Operand {
        parse_operand(text, 0).unwrap()
    }

    #[test]
    fn contacts_take_bits() {
        assert_eq!(
            bit_source(&op("X10")),
            Ok(BitRef::Device(BitArea::X, Address::fixed(8)))
        );
        assert_eq!(
            bit_source(&op("TS3")),
            Ok(BitRef::Device(BitArea::TimerContact, Address::fixed(3)))
        );
        assert_eq!(
            bit_source(&op("D0.F")),
            Ok(BitRef::WordBit(WordArea::D, Address::fixed(0), 15))
        );
        assert_eq!(bit_source(&op("D0")).unwrap_err().code, Code::OperandKind);
        assert_eq!(bit_source(&op("TN3")).unwrap_err().code, Code::OperandKind);
        assert_eq!(bit_source(&op("K1")).unwrap_err().code, Code::OperandKind);
        assert_eq!(bit_source(&op("M8512")).unwrap_err().code, Code::DeviceRange);
        assert_eq!(bit_source(&op("M0[D8512]")).unwrap_err().code, Code::DeviceRange);
    }

    #[test]
    fn outputs_refuse_inputs_and_words() {
        assert_eq!(bit_target(&op("X0")).unwrap_err().code, Code::OperandKind);
        assert_eq!(bit_target(&op("D0")).unwrap_err().code, Code::OperandKind);
        assert_eq!(coil(&op("T5")), Ok(Coil::Timer(5)));
        assert_eq!(coil(&op("C200")), Ok(Coil::Counter(200)));
        assert_eq!(coil(&op("T512")).unwrap_err().code, Code::DeviceRange);
    }

    #[test]
    fn word_widths() {
        assert_eq!(word_source(&op("K-1"), Width::Single), Ok(WordRef::Constant(-1)));
        assert_eq!(word_source(&op("HFFFF"), Width::Single), Ok(WordRef::Constant(-1)));
        assert_eq!(
            word_source(&op("K40000"), Width::Single).unwrap_err().code,
            Code::ConstantRange
        );
        assert_eq!(word_source(&op("K40000"), Width::Double), Ok(WordRef::Constant(40000)));
        assert_eq!(word_source(&op("HFFFFFFFF"), Width::Double), Ok(WordRef::Constant(-1)));
        assert_eq!(
            word_source(&op("D8511"), Width::Double).unwrap_err().code,
            Code::DeviceRange
        );
        assert_eq!(
            word_source(&op("K8M0"), Width::Single).unwrap_err().code,
            Code::OperandKind
        );
        assert_eq!(
            word_source(&op("C200"), Width::Single).unwrap_err().code,
            Code::OperandKind
        );
        assert_eq!(
            word_source(&op("C200"), Width::Double),
            Ok(WordRef::WideCounter(Address::fixed(200)))
        );
        assert_eq!(
            word_source(&op("T0"), Width::Double).unwrap_err().code,
            Code::OperandKind
        );
        assert_eq!(
            word_destination(&op("K1"), Width::Single, 1).unwrap_err().code,
            Code::OperandKind
        );
        assert_eq!(
            word_destination(&op("K4X0"), Width::Single, 1).unwrap_err().code,
            Code::OperandKind
        );
        assert_eq!(
            word_destination(&op("D8510"), Width::Double, 2).unwrap_err().code,
            Code::DeviceRange
        );
    }

    #[test]
    fn counts_labels_levels() {
        assert_eq!(device_count(&op("K3"), 0, 10), Ok(3));
        assert_eq!(device_count(&op("K0"), 0, 10).unwrap_err().code, Code::ConstantRange);
        assert_eq!(device_count(&op("K3"), 8, 10).unwrap_err().code, Code::DeviceRange);
        assert_eq!(label(&op("P4095")), Ok(4095));
        assert_eq!(label(&op("P4096")).unwrap_err().code, Code::DeviceRange);
        assert_eq!(nest_level(&op("N8")).unwrap_err().code, Code::DeviceRange);
        assert_eq!(state(&op("M0")).unwrap_err().code, Code::OperandKind);
    }
}
