//! Where everything lives in a device image.
//!
//! An image is a header (`ImageHeader`: which layout it has), the scan's
//! scalars (elapsed time, scan count, ...; at the same offsets in every
//! image) and arrays (`Array`): the device areas and the bookkeeping the
//! scan keeps per timer, counter, state, edge instruction, ... An array is
//! cut into segments (`SEGMENTS`) where a program uses parts apart: M0-M7999
//! and the special relays M8000-M8511, D likewise, the 16-bit and the
//! 32-bit counters, the buffer memory of each unit.
//!
//! A `Layout` says, for every segment, which devices of it the image holds
//! (a `Run`: first device, count) and at which byte offset. The full layout
//! (`FULL`) holds every device at the offsets of the `Memory` struct; a
//! compact layout (`LayoutBuilder`) holds only the devices one program and
//! its host use, packed. The runtime reads and writes every image through
//! its layout (`image.rs`), so both are served by the same code.

use crate::device::{
    BitArea, WordArea, BUFFER_UNITS, BUFFER_WORDS_PER_UNIT, COUNTER_COUNT, EDGE_SLOT_COUNT, FIRST_WIDE_COUNTER,
    HSC_INPUTS, PULSE_OUTPUTS, SORT_INSTANCES, STATE_INSTANCES, TIMER_COUNT,
};
use crate::memory::Memory;
use bytemuck::{Pod, Zeroable};
use core::mem::offset_of;

/// Size of `Memory` (the full layout) in bytes.
pub const MEMORY_SIZE: usize = size_of::<Memory>();
/// Alignment of every image in bytes.
pub const MEMORY_ALIGN: usize = align_of::<Memory>();

/// The version of this file's rules: arrays, segments, header, scalars.
/// Layout tables carry it; the runtime refuses a table of another version.
pub const LAYOUT_VERSION: u32 = 5;

/// Names the layout rules in the symbol that compiled objects import
/// (`ladder_rt_begin_scan_<tag>`), so that an object linked against a runtime
/// with other rules fails to link instead of corrupting memory. Change it
/// whenever an offset changes; `layout_fingerprint_is_recorded` insists.
pub const LAYOUT_TAG: &str = "v5_666520";

/// The begin-scan entry compiled objects call; carries the layout tag.
pub const TAGGED_BEGIN_SCAN: &str = "ladder_rt_begin_scan_v5_666520";

/// The end-scan entry compiled objects call (the C API's `ladder_end_scan`).
pub const END_SCAN: &str = "ladder_end_scan";

/// `ImageHeader::magic` of an image with the full layout ("LDRF").
pub const FULL_MAGIC: u32 = u32::from_le_bytes(*b"LDRF");
/// `ImageHeader::magic` of an image with a compact layout ("LDRC").
pub const COMPACT_MAGIC: u32 = u32::from_le_bytes(*b"LDRC");

/// The first bytes of every image: which layout the rest has. Written by
/// `ladder_init` or `ladder_init_layout`; an image whose magic is neither
/// (storage that was never initialised) is refused by every entry point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct ImageHeader {
    /// `FULL_MAGIC` or `COMPACT_MAGIC`.
    pub magic: u32,
    /// Bytes of the image.
    pub size: u32,
    /// A compact image's layout table, by address (low and high 32 bits);
    /// 0 for the full layout.
    pub layout_low: u32,
    pub layout_high: u32,
}

impl ImageHeader {
    /// The header of a full image.
    pub const FULL: ImageHeader = ImageHeader {
        magic: FULL_MAGIC,
        size: MEMORY_SIZE as u32,
        layout_low: 0,
        layout_high: 0,
    };
}

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
        }
    }
}

/// Where the arrays of a compact image start: after the header and the
/// scalars, which every image has at the same offsets.
pub const ARRAYS_START: usize = offset_of!(Memory, x);

/// The arrays of an image. Each is numbered as its devices are (a timer
/// array by timer number, the 32-bit counter values C200-C255 by counter
/// number, edge slots by slot); `Array::first`..`Array::end`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Array {
    // ---- bit devices (a byte each, 0 or 1) ----
    X,
    Y,
    M,
    S,
    Sm,
    TimerContact,
    CounterContact,
    // ---- word devices (i16) ----
    D,
    Sd,
    R,
    TimerValue,
    CounterValue,
    /// Current values of the 32-bit counters C200-C255 (i32).
    WideCounterValue,
    /// Index registers: Z0, V0, Z1, V1, ...
    Index,
    // ---- scan bookkeeping ----
    /// Milliseconds below the timer's resolution carried to the next scan (u16).
    TimerRemainder,
    /// 1 when the timer's coil was ON at its previous execution.
    TimerCoilWasOn,
    /// 1 when the counter's coil was ON at its previous execution.
    CounterCoilWasOn,
    /// 1 when a SET transfer left the state to be turned OFF at the next scan.
    StlPendingOff,
    /// 1 when the state's block last ran with its state ON.
    StlBlockActive,
    /// Previous-scan slots of the program's edge instructions.
    EdgeSlot,
    /// Each sort instruction's job (`memory::SORT_IDLE`, ...).
    SortState,
    /// Scans a running sort has executed.
    SortScans,
    /// What the host last wrote to the inputs; copied to X at each scan.
    InputImage,
    /// Y as it was at the end of the latest scan.
    OutputImage,
    /// Force tables: `FORCE_NONE`, `FORCE_OFF` or `FORCE_ON` per device.
    ForceX,
    ForceY,
    ForceM,
    ForceTimer,
    ForceCounter,
    // ---- the machine around the program ----
    /// Rising edges a host reported for X0-X7 (u32).
    PulsesPending,
    /// Rising edges of X0-X7 the latest input refresh saw (u32).
    InputEdges,
    /// The state of each instruction that keeps one (`InstanceState`, 16 bytes).
    Instance,
    /// The instance driving pulse output Y0-Y3, plus one; 0 when free (u32).
    PulseOwner,
    /// Pulses × 1000 not yet output, per pulse output (u32).
    PulseRemainder,
    /// Buffer memories of units 0-7 (i16), unit after unit.
    Buffer,
}

/// The first special relay M8000 and special register D8000: the devices
/// a program uses from them are laid out apart from M0-M7999 and D0-D7999.
pub const FIRST_SPECIAL: u32 = 8000;

impl Array {
    pub const ALL: [Array; 35] = [
        Array::X,
        Array::Y,
        Array::M,
        Array::S,
        Array::Sm,
        Array::TimerContact,
        Array::CounterContact,
        Array::D,
        Array::Sd,
        Array::R,
        Array::TimerValue,
        Array::CounterValue,
        Array::WideCounterValue,
        Array::Index,
        Array::TimerRemainder,
        Array::TimerCoilWasOn,
        Array::CounterCoilWasOn,
        Array::StlPendingOff,
        Array::StlBlockActive,
        Array::EdgeSlot,
        Array::SortState,
        Array::SortScans,
        Array::InputImage,
        Array::OutputImage,
        Array::ForceX,
        Array::ForceY,
        Array::ForceM,
        Array::ForceTimer,
        Array::ForceCounter,
        Array::PulsesPending,
        Array::InputEdges,
        Array::Instance,
        Array::PulseOwner,
        Array::PulseRemainder,
        Array::Buffer,
    ];

    /// Bytes per element.
    pub const fn size(self) -> usize {
        match self {
            Array::X
            | Array::Y
            | Array::M
            | Array::S
            | Array::Sm
            | Array::TimerContact
            | Array::CounterContact
            | Array::TimerCoilWasOn
            | Array::CounterCoilWasOn
            | Array::StlPendingOff
            | Array::StlBlockActive
            | Array::EdgeSlot
            | Array::SortState
            | Array::SortScans
            | Array::InputImage
            | Array::OutputImage
            | Array::ForceX
            | Array::ForceY
            | Array::ForceM
            | Array::ForceTimer
            | Array::ForceCounter => 1,
            Array::D
            | Array::Sd
            | Array::R
            | Array::TimerValue
            | Array::CounterValue
            | Array::Index
            | Array::TimerRemainder
            | Array::Buffer => 2,
            Array::WideCounterValue
            | Array::PulsesPending
            | Array::InputEdges
            | Array::PulseOwner
            | Array::PulseRemainder => 4,
            Array::Instance => size_of::<crate::memory::InstanceState>(),
        }
    }

    /// The first element's number.
    pub const fn first(self) -> u32 {
        match self {
            Array::WideCounterValue => FIRST_WIDE_COUNTER,
            _ => 0,
        }
    }

    /// One past the last element's number.
    pub const fn end(self) -> u32 {
        match self {
            Array::X | Array::Y | Array::InputImage | Array::OutputImage | Array::ForceX | Array::ForceY => {
                BitArea::X.count()
            }
            Array::M | Array::ForceM => BitArea::M.count(),
            Array::S | Array::StlPendingOff | Array::StlBlockActive => BitArea::S.count(),
            Array::Sm => BitArea::Sm.count(),
            Array::TimerContact
            | Array::TimerValue
            | Array::TimerRemainder
            | Array::TimerCoilWasOn
            | Array::ForceTimer => TIMER_COUNT,
            Array::CounterContact | Array::CounterCoilWasOn | Array::ForceCounter | Array::WideCounterValue => {
                COUNTER_COUNT
            }
            Array::D => WordArea::D.count(),
            Array::Sd => WordArea::Sd.count(),
            Array::R => WordArea::R.count(),
            Array::CounterValue => WordArea::CounterValue.count(),
            Array::Index => WordArea::Index.count(),
            Array::Buffer => WordArea::Buffer.count(),
            Array::EdgeSlot => EDGE_SLOT_COUNT,
            Array::SortState | Array::SortScans => SORT_INSTANCES,
            Array::PulsesPending | Array::InputEdges => HSC_INPUTS,
            Array::Instance => STATE_INSTANCES,
            Array::PulseOwner | Array::PulseRemainder => PULSE_OUTPUTS,
        }
    }

    /// The array of a bit area.
    pub const fn of_bits(area: BitArea) -> Array {
        match area {
            BitArea::X => Array::X,
            BitArea::Y => Array::Y,
            BitArea::M => Array::M,
            BitArea::S => Array::S,
            BitArea::Sm => Array::Sm,
            BitArea::TimerContact => Array::TimerContact,
            BitArea::CounterContact => Array::CounterContact,
        }
    }

    /// The array of a word area.
    pub const fn of_words(area: WordArea) -> Array {
        match area {
            WordArea::D => Array::D,
            WordArea::Sd => Array::Sd,
            WordArea::R => Array::R,
            WordArea::TimerValue => Array::TimerValue,
            WordArea::CounterValue => Array::CounterValue,
            WordArea::Index => Array::Index,
            WordArea::Buffer => Array::Buffer,
        }
    }

    /// Offset of the array in `Memory`.
    const fn full_offset(self) -> usize {
        match self {
            Array::X => offset_of!(Memory, x),
            Array::Y => offset_of!(Memory, y),
            Array::M => offset_of!(Memory, m),
            Array::S => offset_of!(Memory, s),
            Array::Sm => offset_of!(Memory, sm),
            Array::TimerContact => offset_of!(Memory, timer_contact),
            Array::CounterContact => offset_of!(Memory, counter_contact),
            Array::D => offset_of!(Memory, d),
            Array::Sd => offset_of!(Memory, sd),
            Array::R => offset_of!(Memory, r),
            Array::TimerValue => offset_of!(Memory, timer_value),
            Array::CounterValue => offset_of!(Memory, counter_value),
            Array::WideCounterValue => offset_of!(Memory, wide_counter_value),
            Array::Index => offset_of!(Memory, index),
            Array::TimerRemainder => offset_of!(Memory, timer_remainder_ms),
            Array::TimerCoilWasOn => offset_of!(Memory, timer_coil_was_on),
            Array::CounterCoilWasOn => offset_of!(Memory, counter_coil_was_on),
            Array::StlPendingOff => offset_of!(Memory, stl_pending_off),
            Array::StlBlockActive => offset_of!(Memory, stl_block_active),
            Array::EdgeSlot => offset_of!(Memory, edge_slot),
            Array::SortState => offset_of!(Memory, sort_state),
            Array::SortScans => offset_of!(Memory, sort_scans),
            Array::InputImage => offset_of!(Memory, input_image),
            Array::OutputImage => offset_of!(Memory, output_image),
            Array::ForceX => offset_of!(Memory, force_x),
            Array::ForceY => offset_of!(Memory, force_y),
            Array::ForceM => offset_of!(Memory, force_m),
            Array::ForceTimer => offset_of!(Memory, force_timer),
            Array::ForceCounter => offset_of!(Memory, force_counter),
            Array::PulsesPending => offset_of!(Memory, pulses_pending),
            Array::InputEdges => offset_of!(Memory, input_edges),
            Array::Instance => offset_of!(Memory, instance),
            Array::PulseOwner => offset_of!(Memory, pulse_owner),
            Array::PulseRemainder => offset_of!(Memory, pulse_remainder),
            Array::Buffer => offset_of!(Memory, buffer),
        }
    }

    /// Where the array's segments meet (device numbers), in order.
    const fn splits(self) -> &'static [u32] {
        const UNITS: [u32; BUFFER_UNITS as usize - 1] = {
            let mut starts = [0; BUFFER_UNITS as usize - 1];
            let mut unit = 1;
            while unit < BUFFER_UNITS {
                starts[unit as usize - 1] = unit * BUFFER_WORDS_PER_UNIT;
                unit += 1;
            }
            starts
        };
        match self {
            Array::M | Array::ForceM | Array::D => &[FIRST_SPECIAL],
            Array::CounterContact | Array::CounterCoilWasOn | Array::ForceCounter => &[FIRST_WIDE_COUNTER],
            Array::Buffer => &UNITS,
            _ => &[],
        }
    }

    /// The segment that holds element `n`; `None` outside the array.
    #[inline]
    pub const fn segment(self, n: u32) -> Option<usize> {
        if n < self.first() || n >= self.end() {
            return None;
        }
        let splits = self.splits();
        let mut segment = FIRST_SEGMENT[self as usize];
        let mut i = 0;
        while i < splits.len() && n >= splits[i] {
            segment += 1;
            i += 1;
        }
        Some(segment)
    }

    /// The segments of the array, in order.
    pub const fn segments(self) -> core::ops::Range<usize> {
        let first = FIRST_SEGMENT[self as usize];
        first..first + self.splits().len() + 1
    }
}

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
const FIRST_SEGMENT: [usize; Array::ALL.len()] = {
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

/// The arrays that follow the devices of a bit area one for one: the area
/// itself, its images, its force table, the bookkeeping of its timers,
/// counters and states. A compact layout holds the same devices of each.
pub const fn bit_arrays(area: BitArea) -> &'static [Array] {
    match area {
        BitArea::X => &[Array::X, Array::InputImage, Array::ForceX],
        BitArea::Y => &[Array::Y, Array::OutputImage, Array::ForceY],
        BitArea::M => &[Array::M, Array::ForceM],
        BitArea::S => &[Array::S, Array::StlPendingOff, Array::StlBlockActive],
        BitArea::Sm => &[Array::Sm],
        BitArea::TimerContact => &TIMER_ARRAYS,
        BitArea::CounterContact => &COUNTER_ARRAYS,
    }
}

/// The same for a word area.
pub const fn word_arrays(area: WordArea) -> &'static [Array] {
    match area {
        WordArea::TimerValue => &TIMER_ARRAYS,
        WordArea::CounterValue => &COUNTER_ARRAYS,
        WordArea::D => &[Array::D],
        WordArea::Sd => &[Array::Sd],
        WordArea::R => &[Array::R],
        WordArea::Index => &[Array::Index],
        WordArea::Buffer => &[Array::Buffer],
    }
}

/// Everything a timer has.
const TIMER_ARRAYS: [Array; 5] = [
    Array::TimerContact,
    Array::TimerValue,
    Array::TimerRemainder,
    Array::TimerCoilWasOn,
    Array::ForceTimer,
];
/// Everything a counter has (16-bit values for C0-C199, 32-bit above).
pub const COUNTER_ARRAYS: [Array; 5] = [
    Array::CounterContact,
    Array::CounterValue,
    Array::WideCounterValue,
    Array::CounterCoilWasOn,
    Array::ForceCounter,
];

/// Builds a compact layout: the devices to hold, segment by segment (each
/// segment holds one run from the lowest to the highest device asked for).
#[derive(Clone, Debug)]
pub struct LayoutBuilder {
    /// (first, end) per segment; first >= end is empty.
    windows: [(u32, u32); SEGMENT_COUNT],
}

impl Default for LayoutBuilder {
    fn default() -> Self {
        LayoutBuilder {
            windows: [(u32::MAX, 0); SEGMENT_COUNT],
        }
    }
}

impl LayoutBuilder {
    pub fn new() -> LayoutBuilder {
        LayoutBuilder::default()
    }

    /// Holds elements `first`..`end` of `array` (clipped to the array).
    pub fn include(&mut self, array: Array, first: u32, end: u32) -> &mut Self {
        for s in array.segments() {
            let segment = SEGMENTS[s];
            let (low, high) = (first.max(segment.first), end.min(segment.end));
            if low < high {
                let window = &mut self.windows[s];
                *window = (window.0.min(low), window.1.max(high));
            }
        }
        self
    }

    /// Holds the whole array.
    pub fn include_whole(&mut self, array: Array) -> &mut Self {
        self.include(array, array.first(), array.end())
    }

    /// Holds devices `first`..`end` of a bit area, with everything that
    /// follows them (`bit_arrays`).
    pub fn include_bits(&mut self, area: BitArea, first: u32, end: u32) -> &mut Self {
        for &array in bit_arrays(area) {
            self.include(array, first, end);
        }
        self
    }

    /// Holds words `first`..`end` of a word area (`word_arrays`).
    pub fn include_words(&mut self, area: WordArea, first: u32, end: u32) -> &mut Self {
        for &array in word_arrays(area) {
            self.include(array, first, end);
        }
        self
    }

    /// Does the builder hold element `n` of `array`?
    pub fn holds(&self, array: Array, n: u32) -> bool {
        array.segment(n).is_some_and(|s| {
            let (first, end) = self.windows[s];
            first <= n && n < end
        })
    }

    /// The layout: runs packed after the scalars, the largest elements
    /// first (so no run needs padding), each array's segments in order
    /// (so an array held whole is one contiguous run).
    pub fn build(&self) -> Layout {
        let mut runs = [Run::default(); SEGMENT_COUNT];
        let mut offset = ARRAYS_START;
        for size in [16, 4, 2, 1] {
            for (s, segment) in SEGMENTS.iter().enumerate() {
                let (first, end) = self.windows[s];
                if segment.array.size() != size || first >= end {
                    continue;
                }
                runs[s] = Run {
                    offset: offset as u32,
                    first,
                    count: end - first,
                };
                offset += (end - first) as usize * size;
            }
        }
        Layout {
            version: LAYOUT_VERSION,
            size: offset.next_multiple_of(MEMORY_ALIGN) as u32,
            runs,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
            "56,312,568,9080,13176,14200,14712,14968,31992,34040,99576,100600,101000,101224,101256,102280,102792,103048,107144,111240,127624,127688,127752,128008,128264,128520,128776,137288,137800,138056,138088,138120,142216,142232,142248,16,20,24,28,32,36,40,44,48,52,48,666520",
            "the memory layout changed: bump LAYOUT_TAG (and the tagged symbol) and record the new fingerprint"
        );
        assert_eq!(TAGGED_BEGIN_SCAN, format!("ladder_rt_begin_scan_{LAYOUT_TAG}"));
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
        assert_eq!(size_of::<InstanceState>(), 16);
    }

    fn buffer_index(unit: u32, word: u32) -> usize {
        crate::device::buffer_word(unit, word) as usize
    }

    #[test]
    fn compact_layouts_hold_what_was_asked_and_pack_it() {
        let mut builder = LayoutBuilder::new();
        builder
            .include_bits(BitArea::Y, 0, 3)
            .include_bits(BitArea::M, 8000, 8003)
            .include_bits(BitArea::M, 8067, 8068)
            .include_words(WordArea::D, 8067, 8070)
            .include_bits(BitArea::TimerContact, 0, 3)
            .include_whole(Array::Index);
        let layout = builder.build();
        assert!(layout.is_valid());
        assert_eq!(layout.offset(Array::Y, 2).map(|o| o >= ARRAYS_START), Some(true));
        assert_eq!(layout.offset(Array::Y, 3), None);
        assert_eq!(layout.offset(Array::M, 7999), None);
        assert!(layout.offset(Array::ForceM, 8067).is_some());
        assert!(layout.offset(Array::TimerRemainder, 2).is_some());
        assert_eq!(layout.offset(Array::D, 0), None);
        assert!(layout.whole(Array::Index).is_some());
        assert_eq!(layout.whole(Array::Y), None);
        assert!(layout.size < 300, "{}", layout.size);
        // Runs never overlap, and each is aligned to its element size.
        let mut taken = vec![false; layout.size as usize];
        for (run, segment) in layout.runs.iter().zip(SEGMENTS) {
            let size = segment.array.size();
            assert_eq!(run.offset as usize % size.min(4), 0, "{segment:?}");
            let bytes = run.offset as usize..run.offset as usize + run.count as usize * size;
            for byte in &mut taken[bytes] {
                assert!(!*byte, "{segment:?} overlaps");
                *byte = true;
            }
        }
        // A whole array is one run even when it has several segments.
        let whole_d = LayoutBuilder::new().include_whole(Array::D).build();
        assert!(whole_d.whole(Array::D).is_some());
        assert_eq!(whole_d.size as usize, ARRAYS_START + 2 * 8512);
    }

    #[test]
    fn damaged_tables_are_refused() {
        let mut layout = LayoutBuilder::new().include_bits(BitArea::X, 0, 8).build();
        assert!(layout.is_valid());
        layout.runs[0].count = 300;
        assert!(!layout.is_valid(), "past the segment");
        let mut layout = LayoutBuilder::new().include_bits(BitArea::X, 0, 8).build();
        layout.size = 20;
        assert!(!layout.is_valid(), "past the image");
        let mut layout = FULL;
        layout.version += 1;
        assert!(!layout.is_valid());
    }
}
