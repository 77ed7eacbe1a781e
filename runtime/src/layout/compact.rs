//! Compact layouts: the arrays that follow a device one for one, and the
//! builder that packs the devices one program and its host use.

use super::{Array, Layout, Run, ARRAYS_START, LAYOUT_VERSION, MEMORY_ALIGN, SEGMENTS, SEGMENT_COUNT};
use crate::device::{BitArea, WordArea};

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
        // Every element size there is, largest first (an array whose size
        // were missing here would be left out of every compact image).
        let mut sizes = [0usize; SEGMENT_COUNT];
        for (size, segment) in sizes.iter_mut().zip(SEGMENTS.iter()) {
            *size = segment.array.size();
        }
        sizes.sort_unstable_by(|a, b| b.cmp(a));
        for (k, &size) in sizes.iter().enumerate() {
            if k > 0 && sizes[k - 1] == size {
                continue;
            }
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
    use crate::layout::FULL;

    #[test]
    fn every_array_can_be_held() {
        for array in Array::ALL {
            let mut builder = LayoutBuilder::new();
            builder.include_whole(array);
            let layout = builder.build();
            assert!(layout.is_valid(), "{array:?}");
            assert!(layout.whole(array).is_some(), "{array:?} is left out of compact images");
        }
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
