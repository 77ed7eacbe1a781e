//! Instructions and devices as text, from the checked program: device
//! names as a vendor editor shows them (`X000`, `D100Z0`, `K4M0`,
//! `U0\G10`), and every instruction's mnemonic and operands, for the
//! diagram and for giving the program back as IL.

use ladder_front::isa::{CompareOp, OperandKind, Role};
use ladder_front::program::{
    Address, AppInstruction, AppOperand, BitRef, CheckedProgram, Contact, CounterRef, Element, Line, Logic, Op, Output,
    RangeEnd, ResetTarget, WordRef,
};
use ladder_runtime::device::BUFFER_WORDS_PER_UNIT;
use ladder_runtime::{BitArea, Width, WordArea};

/// The index modification of an address: `Z0`, `V3` or `[D2]`.
fn modifier(address: Address) -> String {
    match address.index_register {
        None => String::new(),
        Some(register) => match register.area {
            WordArea::Index if register.number % 2 == 1 => format!("V{}", register.number / 2),
            WordArea::Index => format!("Z{}", register.number / 2),
            WordArea::D
            | WordArea::Sd
            | WordArea::R
            | WordArea::TimerValue
            | WordArea::CounterValue
            | WordArea::Buffer => format!("[{}{}]", register.area.prefix(), register.number),
        },
    }
}

/// A bit device's name: X and Y in three octal digits as GX Works2 shows
/// them.
fn bit_device(area: BitArea, number: u32) -> String {
    match area {
        BitArea::X | BitArea::Y => format!("{}{number:03o}", area.prefix()),
        BitArea::M | BitArea::S | BitArea::Sm | BitArea::TimerContact | BitArea::CounterContact => {
            format!("{}{number}", area.prefix())
        }
    }
}

pub fn bit_name(bit: &BitRef) -> String {
    match *bit {
        BitRef::Device(area, address) => format!("{}{}", bit_device(area, address.index), modifier(address)),
        BitRef::WordBit(area, address, b) => format!("{}.{b:X}{}", word_device(area, address.index), modifier(address)),
    }
}

fn word_device(area: WordArea, number: u32) -> String {
    match area {
        WordArea::Buffer => format!(
            "U{}\\G{}",
            number / BUFFER_WORDS_PER_UNIT,
            number % BUFFER_WORDS_PER_UNIT
        ),
        WordArea::D | WordArea::Sd | WordArea::R | WordArea::TimerValue | WordArea::CounterValue | WordArea::Index => {
            area.device_name(number)
        }
    }
}

pub fn word_name(word: &WordRef) -> String {
    match *word {
        WordRef::Constant(value) => format!("K{value}"),
        WordRef::Word(area, address) => format!("{}{}", word_device(area, address.index), modifier(address)),
        WordRef::WideCounter(address) => format!("C{}{}", address.index, modifier(address)),
        WordRef::Digits(area, address, digits) => {
            format!("K{digits}{}{}", bit_device(area, address.index), modifier(address))
        }
    }
}

/// A real number constant: the shortest decimal that reads back exactly.
fn real_name(bits: i32) -> String {
    format!("E{:?}", f32::from_bits(bits as u32))
}

fn timer_name(address: Address) -> String {
    format!("T{}{}", address.index, modifier(address))
}

fn counter_name(address: Address) -> String {
    format!("C{}{}", address.index, modifier(address))
}

fn operand_name(operand: &AppOperand, kind: OperandKind) -> String {
    match operand {
        AppOperand::Word(WordRef::Constant(bits)) if kind == OperandKind::RealSource => real_name(*bits),
        AppOperand::Word(word) | AppOperand::Element(Element::Word(word)) => word_name(word),
        AppOperand::Bit(bit) | AppOperand::Element(Element::Bits(bit)) | AppOperand::RangeEnd(RangeEnd::Bit(bit)) => {
            bit_name(bit)
        }
        AppOperand::RangeEnd(RangeEnd::Word(area, address)) => word_name(&WordRef::Word(*area, *address)),
        AppOperand::RangeEnd(RangeEnd::Timer(address)) | AppOperand::Timer(address) => timer_name(*address),
        AppOperand::RangeEnd(RangeEnd::Counter(address)) | AppOperand::Counter(CounterRef(address)) => {
            counter_name(*address)
        }
        AppOperand::Digits(group) => word_name(&WordRef::Digits(group.area, group.address, group.digits)),
    }
}

/// An application instruction's mnemonic as written (`DMOVP`).
fn app_mnemonic(app: &AppInstruction) -> String {
    let spec = app.args.op().spec();
    let base = match (app.width, spec.wide_name) {
        (Width::Double, Some(wide)) => wide,
        (Width::Single, _) | (Width::Double, None) => spec.name,
    };
    if app.pulse_slot.is_some() {
        format!("{base}P")
    } else {
        base.to_string()
    }
}

fn app_operands(app: &AppInstruction) -> Vec<String> {
    app.args
        .operands()
        .iter()
        .zip(app.args.op().spec().operands)
        .map(|(operand, decl)| operand_name(operand, decl.kind))
        .collect()
}

fn count_suffix(count: u32) -> Vec<String> {
    if count > 1 {
        vec![format!("K{count}")]
    } else {
        Vec::new()
    }
}

fn compare_symbol(op: CompareOp) -> &'static str {
    op.symbol()
}

/// A contact's mnemonic in `role` and its operands.
fn contact(contact: &Contact, role: Role) -> (String, Vec<String>) {
    let (open, closed, rising, falling) = match role {
        Role::Load => ("LD", "LDI", "LDP", "LDF"),
        Role::And => ("AND", "ANI", "ANDP", "ANDF"),
        Role::Or => ("OR", "ORI", "ORP", "ORF"),
    };
    match contact {
        Contact::Level { bit, closed: false } => (open.to_string(), vec![bit_name(bit)]),
        Contact::Level { bit, closed: true } => (closed.to_string(), vec![bit_name(bit)]),
        Contact::Edge {
            bit, falling: false, ..
        } => (rising.to_string(), vec![bit_name(bit)]),
        Contact::Edge { bit, falling: true, .. } => (falling.to_string(), vec![bit_name(bit)]),
        Contact::Constant(on) => ((if *on { "ATI" } else { "AFI" }).to_string(), Vec::new()),
        Contact::Compare { op, width, left, right } => {
            let double = if *width == Width::Double { "D" } else { "" };
            (
                format!("{open}{double}{}", compare_symbol(*op)),
                vec![word_name(left), word_name(right)],
            )
        }
    }
}

/// The instruction at `index` as mnemonic and operands; `role` decides
/// the form of a contact (LD, AND or OR).
pub fn instruction(program: &CheckedProgram, index: usize, role: Role) -> (String, Vec<String>) {
    let Some(instruction) = program.instructions.get(index) else {
        return (String::new(), Vec::new());
    };
    let words = |mnemonic: &str, operands: Vec<String>| (mnemonic.to_string(), operands);
    match &instruction.op {
        Op::Load { contact: c, .. } | Op::And(c) | Op::Or(c) => contact(c, role),
        Op::Logic(Logic::AndBlock) => words("ANB", Vec::new()),
        Op::Logic(Logic::OrBlock) => words("ORB", Vec::new()),
        Op::Logic(Logic::BranchPush) => words("MPS", Vec::new()),
        Op::Logic(Logic::BranchRead) => words("MRD", Vec::new()),
        Op::Logic(Logic::BranchPop) => words("MPP", Vec::new()),
        Op::Logic(Logic::Invert) => words("INV", Vec::new()),
        Op::Logic(Logic::ResultEdge { falling, .. }) => words(if *falling { "MEF" } else { "MEP" }, Vec::new()),
        Op::Output(output) => match output {
            Output::Coil(bit) => words("OUT", vec![bit_name(bit)]),
            Output::Timer { timer, preset } => words("OUT", vec![format!("T{timer}"), word_name(preset)]),
            Output::Counter { counter, preset } => words("OUT", vec![format!("C{counter}"), word_name(preset)]),
            Output::Set {
                target,
                count,
                written_out,
                ..
            } => {
                let mut operands = vec![bit_name(target)];
                operands.extend(count_suffix(*count));
                words(if *written_out { "OUT" } else { "SET" }, operands)
            }
            Output::Reset { target, count } => {
                let mut operands = vec![match target {
                    ResetTarget::Bit(bit) => bit_name(bit),
                    ResetTarget::Timer(n) => format!("T{n}"),
                    ResetTarget::Counter(n) => format!("C{n}"),
                    ResetTarget::Word(area, address) => word_name(&WordRef::Word(*area, *address)),
                }];
                operands.extend(count_suffix(*count));
                words("RST", operands)
            }
            Output::Pulse { target, sense, .. } => {
                let mnemonic = match sense {
                    ladder_front::isa::Sense::Falling => "PLF",
                    ladder_front::isa::Sense::Open
                    | ladder_front::isa::Sense::Closed
                    | ladder_front::isa::Sense::Rising => "PLS",
                };
                words(mnemonic, vec![bit_name(target)])
            }
            Output::StateJump { state } => words("ST", vec![format!("S{state}")]),
            Output::MasterControl { level, relay } => words("MC", vec![format!("N{level}"), bit_name(relay)]),
            Output::App(app) => (app_mnemonic(app), app_operands(app)),
        },
        Op::Jump { label, .. } => words("CJ", vec![format!("P{label}")]),
        Op::Call { subroutine, slot } => {
            let label = program.subroutines.get(*subroutine).map_or(0, |s| s.label);
            words(if slot.is_some() { "CALLP" } else { "CALL" }, vec![format!("P{label}")])
        }
        Op::Line(Line::Label { number }) => words(&format!("P{number}"), Vec::new()),
        Op::Line(Line::MasterControlReset { level }) => words("MCR", vec![format!("N{level}")]),
        Op::Line(Line::StlBegin { block }) => {
            let state = program.stl_blocks.get(*block).map_or(0, |b| b.state);
            words("STL", vec![format!("S{state}")])
        }
        Op::Line(Line::StlEnd) => words("RET", Vec::new()),
        Op::Line(Line::MainEnd) => words("FEND", Vec::new()),
        Op::Line(Line::SubroutineReturn) => words("SRET", Vec::new()),
        Op::Line(Line::LoopStart { count, .. }) => words("FOR", vec![word_name(count)]),
        Op::Line(Line::LoopEnd { .. }) => words("NEXT", Vec::new()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ladder_front::program::IndexRegister;

    #[test]
    fn names_as_an_editor_shows_them() {
        let x = BitRef::Device(BitArea::X, Address::fixed(8));
        assert_eq!(bit_name(&x), "X010");
        let indexed = Address {
            index: 100,
            index_register: Some(IndexRegister {
                area: WordArea::Index,
                number: 3,
            }),
        };
        assert_eq!(word_name(&WordRef::Word(WordArea::D, indexed)), "D100V1");
        assert_eq!(
            word_name(&WordRef::Word(WordArea::Buffer, Address::fixed(32_767 + 5))),
            "U1\\G5"
        );
        assert_eq!(word_name(&WordRef::Digits(BitArea::M, Address::fixed(0), 4)), "K4M0");
        assert_eq!(real_name(1.5f32.to_bits() as i32), "E1.5");
        assert_eq!(real_name((-2.5e-7f32).to_bits() as i32), "E-2.5e-7");
    }
}
