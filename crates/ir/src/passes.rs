//! IR passes that pay for themselves on real programs:
//!
//! - constant folding, including the always-ON/OFF relays (SM0, M8000, M8001,
//!   ...) when the program never writes them: `LD M8000` costs nothing; a
//!   run-time index that folds to a device of its area becomes a fixed one
//!   (addressed directly, and all a compact image needs to hold); a
//!   comparison its operands' ranges decide (`ranges.rs`) becomes a
//!   constant;
//! - branch folding and removal of unreachable blocks;
//! - merging a block into its only predecessor;
//! - equal pure computations close together in a block share one value;
//! - removal of pure instructions whose values are never used;
//! - memory forwarding across rungs (`memory.rs`).

use super::cfg::reverse_postorder;
use super::ranges::Ranges;
use super::replacements::Replacements;
use super::{
    BinOp, Block, BlockId, Cell, Effect, Function, Index, Inst, OperandMut, Program, Space, Terminator, Type, UnaryOp,
    Value,
};
use crate::CompareOp;
use ladder_runtime::helpers::{Param, Writes};
use ladder_runtime::special::{M_ALWAYS_OFF, M_ALWAYS_ON, M_OPERATION_ERROR, SM_ALWAYS_OFF, SM_ALWAYS_ON};
use ladder_runtime::{BitArea, Place};
use rustc_hash::FxHashMap;
use std::collections::VecDeque;

/// Runs every pass on every function of the program. The relays the
/// runtime holds constant are found over the whole program (a subroutine
/// may write one), before any pass removes a write. In debug builds (and
/// so in every test) the verifier checks each function after every pass.
pub fn optimize(program: &mut Program) {
    let relays = constant_relays(std::iter::once(&program.main).chain(&program.subroutines));
    let subroutines = program.subroutines.len();
    let names = std::iter::once("main".to_string()).chain((0..subroutines).map(|n| format!("sub{n}")));
    for (function, name) in std::iter::once(&mut program.main)
        .chain(&mut program.subroutines)
        .zip(names)
    {
        let mut passes = Passes {
            function,
            name: &name,
            subroutines,
        };
        passes.optimize(&relays);
    }
}

/// One function on its way through the passes.
struct Passes<'f> {
    function: &'f mut Function,
    name: &'f str,
    subroutines: usize,
}

impl Passes<'_> {
    /// Forwarding memory works best on merged blocks; what it forwards, and
    /// the computations shared after it, may fold further.
    fn optimize(&mut self, relays: &Relays) {
        self.simplify_control(relays);
        self.run("forward_memory", super::memory::forward_memory);
        self.run("share_pure_values", share_pure_values);
        self.simplify_control(relays);
        self.run("remove_dead_values", remove_dead_values);
    }

    fn simplify_control(&mut self, relays: &Relays) {
        self.run("fold_constants", |function| fold_constants(function, relays));
        self.run("fold_branches", fold_branches);
        self.run("remove_unreachable", remove_unreachable);
        self.run("thread_jumps", thread_jumps);
        self.run("merge_blocks", merge_blocks);
    }

    fn run(&mut self, pass: &str, run: impl FnOnce(&mut Function)) {
        run(self.function);
        if cfg!(debug_assertions) {
            assert_well_formed(self.function, self.name, self.subroutines, pass);
        }
    }
}

/// Panics with the verifier's report when `function` is not well formed
/// after `stage`: a compiler bug, caught where it is made (debug builds).
fn assert_well_formed(function: &Function, name: &str, subroutines: usize, stage: &str) {
    if let Err(error) = super::verify_function(function, name, subroutines) {
        // A large function's text would bury the report.
        let text = function.to_string();
        let listing = if text.len() <= 8_000 { text } else { String::new() };
        panic!("the IR is not well formed after `{stage}`:\n{error}\n{listing}");
    }
}

/// Sends jumps and branches that land on an empty block that only jumps on
/// straight to where it jumps.
pub fn thread_jumps(function: &mut Function) {
    let forward: Vec<Option<BlockId>> = function
        .blocks
        .iter()
        .enumerate()
        .map(|(index, block)| match block.terminator {
            Terminator::Jump(target) if index != 0 && block.insts.is_empty() && target.0 as usize != index => {
                Some(target)
            }
            Terminator::Jump(_) | Terminator::Branch { .. } | Terminator::Return => None,
        })
        .collect();
    let resolve = |mut block: BlockId| {
        // Follow chains of empty blocks, at most once around any cycle.
        for _ in 0..forward.len() {
            match forward[block.0 as usize] {
                Some(next) => block = next,
                None => break,
            }
        }
        block
    };
    for block in &mut function.blocks {
        block.terminator = block.terminator.map_targets(resolve);
    }
    fold_branches(function);
    remove_unreachable(function);
}

/// Relays with a value known for the whole program run.
type Relays = FxHashMap<(BitArea, u32), bool>;

/// The relays the runtime holds constant during the program, and their value,
/// unless some function of the program may write them.
fn constant_relays<'f>(functions: impl Iterator<Item = &'f Function>) -> Relays {
    let mut known: FxHashMap<(BitArea, u32), bool> = FxHashMap::default();
    known.insert((BitArea::Sm, SM_ALWAYS_ON), true);
    known.insert((BitArea::Sm, SM_ALWAYS_OFF), false);
    for n in M_ALWAYS_ON {
        known.insert((BitArea::M, n), true);
    }
    for n in M_ALWAYS_OFF {
        known.insert((BitArea::M, n), false);
    }
    for function in functions {
        let constants = function.constants();
        for block in &function.blocks {
            for (_, inst) in &block.insts {
                for (area, start, count) in written_bits(inst, &constants) {
                    match start {
                        Some(start) => known.retain(|&(a, n), _| a != area || !(start..start + count).contains(&n)),
                        None => known.retain(|&(a, _), _| a != area),
                    }
                }
            }
        }
    }
    known
}

/// The bit devices an instruction may write: (area, first, count), with no
/// first when the index is dynamic (the whole area may be written).
fn written_bits(inst: &Inst, constants: &FxHashMap<Value, i64>) -> Vec<(BitArea, Option<u32>, u32)> {
    let fixed = |index: Index| match index {
        Index::Fixed(n) => Some(n),
        Index::Dynamic(_) => None,
    };
    match inst.effect() {
        Effect::Store(span, _) | Effect::Fill(span) => match span.space {
            Space::Bits(area) => vec![(area, fixed(span.start), span.count)],
            Space::Words(_) | Space::WideCounters | Space::EdgeSlots | Space::BlockActive | Space::Bookkeeping(_) => {
                Vec::new()
            }
        },
        Effect::Helper(helper, args) => {
            let decl = helper.decl();
            let effects = decl.writes.iter().flat_map(|w| match w {
                // The error flag is one relay, not the whole of M.
                Writes::OperationError => vec![(BitArea::M, Some(M_OPERATION_ERROR), 1)],
                Writes::Timers | Writes::Counters | Writes::StlBookkeeping | Writes::Bits(_) | Writes::Image => {
                    w.bit_areas().iter().map(|&area| (area, None, 0)).collect()
                }
            });
            let places = decl
                .params
                .iter()
                .zip(args)
                .filter(|((_, param), _)| *param == Param::DestinationPlace)
                .flat_map(|(_, arg)| {
                    let place = constants.get(arg).and_then(|&packed| Place::unpack(packed as u32));
                    match place {
                        // A digit group writes bits of its area.
                        Some(Place::Digits(area, ..) | Place::Bit(area, _)) => vec![(area, None, 0)],
                        Some(Place::Word(..) | Place::WordBit(..) | Place::WideCounter(_) | Place::Constant(_)) => {
                            Vec::new()
                        }
                        // Not known here: any bit area.
                        None => BitArea::ALL.iter().map(|&area| (area, None, 0)).collect(),
                    }
                });
            effects.chain(places).collect()
        }
        Effect::OperationError => vec![(BitArea::M, Some(M_OPERATION_ERROR), 1)],
        // The subroutine's own writes are counted with its function.
        Effect::Subroutine | Effect::Pure | Effect::ReadsLocal | Effect::WritesLocal | Effect::Load(_) => Vec::new(),
    }
}

fn fold_binary(op: BinOp, ty: Type, a: i64, b: i64) -> Option<i64> {
    let value = match op {
        BinOp::Add => a.wrapping_add(b),
        BinOp::Sub => a.wrapping_sub(b),
        BinOp::Mul => a.wrapping_mul(b),
        BinOp::Div | BinOp::Rem if b == 0 => return None,
        BinOp::Div => a.wrapping_div(b),
        BinOp::Rem => a.wrapping_rem(b),
        BinOp::And => a & b,
        BinOp::Or => a | b,
        BinOp::Xor => a ^ b,
        BinOp::Shl => a.wrapping_shl(b as u32),
        BinOp::Shr => a.wrapping_shr(b as u32),
        BinOp::UShr => (unsigned(ty, a)).wrapping_shr(b as u32) as i64,
    };
    Some(ty.wrap(value))
}

/// The bits of `value` at `ty`, as an unsigned number.
fn unsigned(ty: Type, value: i64) -> u64 {
    match ty {
        Type::Bit => value as u64 & 1,
        Type::I16 => u64::from(value as u16),
        Type::I32 | Type::F32 => u64::from(value as u32),
        Type::I64 | Type::F64 => value as u64,
    }
}

fn fold_unary(op: UnaryOp, ty: Type, value: i64) -> Option<i64> {
    let bits = unsigned(ty, value);
    Some(match op {
        UnaryOp::PopCount => i64::from(bits.count_ones()),
        UnaryOp::LeadingZeros => i64::from(bits.leading_zeros() - (64 - ty.bits())),
        UnaryOp::SquareRoot if value < 0 => return None,
        UnaryOp::SquareRoot => (value as u64).isqrt() as i64,
    })
}

fn compare(op: CompareOp, a: i64, b: i64) -> bool {
    op.holds(a, b)
}

/// What an instruction folds to.
enum Folded {
    Constant(i64),
    /// The instruction computes an existing value.
    Same(Value),
    Nothing,
}

/// AND (`absorbing` 0) or OR (`absorbing` 1) with known operands.
fn fold_logic(a: Value, b: Value, known_a: Option<i64>, known_b: Option<i64>, absorbing: i64) -> Folded {
    match (known_a, known_b) {
        (Some(v), _) | (_, Some(v)) if v == absorbing => Folded::Constant(absorbing),
        (Some(_), Some(_)) => Folded::Constant(1 - absorbing),
        (Some(_), None) => Folded::Same(b),
        (None, Some(_)) => Folded::Same(a),
        (None, None) if a == b => Folded::Same(a),
        (None, None) => Folded::Nothing,
    }
}

/// Folds one instruction given the constants and extensions known so far.
fn fold(
    inst: &Inst,
    ty: Type,
    types: &[Type],
    constants: &FxHashMap<Value, i64>,
    extended_from: &FxHashMap<Value, Value>,
    relays: &FxHashMap<(BitArea, u32), bool>,
    ranges: &Ranges,
) -> Folded {
    let known = |v: &Value| constants.get(v).copied();
    let constant = |value: Option<i64>| value.map_or(Folded::Nothing, Folded::Constant);
    match inst {
        Inst::Const { value, .. } => Folded::Constant(*value),
        Inst::Load {
            cell: Cell::Bit {
                area,
                index: Index::Fixed(n),
            },
        } => constant(relays.get(&(*area, *n)).map(|&on| on as i64)),
        Inst::Not { value } => constant(known(value).map(|v| 1 - v)),
        Inst::And { a, b } => fold_logic(*a, *b, known(a), known(b), 0),
        Inst::Or { a, b } => fold_logic(*a, *b, known(a), known(b), 1),
        Inst::Binary { op, a, b } => match (known(a), known(b)) {
            (Some(x), Some(y)) => constant(fold_binary(*op, ty, x, y)),
            (None, Some(k)) if right_identity(*op) == Some(k) => Folded::Same(*a),
            (Some(k), None) if left_identity(*op) == Some(k) => Folded::Same(*b),
            (None, Some(_)) | (Some(_), None) | (None, None) => Folded::Nothing,
        },
        Inst::Unary { op, value } => constant(known(value).and_then(|v| fold_unary(*op, ty, v))),
        Inst::Compare { op, a, b } => match (known(a), known(b)) {
            (Some(x), Some(y)) => Folded::Constant(compare(*op, x, y) as i64),
            // A number compared with itself (values shared by
            // `share_pure_values`).
            (None, None) if a == b => Folded::Constant(compare(*op, 0, 0) as i64),
            // Decided by the operands' ranges, or not at all.
            _ => constant(ranges.decide(*op, *a, *b, types, constants).map(i64::from)),
        },
        Inst::Extend { value, signed, .. } => {
            constant(known(value).map(|v| match (*signed, types[value.0 as usize]) {
                (false, Type::I16) => i64::from(v as u16),
                (false, Type::I32) => i64::from(v as u32),
                // Constants are held sign-extended; a bit is 0 or 1.
                (true, _) | (false, Type::Bit | Type::I64 | Type::F32 | Type::F64) => v,
            }))
        }
        Inst::Truncate { value, to } => match (known(value), extended_from.get(value)) {
            (Some(v), _) => Folded::Constant(to.wrap(v)),
            // trunc(ext(x)) back to x's own type is x.
            (None, Some(&inner)) if types[inner.0 as usize] == *to => Folded::Same(inner),
            _ => Folded::Nothing,
        },
        Inst::Select {
            condition,
            if_true,
            if_false,
        } => match known(condition) {
            Some(c) => {
                let chosen = if c != 0 { *if_true } else { *if_false };
                known(&chosen).map_or(Folded::Same(chosen), Folded::Constant)
            }
            None if if_true == if_false => Folded::Same(*if_true),
            None => Folded::Nothing,
        },
        // Float arithmetic is left to the machine (folding it would need
        // the same rounding here as there), and bit casts keep their bits.
        Inst::Bitcast { value, .. } => constant(known(value)),
        Inst::Float { .. } | Inst::FloatUnary { .. } | Inst::FloatCompare { .. } | Inst::Convert { .. } => {
            Folded::Nothing
        }
        // Loads of the image and of bookkeeping, and effects: nothing known.
        Inst::LoadLoopCount { .. }
        | Inst::StoreLoopCount { .. }
        | Inst::CallSubroutine { .. }
        | Inst::Load { .. }
        | Inst::Store { .. }
        | Inst::FillBits { .. }
        | Inst::ClearWords { .. }
        | Inst::LoadElapsed
        | Inst::GetLocal { .. }
        | Inst::SetLocal { .. }
        | Inst::RecordError { .. }
        | Inst::Call { .. } => Folded::Nothing,
    }
}

/// The constant `k` with `x op k == x`: x + 0, x - 0, x | 0, x << 0,
/// x >> 0, x * 1.
fn right_identity(op: BinOp) -> Option<i64> {
    match op {
        BinOp::Add | BinOp::Sub | BinOp::Or | BinOp::Shl | BinOp::Shr => Some(0),
        BinOp::Mul => Some(1),
        BinOp::Div | BinOp::Rem | BinOp::And | BinOp::Xor | BinOp::UShr => None,
    }
}

/// The constant `k` with `k op x == x`: 0 + x, 0 | x, 1 * x.
fn left_identity(op: BinOp) -> Option<i64> {
    match op {
        BinOp::Add | BinOp::Or => Some(0),
        BinOp::Mul => Some(1),
        BinOp::Sub | BinOp::Div | BinOp::Rem | BinOp::And | BinOp::Xor | BinOp::Shl | BinOp::Shr | BinOp::UShr => None,
    }
}

/// Makes a run-time index that is a known constant a fixed one, when the
/// device (or the run of `count` from it) lies inside its area: there code
/// generation addresses both the same way, while outside it clamps a
/// run-time index differently from a fixed one (a negative index clamps to
/// the last device), so those stay as they are.
fn fix_index(inst: &mut Inst, constants: &FxHashMap<Value, i64>) {
    let span = match inst.effect() {
        Effect::Load(span) | Effect::Store(span, _) | Effect::Fill(span) => span,
        Effect::Pure
        | Effect::ReadsLocal
        | Effect::WritesLocal
        | Effect::Helper(..)
        | Effect::OperationError
        | Effect::Subroutine => return,
    };
    let array = span.space.array();
    let (first, end) = (array.first(), array.end());
    inst.visit_operands_mut(|operand| match operand {
        OperandMut::Index(index) => {
            if let Index::Dynamic(value) = *index {
                if let Some(&n) = constants.get(&value) {
                    if n >= i64::from(first) && n + i64::from(span.count.max(1)) <= i64::from(end) {
                        *index = Index::Fixed(n as u32);
                    }
                }
            }
        }
        OperandMut::Value(_) => {}
    });
}

/// Folds instructions with constant operands to constants, comparisons
/// the operands' ranges decide too, and instructions that compute an
/// existing value (`x AND 1`, `x + 0`) to that value.
pub fn fold_constants(function: &mut Function, relays: &Relays) {
    let mut constants: FxHashMap<Value, i64> = FxHashMap::default();
    let mut replaced = Replacements::default();
    // Value defined by an Extend -> the value it extended.
    let mut extended_from: FxHashMap<Value, Value> = FxHashMap::default();
    let mut ranges = Ranges::default();
    let types = function.value_types.clone();
    for block in reverse_postorder(function) {
        let block = &mut function.blocks[block.0 as usize];
        for (result, inst) in block.insts.iter_mut() {
            replaced.in_operands(inst);
            fix_index(inst, &constants);
            let Some(result) = *result else { continue };
            let ty = types[result.0 as usize];
            if let Inst::Extend { value, .. } = inst {
                extended_from.insert(result, *value);
            }
            match fold(inst, ty, &types, &constants, &extended_from, relays, &ranges) {
                Folded::Constant(value) => {
                    let value = ty.wrap(value);
                    constants.insert(result, value);
                    *inst = Inst::Const { ty, value };
                }
                Folded::Same(other) => {
                    replaced.insert(result, other);
                }
                Folded::Nothing => ranges.record(result, inst, &types, &constants),
            }
        }
    }
    replaced.in_conditions(function);
}

/// A branch on a constant becomes a jump.
pub fn fold_branches(function: &mut Function) {
    let constants = function.constants();
    for block in &mut function.blocks {
        if let Terminator::Branch {
            condition,
            then,
            otherwise,
        } = block.terminator
        {
            match constants.get(&condition) {
                Some(0) => block.terminator = Terminator::Jump(otherwise),
                Some(_) => block.terminator = Terminator::Jump(then),
                None if then == otherwise => block.terminator = Terminator::Jump(then),
                None => {}
            }
        }
    }
}

/// Drops blocks the entry cannot reach and renumbers the rest in reverse
/// postorder (so the text form reads top to bottom).
pub fn remove_unreachable(function: &mut Function) {
    let order = reverse_postorder(function);
    let mut renumber = vec![None; function.blocks.len()];
    for (new, old) in order.iter().enumerate() {
        renumber[old.0 as usize] = Some(BlockId(new as u32));
    }
    let map = |b: BlockId| renumber[b.0 as usize].expect("successor of a reachable block is reachable");
    let mut old_blocks: Vec<Option<Block>> = std::mem::take(&mut function.blocks).into_iter().map(Some).collect();
    function.blocks = order
        .iter()
        .map(|old| {
            let mut block = old_blocks[old.0 as usize].take().expect("each block once");
            block.terminator = block.terminator.map_targets(map);
            block
        })
        .collect();
}

/// Appends a block to its predecessor when the predecessor jumps to it and
/// nothing else does. The merged block keeps its predecessor's `cold`
/// mark: the appended block runs exactly when the predecessor does. Merging keeps every other block's predecessor count, so
/// one sweep with counts taken once is enough.
pub fn merge_blocks(function: &mut Function) {
    let mut predecessors = vec![0usize; function.blocks.len()];
    for block in &function.blocks {
        for successor in block.terminator.successors() {
            predecessors[successor.0 as usize] += 1;
        }
    }
    for into in 0..function.blocks.len() {
        while let Terminator::Jump(target) = function.blocks[into].terminator {
            let from = target.0 as usize;
            if from == 0 || from == into || predecessors[from] != 1 {
                break;
            }
            let moved = std::mem::replace(
                &mut function.blocks[from],
                Block {
                    insts: Vec::new(),
                    terminator: Terminator::Return,
                    cold: false,
                },
            );
            predecessors[from] = 0;
            let target = &mut function.blocks[into];
            target.insts.extend(moved.insts);
            target.terminator = moved.terminator;
        }
    }
    // The emptied blocks are unreachable now.
    remove_unreachable(function);
}

/// How far apart (in instructions of one block) two equal computations
/// may be for the later to use the earlier's value: further, the value
/// would hold a register over more code than recomputing it costs.
const SHARE_DISTANCE: usize = 32;

/// Gives a pure computation the value of an equal one shortly before it in
/// the same block (`v8 = sext v7 ... v20 = sext v7`: the uses of v20 read
/// v8), as a C compiler's value numbering does; Cranelift without its
/// optimiser would compute it again. Constants are left alone (code
/// generation makes them where they are used). The duplicates are left to
/// `remove_dead_values`.
pub fn share_pure_values(function: &mut Function) {
    let mut replaced = Replacements::default();
    for block in reverse_postorder(function) {
        let block = &mut function.blocks[block.0 as usize];
        // The pure computations of the last `SHARE_DISTANCE` instructions,
        // oldest first: (position, value, computation).
        let mut recent: VecDeque<(usize, Value, Inst)> = VecDeque::new();
        for (position, (result, inst)) in block.insts.iter_mut().enumerate() {
            replaced.in_operands(inst);
            while recent.front().is_some_and(|&(at, _, _)| position - at > SHARE_DISTANCE) {
                recent.pop_front();
            }
            let Some(result) = *result else { continue };
            if !shareable(inst) {
                continue;
            }
            match recent.iter().find(|(_, _, earlier)| earlier == inst) {
                Some(&(_, earlier, _)) => {
                    replaced.insert(result, earlier);
                }
                None => recent.push_back((position, result, inst.clone())),
            }
        }
    }
    replaced.in_conditions(function);
}

/// A computation whose value depends on its operands alone, other than a
/// constant or a NOT: code generation makes a constant where it is used,
/// and folds a NOT with one use into the AND or OR that uses it (x86-64's
/// ANDN), which a shared NOT would lose.
fn shareable(inst: &Inst) -> bool {
    if let Inst::Const { .. } | Inst::Not { .. } = inst {
        return false;
    }
    match inst.effect() {
        Effect::Pure => true,
        Effect::ReadsLocal
        | Effect::WritesLocal
        | Effect::Load(_)
        | Effect::Store(..)
        | Effect::Fill(_)
        | Effect::Helper(..)
        | Effect::OperationError
        | Effect::Subroutine => false,
    }
}

/// Removes pure instructions whose values nothing uses, following chains:
/// removing a use may make its operands dead in turn.
pub fn remove_dead_values(function: &mut Function) {
    let mut uses = function.use_counts();
    // Walk each block backwards so a dead use is removed before its operands
    // are judged; repeat while a sweep removes something in an earlier block.
    loop {
        let mut removed = false;
        for block in function.blocks.iter_mut().rev() {
            let mut kept = Vec::with_capacity(block.insts.len());
            for (result, inst) in block.insts.drain(..).rev() {
                let dead = inst.is_pure() && matches!(result, Some(v) if uses[v.0 as usize] == 0);
                if dead {
                    removed = true;
                    for operand in inst.operands() {
                        uses[operand.0 as usize] -= 1;
                    }
                } else {
                    kept.push((result, inst));
                }
            }
            kept.reverse();
            block.insts = kept;
        }
        if !removed {
            break;
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use ladder_front::check::compile_source;
    use ladder_front::source::SourceFile;

    /// The optimised IR of a program text.
    pub(crate) fn ir(text: &str) -> String {
        let (program, diagnostics) = compile_source(&SourceFile::new("t.il", text));
        let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
        crate::lower_and_optimize(&program).to_string()
    }

    #[test]
    fn equal_computations_nearby_share_one_value() {
        // ADD's result D1 (forwarded) is sign-extended for its flags, for
        // MUL and for the comparison: once.
        let text = ir("LD SM0\nADD D0 K3 D1\nMUL D1 K2 D2\nLD> D1 K1000\nOUT Y0\n");
        assert_eq!(text.matches(" = sext.i64 ").count(), 2, "D0 and D1 once each:\n{text}");
        // A NOT is left to fold into its AND (ANDN): both rungs have one.
        let text = ir("LD X0\nANI M1\nOUT Y0\nLD X2\nANI M1\nOUT Y1\n");
        assert_eq!(text.matches(" = not ").count(), 2, "{text}");
        // A word compared with itself is decided.
        let text = ir("LD= D0 D0\nOUT Y0\nLD< D0 D0\nOUT Y1\n");
        assert!(!text.contains("cmp"), "{text}");
        assert!(text.contains("const.bit 1") && text.contains("const.bit 0"), "{text}");
    }

    #[test]
    fn always_on_relays_cost_nothing() {
        let text = ir("LD M8000\nAND X0\nOUT Y0\nLD M8001\nOUT Y1\n");
        assert!(!text.contains("M8000") && !text.contains("M8001"), "{text}");
        assert!(text.contains("store.bit Y1, v"), "{text}");
        assert_eq!(text.matches("block").count(), 1, "one block:\n{text}");
    }

    #[test]
    fn written_special_relays_are_not_folded() {
        let text = ir("LD X0\nOUT M8000\nLD M8000\nOUT Y0\n");
        // Y0 gets what was stored in M8000 (forwarded), not a constant.
        assert!(!text.contains("const"), "{text}");
        assert!(
            text.contains("v2 = load.bit X0") && text.contains("store.bit Y0, v2"),
            "{text}"
        );
    }

    #[test]
    fn logic_stack_makes_no_memory_traffic() {
        let text = ir("LD X0\nOR X1\nLD X2\nOR X3\nANB\nMPS\nAND X4\nOUT Y0\nMPP\nOUT Y1\n");
        assert_eq!(text.matches("load.").count(), 5, "{text}");
        assert_eq!(text.matches("store.").count(), 2, "{text}");
    }

    #[test]
    fn dead_set_branches_disappear() {
        let text = ir("LD M8001\nSET Y0\nLD SM0\nRST Y1\n");
        assert!(!text.contains("Y0"), "{text}");
        assert!(text.contains("const.bit 0") && text.contains("store.bit Y1"), "{text}");
        assert!(!text.contains("br "), "{text}");
    }
}
