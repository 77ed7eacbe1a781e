//! What each IR instruction reads and writes, declared once (`Inst::effect`).
//! Every pass that needs to know asks this instead of matching the
//! instructions again: memory forwarding (`memory.rs`), dead values and the
//! always-ON/OFF relays (`passes.rs`), the compact image's footprint
//! (`image/`), and which bit loads may read four bytes in code generation.
//! A new instruction is described here, and the compiler points at this
//! match and at the back ends' translations, nowhere else.

use super::{Bookkeeping, Cell, Index, Inst, Value};
use ladder_runtime::helpers::Helper;
use ladder_runtime::layout::Array;
use ladder_runtime::{BitArea, WordArea};

/// Which part of the image an access addresses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Space {
    Bits(BitArea),
    Words(WordArea),
    /// The values of the 32-bit counters, by device number (C200-C255).
    WideCounters,
    /// The previous-scan values of edge instructions, by slot.
    EdgeSlots,
    /// Whether each STL block last ran with its state ON, by state.
    BlockActive,
    /// The runtime's state of each timer or counter, by device number.
    Bookkeeping(Bookkeeping),
}

impl Space {
    /// The layout's array of this space.
    pub fn array(self) -> Array {
        match self {
            Space::Bits(area) => Array::of_bits(area),
            Space::Words(area) => Array::of_words(area),
            Space::WideCounters => Array::WideCounterValue,
            Space::EdgeSlots => Array::EdgeSlot,
            Space::BlockActive => Array::StlBlockActive,
            Space::Bookkeeping(field) => field.array(),
        }
    }
}

/// `count` consecutive elements of a space from `start`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    pub space: Space,
    pub start: Index,
    pub count: u32,
}

/// What an instruction does besides defining its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect<'a> {
    /// Nothing: its value comes from its operands alone (constants, logic,
    /// arithmetic, comparisons, conversions), or from the scan's elapsed
    /// time, which nothing changes while the program runs.
    Pure,
    /// Reads a variable of its function (a local or a loop count), never
    /// the image.
    ReadsLocal,
    /// Writes a variable of its function.
    WritesLocal,
    /// Reads one element of the image.
    Load(Span),
    /// Writes `value` into one element.
    Store(Span, Value),
    /// Overwrites a run without reading it (SET/RST of several bits, RST of
    /// several words). Code generation clamps the run into its area: at
    /// least one element, the start moved back so that it fits.
    Fill(Span),
    /// Calls a runtime helper with these arguments; the helper's declaration
    /// (`Helper::decl`: its parameters, what it writes) says what it may
    /// touch.
    Helper(Helper, &'a [Value]),
    /// Records an operation error: sets M8067, D8067 and D8069, reads
    /// nothing.
    OperationError,
    /// Runs a subroutine, which may read and write anything.
    Subroutine,
}

impl Effect<'_> {
    /// The instruction may be removed when nothing uses its value.
    pub fn is_removable(self) -> bool {
        match self {
            Effect::Pure | Effect::ReadsLocal | Effect::Load(_) => true,
            Effect::WritesLocal
            | Effect::Store(..)
            | Effect::Fill(_)
            | Effect::Helper(..)
            | Effect::OperationError
            | Effect::Subroutine => false,
        }
    }
}

impl Span {
    fn one(space: Space, start: Index) -> Span {
        Span { space, start, count: 1 }
    }

    /// The elements of a run at a fixed start in an area of `area_count`
    /// elements, as code generation writes them (`Effect::Fill`): `None`
    /// for a run-time start (or an empty area).
    pub fn fixed_run(self, area_count: u32) -> Option<std::ops::Range<u32>> {
        let Index::Fixed(n) = self.start else { return None };
        if area_count == 0 {
            return None;
        }
        let count = self.count.clamp(1, area_count);
        let first = n.min(area_count - count);
        Some(first..first + count)
    }
}

impl Cell {
    /// Where the cell lies in the image.
    pub fn span(self) -> Span {
        let (space, index) = match self {
            Cell::Bit { area, index } => (Space::Bits(area), index),
            Cell::Word { area, index } => (Space::Words(area), index),
            Cell::WideCounter { index } => (Space::WideCounters, index),
            Cell::Slot { slot } => (Space::EdgeSlots, Index::Fixed(slot)),
            Cell::BlockActive { state } => (Space::BlockActive, Index::Fixed(state)),
            Cell::Bookkeeping { field, index } => (Space::Bookkeeping(field), Index::Fixed(index)),
        };
        Span::one(space, index)
    }

    /// The layout's array the cell is an element of.
    pub fn array(self) -> Array {
        self.span().space.array()
    }
}

impl Inst {
    /// What the instruction reads and writes (see `Effect`).
    pub fn effect(&self) -> Effect<'_> {
        match self {
            Inst::Load { cell } => Effect::Load(cell.span()),
            Inst::Store { cell, value } => Effect::Store(cell.span(), *value),
            Inst::FillBits { area, start, count, .. } => Effect::Fill(Span {
                space: Space::Bits(*area),
                start: *start,
                count: *count,
            }),
            Inst::ClearWords { area, start, count } => Effect::Fill(Span {
                space: Space::Words(*area),
                start: *start,
                count: *count,
            }),
            Inst::GetLocal { .. } | Inst::LoadLoopCount { .. } => Effect::ReadsLocal,
            Inst::SetLocal { .. } | Inst::StoreLoopCount { .. } => Effect::WritesLocal,
            Inst::Call { helper, args } => Effect::Helper(*helper, args),
            Inst::RecordError { .. } => Effect::OperationError,
            Inst::CallSubroutine { .. } => Effect::Subroutine,
            Inst::Const { .. }
            | Inst::LoadElapsed
            | Inst::Not { .. }
            | Inst::And { .. }
            | Inst::Or { .. }
            | Inst::Binary { .. }
            | Inst::Unary { .. }
            | Inst::Compare { .. }
            | Inst::Extend { .. }
            | Inst::Truncate { .. }
            | Inst::Select { .. }
            | Inst::Float { .. }
            | Inst::FloatUnary { .. }
            | Inst::FloatCompare { .. }
            | Inst::Bitcast { .. }
            | Inst::Convert { .. } => Effect::Pure,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ladder_runtime::device::{FIRST_WIDE_COUNTER, WIDE_COUNTER_COUNT};

    /// Constant folding makes a run-time index fixed only inside its
    /// space's array (`passes::fix_index`), so each array spans exactly the
    /// devices of its area.
    #[test]
    fn each_space_spans_the_devices_of_its_area() {
        for area in BitArea::ALL {
            let array = Space::Bits(area).array();
            assert_eq!((array.first(), array.end()), (0, area.count()), "{area:?}");
        }
        for area in WordArea::ALL {
            let array = Space::Words(area).array();
            assert_eq!((array.first(), array.end()), (0, area.count()), "{area:?}");
        }
        let wide = Space::WideCounters.array();
        assert_eq!(
            (wide.first(), wide.end()),
            (FIRST_WIDE_COUNTER, FIRST_WIDE_COUNTER + WIDE_COUNTER_COUNT)
        );
    }
}
