//! One run of the program's IR as a function from the image at the start
//! of the program (step 3 of the scan) to the image at its end, built bit
//! by bit into an AIG. Blocks are visited in reverse postorder with the
//! condition under which each runs; a store in a block keeps the old value
//! where the block does not run (`mux`). Because one path through an
//! acyclic function runs per scan, that is exact. A loop (FOR/NEXT, a CJ
//! backwards) is unrolled, a copy of the blocks per repetition, up to 256
//! repetitions in a scan; where it may repeat more, every device is taken
//! as arbitrary.
//!
//! What is not modelled exactly becomes a fresh free input each scan
//! (`havoc`): real numbers, indexed devices, helpers without a model. Such
//! a model may over-approximate: a proof stays sound, and a counterexample
//! is replayed on the interpreter before it is believed (`witness.rs`).

use super::aig::{Aig, Lit};
use super::words::{self, Word};
use ladder_ir::{BinOp, Cell, Function, Index, Inst, Program, Terminator, Type, UnaryOp, Value};
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER, MAX_TRANSFER_UNITS};
use ladder_runtime::helpers::Helper;
use ladder_runtime::hsc::FIRST_HSC;
use ladder_runtime::layout::{Array, FULL};
use ladder_runtime::place::Place;
use ladder_runtime::special::{
    OperationError, D_ERROR_CODE, D_ERROR_LINE, LOOP_REPETITION_LIMIT, M_COUNTER_DIRECTION_BASE, M_OPERATION_ERROR,
};
use ladder_runtime::Memory;
use rustc_hash::{FxHashMap, FxHashSet};

/// Why a program or file cannot be encoded (the explicit engine's answer
/// stands).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unsupported(pub String);

/// An element of the image.
pub type Key = (Array, u32);

/// Bits a symbolic element of `array` has: `None` for arrays the model
/// does not hold (the runtime's own state of helpers, the I/O images).
pub fn width(array: Array) -> Option<u32> {
    if NOT_MODELLED.contains(&array) {
        return None;
    }
    // A byte holds 0 or 1 (a bit, a flag, a force), wider elements a
    // number of their bits.
    Some(match array.size() {
        1 => 1,
        bytes => 8 * bytes as u32,
    })
}

/// The arrays the model holds nothing of: the runtime's own state of
/// helpers (which are not modelled but taken as arbitrary), the I/O images
/// (inputs are free, outputs follow Y).
const NOT_MODELLED: [Array; 9] = [
    Array::SortState,
    Array::SortScans,
    Array::InputImage,
    Array::OutputImage,
    Array::PulsesPending,
    Array::InputEdges,
    Array::Instance,
    Array::PulseOwner,
    Array::PulseRemainder,
];

/// The value an element has in `mem`, as a constant word.
pub fn initial(mem: &Memory, key: Key) -> Option<Word> {
    let (array, n) = key;
    let bits = width(array)?;
    let offset = FULL.offset(array, n)?;
    let bytes = bytemuck::bytes_of(mem);
    let value = match bits {
        1 => i64::from(*bytes.get(offset)? != 0),
        16 => i64::from(i16::from_ne_bytes([*bytes.get(offset)?, *bytes.get(offset + 1)?])),
        _ => i64::from(i32::from_ne_bytes(bytes.get(offset..offset + 4)?.try_into().ok()?)),
    };
    Some(words::constant(value, bits))
}

/// The symbolic image while a scan is built.
pub struct Image<'a> {
    pub aig: &'a mut Aig,
    /// The current value of every element touched so far.
    pub memory: FxHashMap<Key, Word>,
    /// Every element the scan touches (learnt by a first build), so that
    /// an indexed store can overwrite each element it may reach.
    pub known: FxHashSet<Key>,
    /// The elapsed time of this scan (32 bits).
    pub elapsed: Word,
    /// The loop watchdog's count of repetitions in this scan (32 bits,
    /// from 0 at the scan's start).
    pub loop_repetitions: Word,
    /// What was taken as arbitrary, said once each.
    pub unmodelled: Vec<String>,
    /// Makes the value of an element not touched before.
    pub fresh_element: &'a mut dyn FnMut(&mut Aig, Key) -> Word,
}

impl Image<'_> {
    pub fn read(&mut self, key: Key) -> Word {
        if let Some(word) = self.memory.get(&key) {
            return word.clone();
        }
        self.known.insert(key);
        let word = (self.fresh_element)(self.aig, key);
        self.memory.insert(key, word.clone());
        word
    }

    /// Writes `value` where `guard` holds.
    pub fn write(&mut self, key: Key, guard: Lit, value: &[Lit]) {
        let Some(bits) = width(key.0) else { return };
        let old = self.read(key);
        let value = words::resize(value, bits, false);
        let new = words::mux(self.aig, guard, &value, &old);
        self.memory.insert(key, new);
    }

    pub fn note(&mut self, what: impl Into<String>) {
        let what = what.into();
        if !self.unmodelled.contains(&what) {
            self.unmodelled.push(what);
        }
    }

    fn fresh(&mut self, bits: u32) -> Word {
        (0..bits).map(|_| self.aig.input()).collect()
    }

    /// Every known element of `arrays` takes an arbitrary value where
    /// `guard` holds.
    pub fn havoc(&mut self, guard: Lit, arrays: &[Array]) {
        let mut keys: Vec<Key> = self.known.iter().filter(|(a, _)| arrays.contains(a)).copied().collect();
        keys.sort_unstable_by_key(|&(a, n)| (a as u32, n));
        for key in keys {
            let Some(bits) = width(key.0) else { continue };
            let value = self.fresh(bits);
            self.write(key, guard, &value);
        }
    }
}

/// Runs `program`'s main function on `image`.
pub fn run_program(image: &mut Image, program: &Program) -> Result<(), Unsupported> {
    run_function(image, program, &program.main, Lit::TRUE, 0)
}

/// Subroutines nested deeper than this are not encoded.
const CALL_DEPTH: u32 = 16;

fn run_function(
    image: &mut Image,
    program: &Program,
    function: &Function,
    reach: Lit,
    depth: u32,
) -> Result<(), Unsupported> {
    if depth > CALL_DEPTH {
        return Err(Unsupported("subroutines nested more than 16 deep".to_string()));
    }
    let order = reverse_postorder(function);
    let mut position = vec![usize::MAX; function.blocks.len()];
    for (i, b) in order.iter().enumerate() {
        position[*b] = i;
    }
    let mut values: Vec<Option<Word>> = vec![None; function.value_types.len()];
    let mut locals: Vec<Lit> = vec![Lit::FALSE; usize::from(function.locals)];
    let mut loop_counts: Vec<Word> = vec![words::constant(0, 32); usize::from(function.loop_levels)];
    // Loops are unrolled: copy c + 1 of the blocks is entered by the jumps
    // back out of copy c. Copies run in order, each in reverse postorder,
    // which is an order of execution: a block of a copy is reached from
    // earlier blocks of its copy or from the copy before.
    let mut block_reach = vec![vec![Lit::FALSE; function.blocks.len()]];
    if let Some(&entry) = order.first() {
        block_reach[0][entry] = reach;
    }
    // Where a repetition past the last copy would begin.
    let mut beyond = Lit::FALSE;
    let mut copy = 0;
    while copy < block_reach.len() {
        for &b in &order {
            let guard = block_reach[copy][b];
            if guard == Lit::FALSE {
                continue;
            }
            let block = &function.blocks[b];
            for (result, inst) in &block.insts {
                let mut state = State {
                    image,
                    program,
                    function,
                    values: &mut values,
                    locals: &mut locals,
                    loop_counts: &mut loop_counts,
                    guard,
                    depth,
                };
                let value = state.inst(inst)?;
                if let (Some(result), Some(value)) = (result, value) {
                    if let Some(slot) = values.get_mut(result.0 as usize) {
                        *slot = Some(value);
                    }
                }
            }
            let edges: Vec<(usize, Lit)> = match block.terminator {
                Terminator::Jump(target) => vec![(target.0 as usize, guard)],
                Terminator::Branch {
                    condition,
                    then,
                    otherwise,
                } => {
                    let c = value_bit(image, &values, condition);
                    let taken = image.aig.and(guard, c);
                    let not_taken = image.aig.and(guard, !c);
                    vec![(then.0 as usize, taken), (otherwise.0 as usize, not_taken)]
                }
                Terminator::Return => Vec::new(),
            };
            for (target, condition) in edges {
                if condition == Lit::FALSE || target >= function.blocks.len() {
                    continue;
                }
                let back = position[target] <= position[b];
                let into = if back { copy + 1 } else { copy };
                if into >= LOOP_COPIES {
                    beyond = image.aig.or(beyond, condition);
                    continue;
                }
                if into == block_reach.len() {
                    block_reach.push(vec![Lit::FALSE; function.blocks.len()]);
                }
                block_reach[into][target] = image.aig.or(block_reach[into][target], condition);
            }
        }
        copy += 1;
    }
    if beyond != Lit::FALSE {
        // What the rest of the function would do is not encoded: where it
        // would run, every element takes an arbitrary value (sound, and
        // moot where the inputs' ranges keep the count low).
        image.note(format!(
            "loops repeating more than {LOOP_COPIES} times in a scan (then every device is taken as arbitrary)"
        ));
        image.havoc(beyond, &Array::ALL);
        let arbitrary = image.fresh(32);
        image.loop_repetitions = words::mux(image.aig, beyond, &arbitrary, &image.loop_repetitions.clone());
    }
    Ok(())
}

/// Repetitions of a loop in one scan that are unrolled (a FOR/NEXT of a
/// constant count up to this many is exact; past them everything is
/// taken as arbitrary).
const LOOP_COPIES: usize = 256;

/// The instruction a helper runs, as its declaration's text names it
/// first (`ZRST (`on` 0) ...` is ZRST), else the helper's C name.
fn instruction_name(helper: Helper) -> String {
    let decl = helper.decl();
    let first = decl.doc.trim_start().split([' ', ':', ',', '(']).next().unwrap_or("");
    if first.len() >= 2 && first.chars().all(|c| c.is_ascii_uppercase() || c.is_ascii_digit()) {
        first.to_string()
    } else {
        decl.name.to_string()
    }
}

fn reverse_postorder(function: &Function) -> Vec<usize> {
    let count = function.blocks.len();
    let mut seen = vec![false; count];
    let mut post = Vec::with_capacity(count);
    let mut stack: Vec<(usize, usize)> = Vec::new();
    if count > 0 {
        seen[0] = true;
        stack.push((0, 0));
    }
    while let Some(&mut (b, ref mut next)) = stack.last_mut() {
        let successors = function.blocks[b].terminator.successors();
        if let Some(s) = successors.get(*next) {
            *next += 1;
            let s = s.0 as usize;
            if s < count && !seen[s] {
                seen[s] = true;
                stack.push((s, 0));
            }
        } else {
            post.push(b);
            stack.pop();
        }
    }
    post.reverse();
    post
}

fn value_bit(image: &mut Image, values: &[Option<Word>], value: Value) -> Lit {
    match values.get(value.0 as usize) {
        Some(Some(word)) => word.first().copied().unwrap_or(Lit::FALSE),
        // A value of a block that cannot run: anything will do.
        Some(None) | None => image.aig.input(),
    }
}

struct State<'s, 'a> {
    image: &'s mut Image<'a>,
    program: &'s Program,
    function: &'s Function,
    values: &'s mut Vec<Option<Word>>,
    locals: &'s mut Vec<Lit>,
    loop_counts: &'s mut Vec<Word>,
    guard: Lit,
    depth: u32,
}

impl State<'_, '_> {
    fn get(&mut self, value: Value) -> Word {
        let bits = self
            .function
            .value_types
            .get(value.0 as usize)
            .map_or(1, |t: &Type| t.bits());
        match self.values.get(value.0 as usize) {
            Some(Some(word)) => word.clone(),
            Some(None) | None => self.image.fresh(bits),
        }
    }

    fn bits_of(&self, value: Value) -> u32 {
        self.function.value_types.get(value.0 as usize).map_or(1, |t| t.bits())
    }

    fn constant(&self, value: Value) -> Option<i64> {
        match self.values.get(value.0 as usize) {
            Some(Some(word)) => words::constant_value(word),
            Some(None) | None => None,
        }
    }

    /// The element a cell names, when it is fixed (constant folding
    /// fixes every constant index inside its array; one left at run time
    /// is clamped by code generation, so it is taken as unknown here).
    fn cell_key(&mut self, cell: Cell) -> Option<Key> {
        let span = cell.span();
        match span.start {
            Index::Fixed(n) => Some((span.space.array(), n)),
            Index::Dynamic(_) => None,
        }
    }

    /// The instruction's value, if it defines one.
    fn inst(&mut self, inst: &Inst) -> Result<Option<Word>, Unsupported> {
        let guard = self.guard;
        Ok(Some(match inst {
            Inst::Const { ty, value } => words::constant(*value, ty.bits()),
            Inst::Load { cell } => {
                let bits = cell.value_type().bits();
                match self.cell_key(*cell) {
                    Some(key) => words::resize(&self.image.read(key), bits, false),
                    None => {
                        self.image.note("indexed devices (their values are taken as arbitrary)");
                        self.image.fresh(bits)
                    }
                }
            }
            Inst::Store { cell, value } => {
                let word = self.get(*value);
                match self.cell_key(*cell) {
                    Some(key) => self.image.write(key, guard, &word),
                    None => {
                        self.image.note("indexed devices (their values are taken as arbitrary)");
                        self.image.havoc(guard, &[cell.array()]);
                    }
                }
                return Ok(None);
            }
            Inst::FillBits { area, on, .. } => {
                self.fill(inst, area.count(), &[Lit::constant(*on)]);
                return Ok(None);
            }
            Inst::ClearWords { area, .. } => {
                self.fill(inst, area.count(), &words::constant(0, 16));
                return Ok(None);
            }
            Inst::LoadElapsed => self.image.elapsed.clone(),
            Inst::GetLocal { local } => vec![self.locals.get(usize::from(local.0)).copied().unwrap_or(Lit::FALSE)],
            Inst::SetLocal { local, value } => {
                let bit = self.get(*value)[0];
                if let Some(slot) = self.locals.get_mut(usize::from(local.0)) {
                    *slot = self.image.aig.mux(guard, bit, *slot);
                }
                return Ok(None);
            }
            Inst::LoadLoopCount { level } => self
                .loop_counts
                .get(usize::from(*level))
                .cloned()
                .unwrap_or_else(|| words::constant(0, 32)),
            Inst::StoreLoopCount { level, value } => {
                let word = words::resize(&self.get(*value), 32, true);
                if let Some(slot) = self.loop_counts.get(usize::from(*level)).cloned() {
                    let new = words::mux(self.image.aig, guard, &word, &slot);
                    self.loop_counts[usize::from(*level)] = new;
                }
                return Ok(None);
            }
            Inst::CallSubroutine { subroutine } => {
                let Some(function) = self.program.subroutines.get(*subroutine as usize) else {
                    return Err(Unsupported(format!("subroutine {subroutine} is missing")));
                };
                run_function(self.image, self.program, function, guard, self.depth + 1)?;
                return Ok(None);
            }
            Inst::Not { value } => vec![!self.get(*value)[0]],
            Inst::And { a, b } => {
                let (a, b) = (self.get(*a)[0], self.get(*b)[0]);
                vec![self.image.aig.and(a, b)]
            }
            Inst::Or { a, b } => {
                let (a, b) = (self.get(*a)[0], self.get(*b)[0]);
                vec![self.image.aig.or(a, b)]
            }
            Inst::Binary { op, a, b } => {
                let (a, b) = (self.get(*a), self.get(*b));
                self.binary(*op, &a, &b)
            }
            Inst::Unary { op, value } => {
                let word = self.get(*value);
                match op {
                    UnaryOp::PopCount => words::pop_count(self.image.aig, &word),
                    UnaryOp::LeadingZeros => words::leading_zeros(self.image.aig, &word),
                    UnaryOp::SquareRoot => {
                        self.image.note("square roots (taken as arbitrary)");
                        self.image.fresh(word.len() as u32)
                    }
                }
            }
            Inst::Compare { op, a, b } => {
                // Bits compare as 0 and 1, words as signed numbers.
                let signed = |s: &Self, v: Value| s.bits_of(v) > 1;
                let width = self.bits_of(*a).max(self.bits_of(*b)) + 1;
                let (sa, sb) = (signed(self, *a), signed(self, *b));
                let a = words::resize(&self.get(*a), width, sa);
                let b = words::resize(&self.get(*b), width, sb);
                let aig = &mut *self.image.aig;
                let lit = match op {
                    ladder_ir::CompareOp::Eq => words::equal(aig, &a, &b),
                    ladder_ir::CompareOp::Ne => !words::equal(aig, &a, &b),
                    ladder_ir::CompareOp::Lt => words::less_signed(aig, &a, &b),
                    ladder_ir::CompareOp::Gt => words::less_signed(aig, &b, &a),
                    ladder_ir::CompareOp::Le => !words::less_signed(aig, &b, &a),
                    ladder_ir::CompareOp::Ge => !words::less_signed(aig, &a, &b),
                };
                vec![lit]
            }
            Inst::Extend { value, to, signed } => words::resize(&self.get(*value), to.bits(), *signed),
            Inst::Truncate { value, to } => words::resize(&self.get(*value), to.bits(), false),
            Inst::Select {
                condition,
                if_true,
                if_false,
            } => {
                let c = self.get(*condition)[0];
                let (t, f) = (self.get(*if_true), self.get(*if_false));
                words::mux(self.image.aig, c, &t, &f)
            }
            Inst::Float { a, .. } => {
                self.image.note("real numbers (taken as arbitrary)");
                let bits = self.bits_of(*a);
                self.image.fresh(bits)
            }
            Inst::FloatUnary { value, .. } => {
                self.image.note("real numbers (taken as arbitrary)");
                let bits = self.bits_of(*value);
                self.image.fresh(bits)
            }
            Inst::FloatCompare { .. } => {
                self.image.note("real numbers (taken as arbitrary)");
                self.image.fresh(1)
            }
            Inst::Bitcast { value, to } => words::resize(&self.get(*value), to.bits(), false),
            Inst::Convert { to, .. } => {
                self.image.note("real numbers (taken as arbitrary)");
                self.image.fresh(to.bits())
            }
            Inst::RecordError { error, line } => {
                self.record_error(i64::from(error.code()), i64::from(*line as u16));
                return Ok(None);
            }
            Inst::Call { helper, args } => return self.call(*helper, args),
        }))
    }

    fn binary(&mut self, op: BinOp, a: &[Lit], b: &[Lit]) -> Word {
        let aig = &mut *self.image.aig;
        match op {
            BinOp::Add => words::add(aig, a, b),
            BinOp::Sub => words::sub(aig, a, b),
            BinOp::Mul => words::mul(aig, a, b),
            BinOp::Div => words::divide_signed(aig, a, b).0,
            BinOp::Rem => words::divide_signed(aig, a, b).1,
            BinOp::And => words::bitwise(a, b, |x, y| aig.and(x, y)),
            BinOp::Or => words::bitwise(a, b, |x, y| aig.or(x, y)),
            BinOp::Xor => words::bitwise(a, b, |x, y| aig.xor(x, y)),
            BinOp::Shl => words::shift(aig, a, b, true, false),
            BinOp::Shr => words::shift(aig, a, b, false, true),
            BinOp::UShr => words::shift(aig, a, b, false, false),
        }
    }

    fn fill(&mut self, inst: &Inst, area_count: u32, value: &[Lit]) {
        let ladder_ir::Effect::Fill(span) = inst.effect() else {
            return;
        };
        let array = span.space.array();
        match span.fixed_run(area_count) {
            Some(run) => {
                for n in run {
                    self.image.write((array, n), self.guard, value);
                }
            }
            None => {
                self.image.note("indexed devices (their values are taken as arbitrary)");
                self.image.havoc(self.guard, &[array]);
            }
        }
    }

    /// `OUT Cn preset` as the runtime's coil runs it (`counter.rs`):
    /// 16-bit counters count rising edges up to the preset, 32-bit ones up
    /// or down (M8200+) with wrap-around; the contact is ON at or above the
    /// preset. A forced counter keeps its coil's edge and nothing else.
    fn counter_coil(&mut self, counter: u32, coil: Lit, preset: &[Lit]) {
        if counter >= COUNTER_COUNT {
            return;
        }
        let was = self.image.read((Array::CounterCoilWasOn, counter))[0];
        let rising = self.image.aig.and(coil, !was);
        self.image
            .write((Array::CounterCoilWasOn, counter), self.guard, &[coil]);
        let forced = self.image.read((Array::ForceCounter, counter))[0];
        let saved = self.guard;
        self.guard = self.image.aig.and(saved, !forced);
        self.count(counter, rising, preset);
        self.guard = saved;
    }

    /// The counting part of `counter_coil`, under `self.guard`.
    fn count(&mut self, counter: u32, rising: Lit, preset: &[Lit]) {
        let guard = self.guard;
        let value = if counter >= FIRST_WIDE_COUNTER {
            let old = self.image.read((Array::WideCounterValue, counter));
            let new = if counter < FIRST_HSC {
                let down = self
                    .image
                    .read((Array::M, M_COUNTER_DIRECTION_BASE + counter - FIRST_WIDE_COUNTER))[0];
                let aig = &mut *self.image.aig;
                let step = words::mux(aig, down, &words::constant(-1, 32), &words::constant(1, 32));
                let counted = words::add(aig, &old, &step);
                words::mux(aig, rising, &counted, &old)
            } else {
                old
            };
            self.image.write((Array::WideCounterValue, counter), guard, &new);
            new
        } else {
            let old = words::resize(&self.image.read((Array::CounterValue, counter)), 32, true);
            let aig = &mut *self.image.aig;
            let below = words::less_signed(aig, &old, preset);
            let counts = aig.and(rising, below);
            let counted = words::add(aig, &old, &words::constant(1, 32));
            let new = words::mux(aig, counts, &counted, &old);
            self.image.write((Array::CounterValue, counter), guard, &new[..16]);
            new
        };
        let reached = !words::less_signed(self.image.aig, &value, preset);
        self.image.write((Array::CounterContact, counter), guard, &[reached]);
    }

    /// BMOV and FMOV between fixed word places inside their areas, as the
    /// runtime moves them: every value read before any is written, at
    /// most `MAX_TRANSFER_UNITS`. `None` (not encoded here) for anything
    /// else.
    fn block_move(&mut self, helper: Helper, args: &[Value]) -> Option<()> {
        let constant = |s: &Self, i: usize| args.get(i).and_then(|&a| s.constant(a));
        let fill = matches!(helper, Helper::Fill);
        let (destination, n, width) = if fill {
            (constant(self, 0)?, constant(self, 1)?, constant(self, 2)?)
        } else {
            (constant(self, 1)?, constant(self, 2)?, constant(self, 3)?)
        };
        if !(1..=2).contains(&width) {
            return None;
        }
        let count = u32::try_from(n).ok()?.min(MAX_TRANSFER_UNITS) * width as u32;
        let words_of = |packed: i64| match Place::unpack(packed as u32)? {
            Place::Word(area, start) if start.checked_add(count)? <= area.count() => {
                Some((Array::of_words(area), start))
            }
            Place::Word(..)
            | Place::WordBit(..)
            | Place::Bit(..)
            | Place::Digits(..)
            | Place::WideCounter(_)
            | Place::Constant(_) => None,
        };
        let (to, at) = words_of(destination)?;
        let values: Vec<Word> = if fill {
            let value = words::resize(&self.get(*args.get(3)?), 32, true);
            (0..count)
                .map(|k| {
                    let half = if width == 2 && k % 2 == 1 { 16 } else { 0 };
                    value[half..half + 16].to_vec()
                })
                .collect()
        } else {
            let (from, start) = words_of(constant(self, 0)?)?;
            (0..count).map(|k| self.image.read((from, start + k))).collect()
        };
        for (k, value) in (0..count).zip(values) {
            self.image.write((to, at + k), self.guard, &value);
        }
        Some(())
    }

    /// NEXT's question to the loop watchdog (`scan.rs`): 1 and one more
    /// repetition counted while fewer than the limit were made in this
    /// scan, else 0 with 6509H recorded.
    fn loop_repeat(&mut self, line: u32) -> Word {
        let guard = self.guard;
        let count = self.image.loop_repetitions.clone();
        let aig = &mut *self.image.aig;
        let wide = words::resize(&count, 34, false);
        let limit = words::constant(i64::from(LOOP_REPETITION_LIMIT), 34);
        let allowed = words::less_signed(aig, &wide, &limit);
        let counted = words::add(aig, &count, &words::constant(1, 32));
        let counts = aig.and(guard, allowed);
        self.image.loop_repetitions = words::mux(aig, counts, &counted, &count);
        let refused = aig.and(guard, !allowed);
        let saved = self.guard;
        self.guard = refused;
        self.record_error(i64::from(OperationError::LoopWatchdog.code()), i64::from(line as u16));
        self.guard = saved;
        words::resize(&[allowed], 32, false)
    }

    fn record_error(&mut self, code: i64, line: i64) {
        let guard = self.guard;
        self.image.write((Array::M, M_OPERATION_ERROR), guard, &[Lit::TRUE]);
        self.image
            .write((Array::D, D_ERROR_CODE), guard, &words::constant(code, 16));
        self.image
            .write((Array::D, D_ERROR_LINE), guard, &words::constant(line, 16));
    }

    fn call(&mut self, helper: Helper, args: &[Value]) -> Result<Option<Word>, Unsupported> {
        let guard = self.guard;
        let first = args
            .first()
            .and_then(|&a| self.constant(a))
            .and_then(|n| u32::try_from(n).ok());
        if matches!(helper, Helper::ScheduleStateOff) {
            if let Some(state) = first {
                self.image.write((Array::StlPendingOff, state), guard, &[Lit::TRUE]);
                return Ok(None);
            }
        } else if matches!(helper, Helper::ResetTimer) {
            if let Some(timer) = first {
                // Without forces (a file with `force` is not encoded) the
                // contact is cleared too.
                self.image
                    .write((Array::TimerValue, timer), guard, &words::constant(0, 16));
                self.image
                    .write((Array::TimerRemainder, timer), guard, &words::constant(0, 16));
                self.image.write((Array::TimerContact, timer), guard, &[Lit::FALSE]);
                return Ok(None);
            }
        } else if matches!(helper, Helper::ResetCounter) {
            if let Some(counter) = first {
                if counter >= FIRST_WIDE_COUNTER {
                    self.image
                        .write((Array::WideCounterValue, counter), guard, &words::constant(0, 32));
                } else {
                    self.image
                        .write((Array::CounterValue, counter), guard, &words::constant(0, 16));
                }
                self.image.write((Array::CounterContact, counter), guard, &[Lit::FALSE]);
                return Ok(None);
            }
        } else if matches!(helper, Helper::CounterCoil) {
            if let (Some(counter), Some(&coil), Some(&preset)) = (first, args.get(1), args.get(2)) {
                let coil = self.get(coil)[0];
                let preset = words::resize(&self.get(preset), 32, true);
                self.counter_coil(counter, coil, &preset);
                return Ok(None);
            }
        } else if matches!(helper, Helper::BlockMove | Helper::Fill) {
            if self.block_move(helper, args).is_some() {
                return Ok(None);
            }
        } else if matches!(helper, Helper::LoopRepeat) {
            if let Some(line) = first {
                return Ok(Some(self.loop_repeat(line)));
            }
        } else if matches!(helper, Helper::RecordError) {
            let line = args.get(1).and_then(|&a| self.constant(a));
            // The runtime records only the codes it knows.
            let known = first.and_then(OperationError::from_code);
            if let (Some(code), Some(line), Some(_)) = (first, line, known) {
                self.record_error(i64::from(code), line & 0xFFFF);
                return Ok(None);
            }
        }
        // Anything else: what it may write takes arbitrary values. Its
        // declaration names what it writes besides its places, but a
        // place may also come as numbers (ZRST's first and last device),
        // so everything is taken as written, except by the helpers that
        // only compute their result from their arguments.
        let decl = helper.decl();
        self.image.note(format!(
            "{} (its results are taken as arbitrary)",
            instruction_name(helper)
        ));
        let pure = matches!(
            helper,
            Helper::RealFunction | Helper::RealToDecimal | Helper::DecimalToReal | Helper::Segments
        );
        let arrays: Vec<Array> = if pure { Vec::new() } else { Array::ALL.to_vec() };
        self.image.havoc(guard, &arrays);
        Ok(decl.returns.map(|_| self.image.fresh(32)))
    }
}
