//! Which bit loads may read four bytes on x86-64.
//!
//! A bit device is one byte, 0 or 1. An x86 instruction can take one of its
//! operands from memory (`and eax, [rdi+0x5a7]`: the load and the AND in one
//! micro-fused operation), which halves what a contact costs; Cranelift does
//! that for loads of 32 bits and more only. So on x86-64 a contact's device
//! is loaded as the 32-bit word that starts at its byte, and bit values are
//! computed in 32-bit registers (`translate.rs`): byte 0 holds the bit
//! (every device byte is 0 or 1, and AND, OR, XOR with 1 and AND-NOT keep
//! bits 1-7 at 0), bits 8-31 are whatever the next three bytes held and are
//! never looked at — a bit is stored, tested or widened from byte 0.
//!
//! Reading four bytes where the program recently stored one of them would
//! stall the processor: a load that a pending store only partly covers
//! waits until the store has left the store buffer (store forwarding
//! fails), about as long as a dozen instructions. So a load reads four
//! bytes only when none of them was stored within `HAZARD_DISTANCE` IR
//! instructions before it: not by the program, not by a helper or
//! subroutine it called (which may write anything), not by the runtime
//! before the function started (its begin-scan writes inputs and special
//! relays), and not inside a loop (where a later store comes before the
//! load again). A value the program stored is usually forwarded in a
//! register by the memory pass anyway (`crates/ir/src/memory.rs`).

use ladder_ir::{Effect, Function, Index, Inst, Space, Span};
use ladder_runtime::helpers::Helper;
use ladder_runtime::layout::{Array, Layout};
use rustc_hash::FxHashMap;

/// How far back (in IR instructions, about one machine instruction each) a
/// store to one of the four bytes keeps a load narrow. Measured on the
/// benchmarks' bit logic (x86-64): distances from 1 to 128 are as fast
/// (stores this far back have mostly left the store buffer when the load
/// runs), 512 is 4 % slower (more narrow loads), no wide loads at all 25 %.
const HAZARD_DISTANCE: usize = 64;

/// Bytes a wide bit load reads.
pub const WIDE_LOAD_BYTES: u32 = 4;

/// What an instruction writes in the image, for the analysis.
enum Writes {
    Nothing,
    /// Bytes `start..end` of the image.
    Bytes(u32, u32),
    /// These byte ranges (a helper's declared effects).
    Ranges(Vec<(u32, u32)>),
    /// Anything (a call of a subroutine or of a helper that takes places).
    Everything,
}

impl Writes {
    fn ranges(self) -> Vec<(u32, u32)> {
        match self {
            Writes::Nothing | Writes::Everything => Vec::new(),
            Writes::Bytes(start, end) => vec![(start, end)],
            Writes::Ranges(ranges) => ranges,
        }
    }
}

/// What a helper call may write: what its declaration says, or anything
/// when it takes places (it writes its destination, wherever that is).
fn call_writes(layout: &Layout, helper: Helper) -> Writes {
    use ladder_runtime::helpers::{Param, Writes as Declared};
    use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
    let decl = helper.decl();
    if decl.params.iter().any(|(_, param)| match param {
        Param::SourcePlace | Param::DestinationPlace => true,
        Param::U32 | Param::I32 => false,
    }) {
        return Writes::Everything;
    }
    let mut ranges = Vec::new();
    for &declared in decl.writes {
        let arrays: &[Array] = match declared {
            Declared::Timers => &[
                Array::TimerContact,
                Array::TimerValue,
                Array::TimerRemainder,
                Array::TimerCoilWasOn,
            ],
            Declared::Counters => &[
                Array::CounterContact,
                Array::CounterValue,
                Array::WideCounterValue,
                Array::CounterCoilWasOn,
            ],
            Declared::StlBookkeeping => &[Array::StlPendingOff],
            Declared::OperationError => {
                for (array, n) in [
                    (Array::M, M_OPERATION_ERROR),
                    (Array::D, D_ERROR_CODE),
                    (Array::D, D_ERROR_LINE),
                ] {
                    ranges.extend(element(layout, array, Index::Fixed(n)).ranges());
                }
                &[]
            }
            Declared::Bits(area) => {
                ranges.extend(whole(layout, Array::of_bits(area)).ranges());
                &[]
            }
            Declared::Image => return Writes::Everything,
        };
        for &array in arrays {
            ranges.extend(whole(layout, array).ranges());
        }
    }
    Writes::Ranges(ranges)
}

/// The bytes of a whole array in `layout`, or nothing if it lacks it.
fn whole(layout: &Layout, array: Array) -> Writes {
    match layout.whole(array) {
        Some(start) => {
            let count = array.end() - array.first();
            let end = start as u32 + count * array.size() as u32;
            Writes::Bytes(start as u32, end)
        }
        None => Writes::Nothing,
    }
}

/// The image offset of element `n` of `array` as the translation addresses
/// it (a number past the array clamped into it), if the layout holds it.
pub fn fixed_offset(layout: &Layout, array: Array, n: u32) -> Option<u32> {
    layout
        .offset(array, n.clamp(array.first(), array.end() - 1))
        .map(|at| at as u32)
}

/// The bytes of element `n` of `array`, `size` bytes from its start, or the
/// whole array for a run-time index.
fn element(layout: &Layout, array: Array, index: Index) -> Writes {
    match index {
        Index::Fixed(n) => match fixed_offset(layout, array, n) {
            Some(at) => Writes::Bytes(at, at + array.size() as u32),
            None => Writes::Nothing,
        },
        Index::Dynamic(_) => whole(layout, array),
    }
}

fn writes(layout: &Layout, inst: &Inst) -> Writes {
    match inst.effect() {
        Effect::Store(span, _) => element(layout, span.space.array(), span.start),
        Effect::Fill(span) => whole(layout, span.space.array()),
        Effect::Helper(helper, _) => call_writes(layout, helper),
        Effect::OperationError => call_writes(layout, Helper::RecordError),
        Effect::Subroutine => Writes::Everything,
        Effect::Pure | Effect::ReadsLocal | Effect::WritesLocal | Effect::Load(_) => Writes::Nothing,
    }
}

/// The image offset of the bit a load reads, when the load may read four
/// bytes there (all inside the image): a bit device at a fixed number.
fn wide_candidate(layout: &Layout, span: Span) -> Option<u32> {
    let Index::Fixed(n) = span.start else { return None };
    let array = match span.space {
        Space::Bits(area) => Array::of_bits(area),
        Space::Words(_) | Space::WideCounters | Space::EdgeSlots | Space::BlockActive | Space::Bookkeeping(_) => {
            return None
        }
    };
    let at = fixed_offset(layout, array, n)?;
    (at.checked_add(WIDE_LOAD_BYTES)? <= layout.size).then_some(at)
}

/// For blocks `range` of `function` (compiled as one machine function,
/// entered after unknown stores), which loads of bits may read
/// four bytes: `result[b][i]` for instruction `i` of block `range.start + b`.
pub fn wide_bit_loads(layout: &Layout, function: &Function, range: std::ops::Range<usize>) -> Vec<Vec<bool>> {
    let blocks = &function.blocks[range.clone()];
    // Blocks inside a loop (from a back edge's target to its source).
    let mut in_loop = vec![false; blocks.len()];
    for (number, block) in blocks.iter().enumerate() {
        for successor in block.terminator.successors() {
            let target = successor.0 as usize;
            if (range.start..=range.start + number).contains(&target) {
                for flag in &mut in_loop[target - range.start..=number] {
                    *flag = true;
                }
            }
        }
    }
    // Where each image byte was last stored, and the last call; the
    // function's entry counts as a call (the caller, or the runtime's
    // begin-scan, stored just before it).
    let mut stored_at: FxHashMap<u32, usize> = FxHashMap::default();
    let mut wide_stores: Vec<(u32, u32, usize)> = Vec::new();
    let mut last_call = 0usize;
    let mut position = 0usize;
    let recent = |at: usize, now: usize| now - at < HAZARD_DISTANCE;
    let mut result = Vec::with_capacity(blocks.len());
    for (block, looping) in blocks.iter().zip(in_loop) {
        let mut flags = Vec::with_capacity(block.insts.len());
        for (_, inst) in &block.insts {
            position += 1;
            let wide = match inst.effect() {
                Effect::Load(span) if !looping && !recent(last_call, position) => wide_candidate(layout, span)
                    .is_some_and(|at| {
                        let bytes = at..at + WIDE_LOAD_BYTES;
                        !bytes
                            .clone()
                            .any(|b| stored_at.get(&b).is_some_and(|&p| recent(p, position)))
                            && !wide_stores
                                .iter()
                                .any(|&(start, end, p)| start < bytes.end && bytes.start < end && recent(p, position))
                    }),
                Effect::Load(_)
                | Effect::Pure
                | Effect::ReadsLocal
                | Effect::WritesLocal
                | Effect::Store(..)
                | Effect::Fill(_)
                | Effect::Helper(..)
                | Effect::OperationError
                | Effect::Subroutine => false,
            };
            flags.push(wide);
            match writes(layout, inst) {
                Writes::Nothing => {}
                Writes::Everything => last_call = position,
                Writes::Bytes(start, end) if end - start <= WIDE_LOAD_BYTES => {
                    for byte in start..end {
                        stored_at.insert(byte, position);
                    }
                }
                Writes::Bytes(start, end) => {
                    wide_stores.retain(|&(_, _, p)| recent(p, position));
                    wide_stores.push((start, end, position));
                }
                Writes::Ranges(ranges) => {
                    wide_stores.retain(|&(_, _, p)| recent(p, position));
                    wide_stores.extend(ranges.into_iter().map(|(start, end)| (start, end, position)));
                }
            }
        }
        result.push(flags);
    }
    result
}
