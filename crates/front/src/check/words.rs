//! Word operands: a value an instruction reads or writes at its width (16
//! or 32 bits): constants, registers, timer and counter values, index
//! registers, digit groups, real numbers, and the runs of words some
//! instructions take.

use super::devices::{
    area_text_bits, area_text_words, bit_area, check_extent, kind_error, named_device, text_of, Resolved,
};
use super::index_registers::{index_register_value, indexed};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{Address, DigitGroup, WordRef};
use crate::syntax::{Constant, DeviceSyntax, Operand, OperandSyntax, Prefix};
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER, TIMER_COUNT};
use ladder_runtime::{BitArea, Width, WordArea};

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

/// An E constant where an integer is read.
pub(super) fn real_here(operand: &Operand) -> Diagnostic {
    kind_error(
        operand,
        "a real (E) constant is read only by the floating-point instructions (DEMOV, DEADD, DECMP, ...)",
        "real constant",
    )
    .with_note("for an integer write K or H; to make a real number of an integer, use FLT")
}

/// A value the instruction reads at `width`: a constant or a word device.
pub fn word_source(operand: &Operand, width: Width) -> Resolved<WordRef> {
    match &operand.syntax {
        OperandSyntax::Constant(c) => Ok(WordRef::Constant(constant(operand, c, width)?)),
        OperandSyntax::Real(_) => Err(real_here(operand)),
        OperandSyntax::Device(d) => word_device(operand, d, width, 1),
    }
}

/// A word device the instruction reads (no constant): the start of a block.
pub fn word_device_source(operand: &Operand, width: Width) -> Resolved<WordRef> {
    let d = named_device(operand, "this operand is a device, not a constant", "constant here")?;
    word_device(operand, d, width, 1)
}

/// One end of a run of words (MAX S1, S2): the device itself must exist;
/// how far the run reaches is checked when the instruction runs.
pub fn table_end(operand: &Operand, width: Width) -> Resolved<WordRef> {
    let d = named_device(operand, "this operand is a device, not a constant", "constant here")?;
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

/// A word the instruction writes; `multiple` = 2 for MUL/DIV results.
pub fn word_destination(operand: &Operand, width: Width, multiple: u32) -> Resolved<WordRef> {
    let d = named_device(operand, "a constant cannot be a destination", "constant as destination")?;
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

/// A word device at `width` (`multiple` times its words): a register, a
/// timer's or counter's value, an index register, a digit group.
pub(super) fn word_device(operand: &Operand, d: &DeviceSyntax, width: Width, multiple: u32) -> Resolved<WordRef> {
    let address = indexed(d)?;
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
                COUNTER_COUNT,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::operand::parse_operand;

    fn op(text: &str) -> Operand {
        parse_operand(text, 0).unwrap()
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
}
