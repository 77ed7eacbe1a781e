//! The arrays of an image and the segments they are cut into.

use super::FIRST_SEGMENT;
use crate::device::{
    BitArea, WordArea, BUFFER_UNITS, BUFFER_WORDS_PER_UNIT, COUNTER_COUNT, EDGE_SLOT_COUNT, FIRST_WIDE_COUNTER,
    HSC_INPUTS, PULSE_OUTPUTS, SORT_INSTANCES, STATE_INSTANCES, TIMER_COUNT,
};
use crate::memory::Memory;
use core::mem::offset_of;

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
    /// The state of each instruction that keeps one (`InstanceState`, 24 bytes).
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
            Array::X
            | Array::Y
            | Array::M
            | Array::S
            | Array::Sm
            | Array::TimerContact
            | Array::CounterContact
            | Array::D
            | Array::Sd
            | Array::R
            | Array::TimerValue
            | Array::CounterValue
            | Array::Index
            | Array::TimerRemainder
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
            | Array::ForceCounter
            | Array::PulsesPending
            | Array::InputEdges
            | Array::Instance
            | Array::PulseOwner
            | Array::PulseRemainder
            | Array::Buffer => 0,
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
    pub(super) const fn full_offset(self) -> usize {
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
    pub(super) const fn splits(self) -> &'static [u32] {
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
            Array::X
            | Array::Y
            | Array::S
            | Array::Sm
            | Array::TimerContact
            | Array::Sd
            | Array::R
            | Array::TimerValue
            | Array::CounterValue
            | Array::WideCounterValue
            | Array::Index
            | Array::TimerRemainder
            | Array::TimerCoilWasOn
            | Array::StlPendingOff
            | Array::StlBlockActive
            | Array::EdgeSlot
            | Array::SortState
            | Array::SortScans
            | Array::InputImage
            | Array::OutputImage
            | Array::ForceX
            | Array::ForceY
            | Array::ForceTimer
            | Array::PulsesPending
            | Array::InputEdges
            | Array::Instance
            | Array::PulseOwner
            | Array::PulseRemainder => &[],
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
