//! Index registers V0-V7/Z0-Z7 as operands: the FX modifiers `DEVZn` and
//! `DEVVn` (the same run-time offset as `DEV[Dk]`), and `Vn`/`Zn` as words,
//! where a 32-bit `Zn` is the pair (Vn, Zn).

use super::devices::{area_text_words, check_extent, kind_error, text_of, Resolved};
use crate::diagnostics::{Code, Diagnostic};
use crate::program::{Address, IndexRegister, WordRef};
use crate::syntax::{DeviceSyntax, OffsetKind, Operand, Prefix};
use ladder_runtime::device::{index_register_word, INDEX_REGISTER_COUNT};
use ladder_runtime::WordArea;

/// The device's number with its index register, if it has one.
pub(super) fn indexed(d: &DeviceSyntax) -> Resolved<Address> {
    Ok(Address {
        index: d.number,
        index_register: index_register(d)?,
    })
}

/// The index register must be a D, Z or V in range; an index register
/// cannot itself be modified.
fn index_register(d: &DeviceSyntax) -> Resolved<Option<IndexRegister>> {
    let Some(o) = d.offset else {
        return Ok(None);
    };
    if matches!(d.prefix, Prefix::V | Prefix::Z) {
        return Err(Diagnostic::new(
            Code::OperandKind,
            o.span,
            format!("`{}`: an index register cannot be modified", text_of(d)),
        )
        .with_label("modifier on an index register"));
    }
    let (letter, in_range, range) = match o.kind {
        OffsetKind::D => ("D", o.register < WordArea::D.count(), area_text_words(WordArea::D)),
        OffsetKind::Z => (
            "Z",
            o.register < INDEX_REGISTER_COUNT,
            "index registers are Z0..Z7".to_string(),
        ),
        OffsetKind::V => (
            "V",
            o.register < INDEX_REGISTER_COUNT,
            "index registers are V0..V7".to_string(),
        ),
    };
    if !in_range {
        return Err(Diagnostic::new(
            Code::DeviceRange,
            o.span,
            format!("offset register {letter}{} is out of range", o.register),
        )
        .with_label(range)
        .with_note(format!("in operand `{}`", text_of(d))));
    }
    Ok(Some(match o.kind {
        OffsetKind::D => IndexRegister {
            area: WordArea::D,
            number: o.register,
        },
        OffsetKind::Z | OffsetKind::V => IndexRegister {
            area: WordArea::Index,
            number: index_register_word(o.register, o.kind == OffsetKind::V),
        },
    }))
}

/// `Vn`/`Zn` as a word; as a 32-bit operand `Zn` is the pair (Vn, Zn).
pub(super) fn index_register_value(
    operand: &Operand,
    d: &DeviceSyntax,
    wide: bool,
    multiple: u32,
) -> Resolved<WordRef> {
    let name = text_of(d);
    check_extent(
        operand,
        || name.to_string(),
        d.number,
        1,
        INDEX_REGISTER_COUNT,
        || format!("index registers are {0}0..{0}7", d.prefix.as_str()),
    )?;
    if multiple > 1 {
        return Err(kind_error(
            operand,
            "this result is several words long; use D, R, SD or a digit group",
            "index register",
        ));
    }
    let v = d.prefix == Prefix::V;
    if wide && v {
        return Err(kind_error(
            operand,
            format!(
                "`{name}` cannot be a 32-bit operand: the 32-bit index register is Z{} (V{} is its high word)",
                d.number, d.number
            ),
            "V as a 32-bit operand",
        ));
    }
    Ok(WordRef::Word(
        WordArea::Index,
        Address::fixed(index_register_word(d.number, v)),
    ))
}
