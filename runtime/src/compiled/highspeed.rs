//! SPD in compiled code: the rule of the interpreter's kernel, written
//! apart from it.

use crate::device::Width;
use crate::image::ImageMut;
use crate::layout::{Array, Scalar};
use crate::place::Place;

/// SPD: edges of X`input` counted over `period` ms: D the last whole
/// period's count, D+1 the count so far, D+2 the time left.
pub fn speed(mem: &mut ImageMut<'_>, input: u32, period: i64, destination: Place, width: Width) {
    if !mem.holds(Array::InputEdges, input) {
        return;
    }
    let edges = mem.get_u32(Array::InputEdges, input);
    let slot = |unit| destination.nth(unit, width);
    let counted = i64::from(slot(1).read(mem, width));
    let left = i64::from(slot(2).read(mem, width));
    let (mut counted, mut left) = if left > 0 { (counted, left) } else { (0, period) };
    counted += i64::from(edges);
    left -= i64::from(mem.scalar(Scalar::ElapsedMs));
    if left <= 0 {
        slot(0).write(mem, width, counted);
        counted = 0;
        left = period;
    }
    slot(1).write(mem, width, counted);
    slot(2).write(mem, width, left);
}
