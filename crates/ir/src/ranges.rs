//! The ranges values lie in, for the constant pass: a comparison that
//! holds (or fails) for every value its operands can take is a constant.
//! A C compiler decides these from the same facts, and Cranelift without
//! its optimiser does not; the commonest is ADD's underflow flag M8021
//! after a 16-bit operand plus a positive constant, which can never be ON.
//!
//! A value's range comes from its type (a bit is 0 or 1, an `I16` is a
//! signed 16-bit number), from the extension that made it (an `I64` made
//! from an `I16` is still a 16-bit number) and from additions and
//! subtractions that cannot wrap. Numbers are compared signed, as the IR
//! compares them; floats have no range here.

use super::{BinOp, Inst, Type, Value};
use crate::CompareOp;
use rustc_hash::FxHashMap;

/// The least and greatest value, both included.
type Range = (i64, i64);

/// The ranges found so far, for values narrower than their type.
#[derive(Default)]
pub struct Ranges(FxHashMap<Value, Range>);

impl Ranges {
    /// The range of `value` of type `ty`, a constant's being its value.
    fn of(&self, value: Value, ty: Type, constants: &FxHashMap<Value, i64>) -> Option<Range> {
        if let Some(&c) = constants.get(&value) {
            return Some((c, c));
        }
        self.0.get(&value).copied().or_else(|| type_range(ty))
    }

    /// Records the range of `result`, defined by `inst` (after folding).
    pub fn record(&mut self, result: Value, inst: &Inst, types: &[Type], constants: &FxHashMap<Value, i64>) {
        let ty = types[result.0 as usize];
        let of = |v: &Value| self.of(*v, types[v.0 as usize], constants);
        // Only extensions, additions and subtractions narrow a range; any
        // other instruction gets what its type allows, which is always true
        // of it. This is the one place where a new instruction is meant to
        // fall to a default (it is sound without a range), hence no
        // exhaustive match.
        let range = if let Inst::Extend { value, signed, .. } = inst {
            of(value).map(|(low, high)| {
                if *signed || low >= 0 {
                    (low, high)
                } else {
                    // Zero-extended: the operand's bits read as unsigned.
                    (0, unsigned_max(types[value.0 as usize]))
                }
            })
        } else if let Inst::Binary { op, a, b } = inst {
            of(a)
                .zip(of(b))
                .and_then(|((a_low, a_high), (b_low, b_high))| match op {
                    BinOp::Add => a_low.checked_add(b_low).zip(a_high.checked_add(b_high)),
                    BinOp::Sub => a_low.checked_sub(b_high).zip(a_high.checked_sub(b_low)),
                    BinOp::Mul
                    | BinOp::Div
                    | BinOp::Rem
                    | BinOp::And
                    | BinOp::Or
                    | BinOp::Xor
                    | BinOp::Shl
                    | BinOp::Shr
                    | BinOp::UShr => None,
                })
        } else {
            None
        };
        // Kept only where narrower than the type (a wrapped result is not).
        if let (Some((low, high)), Some((type_low, type_high))) = (range, type_range(ty)) {
            if type_low <= low && high <= type_high && (low, high) != (type_low, type_high) {
                self.0.insert(result, (low, high));
            }
        }
    }

    /// Whether `a op b` holds for every value of the operands (`Some(true)`),
    /// for none (`Some(false)`), or depends on them.
    pub fn decide(
        &self,
        op: CompareOp,
        a: Value,
        b: Value,
        types: &[Type],
        constants: &FxHashMap<Value, i64>,
    ) -> Option<bool> {
        let (a_low, a_high) = self.of(a, types[a.0 as usize], constants)?;
        let (b_low, b_high) = self.of(b, types[b.0 as usize], constants)?;
        let below = a_high < b_low;
        let above = a_low > b_high;
        let single_equal = a_low == a_high && b_low == b_high && a_low == b_low;
        let (always, never) = match op {
            CompareOp::Lt => (below, a_low >= b_high),
            CompareOp::Le => (a_high <= b_low, above),
            CompareOp::Gt => (above, a_high <= b_low),
            CompareOp::Ge => (a_low >= b_high, below),
            CompareOp::Eq => (single_equal, below || above),
            CompareOp::Ne => (below || above, single_equal),
        };
        match (always, never) {
            (true, _) => Some(true),
            (false, true) => Some(false),
            (false, false) => None,
        }
    }
}

/// The values of a type, signed; none for floats.
fn type_range(ty: Type) -> Option<Range> {
    match ty {
        Type::Bit => Some((0, 1)),
        Type::I16 => Some((i64::from(i16::MIN), i64::from(i16::MAX))),
        Type::I32 => Some((i64::from(i32::MIN), i64::from(i32::MAX))),
        Type::I64 => Some((i64::MIN, i64::MAX)),
        Type::F32 | Type::F64 => None,
    }
}

/// The greatest value of a type's bits read as unsigned (within an i64).
fn unsigned_max(ty: Type) -> i64 {
    match ty {
        Type::Bit => 1,
        Type::I16 => i64::from(u16::MAX),
        Type::I32 => i64::from(u32::MAX),
        Type::I64 | Type::F32 | Type::F64 => i64::MAX,
    }
}

#[cfg(test)]
mod tests {
    use crate::passes::tests::ir;

    #[test]
    fn add_of_a_16_bit_word_and_a_positive_constant_never_underflows() {
        // M8021 (underflow) is stored as a constant OFF; M8022 (overflow)
        // still compares.
        let text = ir("LD SM0\nADD D0 K3 D1\n");
        assert!(text.contains("store.bit M8021, v"), "{text}");
        let flag = text
            .lines()
            .find(|line| line.contains("store.bit M8021"))
            .and_then(|line| line.rsplit(' ').next())
            .expect("M8021 is stored");
        assert!(text.contains(&format!("{flag} = const.bit 0")), "{text}");
        assert!(!text.contains("cmp< "), "{text}");
        assert!(text.contains("cmp> "), "{text}");
    }

    #[test]
    fn a_comparison_that_depends_on_the_operand_stays() {
        // D0 + D1 can underflow: both flags compare.
        let text = ir("LD SM0\nADD D0 D1 D2\n");
        assert!(text.contains("cmp< "), "{text}");
        assert!(text.contains("cmp> "), "{text}");
    }
}
