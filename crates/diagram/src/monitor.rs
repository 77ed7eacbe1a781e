//! What the monitor shows on the drawing, as GX Works2's monitor mode
//! shows it: for each element of the running program whether it passes
//! power (a contact) or is ON (a coil, the bit of SET/RST, an active STL
//! step), whether its device is forced, and the values of its word
//! operands. Everything is read from an image; nothing is written, and an
//! index register out of range shows `?` instead of recording an error.

use ladder_front::isa::OperandKind;
use ladder_front::program::{
    AppOperand, BitRef, CheckedProgram, Contact, CounterRef, LineReads, Op, Output, ResetTarget, WordRef,
};
use ladder_interp::access::{bit_place, effective_index, resolve_word};
use ladder_runtime::{BitArea, Memory, Place, Width};

/// One element as the monitor draws it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ElementState {
    /// A contact passes power, a coil or bit is ON (`None`: nothing to show
    /// as ON or OFF, such as an instruction box).
    pub on: Option<bool>,
    /// The element's bit device is forced.
    pub forced: bool,
    /// The values for the drawing's value slots, in slot order (empty: no
    /// value under that operand, such as a constant).
    pub values: Vec<String>,
}

/// The state of the element for instruction `index` of `program` in `mem`.
pub fn element_state(program: &CheckedProgram, index: usize, mem: &Memory) -> ElementState {
    let Some(instruction) = program.instructions.get(index) else {
        return ElementState::default();
    };
    let bit = |bit: &BitRef| read_bit(mem, bit);
    match &instruction.op {
        Op::Load { contact, .. } | Op::And(contact) | Op::Or(contact) => match contact {
            Contact::Level { bit: b, closed } => ElementState {
                on: bit(b).map(|on| on != *closed),
                forced: forced(mem, b),
                values: Vec::new(),
            },
            Contact::Edge { bit: b, .. } => ElementState {
                on: None,
                forced: forced(mem, b),
                values: vec![bit(b).map_or("?".into(), |on| u8::from(on).to_string())],
            },
            Contact::Constant(on) => ElementState {
                on: Some(*on),
                ..ElementState::default()
            },
            Contact::Compare { op, width, left, right } => {
                let (a, b) = (read_word(mem, left, *width), read_word(mem, right, *width));
                ElementState {
                    on: a.zip(b).map(|(a, b)| op.holds(i64::from(a), i64::from(b))),
                    forced: false,
                    values: vec![shown(left, a), shown(right, b)],
                }
            }
        },
        Op::Output(output) => match output {
            Output::Coil(b) => ElementState {
                on: bit(b),
                forced: forced(mem, b),
                values: Vec::new(),
            },
            Output::Timer { timer, .. } => ElementState {
                on: mem.timer_coil_was_on.get(*timer as usize).map(|&on| on != 0),
                forced: mem.forced(BitArea::TimerContact, *timer).is_some(),
                values: vec![mem
                    .timer_value
                    .get(*timer as usize)
                    .map_or("?".into(), |v| v.to_string())],
            },
            Output::Counter { counter, .. } => ElementState {
                on: mem.counter_coil_was_on.get(*counter as usize).map(|&on| on != 0),
                forced: mem.forced(BitArea::CounterContact, *counter).is_some(),
                values: vec![counter_value(mem, *counter)],
            },
            // A box is not ON or OFF (its rung's power is not kept): the
            // value of the bit it drives stands under it.
            Output::Set { target: b, .. } | Output::Pulse { target: b, .. } => ElementState {
                on: None,
                forced: forced(mem, b),
                values: vec![bit(b).map_or("?".into(), |on| u8::from(on).to_string())],
            },
            Output::Reset { target, .. } => match target {
                ResetTarget::Bit(b) => ElementState {
                    on: None,
                    forced: forced(mem, b),
                    values: vec![bit(b).map_or("?".into(), |on| u8::from(on).to_string())],
                },
                ResetTarget::Timer(n) => ElementState {
                    on: None,
                    forced: false,
                    values: vec![mem.timer_value.get(*n as usize).map_or("?".into(), |v| v.to_string())],
                },
                ResetTarget::Counter(n) => ElementState {
                    on: None,
                    forced: false,
                    values: vec![counter_value(mem, *n)],
                },
                ResetTarget::Word(area, address) => ElementState {
                    on: None,
                    forced: false,
                    values: vec![shown(
                        &WordRef::Word(*area, *address),
                        read_word(mem, &WordRef::Word(*area, *address), Width::Single),
                    )],
                },
            },
            Output::StateJump { state } => ElementState {
                values: vec![mem.s.get(*state as usize).map_or("?".into(), |v| v.to_string())],
                ..ElementState::default()
            },
            Output::MasterControl { relay, .. } => ElementState {
                on: None,
                forced: forced(mem, relay),
                // Under the level N nothing; under the relay its value.
                values: vec![
                    String::new(),
                    bit(relay).map_or("?".into(), |on| u8::from(on).to_string()),
                ],
            },
            Output::App(app) => {
                let declared = app.args.op().spec().operands;
                let values = app
                    .args
                    .operands()
                    .iter()
                    .zip(declared)
                    .map(|(operand, decl)| operand_value(mem, operand, decl.kind, app.width))
                    .collect();
                ElementState {
                    on: None,
                    forced: false,
                    values,
                }
            }
        },
        Op::Line(line) => match line.reads() {
            LineReads::State(block) => ElementState {
                on: program
                    .stl_blocks
                    .get(block)
                    .and_then(|b| mem.s.get(b.state as usize))
                    .map(|&on| on != 0),
                ..ElementState::default()
            },
            LineReads::Word(count) => ElementState {
                values: vec![shown(count, read_word(mem, count, Width::Single))],
                ..ElementState::default()
            },
            LineReads::Nothing => ElementState::default(),
        },
        Op::Logic(_) | Op::Jump { .. } | Op::Call { .. } => ElementState::default(),
    }
}

fn bit_index(mem: &Memory, bit: &BitRef) -> Option<(BitArea, u32)> {
    let BitRef::Device(area, address) = *bit else {
        return None;
    };
    let index = effective_index(mem, address);
    (0..i64::from(area.count()))
        .contains(&index)
        .then_some((area, index as u32))
}

fn read_bit(mem: &Memory, bit: &BitRef) -> Option<bool> {
    let (address, count) = match *bit {
        BitRef::Device(area, address) => (address, area.count()),
        BitRef::WordBit(area, address, _) => (address, area.count()),
    };
    let index = effective_index(mem, address);
    (0..i64::from(count))
        .contains(&index)
        .then(|| bit_place(*bit, index as u32).read(mem, Width::Single) != 0)
}

fn forced(mem: &Memory, bit: &BitRef) -> bool {
    bit_index(mem, bit).is_some_and(|(area, index)| mem.forced(area, index).is_some())
}

fn read_word(mem: &Memory, word: &WordRef, width: Width) -> Option<i32> {
    resolve_word(mem, *word, width, 1).map(|place| place.read(mem, width))
}

fn counter_value(mem: &Memory, counter: u32) -> String {
    let value = if counter >= ladder_runtime::device::FIRST_WIDE_COUNTER {
        Place::WideCounter(counter).read(mem, Width::Double)
    } else {
        match mem.counter_value.get(counter as usize) {
            Some(&v) => i32::from(v),
            None => return "?".into(),
        }
    };
    value.to_string()
}

/// A word's value for its slot: nothing under a constant (its text is the
/// value), `?` out of range.
fn shown(word: &WordRef, value: Option<i32>) -> String {
    match (word, value) {
        (WordRef::Constant(_), _) => String::new(),
        (_, Some(value)) => value.to_string(),
        (_, None) => "?".into(),
    }
}

/// The value under one operand of an instruction box.
fn operand_value(mem: &Memory, operand: &AppOperand, kind: OperandKind, width: Width) -> String {
    match operand {
        AppOperand::Word(word) => {
            let real = matches!(
                kind,
                OperandKind::RealSource | OperandKind::RealDestination | OperandKind::RealModified
            );
            let width = if kind == OperandKind::Count {
                Width::Single
            } else {
                width
            };
            match (word, real) {
                (WordRef::Constant(_), _) => String::new(),
                (_, true) => read_word(mem, word, Width::Double).map_or("?".into(), |bits| {
                    let value = f32::from_bits(bits as u32);
                    format!("{value:?}")
                }),
                (_, false) => shown(word, read_word(mem, word, width)),
            }
        }
        AppOperand::Bit(bit) => read_bit(mem, bit).map_or("?".into(), |on| u8::from(on).to_string()),
        AppOperand::Timer(address) => {
            let index = effective_index(mem, *address);
            usize::try_from(index)
                .ok()
                .and_then(|i| mem.timer_value.get(i))
                .map_or("?".into(), |v| v.to_string())
        }
        AppOperand::Counter(CounterRef(address)) => {
            let index = effective_index(mem, *address);
            u32::try_from(index).map_or("?".into(), |n| counter_value(mem, n))
        }
        AppOperand::Digits(group) => shown(
            &WordRef::Digits(group.area, group.address, group.digits),
            read_word(mem, &WordRef::Digits(group.area, group.address, group.digits), width),
        ),
        AppOperand::Element(_) | AppOperand::RangeEnd(_) => String::new(),
    }
}
