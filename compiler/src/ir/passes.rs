//! IR passes that pay for themselves on real programs:
//!
//! - constant folding, including the always-ON/OFF relays (SM0, M8000, M8001,
//!   ...) when the program never writes them: `LD M8000` costs nothing;
//! - branch folding and removal of unreachable blocks;
//! - merging a block into its only predecessor;
//! - removal of pure instructions whose values are never used.

use super::{BinOp, Block, BlockId, Function, Index, Inst, Terminator, Type, Value};
use crate::isa::CompareOp;
use ladder_runtime::special::{M_ALWAYS_OFF, M_ALWAYS_ON, SM_ALWAYS_OFF, SM_ALWAYS_ON};
use ladder_runtime::BitArea;
use std::collections::HashMap;

/// Runs every pass.
pub fn optimize(function: &mut Function) {
    fold_constants(function);
    fold_branches(function);
    remove_unreachable(function);
    thread_jumps(function);
    merge_blocks(function);
    remove_dead_values(function);
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
            _ => None,
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
        block.terminator = match block.terminator {
            Terminator::Jump(target) => Terminator::Jump(resolve(target)),
            Terminator::Branch {
                condition,
                then,
                otherwise,
            } => Terminator::Branch {
                condition,
                then: resolve(then),
                otherwise: resolve(otherwise),
            },
            Terminator::Return => Terminator::Return,
        };
    }
    fold_branches(function);
    remove_unreachable(function);
}

/// Blocks in reverse postorder from the entry: every definition comes before
/// its uses in this order.
fn reverse_postorder(function: &Function) -> Vec<BlockId> {
    let mut visited = vec![false; function.blocks.len()];
    let mut order = Vec::new();
    let mut stack = vec![(BlockId(0), false)];
    while let Some((block, done)) = stack.pop() {
        if done {
            order.push(block);
            continue;
        }
        if std::mem::replace(&mut visited[block.0 as usize], true) {
            continue;
        }
        stack.push((block, true));
        for successor in function.block(block).terminator.successors().into_iter().rev() {
            if !visited[successor.0 as usize] {
                stack.push((successor, false));
            }
        }
    }
    order.reverse();
    order
}

/// The relays the runtime holds constant during the program, and their value,
/// unless the program may write them.
fn constant_relays(function: &Function) -> HashMap<(BitArea, u32), bool> {
    let mut known: HashMap<(BitArea, u32), bool> = HashMap::new();
    known.insert((BitArea::Sm, SM_ALWAYS_ON), true);
    known.insert((BitArea::Sm, SM_ALWAYS_OFF), false);
    for n in M_ALWAYS_ON {
        known.insert((BitArea::M, n), true);
    }
    for n in M_ALWAYS_OFF {
        known.insert((BitArea::M, n), false);
    }
    for block in &function.blocks {
        for (_, inst) in &block.insts {
            let written: Option<(BitArea, Index, u32)> = match inst {
                Inst::StoreBit { area, index, .. } => Some((*area, *index, 1)),
                Inst::FillBits { area, start, count, .. } => Some((*area, *start, *count)),
                Inst::BlockMove { destination, .. } => {
                    // A digit-group destination writes bits of some area.
                    let bits = destination.kind.checked_sub(ladder_runtime::place::PLACE_DIGITS);
                    let area = BitArea::ALL.iter().find(|a| Some(**a as u32) == bits);
                    area.map(|&area| (area, Index::Dynamic(Value(0)), 0))
                }
                _ => None,
            };
            match written {
                Some((area, Index::Fixed(start), count)) => {
                    known.retain(|&(a, n), _| a != area || !(start..start + count).contains(&n));
                }
                Some((area, Index::Dynamic(_), _)) => known.retain(|&(a, _), _| a != area),
                None => {}
            }
        }
    }
    known
}

/// Wraps `value` to the bits of `ty`, sign-extended (Bits are 0/1).
fn wrap(ty: Type, value: i64) -> i64 {
    match ty {
        Type::Bit => value & 1,
        Type::I16 => i64::from(value as i16),
        Type::I32 => i64::from(value as i32),
        Type::I64 => value,
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
        BinOp::Shl => a.wrapping_shl(b as u32),
        BinOp::Shr => a.wrapping_shr(b as u32),
    };
    Some(wrap(ty, value))
}

fn compare(op: CompareOp, a: i64, b: i64) -> bool {
    op.holds(a, b)
}

/// Folds instructions with constant operands to constants, and logic with one
/// constant operand to the other operand.
pub fn fold_constants(function: &mut Function) {
    let relays = constant_relays(function);
    let mut constants: HashMap<Value, i64> = HashMap::new();
    let mut replaced: HashMap<Value, Value> = HashMap::new();
    // Value defined by an Extend -> the value it extended.
    let mut extended_from: HashMap<Value, Value> = HashMap::new();
    for block in reverse_postorder(function) {
        let types = function.value_types.clone();
        let insts = &mut function.blocks[block.0 as usize].insts;
        for (result, inst) in insts.iter_mut() {
            rewrite_operands(inst, &replaced);
            let Some(result) = *result else { continue };
            let ty = types[result.0 as usize];
            let known = |v: &Value| constants.get(v).copied();
            let folded: Option<i64> = match &*inst {
                Inst::Const { value, .. } => Some(*value),
                Inst::LoadBit {
                    area,
                    index: Index::Fixed(n),
                } => relays.get(&(*area, *n)).map(|&on| on as i64),
                Inst::Not { value } => known(value).map(|v| 1 - v),
                Inst::And { a, b } => match (known(a), known(b)) {
                    (Some(0), _) | (_, Some(0)) => Some(0),
                    (Some(x), Some(y)) => Some(x & y),
                    (Some(_), None) => {
                        replaced.insert(result, *b);
                        None
                    }
                    (None, Some(_)) => {
                        replaced.insert(result, *a);
                        None
                    }
                    (None, None) if a == b => {
                        replaced.insert(result, *a);
                        None
                    }
                    _ => None,
                },
                Inst::Or { a, b } => match (known(a), known(b)) {
                    (Some(1), _) | (_, Some(1)) => Some(1),
                    (Some(x), Some(y)) => Some(x | y),
                    (Some(_), None) => {
                        replaced.insert(result, *b);
                        None
                    }
                    (None, Some(_)) => {
                        replaced.insert(result, *a);
                        None
                    }
                    (None, None) if a == b => {
                        replaced.insert(result, *a);
                        None
                    }
                    _ => None,
                },
                Inst::Binary { op, a, b } => match (op, known(a), known(b)) {
                    (_, Some(x), Some(y)) => fold_binary(*op, ty, x, y),
                    // x + 0, x - 0, x | 0, x << 0, x >> 0, x * 1
                    (BinOp::Add | BinOp::Sub | BinOp::Or | BinOp::Shl | BinOp::Shr, None, Some(0))
                    | (BinOp::Mul, None, Some(1)) => {
                        replaced.insert(result, *a);
                        None
                    }
                    // 0 + x, 0 | x, 1 * x
                    (BinOp::Add | BinOp::Or, Some(0), None) | (BinOp::Mul, Some(1), None) => {
                        replaced.insert(result, *b);
                        None
                    }
                    _ => None,
                },
                Inst::Compare { op, a, b } => match (known(a), known(b)) {
                    (Some(x), Some(y)) => Some(compare(*op, x, y) as i64),
                    _ => None,
                },
                Inst::Extend { value, signed, .. } => known(value).map(|v| {
                    let from = types[value.0 as usize];
                    if *signed || from == Type::Bit {
                        v
                    } else {
                        match from {
                            Type::I16 => i64::from(v as u16),
                            Type::I32 => i64::from(v as u32),
                            _ => v,
                        }
                    }
                }),
                Inst::Truncate { value, to } => match (known(value), extended_from.get(value)) {
                    (Some(v), _) => Some(wrap(*to, v)),
                    // trunc(ext(x)) back to x's own type is x.
                    (None, Some(&inner)) if types[inner.0 as usize] == *to => {
                        replaced.insert(result, inner);
                        None
                    }
                    _ => None,
                },
                Inst::Select {
                    condition,
                    if_true,
                    if_false,
                } => match known(condition) {
                    Some(c) => {
                        let chosen = if c != 0 { *if_true } else { *if_false };
                        match known(&chosen) {
                            Some(v) => Some(v),
                            None => {
                                replaced.insert(result, chosen);
                                None
                            }
                        }
                    }
                    None if if_true == if_false => {
                        replaced.insert(result, *if_true);
                        None
                    }
                    None => None,
                },
                _ => None,
            };
            if let Inst::Extend { value, .. } = &*inst {
                extended_from.insert(result, *value);
            }
            if let Some(value) = folded {
                let value = wrap(ty, value);
                constants.insert(result, value);
                *inst = Inst::Const { ty, value };
            }
        }
        let terminator = &mut function.blocks[block.0 as usize].terminator;
        if let Terminator::Branch { condition, .. } = terminator {
            if let Some(&other) = replaced.get(condition) {
                *condition = other;
            }
        }
    }
    // Terminators of blocks visited before a replacement was known.
    for block in &mut function.blocks {
        if let Terminator::Branch { condition, .. } = &mut block.terminator {
            if let Some(&other) = replaced.get(condition) {
                *condition = other;
            }
        }
    }
}

/// Replaces operands by the values they were folded to.
fn rewrite_operands(inst: &mut Inst, replaced: &HashMap<Value, Value>) {
    if replaced.is_empty() {
        return;
    }
    let map = |v: &mut Value| {
        // Chains are resolved in definition order, so one step suffices.
        if let Some(&other) = replaced.get(v) {
            *v = other;
        }
    };
    let index = |i: &mut Index| {
        if let Index::Dynamic(v) = i {
            map(v);
        }
    };
    match inst {
        Inst::Const { .. }
        | Inst::LoadSlot { .. }
        | Inst::LoadBlockActive { .. }
        | Inst::GetLocal { .. }
        | Inst::RecordError { .. }
        | Inst::ResetTimer { .. }
        | Inst::ResetCounter { .. }
        | Inst::ScheduleStateOff { .. } => {}
        Inst::LoadBit { index: i, .. } | Inst::LoadWord { index: i, .. } | Inst::LoadWideCounter { index: i } => {
            index(i)
        }
        Inst::FillBits { start, .. } | Inst::ClearWords { start, .. } => index(start),
        Inst::StoreBit { index: i, value, .. }
        | Inst::StoreWord { index: i, value, .. }
        | Inst::StoreWideCounter { index: i, value } => {
            index(i);
            map(value);
        }
        Inst::StoreSlot { value, .. }
        | Inst::StoreBlockActive { value, .. }
        | Inst::SetLocal { value, .. }
        | Inst::Not { value }
        | Inst::Extend { value, .. }
        | Inst::Truncate { value, .. } => map(value),
        Inst::And { a, b } | Inst::Or { a, b } | Inst::Binary { a, b, .. } | Inst::Compare { a, b, .. } => {
            map(a);
            map(b);
        }
        Inst::Select {
            condition,
            if_true,
            if_false,
        } => {
            map(condition);
            map(if_true);
            map(if_false);
        }
        Inst::TimerCoil { coil, preset, .. } | Inst::CounterCoil { coil, preset, .. } => {
            map(coil);
            map(preset);
        }
        Inst::BlockMove {
            source,
            destination,
            count,
            ..
        } => {
            index(&mut source.index);
            index(&mut destination.index);
            map(count);
        }
    }
}

/// A branch on a constant becomes a jump.
pub fn fold_branches(function: &mut Function) {
    let constants: HashMap<Value, i64> = function
        .blocks
        .iter()
        .flat_map(|b| b.insts.iter())
        .filter_map(|(result, inst)| match (result, inst) {
            (Some(r), Inst::Const { value, .. }) => Some((*r, *value)),
            _ => None,
        })
        .collect();
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
            block.terminator = match block.terminator {
                Terminator::Jump(target) => Terminator::Jump(map(target)),
                Terminator::Branch {
                    condition,
                    then,
                    otherwise,
                } => Terminator::Branch {
                    condition,
                    then: map(then),
                    otherwise: map(otherwise),
                },
                Terminator::Return => Terminator::Return,
            };
            block
        })
        .collect();
}

/// Appends a block to its predecessor when the predecessor jumps to it and
/// nothing else does.
pub fn merge_blocks(function: &mut Function) {
    loop {
        let mut predecessors = vec![0usize; function.blocks.len()];
        for block in &function.blocks {
            for successor in block.terminator.successors() {
                predecessors[successor.0 as usize] += 1;
            }
        }
        let candidate = function
            .blocks
            .iter()
            .enumerate()
            .find_map(|(index, block)| match block.terminator {
                Terminator::Jump(target)
                    if target.0 != 0 && target.0 as usize != index && predecessors[target.0 as usize] == 1 =>
                {
                    Some((index, target.0 as usize))
                }
                _ => None,
            });
        let Some((into, from)) = candidate else { break };
        let moved = std::mem::replace(
            &mut function.blocks[from],
            Block {
                insts: Vec::new(),
                terminator: Terminator::Return,
            },
        );
        let target = &mut function.blocks[into];
        target.insts.extend(moved.insts);
        target.terminator = moved.terminator;
        // The emptied block is now unreachable.
        remove_unreachable(function);
    }
}

/// Removes pure instructions whose values nothing uses.
pub fn remove_dead_values(function: &mut Function) {
    loop {
        let mut used = vec![false; function.value_types.len()];
        for block in &function.blocks {
            for (_, inst) in &block.insts {
                for value in inst.operands() {
                    used[value.0 as usize] = true;
                }
            }
            if let Terminator::Branch { condition, .. } = block.terminator {
                used[condition.0 as usize] = true;
            }
        }
        let mut removed = false;
        for block in &mut function.blocks {
            block.insts.retain(|(result, inst)| {
                let dead = matches!(result, Some(v) if !used[v.0 as usize]) && inst.is_pure();
                removed |= dead;
                !dead
            });
        }
        if !removed {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::check::compile_source;
    use crate::source::SourceFile;

    fn ir(text: &str) -> String {
        let (program, diagnostics) = compile_source(&SourceFile::new("t.il", text));
        let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
        crate::pipeline::ir(&program).to_string()
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
        assert!(text.contains("load.bit M8000"), "{text}");
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
        assert!(text.contains("fill.bit Y1 x1, 0"), "{text}");
        assert!(!text.contains("br "), "{text}");
    }
}
