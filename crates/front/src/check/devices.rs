//! What resolving every operand shares: the device an operand names and how
//! it is written, the bit area of a prefix, whether devices lie in their
//! area, and the two diagnostics of a wrong operand (the wrong kind for its
//! position; outside its area). Below `operands.rs`, `words.rs` and
//! `index_registers.rs`, and importing none of them.

use crate::diagnostics::{Code, Diagnostic};
use crate::syntax::{DeviceSyntax, Operand, OperandSyntax, Prefix};
use ladder_runtime::{BitArea, WordArea};

/// An operand resolved, or the diagnostic that says why it is not.
pub type Resolved<T> = Result<T, Diagnostic>;

/// An operand of the wrong kind for its position.
pub(super) fn kind_error(operand: &Operand, message: impl Into<String>, label: &str) -> Diagnostic {
    Diagnostic::new(Code::OperandKind, operand.span, message).with_label(label)
}

/// An operand outside its area, or a count or run that leaves it.
pub(super) fn range_error(operand: &Operand, message: impl Into<String>, label: impl Into<String>) -> Diagnostic {
    Diagnostic::new(Code::DeviceRange, operand.span, message).with_label(label)
}

/// The device an operand names; `None` for a constant.
pub(super) fn device(operand: &Operand) -> Option<&DeviceSyntax> {
    match &operand.syntax {
        OperandSyntax::Device(d) => Some(d),
        OperandSyntax::Constant(_) | OperandSyntax::Real(_) => None,
    }
}

/// The device as a programmer writes it (`X17`, `U3\G10`).
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

/// The bit area a prefix names; `None` for word devices, labels, levels.
pub(super) fn bit_area(prefix: Prefix) -> Option<BitArea> {
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

/// The diagnostic's label for a bit area: `M is M0..M8511`.
pub(super) fn area_text_bits(area: BitArea) -> String {
    format!(
        "{} is {}..{}",
        area.prefix(),
        area.device_name(0),
        area.device_name(area.count() - 1)
    )
}

/// The diagnostic's label for a word area.
pub(super) fn area_text_words(area: WordArea) -> String {
    format!(
        "{} is {}..{}",
        area.prefix(),
        area.device_name(0),
        area.device_name(area.count() - 1)
    )
}

/// The device an operand names; a constant (or a real) is of the wrong
/// kind, which `message` and `label` say for the operand's position.
pub(super) fn named_device<'a>(operand: &'a Operand, message: &str, label: &str) -> Resolved<&'a DeviceSyntax> {
    device(operand).ok_or_else(|| kind_error(operand, message, label))
}

/// Checks that the one device `d` lies in bit area `area`.
pub(super) fn one_in_area(operand: &Operand, d: &DeviceSyntax, area: BitArea) -> Resolved<()> {
    check_extent(
        operand,
        || text_of(d),
        d.number,
        1,
        area.count(),
        || area_text_bits(area),
    )
}
