//! Operand resolution: operand syntax, checked against what its position
//! accepts, to the devices of the runtime's areas. Here bits (contacts,
//! coils, SET/RST targets), presets and counts, states, levels and labels,
//! counters and timers by number, and what may be bits or words (ENCO's
//! and DECO's runs, ZRST's range ends); word operands are in `words.rs`.

use super::devices::{
    area_text_bits, area_text_words, bit_area, check_extent, device, kind_error, named_device, one_in_area,
    range_error, text_of, Resolved,
};
use super::index_registers::indexed;
use super::words::{constant, real_here, word_destination, word_device, word_source};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{Address, BitRef, CounterRef, Element, RangeEnd, WordRef};
use crate::syntax::{Operand, OperandSyntax, Prefix};
use ladder_runtime::device::FIRST_WIDE_COUNTER;
use ladder_runtime::{BitArea, Width, WordArea};

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

/// A bit a contact reads: X Y M S SM T C, or Dn.b.
pub fn bit_source(operand: &Operand) -> Resolved<BitRef> {
    let d = named_device(operand, "this operand is a bit device, not a constant", "constant here")?;
    if d.digits.is_some() {
        return Err(kind_error(
            operand,
            "a digit group is a word; this operand is one bit",
            "digit group here",
        ));
    }
    let address = indexed(d)?;
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
                one_in_area(operand, d, area)?;
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
            one_in_area(operand, d, area)?;
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

/// A counter by number: `C` or `CS` (`CN` too), with an index register if any.
fn counter_number(operand: &Operand, what: &str) -> Resolved<(u32, Address)> {
    match device(operand) {
        Some(d) if matches!(d.prefix, Prefix::C | Prefix::Cs | Prefix::Cn) && d.digits.is_none() && d.bit.is_none() => {
            Ok((d.number, indexed(d)?))
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
    if !written {
        match &operand.syntax {
            OperandSyntax::Constant(_) => return Ok(Element::Word(word_source(operand, Width::Single)?)),
            OperandSyntax::Real(_) => return Err(real_here(operand)),
            OperandSyntax::Device(_) => {}
        }
    }
    let d = named_device(operand, "a constant cannot be a destination", "constant as destination")?;
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
    let d = named_device(operand, "a range end is a device, not a constant", "constant here")?;
    if d.digits.is_some() {
        return Err(kind_error(
            operand,
            "a range end is one device, not a digit group",
            "digit group here",
        ));
    }
    let address = indexed(d)?;
    let numbered = |area: BitArea| -> Resolved<Address> {
        one_in_area(operand, d, area)?;
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

/// A timer by number: `T3`, `T0[D1]`.
pub fn timer(operand: &Operand) -> Resolved<Address> {
    match device(operand) {
        Some(d) if matches!(d.prefix, Prefix::T | Prefix::Ts | Prefix::Tn) && d.digits.is_none() && d.bit.is_none() => {
            one_in_area(operand, d, BitArea::TimerContact)?;
            indexed(d)
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
