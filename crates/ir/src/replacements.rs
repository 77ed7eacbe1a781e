//! Values that stand for others, as the passes find them (constant folding,
//! value sharing, memory forwarding), and the rewriting of their uses.

use super::{Function, Inst, Terminator, Value};
use rustc_hash::FxHashMap;

/// Values that stand for others (`v20` used as `v8`), as a pass finds them.
/// Passes walk blocks in reverse postorder, so a value is replaced before
/// any use of it is met, and a replacement is never itself replaced (it is
/// an earlier value, already resolved): one step resolves a use.
#[derive(Default)]
pub(crate) struct Replacements(FxHashMap<Value, Value>);

impl Replacements {
    /// From now on, uses of `value` read `by`.
    pub(crate) fn insert(&mut self, value: Value, by: Value) {
        self.0.insert(value, by);
    }

    fn resolve(&self, value: &mut Value) {
        if let Some(&by) = self.0.get(value) {
            *value = by;
        }
    }

    /// Rewrites the values `inst` reads.
    pub(crate) fn in_operands(&self, inst: &mut Inst) {
        inst.for_each_operand_mut(|v| self.resolve(v));
    }

    /// Rewrites the condition of a branch.
    pub(crate) fn in_condition(&self, terminator: &mut Terminator) {
        if let Terminator::Branch { condition, .. } = terminator {
            self.resolve(condition);
        }
    }

    /// Rewrites the condition of every branch of `function`.
    pub(crate) fn in_conditions(&self, function: &mut Function) {
        for block in &mut function.blocks {
            self.in_condition(&mut block.terminator);
        }
    }
}
