//! Where everything lives in a device image.
//!
//! An image is a header (`ImageHeader`: which layout it has; declared with
//! `Memory`, whose first field it is), the scan's scalars (elapsed time,
//! scan count, ...; at the same offsets in every image) and arrays
//! (`Array`): the device areas and the bookkeeping the scan keeps per
//! timer, counter, state, edge instruction, ... An array is
//! cut into segments (`SEGMENTS`) where a program uses parts apart: M0-M7999
//! and the special relays M8000-M8511, D likewise, the 16-bit and the
//! 32-bit counters, the buffer memory of each unit.
//!
//! A `Layout` says, for every segment, which devices of it the image holds
//! (a `Run`: first device, count) and at which byte offset. The full layout
//! (`FULL`) holds every device at the offsets of the `Memory` struct; a
//! compact layout (`LayoutBuilder`) holds only the devices one program and
//! its host use, packed. The runtime reads and writes every image through
//! its layout (`image.rs`), so both are served by the same code. `array.rs`
//! declares the arrays, `compact.rs` builds compact layouts.

pub use crate::memory::{ImageHeader, COMPACT_MAGIC, FULL_MAGIC};

use crate::memory::Memory;
use bytemuck::{Pod, Zeroable};
use core::mem::offset_of;

/// Size of `Memory` (the full layout) in bytes.
pub const MEMORY_SIZE: usize = size_of::<Memory>();
/// Alignment of every image in bytes.
pub const MEMORY_ALIGN: usize = align_of::<Memory>();

/// The version of this file's rules: arrays, segments, header (`memory.rs`),
/// scalars.
/// Layout tables carry it; the runtime refuses a table of another version.
pub const LAYOUT_VERSION: u32 = 6;

/// Names the layout rules in the symbol that compiled objects import
/// (`ladder_rt_begin_scan_<tag>`), so that an object linked against a runtime
/// with other rules fails to link instead of corrupting memory. Change it
/// whenever an offset changes; `layout_fingerprint_is_recorded` insists.
pub const LAYOUT_TAG: &str = "v6_668580";

/// The begin-scan entry compiled objects call; carries the layout tag.
pub const TAGGED_BEGIN_SCAN: &str = "ladder_rt_begin_scan_v6_668580";

/// The end-scan entry compiled objects call; carries the layout tag.
pub const TAGGED_END_SCAN: &str = "ladder_rt_end_scan_v6_668580";

/// Bytes of the header.
pub const HEADER_SIZE: usize = size_of::<ImageHeader>();

/// The scan's single values, right after the header in every image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    /// Number of devices currently forced (lets the scan skip the tables).
    ForcedCount,
    /// Non-zero when some `stl_pending_off` entry is set.
    StlPendingAny,
    /// Milliseconds the host reported for the current scan.
    ElapsedMs,
    /// Completed scans since initialisation (saturating).
    ScanCount,
    /// The reported times modulo one minute (the clock relays).
    ClockMs,
    /// FOR/NEXT repetitions in the current scan (the loop watchdog).
    LoopRepetitions,
    /// The calendar clock: seconds since 1980-01-01 00:00:00.
    CalendarSeconds,
    /// The calendar clock: milliseconds below the second.
    CalendarMs,
    /// `calendar::CALENDAR_FOUR_DIGIT_YEAR` and the clock relays' memory.
    CalendarFlags,
    /// Accesses by the program to devices its image does not hold (a
    /// compact layout that missed one; tests insist on 0).
    LayoutMisses,
    /// The calendar's time as shown, worked out once per second: for which
    /// second (plus one; 0 when none), the packed fields, the year.
    CalendarCacheAt,
    CalendarCacheTime,
    CalendarCacheYear,
}

impl Scalar {
    /// Byte offset in every image.
    pub const fn offset(self) -> usize {
        match self {
            Scalar::ForcedCount => offset_of!(Memory, forced_count),
            Scalar::StlPendingAny => offset_of!(Memory, stl_pending_any),
            Scalar::ElapsedMs => offset_of!(Memory, elapsed_ms),
            Scalar::ScanCount => offset_of!(Memory, scan_count),
            Scalar::ClockMs => offset_of!(Memory, clock_ms),
            Scalar::LoopRepetitions => offset_of!(Memory, loop_repetitions),
            Scalar::CalendarSeconds => offset_of!(Memory, calendar_seconds),
            Scalar::CalendarMs => offset_of!(Memory, calendar_ms),
            Scalar::CalendarFlags => offset_of!(Memory, calendar_flags),
            Scalar::LayoutMisses => offset_of!(Memory, layout_misses),
            Scalar::CalendarCacheAt => offset_of!(Memory, calendar_cache_at),
            Scalar::CalendarCacheTime => offset_of!(Memory, calendar_cache_time),
            Scalar::CalendarCacheYear => offset_of!(Memory, calendar_cache_year),
        }
    }
}

/// Where the arrays of a compact image start: after the header and the
/// scalars, which every image has at the same offsets.
pub const ARRAYS_START: usize = offset_of!(Memory, x);

mod array;
mod compact;

pub use array::{Array, FIRST_SPECIAL};
pub use compact::{bit_arrays, word_arrays, LayoutBuilder, COUNTER_ARRAYS};

/// Part of an array that a layout places as one run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    pub array: Array,
    /// Its first element and one past its last.
    pub first: u32,
    pub end: u32,
}

/// The number of segments.
pub const SEGMENT_COUNT: usize = {
    let mut count = 0;
    let mut i = 0;
    while i < Array::ALL.len() {
        count += Array::ALL[i].splits().len() + 1;
        i += 1;
    }
    count
};

/// Every segment, array by array in `Array` order.
pub const SEGMENTS: [Segment; SEGMENT_COUNT] = {
    let mut segments = [Segment {
        array: Array::X,
        first: 0,
        end: 0,
    }; SEGMENT_COUNT];
    let mut s = 0;
    let mut i = 0;
    while i < Array::ALL.len() {
        let array = Array::ALL[i];
        let splits = array.splits();
        let mut first = array.first();
        let mut k = 0;
        while k <= splits.len() {
            let end = if k < splits.len() { splits[k] } else { array.end() };
            segments[s] = Segment { array, first, end };
            s += 1;
            first = end;
            k += 1;
        }
        i += 1;
    }
    segments
};

/// The first segment of each array, by `Array as usize`.
pub(super) const FIRST_SEGMENT: [usize; Array::ALL.len()] = {
    let mut firsts = [0; Array::ALL.len()];
    let mut s = 0;
    let mut i = 0;
    while i < Array::ALL.len() {
        firsts[Array::ALL[i] as usize] = s;
        s += Array::ALL[i].splits().len() + 1;
        i += 1;
    }
    firsts
};

/// Where a layout places a segment: elements `first`..`first + count` at
/// byte `offset` (nothing when `count` is 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct Run {
    pub offset: u32,
    pub first: u32,
    pub count: u32,
}

/// A layout table: the version of these rules, the image's size, and a run
/// per segment. As 32-bit words (C hosts and generated code see it so):
/// version, size, then offset, first, count of each segment in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct Layout {
    pub version: u32,
    pub size: u32,
    pub runs: [Run; SEGMENT_COUNT],
}

/// 32-bit words of a layout table.
pub const LAYOUT_WORDS: usize = size_of::<Layout>() / 4;

/// The full layout: every device, at the offsets of `Memory`.
pub const FULL: Layout = {
    let mut runs = [Run {
        offset: 0,
        first: 0,
        count: 0,
    }; SEGMENT_COUNT];
    let mut s = 0;
    while s < SEGMENT_COUNT {
        let segment = SEGMENTS[s];
        let array = segment.array;
        runs[s] = Run {
            offset: (array.full_offset() + (segment.first - array.first()) as usize * array.size()) as u32,
            first: segment.first,
            count: segment.end - segment.first,
        };
        s += 1;
    }
    Layout {
        version: LAYOUT_VERSION,
        size: MEMORY_SIZE as u32,
        runs,
    }
};

impl Layout {
    /// Byte offset of element `n` of `array`; `None` when the layout does
    /// not hold it (or it is outside the array).
    #[inline]
    pub fn offset(&self, array: Array, n: u32) -> Option<usize> {
        let run = self.runs[array.segment(n)?];
        let k = n.wrapping_sub(run.first);
        (k < run.count).then(|| run.offset as usize + k as usize * array.size())
    }

    /// The offset of element `array.first()` when the layout holds the whole
    /// array, every segment after the one before, so that element `n` is at
    /// that offset plus `(n - first) * size` (how compiled code addresses an
    /// array with a run-time index).
    pub fn whole(&self, array: Array) -> Option<usize> {
        let mut next = None;
        let mut start = None;
        for s in array.segments() {
            let (run, segment) = (self.runs[s], SEGMENTS[s]);
            if run.first != segment.first || run.count != segment.end - segment.first {
                return None;
            }
            if next.is_some_and(|next| next != run.offset) {
                return None;
            }
            start.get_or_insert(run.offset as usize);
            next = Some(run.offset + run.count * array.size() as u32);
        }
        start
    }

    /// The devices of `array` the layout holds, segment by segment:
    /// (first, count, offset) of every run that is not empty.
    pub fn runs_of(&self, array: Array) -> impl Iterator<Item = Run> + '_ {
        array.segments().map(|s| self.runs[s]).filter(|run| run.count > 0)
    }

    /// Is the table one this runtime can use: its version, and every run
    /// inside its segment and inside the image (after the scalars)?
    pub fn is_valid(&self) -> bool {
        self.version == LAYOUT_VERSION
            && (self.size as usize) >= ARRAYS_START
            && self.runs.iter().zip(SEGMENTS.iter()).all(|(run, segment)| {
                let size = segment.array.size() as u64;
                run.count == 0
                    || (run.first >= segment.first
                        && u64::from(run.first) + u64::from(run.count) <= u64::from(segment.end)
                        && u64::from(run.offset) >= ARRAYS_START as u64
                        && u64::from(run.offset) + u64::from(run.count) * size <= u64::from(self.size))
            })
    }

    /// The table as 32-bit words.
    pub fn words(&self) -> &[u32] {
        bytemuck::cast_slice(core::slice::from_ref(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::BUFFER_WORDS_PER_UNIT;
    use crate::memory::InstanceState;

    /// Every field's offset, in order, and the segments: a change here
    /// changes the layout.
    fn fingerprint() -> String {
        let mut parts: Vec<String> = Array::ALL.iter().map(|a| a.full_offset().to_string()).collect();
        parts.extend(
            [
                Scalar::ForcedCount,
                Scalar::StlPendingAny,
                Scalar::ElapsedMs,
                Scalar::ScanCount,
                Scalar::ClockMs,
                Scalar::LoopRepetitions,
                Scalar::CalendarSeconds,
                Scalar::CalendarMs,
                Scalar::CalendarFlags,
                Scalar::LayoutMisses,
                Scalar::CalendarCacheAt,
                Scalar::CalendarCacheTime,
                Scalar::CalendarCacheYear,
            ]
            .map(|s| s.offset().to_string()),
        );
        parts.push(SEGMENT_COUNT.to_string());
        parts.push(MEMORY_SIZE.to_string());
        parts.join(",")
    }

    #[test]
    fn layout_fingerprint_is_recorded() {
        assert_eq!(
            fingerprint(),
            "68,324,580,9092,13188,14212,14724,14980,32004,34052,99588,100612,101012,101236,101268,102292,102804,103060,107156,111252,127636,127700,127764,128020,128276,128532,128788,137300,137812,138068,138100,138132,144276,144292,144308,16,20,24,28,32,36,40,44,48,52,56,60,64,48,668580",
            "the memory layout changed: bump LAYOUT_TAG (and the tagged symbol) and record the new fingerprint"
        );
        assert_eq!(TAGGED_BEGIN_SCAN, format!("ladder_rt_begin_scan_{LAYOUT_TAG}"));
        assert_eq!(TAGGED_END_SCAN, format!("ladder_rt_end_scan_{LAYOUT_TAG}"));
        assert!(LAYOUT_TAG.ends_with(&MEMORY_SIZE.to_string()));
    }

    #[test]
    fn offsets_address_the_fields() {
        let mut mem = Memory::new_boxed();
        mem.m[17] = 1;
        mem.m[8067] = 1;
        mem.d[5] = -2;
        mem.wide_counter_value[1] = 7;
        mem.buffer[buffer_index(2, 9)] = 3;
        let bytes = bytemuck::bytes_of(&*mem);
        assert_eq!(bytes[FULL.offset(Array::M, 17).unwrap()], 1);
        assert_eq!(bytes[FULL.offset(Array::M, 8067).unwrap()], 1);
        let d5 = FULL.offset(Array::D, 5).unwrap();
        assert_eq!(i16::from_ne_bytes([bytes[d5], bytes[d5 + 1]]), -2);
        let c201 = FULL.offset(Array::WideCounterValue, 201).unwrap();
        assert_eq!(i32::from_ne_bytes(bytes[c201..c201 + 4].try_into().unwrap()), 7);
        let u2g9 = FULL.offset(Array::Buffer, 2 * BUFFER_WORDS_PER_UNIT + 9).unwrap();
        assert_eq!(i16::from_ne_bytes([bytes[u2g9], bytes[u2g9 + 1]]), 3);
        assert_eq!(MEMORY_ALIGN, 4);
        assert!(FULL.is_valid());
        for array in Array::ALL {
            assert_eq!(FULL.whole(array), Some(array.full_offset()), "{array:?}");
            assert_eq!(FULL.offset(array, array.end()), None);
        }
        assert_eq!(SEGMENT_COUNT, 35 + 3 + 3 + 7);
        assert_eq!(size_of::<InstanceState>(), 24);
    }

    fn buffer_index(unit: u32, word: u32) -> usize {
        crate::device::buffer_word(unit, word) as usize
    }
}
