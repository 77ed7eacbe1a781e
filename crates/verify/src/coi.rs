//! The cone of influence: the parts of the image that can influence the
//! devices a property file names, found on the program's IR (the one every
//! back end compiles). A device is in the cone when an instruction that may
//! write a device of the cone reads it, as data (an operand, through SSA
//! values) or as control (a branch deciding whether that instruction runs:
//! control dependence from post-dominators). States that agree on the cone
//! have the same future on it, so the search keys states by the cone alone:
//! the running seconds and the start counter of a motor starter do not
//! multiply the states of its interlock.
//!
//! Where the IR does not say what is read (a subroutine call, a helper that
//! takes places or touches the whole image), there is no cone: the search
//! keys states by the whole compact layout, which is always sound.

use ladder_ir::{BlockId, Effect, Function, Index, Inst, Program, Span, Terminator, Value};
use ladder_runtime::helpers::{Helper, Param};
use ladder_runtime::layout::Array;
use ladder_runtime::place::Place;
use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
use ladder_runtime::{Device, MachineUse};
use rustc_hash::FxHashSet;

/// Elements of the image: one element, or a whole array.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Cone {
    pub elements: FxHashSet<(Array, u32)>,
    pub arrays: FxHashSet<Array>,
}

impl Cone {
    pub fn holds(&self, array: Array, n: u32) -> bool {
        self.arrays.contains(&array) || self.elements.contains(&(array, n))
    }

    fn touches(&self, locations: &Locations) -> bool {
        match locations {
            Locations::Elements(list) => list.iter().any(|&(a, n)| self.holds(a, n)),
            Locations::Arrays(arrays) => arrays
                .iter()
                .any(|a| self.arrays.contains(a) || self.elements.iter().any(|(b, _)| b == a)),
        }
    }

    /// Adds `locations`; true when something was new.
    fn add(&mut self, locations: &Locations) -> bool {
        let mut new = false;
        match locations {
            Locations::Elements(list) => {
                for &(a, n) in list {
                    if !self.holds(a, n) {
                        self.elements.insert((a, n));
                        new = true;
                    }
                }
            }
            Locations::Arrays(arrays) => {
                for &a in arrays {
                    new |= self.arrays.insert(a);
                }
            }
        }
        new
    }
}

/// What an instruction reads or writes in the image.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Locations {
    Elements(Vec<(Array, u32)>),
    Arrays(Vec<Array>),
}

/// The image elements of a device a host names.
pub fn device_elements(device: Device, double: bool) -> Vec<(Array, u32)> {
    match device {
        Device::Bit(area, n) => vec![(Array::of_bits(area), n)],
        Device::Word(area, n) if double => vec![(Array::of_words(area), n), (Array::of_words(area), n + 1)],
        Device::Word(area, n) | Device::WordBit(area, n, _) => vec![(Array::of_words(area), n)],
        Device::Digits(area, n, digits) => (n..n + 4 * u32::from(digits))
            .map(|k| (Array::of_bits(area), k))
            .collect(),
        Device::WideCounter(n) => vec![(Array::WideCounterValue, n)],
    }
}

/// The elements a span covers: a fixed run, or its whole array for a
/// run-time start.
fn span_locations(span: Span) -> Locations {
    let array = span.space.array();
    match span.start {
        Index::Fixed(n) => Locations::Elements((n..n.saturating_add(span.count.max(1))).map(|k| (array, k)).collect()),
        Index::Dynamic(_) => Locations::Arrays(vec![array]),
    }
}

fn operation_error() -> Locations {
    Locations::Elements(vec![
        (Array::M, M_OPERATION_ERROR),
        (Array::D, D_ERROR_CODE),
        (Array::D, D_ERROR_LINE),
    ])
}

const TIMER_ARRAYS: [Array; 5] = [
    Array::TimerContact,
    Array::TimerValue,
    Array::TimerRemainder,
    Array::TimerCoilWasOn,
    Array::ForceTimer,
];
const COUNTER_ARRAYS: [Array; 5] = [
    Array::CounterContact,
    Array::CounterValue,
    Array::WideCounterValue,
    Array::CounterCoilWasOn,
    Array::ForceCounter,
];

/// What a helper reads and writes besides its arguments, for the helpers
/// whose every read and write is known here (`None` for the others: they
/// take device places, touch the machine, or read more than their
/// declaration says, and there is no cone).
fn helper_locations(helper: Helper) -> Option<(Locations, Locations)> {
    let arrays = |list: &[Array]| Locations::Arrays(list.to_vec());
    if matches!(helper, Helper::ScheduleStateOff) {
        // Step 2 of the next scan turns the state OFF.
        Some((arrays(&[]), arrays(&[Array::StlPendingOff])))
    } else if matches!(helper, Helper::ResetTimer) {
        Some((arrays(&[]), arrays(&TIMER_ARRAYS)))
    } else if matches!(helper, Helper::ResetCounter) {
        Some((arrays(&[]), arrays(&COUNTER_ARRAYS)))
    } else if matches!(helper, Helper::TimerCoil) {
        // A coil reads the state it keeps (and the elapsed time).
        Some((arrays(&TIMER_ARRAYS), arrays(&TIMER_ARRAYS)))
    } else if matches!(helper, Helper::CounterCoil) {
        // ... and a 32-bit counter its direction relay M8200+.
        let mut reads = COUNTER_ARRAYS.to_vec();
        reads.push(Array::M);
        Some((Locations::Arrays(reads), arrays(&COUNTER_ARRAYS)))
    } else if matches!(helper, Helper::LoopRepeat) {
        // The watchdog's count is followed apart (`cone`); an overrun is
        // an operation error.
        Some((arrays(&[]), operation_error()))
    } else if matches!(
        helper,
        Helper::RealFunction | Helper::RealToDecimal | Helper::DecimalToReal | Helper::Segments
    ) {
        // Functions of their arguments alone.
        Some((arrays(&[]), arrays(&[])))
    } else {
        None
    }
}

/// Reads and writes of one instruction in the image (`None`: unknown, no
/// cone), from what the IR declares of it (`Inst::effect`).
#[allow(clippy::type_complexity)]
fn accesses(inst: &Inst) -> Option<(Option<Locations>, Option<Locations>)> {
    Some(match inst.effect() {
        Effect::Load(span) => (Some(span_locations(span)), None),
        Effect::Store(span, _) | Effect::Fill(span) => (None, Some(span_locations(span))),
        Effect::OperationError => (None, Some(operation_error())),
        Effect::Helper(helper, _) => {
            let (reads, writes) = helper_locations(helper)?;
            (Some(reads), Some(writes))
        }
        // What a call needs is followed through its subroutine (`cone`).
        Effect::Subroutine => (None, None),
        // Function locals are followed apart (`Variable`).
        Effect::Pure | Effect::ReadsLocal | Effect::WritesLocal => (None, None),
    })
}

/// A function-local variable: a master-control power or a loop count.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Variable {
    Power(u8),
    LoopCount(u8),
}

fn variable_written(inst: &Inst) -> Option<Variable> {
    if let Inst::SetLocal { local, .. } = inst {
        Some(Variable::Power(local.0))
    } else if let Inst::StoreLoopCount { level, .. } = inst {
        Some(Variable::LoopCount(*level))
    } else {
        None
    }
}

fn variable_read(inst: &Inst) -> Option<Variable> {
    if let Inst::GetLocal { local } = inst {
        Some(Variable::Power(local.0))
    } else if let Inst::LoadLoopCount { level } = inst {
        Some(Variable::LoopCount(*level))
    } else {
        None
    }
}

/// For each block, the branch blocks it is control dependent on (`None`
/// when some block cannot reach a return: no cone).
fn control_dependences(function: &Function) -> Option<Vec<Vec<BlockId>>> {
    let n = function.blocks.len();
    // The reversed graph, with a virtual exit (n) before every return.
    let exit = n;
    let mut successors_rev: Vec<Vec<usize>> = vec![Vec::new(); n + 1];
    let mut predecessors_rev: Vec<Vec<usize>> = vec![Vec::new(); n + 1];
    for (b, block) in function.blocks.iter().enumerate() {
        let targets = block.terminator.successors();
        if targets.is_empty() {
            successors_rev[exit].push(b);
            predecessors_rev[b].push(exit);
        }
        for t in targets {
            successors_rev[t.0 as usize].push(b);
            predecessors_rev[b].push(t.0 as usize);
        }
    }
    // Reverse postorder of the reversed graph from the exit.
    let mut order = Vec::new();
    let mut visited = vec![false; n + 1];
    let mut stack = vec![(exit, false)];
    while let Some((node, done)) = stack.pop() {
        if done {
            order.push(node);
            continue;
        }
        if std::mem::replace(&mut visited[node], true) {
            continue;
        }
        stack.push((node, true));
        for &s in successors_rev[node].iter().rev() {
            if !visited[s] {
                stack.push((s, false));
            }
        }
    }
    order.reverse();
    if order.len() != n + 1 {
        return None;
    }
    let mut position = vec![0usize; n + 1];
    for (i, &node) in order.iter().enumerate() {
        position[node] = i;
    }
    let mut ipdom: Vec<Option<usize>> = vec![None; n + 1];
    ipdom[exit] = Some(exit);
    let mut changed = true;
    while changed {
        changed = false;
        for &node in order.iter().skip(1) {
            let mut new: Option<usize> = None;
            for &p in &predecessors_rev[node] {
                if ipdom[p].is_none() {
                    continue;
                }
                new = Some(match new {
                    None => p,
                    Some(mut a) => {
                        let mut b = p;
                        while a != b {
                            while position[a] > position[b] {
                                a = ipdom[a].unwrap_or(exit);
                            }
                            while position[b] > position[a] {
                                b = ipdom[b].unwrap_or(exit);
                            }
                        }
                        a
                    }
                });
            }
            if new.is_some() && ipdom[node] != new {
                ipdom[node] = new;
                changed = true;
            }
        }
    }
    let mut dependences: Vec<Vec<BlockId>> = vec![Vec::new(); n];
    for (a, block) in function.blocks.iter().enumerate() {
        let Terminator::Branch { then, otherwise, .. } = block.terminator else {
            continue;
        };
        let stop = ipdom[a]?;
        for s in [then.0 as usize, otherwise.0 as usize] {
            let mut at = s;
            while at != stop && at != exit {
                if !dependences[at].contains(&BlockId(a as u32)) {
                    dependences[at].push(BlockId(a as u32));
                }
                at = ipdom[at]?;
            }
        }
    }
    Some(dependences)
}

/// One function's part of the analysis.
struct Part<'f> {
    function: &'f Function,
    /// For each block, the branch blocks it is control dependent on.
    dependences: Vec<Vec<BlockId>>,
    /// Every instruction's reads and writes, by block and position.
    accesses: Vec<Vec<(Option<Locations>, Option<Locations>)>>,
    /// Where each value is defined.
    definition: Vec<Option<(usize, usize)>>,
}

impl<'f> Part<'f> {
    fn new(function: &'f Function) -> Option<Part<'f>> {
        let dependences = control_dependences(function)?;
        let mut definition: Vec<Option<(usize, usize)>> = vec![None; function.value_types.len()];
        for (b, block) in function.blocks.iter().enumerate() {
            for (i, (result, _)) in block.insts.iter().enumerate() {
                if let Some(v) = result {
                    definition[v.0 as usize] = Some((b, i));
                }
            }
        }
        let mut part = Part {
            function,
            dependences,
            accesses: Vec::new(),
            definition,
        };
        for block in &function.blocks {
            let mut list = Vec::with_capacity(block.insts.len());
            for (_, inst) in &block.insts {
                list.push(part.accesses_of(inst)?);
            }
            part.accesses.push(list);
        }
        Some(part)
    }

    /// What an instruction reads and writes (`None`: unknown, no cone).
    /// Block moves and fills take packed places: their areas are read off
    /// the constant that packs them.
    #[allow(clippy::type_complexity)]
    fn accesses_of(&self, inst: &Inst) -> Option<(Option<Locations>, Option<Locations>)> {
        if let Inst::Call { helper, args } = inst {
            if matches!(helper, Helper::BlockMove | Helper::Fill) {
                let mut reads = Vec::new();
                let mut writes = Vec::new();
                for (&(_, param), &arg) in helper.decl().params.iter().zip(args) {
                    match param {
                        Param::SourcePlace => reads.push(self.place_array(arg)?),
                        Param::DestinationPlace => writes.push(self.place_array(arg)?),
                        Param::U32 | Param::I32 => {}
                    }
                }
                return Some((Some(Locations::Arrays(reads)), Some(Locations::Arrays(writes))));
            }
        }
        accesses(inst)
    }

    /// The array of the place a packed-place argument names: a constant,
    /// or a constant tag ORed with a run-time index.
    fn place_array(&self, value: Value) -> Option<Array> {
        let defining = |v: Value| {
            let (b, i) = self.definition.get(v.0 as usize).copied().flatten()?;
            Some(&self.function.blocks[b].insts[i].1)
        };
        let constant = |v: Value| {
            if let Some(Inst::Const { value, .. }) = defining(v) {
                Some(*value)
            } else {
                None
            }
        };
        let packed = match constant(value) {
            Some(c) => c,
            None => {
                let Some(Inst::Binary {
                    op: ladder_ir::BinOp::Or,
                    a,
                    b,
                }) = defining(value)
                else {
                    return None;
                };
                constant(*a).or_else(|| constant(*b))?
            }
        };
        Some(match Place::unpack(packed as u32)? {
            Place::Word(area, _) | Place::WordBit(area, _) => Array::of_words(area),
            Place::Bit(area, _) | Place::Digits(area, _, _) => Array::of_bits(area),
            Place::WideCounter(_) => Array::WideCounterValue,
            Place::Constant(_) => return None,
        })
    }
}

/// The cone of `roots` in `program` (`None`: the IR does not say enough).
/// `machine` is what the scan around the program keeps up to date: the
/// high-speed counters (counted at the input refresh) and the alarm
/// monitor (SM248/SD249 from S900-S999) read and write outside the IR, so
/// with them there is no cone.
///
/// Subroutines are part of it: an instruction of a subroutine that the
/// cone needs makes every call of that subroutine needed (where it runs
/// decides whether the instruction does). FOR/NEXT's watchdog (the
/// runtime's count of repetitions in the scan, which `LoopRepeat` keeps)
/// is a variable of its own: a needed `LoopRepeat` needs every other.
pub fn cone(program: &Program, roots: &[(Array, u32)], machine: MachineUse) -> Option<Cone> {
    if machine.contains(MachineUse::HIGH_SPEED) || machine.contains(MachineUse::ALARMS) {
        return None;
    }
    let parts: Vec<Part> = std::iter::once(&program.main)
        .chain(&program.subroutines)
        .map(Part::new)
        .collect::<Option<_>>()?;
    let mut cone = Cone::default();
    cone.add(&Locations::Elements(roots.to_vec()));
    let mut variables: FxHashSet<(usize, Variable)> = FxHashSet::default();
    let mut called: FxHashSet<u32> = FxHashSet::default();
    let mut watchdog = false;
    loop {
        let mut grew = false;
        // The instructions the cone needs, by (function, block, position):
        // those that write it (or a variable, a subroutine, the watchdog it
        // needs), then everything they depend on.
        let mut needed: FxHashSet<(usize, usize, usize)> = FxHashSet::default();
        let mut needed_blocks: FxHashSet<(usize, usize)> = FxHashSet::default();
        let mut work: Vec<(usize, Value)> = Vec::new();
        for (f, part) in parts.iter().enumerate() {
            for (b, list) in part.accesses.iter().enumerate() {
                for (i, (_, writes)) in list.iter().enumerate() {
                    let inst = &part.function.blocks[b].insts[i].1;
                    let seed = writes.as_ref().is_some_and(|w| cone.touches(w))
                        || variable_written(inst).is_some_and(|v| variables.contains(&(f, v)))
                        || matches!(inst, Inst::CallSubroutine { subroutine } if called.contains(subroutine))
                        || (watchdog
                            && matches!(
                                inst,
                                Inst::Call {
                                    helper: Helper::LoopRepeat,
                                    ..
                                }
                            ));
                    if seed {
                        needed.insert((f, b, i));
                        work.extend(inst.operands().into_iter().map(|v| (f, v)));
                        visit_block(part, f, b, &mut work, &mut needed_blocks);
                    }
                }
            }
        }
        while let Some((f, value)) = work.pop() {
            let part = &parts[f];
            let Some((b, i)) = part.definition.get(value.0 as usize).copied().flatten() else {
                continue;
            };
            if !needed.insert((f, b, i)) {
                continue;
            }
            let inst = &part.function.blocks[b].insts[i].1;
            work.extend(inst.operands().into_iter().map(|v| (f, v)));
            visit_block(part, f, b, &mut work, &mut needed_blocks);
        }
        for &(f, b, i) in &needed {
            let part = &parts[f];
            let inst = &part.function.blocks[b].insts[i].1;
            if let Some(v) = variable_read(inst) {
                grew |= variables.insert((f, v));
            }
            if let Some(reads) = &part.accesses[b][i].0 {
                grew |= cone.add(reads);
            }
            if f > 0 {
                grew |= called.insert(f as u32 - 1);
            }
            if matches!(
                inst,
                Inst::Call {
                    helper: Helper::LoopRepeat,
                    ..
                }
            ) && !watchdog
            {
                watchdog = true;
                grew = true;
            }
        }
        // The scan around the program: step 2 turns OFF the states a
        // transfer left pending, so a state's pending flag is in the cone
        // with the state (and with it every transfer that may set it).
        let pending: Vec<(Array, u32)> = cone
            .elements
            .iter()
            .filter(|(a, _)| *a == Array::S)
            .map(|&(_, n)| (Array::StlPendingOff, n))
            .collect();
        grew |= cone.add(&Locations::Elements(pending));
        if cone.arrays.contains(&Array::S) {
            grew |= cone.add(&Locations::Arrays(vec![Array::StlPendingOff]));
        }
        if !grew {
            break;
        }
    }
    // Inputs come from the input image at step 1.
    let inputs: Vec<(Array, u32)> = cone
        .elements
        .iter()
        .filter(|(a, _)| *a == Array::X)
        .map(|&(_, n)| (Array::InputImage, n))
        .collect();
    cone.elements.extend(inputs);
    if cone.arrays.contains(&Array::X) {
        cone.arrays.insert(Array::InputImage);
    }
    Some(cone)
}

/// Marks block `b` of function `f` needed, with the branches it depends on
/// (their conditions go to `work`), transitively.
fn visit_block(
    part: &Part,
    f: usize,
    b: usize,
    work: &mut Vec<(usize, Value)>,
    needed_blocks: &mut FxHashSet<(usize, usize)>,
) {
    let mut pending = vec![b];
    while let Some(b) = pending.pop() {
        if !needed_blocks.insert((f, b)) {
            continue;
        }
        for branch in &part.dependences[b] {
            if let Terminator::Branch { condition, .. } = part.function.block(*branch).terminator {
                work.push((f, condition));
            }
            pending.push(branch.0 as usize);
        }
    }
}
