//! The FMU's variables: one per device the program uses, named as ladderc
//! names devices (`X0`, `Y2`, `M5`, `D100`, `T0` a timer's contact, `TN0`
//! its value, `CN200` a 32-bit counter). Which devices: those of the
//! program's compact image (what the program and the machine around it
//! touch). Which way: X are inputs and Y outputs, as wired; timers' and
//! counters' contacts and values, special relays and registers (SM, SD,
//! M8000 and D8000 up) are outputs (the scan writes them); any
//! other device is an output when the program writes it (the optimised
//! IR's stores, fills, the runtime helpers' declared writes and their
//! destination places, a run from a place taken to the end of its area),
//! else an input the co-simulation may set.

use ladder_front::isa::OperandKind;
use ladder_front::program::{Address, AppOperand, CheckedProgram, Op, Output, WordRef};
use ladder_ir::image::{compact_layout, device_name};
use ladder_ir::{Effect, Function, Index, Inst, Program, Space, Value};
use ladder_runtime::capi::{c_device, LadderDevice};
use ladder_runtime::device::FIRST_WIDE_COUNTER;
use ladder_runtime::helpers::{Param, Writes};
use ladder_runtime::layout::Array;
use ladder_runtime::special::{D_ERROR_CODE, M_OPERATION_ERROR};
use ladder_runtime::Place;
use ladder_runtime::{Basic, BitArea, Width, WordArea};
use std::collections::{HashMap, HashSet};

/// The first special relay (M8000) and register (D8000).
const SPECIAL_FIRST: u32 = 8000;

/// An area the program addresses at run time is in the image whole; the FMU
/// publishes at most this many of its devices (and as many of its special
/// devices, M8000 and D8000 up).
pub const MOST_PER_AREA: u32 = 1024;

/// A variable's type, as FMI 3.0 names it (FMI 2.0: Boolean, Integer).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarType {
    Boolean,
    Int16,
    Int32,
    /// A 32-bit pair of words (n+1, n), as the D instructions use it.
    Pair,
    /// A real number in a pair of words, as the E instructions use it.
    Real,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Input,
    Output,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variable {
    pub name: String,
    /// The kind the C API reads and writes it as.
    pub kind: LadderDevice,
    /// Its number for the C API.
    pub number: u32,
    pub ty: VarType,
    pub causality: Causality,
}

/// How element `n` of a device array becomes a variable: the device it
/// is, its type, and whether the scan writes every element of the array.
/// `None` for the modules' buffer memory (the host's, 64K words a module)
/// and the scan's own bookkeeping.
fn published(array: Array, n: u32) -> Option<(Basic, VarType, bool)> {
    if let Some(area) = BitArea::ALL.into_iter().find(|&area| Array::of_bits(area) == array) {
        let scan_writes = matches!(
            area,
            BitArea::Y | BitArea::Sm | BitArea::TimerContact | BitArea::CounterContact
        );
        return Some((Basic::Bit(area, n), VarType::Boolean, scan_writes));
    }
    if array == Array::WideCounterValue {
        return Some((Basic::WideCounter(n.max(FIRST_WIDE_COUNTER)), VarType::Int32, true));
    }
    let area = WordArea::ALL
        .into_iter()
        .find(|&area| area != WordArea::Buffer && Array::of_words(area) == array)?;
    let scan_writes = matches!(area, WordArea::Sd | WordArea::TimerValue | WordArea::CounterValue);
    Some((Basic::Word(area, n), VarType::Int16, scan_writes))
}

/// What the program writes: elements, whole arrays, or everything.
#[derive(Default)]
struct Written {
    elements: HashSet<(Array, u32)>,
    arrays: HashSet<Array>,
    /// Runs to the end of their array: (array, first).
    starts: Vec<(Array, u32)>,
    everything: bool,
}

impl Written {
    fn of(program: &Program) -> Written {
        let mut written = Written::default();
        for function in std::iter::once(&program.main).chain(&program.subroutines) {
            written.function(function);
        }
        written
    }

    fn function(&mut self, function: &Function) {
        // Helpers take their places as constants the lowering packed.
        let constants: HashMap<Value, i64> = function
            .blocks
            .iter()
            .flat_map(|block| &block.insts)
            .filter_map(|(value, inst)| {
                if let (Some(value), Inst::Const { value: constant, .. }) = (value, inst) {
                    Some((*value, *constant))
                } else {
                    None
                }
            })
            .collect();
        for block in &function.blocks {
            for (_, inst) in &block.insts {
                match inst.effect() {
                    Effect::Store(span, _) | Effect::Fill(span) => self.span(span.space, span.start, span.count),
                    Effect::Helper(helper, args) => {
                        let decl = helper.decl();
                        for writes in decl.writes {
                            self.helper(*writes);
                        }
                        for ((_, param), arg) in decl.params.iter().zip(args) {
                            if *param == Param::DestinationPlace {
                                let place = constants.get(arg).and_then(|&packed| Place::unpack(packed as u32));
                                self.destination(place);
                            }
                        }
                    }
                    Effect::OperationError => self.operation_error(),
                    Effect::Pure | Effect::ReadsLocal | Effect::WritesLocal | Effect::Load(_) | Effect::Subroutine => {}
                }
            }
        }
    }

    fn span(&mut self, space: Space, start: Index, count: u32) {
        let array = space.array();
        match start {
            Index::Fixed(n) => self
                .elements
                .extend((n..n.saturating_add(count.max(1))).map(|n| (array, n))),
            Index::Dynamic(_) => {
                self.arrays.insert(array);
            }
        }
    }

    /// A helper's destination place: a run from it whose length the
    /// helper's other arguments give, so taken to the end of its area; a
    /// place not known here may be anything.
    fn destination(&mut self, place: Option<Place>) {
        match place {
            Some(Place::Word(area, n)) => self.from(Array::of_words(area), n),
            Some(Place::WordBit(area, bit)) => self.from(Array::of_words(area), bit / 16),
            Some(Place::Bit(area, n)) => self.from(Array::of_bits(area), n),
            Some(Place::Digits(area, n, digits)) => {
                let array = Array::of_bits(area);
                self.elements
                    .extend((n..n.saturating_add(4 * u32::from(digits))).map(|n| (array, n)));
            }
            // The 32-bit counters are outputs anyway; a constant is nowhere.
            Some(Place::WideCounter(_) | Place::Constant(_)) => {}
            None => self.everything = true,
        }
    }

    /// Elements `n` to the end of `array`.
    fn from(&mut self, array: Array, n: u32) {
        self.starts.push((array, n));
    }

    fn operation_error(&mut self) {
        self.elements.insert((Array::M, M_OPERATION_ERROR));
        self.elements.insert((Array::D, D_ERROR_CODE));
        self.elements.insert((Array::D, ladder_runtime::special::D_ERROR_LINE));
    }

    fn helper(&mut self, writes: Writes) {
        match writes {
            // The scan's own: timers and counters are outputs anyway.
            Writes::Timers | Writes::Counters | Writes::StlBookkeeping => {}
            Writes::OperationError => self.operation_error(),
            Writes::Bits(area) => {
                self.arrays.insert(Array::of_bits(area));
            }
            Writes::Image => self.everything = true,
        }
    }

    fn contains(&self, array: Array, n: u32) -> bool {
        self.everything
            || self.arrays.contains(&array)
            || self.elements.contains(&(array, n))
            || self.starts.iter().any(|&(a, first)| a == array && n >= first)
    }
}

/// How an instruction operand of `kind` in an instruction of `width` uses a
/// word: as a 32-bit pair, a real number, or neither.
fn wide_use(kind: OperandKind, width: Width) -> Option<VarType> {
    match kind {
        OperandKind::RealSource | OperandKind::RealDestination | OperandKind::RealModified => Some(VarType::Real),
        OperandKind::Source | OperandKind::Destination | OperandKind::Modified | OperandKind::DoubleDestination => {
            match width {
                Width::Double => Some(VarType::Pair),
                Width::Single => None,
            }
        }
        OperandKind::Count
        | OperandKind::BlockSource
        | OperandKind::BlockDestination
        | OperandKind::BitDestination
        | OperandKind::BitSource
        | OperandKind::BitModified
        | OperandKind::BitTriple
        | OperandKind::ElementSource
        | OperandKind::ElementDestination
        | OperandKind::RangeEnd
        | OperandKind::DigitSource
        | OperandKind::DigitDestination
        | OperandKind::TableEnd
        | OperandKind::ByteSource
        | OperandKind::Timer
        | OperandKind::HighSpeedCounter
        | OperandKind::CounterPair => None,
    }
}

/// The word pairs of D and R the program's instructions use as 32-bit
/// values or real numbers at fixed addresses: (area, first word, type).
fn wide_words(checked: &CheckedProgram) -> Vec<(WordArea, u32, VarType)> {
    let mut found = Vec::new();
    for instruction in &checked.instructions {
        let Op::Output(Output::App(app)) = &instruction.op else {
            continue;
        };
        for (operand, decl) in app.args.operands().into_iter().zip(app.args.op().spec().operands) {
            let AppOperand::Word(WordRef::Word(
                area @ (WordArea::D | WordArea::R),
                Address {
                    index,
                    index_register: None,
                },
            )) = operand
            else {
                continue;
            };
            if let Some(ty) = wide_use(decl.kind, app.width) {
                if !found.contains(&(area, index, ty)) {
                    found.push((area, index, ty));
                }
            }
        }
    }
    found.sort_by_key(|&(area, index, ty)| (area, index, ty == VarType::Real));
    found
}

/// The variables of `checked` (optimised as `ir`), in the order of the
/// runtime's arrays and device numbers; then the pairs and reals.
pub fn variables(checked: &CheckedProgram, ir: &Program) -> Vec<Variable> {
    let layout = compact_layout(checked, ir, &[]);
    let written = Written::of(ir);
    let mut variables = Vec::new();
    let mut names = HashSet::new();
    for array in Array::ALL {
        // Devices published so far: the program's own, and the specials
        // (M8000 and D8000 up), each up to the bound, so that an area
        // indexed at run time keeps its special devices.
        let mut taken = [0u32; 2];
        for run in layout.runs_of(array) {
            for n in run.first..run.first + run.count {
                // M8000 and D8000 up are the machine's: the scan writes them.
                let special = matches!(array, Array::M | Array::D) && n >= SPECIAL_FIRST;
                let counted = &mut taken[usize::from(special)];
                if *counted == MOST_PER_AREA {
                    continue;
                }
                let Some((device, ty, scan_writes)) = published(array, n) else {
                    continue;
                };
                let (kind, number) = c_device(device);
                let name = device_name(array, n);
                // A run's clamped start may repeat a device another run holds.
                if !names.insert(name.clone()) {
                    continue;
                }
                *counted += 1;
                let causality = if array != Array::X && (scan_writes || special || written.contains(array, n)) {
                    Causality::Output
                } else {
                    Causality::Input
                };
                variables.push(Variable {
                    name,
                    kind,
                    number,
                    ty,
                    causality,
                });
            }
        }
    }
    // A pair or real aliases its two words (published above as well).
    for (area, first, ty) in wide_words(checked) {
        let array = Array::of_words(area);
        if first + 1 >= area.count() {
            continue;
        }
        let suffix = match ty {
            VarType::Real => "float",
            VarType::Boolean | VarType::Int16 | VarType::Int32 | VarType::Pair => "32",
        };
        let written = written.contains(array, first) || written.contains(array, first + 1);
        let special = area == WordArea::D && first >= SPECIAL_FIRST;
        let (kind, number) = c_device(Basic::Word(area, first));
        variables.push(Variable {
            name: format!("{}:{suffix}", device_name(array, first)),
            kind,
            number,
            ty,
            causality: if written || special {
                Causality::Output
            } else {
                Causality::Input
            },
        });
    }
    variables
}
