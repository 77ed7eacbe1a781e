//! The control-flow graph of a function, as the passes and the verifier
//! see it: blocks in reverse postorder, predecessors, and dominators.
//! Passes walk blocks in reverse postorder so that a definition is met
//! before its uses; the verifier checks that it is (`verify.rs`).

use super::{BlockId, Function};

/// Blocks in reverse postorder from the entry: every definition comes before
/// its uses in this order. Blocks the entry cannot reach are left out.
pub(crate) fn reverse_postorder(function: &Function) -> Vec<BlockId> {
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

/// The immediate dominator of every block the entry reaches (the entry is
/// its own), by the iterative algorithm of Cooper, Harvey and Kennedy ("A
/// Simple, Fast Dominance Algorithm", 2001) over the reverse postorder.
pub(crate) struct Dominators {
    /// By block number: the immediate dominator, `None` for unreachable
    /// blocks.
    idom: Vec<Option<BlockId>>,
    /// By block number: the position in the reverse postorder.
    position: Vec<usize>,
}

impl Dominators {
    /// `order` is `reverse_postorder(function)`.
    pub(crate) fn new(function: &Function, order: &[BlockId]) -> Dominators {
        let blocks = function.blocks.len();
        let mut position = vec![usize::MAX; blocks];
        for (at, block) in order.iter().enumerate() {
            position[block.0 as usize] = at;
        }
        let mut predecessors: Vec<Vec<BlockId>> = vec![Vec::new(); blocks];
        for &block in order {
            for successor in function.block(block).terminator.successors() {
                predecessors[successor.0 as usize].push(block);
            }
        }
        let mut idom: Vec<Option<BlockId>> = vec![None; blocks];
        let Some(&entry) = order.first() else {
            return Dominators { idom, position };
        };
        idom[entry.0 as usize] = Some(entry);
        let mut changed = true;
        while changed {
            changed = false;
            for &block in order.iter().skip(1) {
                let mut new_idom: Option<BlockId> = None;
                for &p in &predecessors[block.0 as usize] {
                    if idom[p.0 as usize].is_none() {
                        continue;
                    }
                    new_idom = Some(match new_idom {
                        None => p,
                        Some(current) => intersect(&idom, &position, p, current),
                    });
                }
                if new_idom.is_some() && idom[block.0 as usize] != new_idom {
                    idom[block.0 as usize] = new_idom;
                    changed = true;
                }
            }
        }
        Dominators { idom, position }
    }

    /// The entry reaches `block`.
    pub(crate) fn is_reachable(&self, block: BlockId) -> bool {
        self.idom.get(block.0 as usize).is_some_and(Option::is_some)
    }

    /// Every path from the entry to `b` passes through `a` (a block
    /// dominates itself). False when either is unreachable.
    pub(crate) fn dominates(&self, a: BlockId, b: BlockId) -> bool {
        if !self.is_reachable(a) || !self.is_reachable(b) {
            return false;
        }
        let mut at = b;
        loop {
            if at == a {
                return true;
            }
            // Dominators come earlier in the reverse postorder: once past
            // `a`'s position, `a` cannot be found above.
            if self.position[at.0 as usize] < self.position[a.0 as usize] {
                return false;
            }
            match self.idom[at.0 as usize] {
                Some(up) if up != at => at = up,
                Some(_) | None => return false,
            }
        }
    }
}

fn intersect(idom: &[Option<BlockId>], position: &[usize], a: BlockId, b: BlockId) -> BlockId {
    let (mut a, mut b) = (a, b);
    while a != b {
        while position[a.0 as usize] > position[b.0 as usize] {
            a = idom[a.0 as usize].unwrap_or(a);
        }
        while position[b.0 as usize] > position[a.0 as usize] {
            b = idom[b.0 as usize].unwrap_or(b);
        }
    }
    a
}
