//! Memory optimisation across rungs, the part of gcc's work that matters
//! for ladder code: a device read after the program wrote or read it uses the
//! value it already has (store-to-load forwarding, redundant loads), a store
//! that a later store to the same device overwrites before anything can read
//! it is dropped, and a store of the value the device already holds is
//! dropped.
//!
//! The IR names every fixed device by (area, number), so two accesses alias
//! exactly when they name the same place; areas are disjoint arrays of the
//! image. What limits the pass:
//! - a dynamic (`DEV[Dk]`) access may touch any device of its area: a
//!   dynamic store forgets what is known about the area, a dynamic load
//!   counts as a read of every store waiting in it;
//! - a runtime helper call reads and writes the image through its pointer:
//!   it is a barrier for everything, except the timer and counter helpers
//!   whose declaration says they only write timer or counter state (see
//!   `call_footprint`);
//! - knowledge flows into a block from its only predecessor, and through a
//!   join as far as every predecessor agrees; stores are only dropped within
//!   one block (a successor may read them).
//!
//! The interpreter has no such pass: it is the specification the
//! differential test holds this against.

use super::{Block, Effect, Function, Index, Inst, Space, Value};
use crate::cfg::reverse_postorder;
use crate::replacements::Replacements;
use crate::Bookkeeping;
use ladder_runtime::device::{FIRST_WIDE_COUNTER, WIDE_COUNTER_COUNT};
use ladder_runtime::helpers::{Helper, Param, Writes};
use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
use ladder_runtime::{BitArea, WordArea};
use rustc_hash::FxHashMap;

/// One memory location the IR can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Place {
    Bit(BitArea, u32),
    Word(WordArea, u32),
    /// By slot (device number minus 200).
    WideCounter(u32),
    Slot(u32),
    BlockActive(u32),
    Bookkeeping(Bookkeeping, u32),
}

/// A group of places a dynamic access or a call may touch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Region {
    Bits(BitArea),
    Words(WordArea),
    WideCounters,
    Bookkeeping(Bookkeeping),
}

impl Place {
    fn region(self) -> Option<Region> {
        match self {
            Place::Bit(area, _) => Some(Region::Bits(area)),
            Place::Word(area, _) => Some(Region::Words(area)),
            Place::WideCounter(_) => Some(Region::WideCounters),
            Place::Bookkeeping(field, _) => Some(Region::Bookkeeping(field)),
            Place::Slot(_) | Place::BlockActive(_) => None,
        }
    }
}

/// The place a fixed index names, clamped as code generation clamps it.
fn bit_place(area: BitArea, n: u32) -> Place {
    Place::Bit(area, n.min(area.count() - 1))
}

fn word_place(area: WordArea, n: u32) -> Place {
    Place::Word(area, n.min(area.count() - 1))
}

fn wide_counter_place(n: u32) -> Place {
    Place::WideCounter(n.saturating_sub(FIRST_WIDE_COUNTER).min(WIDE_COUNTER_COUNT - 1))
}

/// What a helper call may touch.
enum Footprint {
    /// Reads and writes only these regions (and bookkeeping the IR never
    /// names). Timer and counter helpers also read the force tables, which
    /// the IR only reads: nothing changes them while a scan runs.
    Regions(Vec<Region>),
    Everything,
}

/// Timer and counter helpers take numbers, not places, and the declaration
/// says all they write; everything else that takes the image may read or
/// write any device.
fn call_footprint(helper: Helper) -> Footprint {
    let decl = helper.decl();
    let takes_places = decl
        .params
        .iter()
        .any(|(_, param)| matches!(param, Param::SourcePlace | Param::DestinationPlace));
    if takes_places {
        return Footprint::Everything;
    }
    let mut regions = Vec::new();
    for writes in decl.writes {
        match writes {
            // Forces change only between scans, so no helper writes them.
            Writes::Timers => regions.extend([
                Region::Bits(BitArea::TimerContact),
                Region::Words(WordArea::TimerValue),
                Region::Bookkeeping(Bookkeeping::TimerCoil),
                Region::Bookkeeping(Bookkeeping::TimerRemainder),
            ]),
            Writes::Counters => regions.extend([
                Region::Bits(BitArea::CounterContact),
                Region::Words(WordArea::CounterValue),
                Region::WideCounters,
                Region::Bookkeeping(Bookkeeping::CounterCoil),
                // 32-bit counters read their direction relays M8200-M8255.
                Region::Bits(BitArea::M),
            ]),
            // The pending-OFF flags of states, which the IR never names.
            Writes::StlBookkeeping => {}
            Writes::OperationError | Writes::Bits(_) | Writes::Image => return Footprint::Everything,
        }
    }
    Footprint::Regions(regions)
}

/// How many device values may be carried in registers past any point of a
/// function (beyond the values a rung computes with). Carrying every value
/// across the whole program makes more live ranges than there are
/// registers, and the register allocator then spills to the stack (a store
/// and a load), which costs more than the load it saves: a load of the
/// image is one L1 hit, and on x86-64 not even an instruction of its own
/// (the AND or OR takes it as its memory operand, `crates/codegen/src/wide.rs`).
/// Measured on the benchmarks' 11k-instruction bit logic (x86-64): 0 to 2
/// carried values are as fast, 6 is 5 % slower, unlimited 50 %. Which
/// values are carried is decided as each load is met (in the order of
/// where the carried ranges end): a range is taken when no point it spans
/// already carries this many, which keeps the most ranges (the greedy
/// choice is optimal for intervals taken by their end).
const CARRIED_VALUES: i32 = 2;

/// The longest range (in IR instructions) a value is carried over: one
/// held longer would keep a register from every shorter range it spans,
/// and the analysis would look at it for every load (large programs load
/// each device many times).
const LONGEST_CARRY: u64 = 1024;

/// What is known at a point of a block.
#[derive(Clone, Default)]
struct Known {
    /// The value each place holds, and when it was last used (position in
    /// the whole function, in block order).
    values: FxHashMap<Place, (Value, u64)>,
}

impl Known {
    fn forget_region(&mut self, region: Region) {
        self.values.retain(|place, _| place.region() != Some(region));
    }

    /// Drops what was last used before `oldest`: it is never carried
    /// again (`LONGEST_CARRY`), and a program of many blocks would
    /// otherwise copy and compare every place it ever touched at each one.
    fn forget_before(&mut self, oldest: u64) {
        self.values.retain(|_, &mut (_, used)| used >= oldest);
    }

    fn holds(&self, place: Place, value: Value) -> bool {
        matches!(self.values.get(&place), Some(&(known, _)) if known == value)
    }

    /// What every one of `states` agrees on.
    fn meet(states: &[&Known]) -> Known {
        let Some(smallest) = states.iter().min_by_key(|s| s.values.len()) else {
            return Known::default();
        };
        let values = smallest
            .values
            .iter()
            .filter_map(|(place, &(value, _))| {
                let mut last_use = 0;
                for state in states {
                    match state.values.get(place) {
                        Some(&(other, used)) if other == value => last_use = last_use.max(used),
                        Some(_) | None => return None,
                    }
                }
                Some((*place, (value, last_use)))
            })
            .collect();
        Known { values }
    }
}

/// Stores of the current block that nothing has read yet: place → position
/// in the block.
#[derive(Default)]
struct Waiting {
    stores: FxHashMap<Place, usize>,
}

impl Waiting {
    fn read(&mut self, place: Place) {
        self.stores.remove(&place);
    }

    fn read_region(&mut self, region: Region) {
        self.stores.retain(|place, _| place.region() != Some(region));
    }

    /// A new store to `place` at `position`; the store it overwrites unread,
    /// if any.
    fn overwrite(&mut self, place: Place, position: usize) -> Option<usize> {
        self.stores.insert(place, position)
    }
}

/// Runs the pass; uses of a removed load read the value it was known to
/// hold.
pub fn forward_memory(function: &mut Function) {
    let order = reverse_postorder(function);
    let predecessors = crate::cfg::predecessors(function, &order);
    let mut position_in_order = vec![usize::MAX; function.blocks.len()];
    for (position, block) in order.iter().enumerate() {
        position_in_order[block.0 as usize] = position;
    }
    // A block's state at its end, kept until its last successor took it.
    let mut at_end: Vec<Option<Known>> = vec![None; function.blocks.len()];
    let mut successors_left: Vec<usize> = function
        .blocks
        .iter()
        .map(|b| b.terminator.successors().len())
        .collect();
    let mut replaced = Replacements::default();
    let mut now = 0u64;
    let positions: usize = function.blocks.iter().map(|b| b.insts.len()).sum();
    let mut carried = Pressure::new(positions + 1);

    for (position, &block) in order.iter().enumerate() {
        let preds = &predecessors[block.0 as usize];
        // A predecessor later in the order is a back edge: nothing known.
        let from_back_edge = preds.iter().any(|p| position_in_order[p.0 as usize] >= position);
        let mut known = if block.0 == 0 || from_back_edge {
            Known::default()
        } else if let [only] = preds.as_slice() {
            if successors_left[only.0 as usize] == 1 {
                at_end[only.0 as usize].take().unwrap_or_default()
            } else {
                at_end[only.0 as usize].clone().unwrap_or_default()
            }
        } else {
            let states: Vec<&Known> = preds.iter().filter_map(|p| at_end[p.0 as usize].as_ref()).collect();
            if states.len() == preds.len() {
                Known::meet(&states)
            } else {
                Known::default()
            }
        };
        if !from_back_edge {
            for p in preds {
                let left = &mut successors_left[p.0 as usize];
                *left = left.saturating_sub(1);
                if *left == 0 {
                    at_end[p.0 as usize] = None;
                }
            }
        }
        known.forget_before(now.saturating_sub(LONGEST_CARRY));
        let block_data = &mut function.blocks[block.0 as usize];
        optimise_block(block_data, &mut known, &mut replaced, &mut now, &mut carried);
        if successors_left[block.0 as usize] > 0 {
            at_end[block.0 as usize] = Some(known);
        }
    }
}

/// The access an instruction makes, for the analysis.
enum Access {
    Load(Place),
    Store(Place, Value),
    /// Overwrites these places without reading them.
    Fill(Vec<Place>),
    LoadAnywhere(Region),
    /// A store through a dynamic index, which also counts as the region's
    /// stores being possibly overwritten (not read).
    StoreAnywhere(Region),
    Call(Footprint),
    None,
}

fn access(inst: &Inst) -> Access {
    let place = |space: Space, n: u32| match space {
        Space::Bits(area) => bit_place(area, n),
        Space::Words(area) => word_place(area, n),
        Space::WideCounters => wide_counter_place(n),
        Space::EdgeSlots => Place::Slot(n),
        Space::BlockActive => Place::BlockActive(n),
        Space::Bookkeeping(field) => Place::Bookkeeping(field, n),
    };
    // Where a run-time index may land; a space without one (never indexed
    // at run time) is a barrier.
    let region = |space: Space| match space {
        Space::Bits(area) => Some(Region::Bits(area)),
        Space::Words(area) => Some(Region::Words(area)),
        Space::WideCounters => Some(Region::WideCounters),
        Space::Bookkeeping(field) => Some(Region::Bookkeeping(field)),
        Space::EdgeSlots | Space::BlockActive => None,
    };
    let anywhere = |space: Space, access: fn(Region) -> Access| match region(space) {
        Some(region) => access(region),
        None => Access::Call(Footprint::Everything),
    };
    match inst.effect() {
        Effect::Load(span) => match span.start {
            Index::Fixed(n) => Access::Load(place(span.space, n)),
            Index::Dynamic(_) => anywhere(span.space, Access::LoadAnywhere),
        },
        Effect::Store(span, value) => match span.start {
            Index::Fixed(n) => Access::Store(place(span.space, n), value),
            Index::Dynamic(_) => anywhere(span.space, Access::StoreAnywhere),
        },
        Effect::Fill(span) => {
            // Only SET/RST of bit and word runs fill.
            let area_count = match span.space {
                Space::Bits(area) => Some(area.count()),
                Space::Words(area) => Some(area.count()),
                Space::WideCounters | Space::EdgeSlots | Space::BlockActive | Space::Bookkeeping(_) => None,
            };
            match area_count
                .and_then(|count| span.fixed_run(count))
                .filter(|run| run.len() <= 64)
            {
                Some(run) => Access::Fill(run.map(|n| place(span.space, n)).collect()),
                None => anywhere(span.space, Access::StoreAnywhere),
            }
        }
        Effect::Helper(helper, _) => Access::Call(call_footprint(helper)),
        Effect::Subroutine => Access::Call(Footprint::Everything),
        // The runtime's `record_error` sets M8067, D8067 and D8069 and
        // reads nothing.
        Effect::OperationError => Access::Fill(vec![
            bit_place(BitArea::M, M_OPERATION_ERROR),
            word_place(WordArea::D, D_ERROR_CODE),
            word_place(WordArea::D, D_ERROR_LINE),
        ]),
        Effect::Pure | Effect::ReadsLocal | Effect::WritesLocal => Access::None,
    }
}

fn optimise_block(
    block: &mut Block,
    known: &mut Known,
    replaced: &mut Replacements,
    now: &mut u64,
    carried: &mut Pressure,
) {
    let mut waiting = Waiting::default();
    let mut remove = vec![false; block.insts.len()];
    for (position, (result, inst)) in block.insts.iter_mut().enumerate() {
        *now += 1;
        replaced.in_operands(inst);
        match access(inst) {
            Access::Load(place) => {
                let Some(result) = *result else { continue };
                match known.values.get_mut(&place) {
                    // Forwarded: the load goes, and with it its read.
                    Some((value, last_use))
                        if *now - *last_use <= LONGEST_CARRY
                            && carried.take(*last_use as usize, *now as usize, CARRIED_VALUES) =>
                    {
                        *last_use = *now;
                        replaced.insert(result, *value);
                        remove[position] = true;
                    }
                    Some(_) | None => {
                        waiting.read(place);
                        known.values.insert(place, (result, *now));
                    }
                }
            }
            Access::Store(place, value) => {
                if known.holds(place, value) {
                    // The device already holds this value.
                    remove[position] = true;
                    continue;
                }
                if let Some(earlier) = waiting.overwrite(place, position) {
                    remove[earlier] = true;
                }
                known.values.insert(place, (value, *now));
            }
            Access::Fill(places) => {
                for place in places {
                    if let Some(earlier) = waiting.stores.remove(&place) {
                        remove[earlier] = true;
                    }
                    known.values.remove(&place);
                }
            }
            Access::LoadAnywhere(region) => waiting.read_region(region),
            Access::StoreAnywhere(region) => known.forget_region(region),
            Access::Call(Footprint::Regions(regions)) => {
                for region in regions {
                    waiting.read_region(region);
                    known.forget_region(region);
                }
            }
            Access::Call(Footprint::Everything) => {
                waiting.stores.clear();
                known.values.clear();
            }
            Access::None => {}
        }
    }
    replaced.in_condition(&mut block.terminator);
    if remove.iter().any(|&r| r) {
        let mut position = 0;
        block.insts.retain(|_| {
            let keep = !remove[position];
            position += 1;
            keep
        });
    }
}

/// How many carried values span each position of a function: range
/// additions and range maxima over a segment tree with lazy additions.
struct Pressure {
    size: usize,
    /// Per node: the maximum of its range, and what was added to all of it.
    max: Vec<i32>,
    add: Vec<i32>,
}

impl Pressure {
    fn new(positions: usize) -> Pressure {
        let size = positions.max(1).next_power_of_two();
        Pressure {
            size,
            max: vec![0; 2 * size],
            add: vec![0; 2 * size],
        }
    }

    /// Carries a value over positions `first..=last` when no position there
    /// carries `limit` values already; whether it did.
    fn take(&mut self, first: usize, last: usize, limit: i32) -> bool {
        let last = last.min(self.size - 1);
        if first > last {
            return true;
        }
        if self.query(1, 0, self.size - 1, first, last) >= limit {
            return false;
        }
        self.update(1, 0, self.size - 1, first, last);
        true
    }

    fn query(&self, node: usize, low: usize, high: usize, first: usize, last: usize) -> i32 {
        if last < low || high < first {
            return i32::MIN;
        }
        if first <= low && high <= last {
            return self.max[node];
        }
        let middle = (low + high) / 2;
        let below =
            self.query(2 * node, low, middle, first, last)
                .max(self.query(2 * node + 1, middle + 1, high, first, last));
        below.saturating_add(self.add[node])
    }

    fn update(&mut self, node: usize, low: usize, high: usize, first: usize, last: usize) {
        if last < low || high < first {
            return;
        }
        if first <= low && high <= last {
            self.max[node] += 1;
            self.add[node] += 1;
            return;
        }
        let middle = (low + high) / 2;
        self.update(2 * node, low, middle, first, last);
        self.update(2 * node + 1, middle + 1, high, first, last);
        self.max[node] = self.max[2 * node].max(self.max[2 * node + 1]) + self.add[node];
    }
}

#[cfg(test)]
mod tests {
    use crate::passes::tests::ir;

    #[test]
    fn a_coil_read_by_a_later_rung_is_not_loaded_again() {
        let text = ir("LD X0\nAND M1\nOUT M2\nLD M2\nAND M1\nOUT Y0\n");
        assert!(!text.contains("load.bit M2"), "{text}");
        assert_eq!(text.matches("load.bit M1").count(), 1, "{text}");
    }

    #[test]
    fn a_coil_overwritten_before_any_read_is_stored_once() {
        let text = ir("LD X0\nOUT M2\nLD X1\nOUT M2\n");
        assert_eq!(text.matches("store.bit M2").count(), 1, "{text}");
    }

    #[test]
    fn a_dynamic_read_keeps_the_store_before_it() {
        let text = ir("LD X0\nOUT M2\nLD M0[D0]\nOUT Y0\nLD X1\nOUT M2\n");
        assert_eq!(text.matches("store.bit M2").count(), 2, "{text}");
    }

    #[test]
    fn a_dynamic_write_forgets_the_area() {
        let text = ir("LD M2\nOUT Y1\nLD X0\nOUT M0[D0]\nLD M2\nOUT Y0\n");
        assert_eq!(text.matches("load.bit M2").count(), 2, "{text}");
    }

    #[test]
    fn a_helper_call_with_places_is_a_barrier() {
        let text = ir("LD X0\nOUT M2\nLD SM0\nBMOV D0 D10 K2\nLD M2\nOUT Y0\nLD X1\nOUT M2\n");
        assert!(text.contains("call"), "{text}");
        assert_eq!(text.matches("store.bit M2").count(), 2, "{text}");
    }

    #[test]
    fn a_timer_coil_keeps_what_is_known_of_other_devices() {
        let text = ir("LD X0\nOUT M2\nOUT T0 K10\nLD M2\nAND T0\nOUT Y0\n");
        assert!(!text.contains("load.bit M2"), "{text}");
        assert!(text.contains("load.bit T0"), "{text}");
    }

    #[test]
    fn set_and_reset_of_one_bit_need_no_branch() {
        let text = ir("LD X0\nSET M3\nLD X1\nRST Y0\nLD M3\nOUT Y1\n");
        assert!(!text.contains("br "), "{text}");
        assert_eq!(text.matches("load.bit M3").count(), 1, "{text}");
    }
}

#[cfg(test)]
mod pressure_tests {
    use super::Pressure;

    #[test]
    fn ranges_are_taken_while_no_point_is_full() {
        let mut p = Pressure::new(20);
        assert!(p.take(3, 6, 2));
        assert!(p.take(5, 9, 2));
        assert!(!p.take(6, 8, 2), "6 is covered twice");
        assert!(p.take(7, 9, 2));
        assert!(!p.take(9, 12, 2));
        assert!(p.take(10, 12, 2));
    }
}
