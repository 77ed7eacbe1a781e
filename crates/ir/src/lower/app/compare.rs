//! Comparisons: CMP, ZCP.

use super::Step;
use crate::CompareOp;
use crate::Value;

/// S1 > S2, S1 = S2, S1 < S2.
pub fn cmp(step: &mut Step, [a, b]: [Value; 2]) -> [Value; 3] {
    [CompareOp::Gt, CompareOp::Eq, CompareOp::Lt].map(|op| step.b().compare(op, a, b))
}

/// S below, inside, above [S1, S2]; a reversed zone counts as the single
/// value S1.
pub fn zcp(step: &mut Step, [low, high, s]: [Value; 3]) -> [Value; 3] {
    let b = step.b();
    let reversed = b.compare(CompareOp::Gt, low, high);
    let high = b.select(reversed, low, high);
    let below = b.compare(CompareOp::Lt, s, low);
    let above = b.compare(CompareOp::Gt, s, high);
    let outside = b.or(below, above);
    let inside = b.not(outside);
    [below, inside, above]
}
