//! Which parts of the image a function addresses from base registers of
//! its own (x86-64).
//!
//! An x86 memory operand's displacement takes one byte when it lies within
//! -128..=127 of the base register and four bytes otherwise, so
//! `and eax, [rdi+0x5a7]` is six bytes and `and eax, [rsi+0x27]` three. A
//! scan's code is mostly loads and stores of devices at fixed offsets, and a
//! program of thousands of instructions runs from the instruction decoders,
//! not from the micro-op cache, at a number of bytes per cycle: its speed
//! follows the bytes of its code more than the count of its instructions.
//! Measured on the benchmarks' 11k bit logic: with four windows addressed
//! this way its body went from 62.5 KB to 48.1 KB and its scan took 0.77
//! of the time, for the same instructions.
//!
//! So a function gets up to `BASES` pointers into the image, each the
//! middle of a 256-byte window starting at a multiple of 64: greedily, the
//! window with the most accesses at fixed offsets that no window chosen
//! before covers (the image pointer covers offsets 0-127 already), while a
//! window has at least `MIN_ACCESSES`. Each base register holds its pointer for the whole
//! function, and every one more leaves the program's values one register
//! fewer: against four, six and eight bases made the bit logic 3 % and 5 %
//! faster but the mixed plant, whose devices lie far apart, 6 % and 3 %
//! slower; a base for every window it touches, 23 % slower (paired CPU
//! time, x86-64).

use ladder_ir::{Effect, Function, Index, Span};
use ladder_runtime::layout::Layout;
use rustc_hash::FxHashMap;

/// Base registers a function may hold besides the image pointer.
pub const BASES: usize = 4;

/// Accesses a window needs to get a base register of its own: making the
/// pointer costs two instructions at entry and the register.
const MIN_ACCESSES: usize = 16;

/// Offsets the image pointer itself reaches with a one-byte displacement.
const NEAR_IMAGE: u32 = 128;

/// How far a base register reaches: `centre - REACH ..= centre + REACH - 1`.
pub const REACH: u32 = 128;

/// The image offset of an access at a fixed place, as the translation
/// addresses it.
fn fixed_offset(layout: &Layout, span: Span) -> Option<u32> {
    match span.start {
        Index::Fixed(n) => super::wide::fixed_offset(layout, span.space.array(), n),
        Index::Dynamic(_) => None,
    }
}

/// Windows start at multiples of this many bytes: accesses are counted by
/// granule, not sorted one by one.
const GRANULE: u32 = 64;

/// The middles of the windows blocks `range` of `function` address from
/// base registers, most accesses first.
pub fn window_centres(layout: &Layout, function: &Function, range: std::ops::Range<usize>) -> Vec<u32> {
    let mut per_granule: FxHashMap<u32, usize> = FxHashMap::default();
    for (_, inst) in function.blocks[range].iter().flat_map(|block| &block.insts) {
        let offset = match inst.effect() {
            Effect::Load(span) | Effect::Store(span, _) => fixed_offset(layout, span),
            Effect::Pure
            | Effect::Fill(_)
            | Effect::Helper(..)
            | Effect::OperationError
            | Effect::Subroutine
            | Effect::ReadsLocal
            | Effect::WritesLocal => None,
        };
        if let Some(at) = offset.filter(|&at| at >= NEAR_IMAGE) {
            *per_granule.entry(at / GRANULE).or_default() += 1;
        }
    }
    let mut granules: Vec<(u32, usize)> = per_granule.into_iter().collect();
    granules.sort_unstable();
    let mut centres = Vec::new();
    while centres.len() < BASES {
        let Some((start, end, count)) = densest_window(&granules) else {
            break;
        };
        if count < MIN_ACCESSES {
            break;
        }
        centres.push(granules[start].0 * GRANULE + REACH);
        for granule in &mut granules[start..end] {
            granule.1 = 0;
        }
    }
    centres
}

/// Of `granules` (sorted, with their accesses), the window of 2 × `REACH`
/// bytes from one of them that holds the most accesses: the granules'
/// indices `start..end` and the accesses.
fn densest_window(granules: &[(u32, usize)]) -> Option<(usize, usize, usize)> {
    const SPAN: u32 = 2 * REACH / GRANULE;
    let mut best: Option<(usize, usize, usize)> = None;
    let (mut end, mut count) = (0, 0);
    for (start, &(first, _)) in granules.iter().enumerate() {
        while end < granules.len() && granules[end].0 < first + SPAN {
            count += granules[end].1;
            end += 1;
        }
        if best.is_none_or(|(_, _, most)| count > most) {
            best = Some((start, end, count));
        }
        count -= granules[start].1;
    }
    best
}
