//! Operands of application instructions: each declared operand resolved by
//! its kind, then checked against its device table.

use super::devices::Resolved;
use super::{operands, words};
use crate::diagnostics::{Code, Diagnostic, Diagnostics};
use crate::isa::app::ResolveOperand;
use crate::isa::{DeviceClass, Devices, OperandKind};
use crate::program::{AppOperand, BitRef, Element, RangeEnd, WordRef};
use crate::syntax::Operand;
use ladder_runtime::{BitArea, Width, WordArea};

/// The device class of a word operand.
pub fn word_class(word: &WordRef) -> DeviceClass {
    match word {
        WordRef::Constant(_) => DeviceClass::Constant,
        WordRef::Word(area, _) => match area {
            // Where an FX device table takes D it takes V and Z too.
            WordArea::D | WordArea::Index => DeviceClass::D,
            WordArea::Sd => DeviceClass::Sd,
            WordArea::R => DeviceClass::R,
            WordArea::TimerValue => DeviceClass::T,
            WordArea::CounterValue => DeviceClass::C,
            WordArea::Buffer => DeviceClass::Buffer,
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

fn class_of(operand: &AppOperand) -> DeviceClass {
    match operand {
        AppOperand::Word(word) | AppOperand::Element(Element::Word(word)) => word_class(word),
        AppOperand::Bit(bit) | AppOperand::Element(Element::Bits(bit)) | AppOperand::RangeEnd(RangeEnd::Bit(bit)) => {
            bit_class(bit)
        }
        AppOperand::RangeEnd(RangeEnd::Word(area, address)) => word_class(&WordRef::Word(*area, *address)),
        AppOperand::RangeEnd(RangeEnd::Timer(_)) => DeviceClass::T,
        AppOperand::RangeEnd(RangeEnd::Counter(_)) => DeviceClass::C,
        AppOperand::Digits(group) => word_class(&WordRef::Digits(group.area, group.address, group.digits)),
        AppOperand::Timer(_) => DeviceClass::T,
        AppOperand::Counter(_) => DeviceClass::C,
    }
}

/// Resolves one operand by its kind, at the instruction's width. An index
/// register is one word: it cannot start a run of words (BMOV, MEAN, ...),
/// whose next word would be the other register of its pair.
fn resolve_kind(operand: &Operand, kind: OperandKind, width: Width) -> Resolved<AppOperand> {
    let resolved = resolve_any(operand, kind, width)?;
    let runs_on = match kind {
        OperandKind::BlockSource | OperandKind::BlockDestination | OperandKind::TableEnd | OperandKind::ByteSource => {
            true
        }
        // A word element (ENCO S, DECO D) is one word of 16 bits.
        OperandKind::ElementSource
        | OperandKind::ElementDestination
        | OperandKind::Source
        | OperandKind::Count
        | OperandKind::Destination
        | OperandKind::Modified
        | OperandKind::DoubleDestination
        | OperandKind::BitDestination
        | OperandKind::BitSource
        | OperandKind::BitModified
        | OperandKind::BitTriple
        | OperandKind::RangeEnd
        | OperandKind::DigitSource
        | OperandKind::DigitDestination
        | OperandKind::Timer
        | OperandKind::RealSource
        | OperandKind::RealDestination
        | OperandKind::RealModified
        | OperandKind::HighSpeedCounter
        | OperandKind::CounterPair => false,
    };
    let index_register = matches!(resolved, AppOperand::Word(WordRef::Word(WordArea::Index, _)));
    if runs_on && index_register {
        return Err(Diagnostic::new(
            Code::OperandKind,
            operand.span,
            "an index register is a single word; this operand is a run of words",
        )
        .with_label("index register")
        .with_note("use data registers (D) for tables and blocks"));
    }
    Ok(resolved)
}

fn resolve_any(operand: &Operand, kind: OperandKind, width: Width) -> Resolved<AppOperand> {
    Ok(match kind {
        OperandKind::Source => AppOperand::Word(words::word_source(operand, width)?),
        OperandKind::Count => AppOperand::Word(words::word_source(operand, Width::Single)?),
        OperandKind::Destination | OperandKind::Modified => {
            AppOperand::Word(words::word_destination(operand, width, 1)?)
        }
        OperandKind::DoubleDestination => AppOperand::Word(words::word_destination(operand, width, 2)?),
        OperandKind::BlockSource => AppOperand::Word(words::word_device_source(operand, width)?),
        OperandKind::BlockDestination => AppOperand::Word(words::word_destination(operand, width, 1)?),
        OperandKind::BitDestination | OperandKind::BitModified => AppOperand::Bit(operands::bit_target(operand)?),
        OperandKind::BitSource => AppOperand::Bit(operands::bit_source(operand)?),
        OperandKind::BitTriple => AppOperand::Bit(operands::bit_triple(operand)?),
        OperandKind::ElementSource => AppOperand::Element(operands::element(operand, false)?),
        OperandKind::ElementDestination => AppOperand::Element(operands::element(operand, true)?),
        OperandKind::RangeEnd => AppOperand::RangeEnd(operands::range_end(operand)?),
        OperandKind::DigitSource => {
            AppOperand::Digits(words::digit_group(words::word_source(operand, width)?, operand)?)
        }
        OperandKind::DigitDestination => AppOperand::Digits(words::digit_group(
            words::word_destination(operand, width, 1)?,
            operand,
        )?),
        OperandKind::TableEnd => AppOperand::Word(words::table_end(operand, width)?),
        OperandKind::ByteSource => AppOperand::Word(words::byte_source(operand)?),
        OperandKind::Timer => AppOperand::Timer(operands::timer(operand)?),
        OperandKind::RealSource => AppOperand::Word(words::real_source(operand)?),
        OperandKind::RealDestination | OperandKind::RealModified => {
            AppOperand::Word(words::word_destination(operand, Width::Double, 1)?)
        }
        OperandKind::HighSpeedCounter => AppOperand::Counter(operands::high_speed_counter(operand)?),
        OperandKind::CounterPair => AppOperand::Counter(operands::counter_pair(operand)?),
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
        debug_assert!(
            crate::isa::app::fits(kind, resolved),
            "{kind:?} resolved to {resolved:?}, which is not its type"
        );
        // An E constant is resolved to its bits like a K; its class is its own.
        let class = match operand.syntax {
            crate::syntax::OperandSyntax::Real(_) => DeviceClass::Real,
            crate::syntax::OperandSyntax::Constant(_) | crate::syntax::OperandSyntax::Device(_) => class_of(&resolved),
        };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::operand::parse_operand;

    /// Every kind resolves to the type `AppArgs` gives it.
    #[test]
    fn every_kind_resolves_to_its_type() {
        let samples: &[(OperandKind, &[&str])] = &[
            (OperandKind::Source, &["K5", "D0", "K4M0", "TN0"]),
            (OperandKind::Count, &["K5", "D1"]),
            (OperandKind::Destination, &["D0", "K4Y0"]),
            (OperandKind::Modified, &["D0"]),
            (OperandKind::DoubleDestination, &["D0", "K4M0"]),
            (OperandKind::BlockSource, &["D0", "K1X0"]),
            (OperandKind::BlockDestination, &["R0"]),
            (OperandKind::BitDestination, &["M0", "D0.3"]),
            (OperandKind::BitSource, &["X0", "M0", "D0.3"]),
            (OperandKind::BitModified, &["Y0", "D0.3"]),
            (OperandKind::BitTriple, &["M0"]),
            (OperandKind::ElementSource, &["X0", "D0", "K3"]),
            (OperandKind::ElementDestination, &["M0", "D0"]),
            (OperandKind::RangeEnd, &["M0", "T3", "C4", "D5", "D0.1"]),
            (OperandKind::DigitSource, &["K4X0"]),
            (OperandKind::DigitDestination, &["K2M0"]),
            (OperandKind::TableEnd, &["D0", "R5"]),
            (OperandKind::ByteSource, &["D100", "K4M0"]),
            (OperandKind::Timer, &["T3", "T0[D1]"]),
            (OperandKind::RealSource, &["E1.5", "K3", "H10", "D0", "R2"]),
            (OperandKind::RealDestination, &["D0", "R4"]),
            (OperandKind::RealModified, &["D10"]),
            (OperandKind::HighSpeedCounter, &["C235", "C255"]),
            (OperandKind::CounterPair, &["C0", "C198"]),
        ];
        for &kind in OperandKind::ALL {
            let (_, texts) = samples
                .iter()
                .find(|(k, _)| *k == kind)
                .expect("a sample for every kind");
            for text in *texts {
                let operand = parse_operand(text, 0).unwrap();
                let resolved =
                    resolve_kind(&operand, kind, Width::Single).unwrap_or_else(|d| panic!("{kind:?} {text}: {d:?}"));
                assert!(crate::isa::app::fits(kind, resolved), "{kind:?} {text}: {resolved:?}");
            }
        }
    }
}
