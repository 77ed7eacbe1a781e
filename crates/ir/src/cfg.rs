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

/// The predecessors of every block among the blocks of `order` (the
/// reverse postorder: blocks the entry cannot reach have none), in order.
pub(crate) fn predecessors(function: &Function, order: &[BlockId]) -> Vec<Vec<BlockId>> {
    let mut predecessors: Vec<Vec<BlockId>> = vec![Vec::new(); function.blocks.len()];
    for &block in order {
        for successor in function.block(block).terminator.successors() {
            predecessors[successor.0 as usize].push(block);
        }
    }
    predecessors
}

/// The immediate dominator of every block the entry reaches (the entry is
/// its own), by the iterative algorithm of Cooper, Harvey and Kennedy ("A
/// Simple, Fast Dominance Algorithm", 2001) over the reverse postorder.
pub(crate) struct Dominators {
    /// By block number: the immediate dominator, `None` for unreachable
    /// blocks.
    idom: Vec<Option<BlockId>>,
    /// By block number: when a depth-first walk of the dominator tree
    /// enters and leaves the block, so that `a` dominates `b` exactly when
    /// `b`'s interval lies in `a`'s (a query in constant time: the verifier
    /// asks for every use after every pass).
    entered: Vec<usize>,
    left: Vec<usize>,
}

impl Dominators {
    /// `order` is `reverse_postorder(function)`.
    pub(crate) fn new(function: &Function, order: &[BlockId]) -> Dominators {
        let blocks = function.blocks.len();
        let mut position = vec![usize::MAX; blocks];
        for (at, block) in order.iter().enumerate() {
            position[block.0 as usize] = at;
        }
        let predecessors = predecessors(function, order);
        let mut idom: Vec<Option<BlockId>> = vec![None; blocks];
        let Some(&entry) = order.first() else {
            return Dominators {
                idom,
                entered: vec![0; blocks],
                left: vec![0; blocks],
            };
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
        // Number the dominator tree.
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); blocks];
        for (block, parent) in idom.iter().enumerate() {
            if let Some(parent) = parent {
                if parent.0 as usize != block {
                    children[parent.0 as usize].push(block);
                }
            }
        }
        let (mut entered, mut left) = (vec![0; blocks], vec![0; blocks]);
        let mut clock = 0;
        let mut stack = vec![(entry.0 as usize, false)];
        while let Some((block, done)) = stack.pop() {
            clock += 1;
            if done {
                left[block] = clock;
                continue;
            }
            entered[block] = clock;
            stack.push((block, true));
            stack.extend(children[block].iter().map(|&child| (child, false)));
        }
        Dominators { idom, entered, left }
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
        let (a, b) = (a.0 as usize, b.0 as usize);
        self.entered[a] <= self.entered[b] && self.left[b] <= self.left[a]
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
