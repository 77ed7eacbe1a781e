//! Operands of application instructions: each declared operand resolved by
//! its kind, then checked against its device table.

use super::operands::{self, Resolved};
use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::isa::app::ResolveOperand;
use crate::isa::{DeviceClass, Devices, OperandKind};
use crate::program::{AppOperand, BitRef, Element, WordRef};
use crate::syntax::Operand;
use ladder_runtime::{BitArea, Width, WordArea};

/// The device class of a word operand.
pub fn word_class(word: &WordRef) -> DeviceClass {
    match word {
        WordRef::Constant(_) => DeviceClass::Constant,
        WordRef::Word(area, _) => match area {
            WordArea::D => DeviceClass::D,
            WordArea::Sd => DeviceClass::Sd,
            WordArea::R => DeviceClass::R,
            WordArea::TimerValue => DeviceClass::T,
            WordArea::CounterValue => DeviceClass::C,
        },
        WordRef::WideCounter(_) => DeviceClass::WideCounter,
        WordRef::Digits(area, ..) => match area {
            BitArea::X => DeviceClass::KnX,
            BitArea::Y => DeviceClass::KnY,
            BitArea::M => DeviceClass::KnM,
            BitArea::S => DeviceClass::KnS,
            // Digit groups are made of X, Y, M or S (the parser refuses others).
            BitArea::Sm | BitArea::TimerContact | BitArea::CounterContact => DeviceClass::KnM,
        },
    }
}

/// The device class of a bit operand.
pub fn bit_class(bit: &BitRef) -> DeviceClass {
    match bit {
        BitRef::Device(area, _) => match area {
            BitArea::X => DeviceClass::X,
            BitArea::Y => DeviceClass::Y,
            BitArea::M => DeviceClass::M,
            BitArea::S => DeviceClass::S,
            BitArea::Sm => DeviceClass::Sm,
            BitArea::TimerContact => DeviceClass::T,
            BitArea::CounterContact => DeviceClass::C,
        },
        BitRef::WordBit(..) => DeviceClass::WordBit,
    }
}

fn element_class(element: &Element) -> DeviceClass {
    match element {
        Element::Bits(bit) => bit_class(bit),
        Element::Word(word) => word_class(word),
        Element::Timer(_) => DeviceClass::T,
        Element::Counter(_) => DeviceClass::C,
    }
}

fn class_of(operand: &AppOperand) -> DeviceClass {
    match operand {
        AppOperand::Word(word) => word_class(word),
        AppOperand::Bit(bit) => bit_class(bit),
        AppOperand::Element(element) => element_class(element),
    }
}

/// Resolves one operand by its kind, at the instruction's width.
fn resolve_kind(operand: &Operand, kind: OperandKind, width: Width) -> Resolved<AppOperand> {
    Ok(match kind {
        OperandKind::Source => AppOperand::Word(operands::word_source(operand, width)?),
        OperandKind::Count => AppOperand::Word(operands::word_source(operand, Width::Single)?),
        OperandKind::Destination | OperandKind::Modified => {
            AppOperand::Word(operands::word_destination(operand, width, 1)?)
        }
        OperandKind::DoubleDestination => AppOperand::Word(operands::word_destination(operand, width, 2)?),
        OperandKind::BlockSource => AppOperand::Word(operands::word_device_source(operand, width)?),
        OperandKind::BlockDestination => AppOperand::Word(operands::word_destination(operand, width, 1)?),
        OperandKind::BitDestination => AppOperand::Bit(operands::bit_target(operand)?),
        OperandKind::BitTriple => AppOperand::Bit(operands::bit_triple(operand)?),
        OperandKind::ElementSource => AppOperand::Element(operands::element(operand, false)?),
        OperandKind::ElementDestination => AppOperand::Element(operands::element(operand, true)?),
        OperandKind::RangeEnd => AppOperand::Element(operands::range_end(operand)?),
    })
}

/// Resolves the operands of one instruction in declaration order,
/// reporting each bad one.
pub struct AppResolver<'a> {
    pub mnemonic: &'a str,
    pub operands: std::slice::Iter<'a, Operand>,
    pub width: Width,
    pub diagnostics: &'a mut Diagnostics,
}

impl ResolveOperand for AppResolver<'_> {
    fn resolve(&mut self, name: &'static str, kind: OperandKind, devices: Devices) -> Option<AppOperand> {
        let operand = self.operands.next()?;
        let resolved = match resolve_kind(operand, kind, self.width) {
            Ok(resolved) => resolved,
            Err(diagnostic) => {
                self.diagnostics.push(diagnostic);
                return None;
            }
        };
        let class = class_of(&resolved);
        if !devices.contains(class) {
            self.diagnostics.push(
                Diagnostic::new(
                    Code::OperandKind,
                    operand.span,
                    format!(
                        "{} does not take {} as ({})",
                        self.mnemonic,
                        class.name(),
                        name.to_ascii_uppercase()
                    ),
                )
                .with_label("not in this operand's device table")
                .with_note(format!("({}) takes {devices}", name.to_ascii_uppercase())),
            );
            return None;
        }
        Some(resolved)
    }
}
