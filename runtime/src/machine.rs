//! Which parts of the machine around the program a scan keeps up to date.
//!
//! Before and after the program runs, the scan updates what a PLC's
//! firmware updates: the special relays of every scan (M8000-M8003, SM0-SM3),
//! the clock relays M8011-M8014, the calendar D8013-D8019 with M8015-M8019,
//! the scan-time registers D8010-D8012, the high-speed counters' counting at
//! the input refresh and the alarm monitor (SM248/SD249 under SM249). A
//! program that uses none of them should not pay for them at every scan, so
//! a compiled program says which it uses (`MachineUse`, decided at build time
//! from the devices the program and its host name) and the scan updates
//! only those. The input refresh, the output image, forces, pending STL
//! states, the scan count and the time the clocks keep internally
//! (`ladder_get_clock` reads it whether or not D8013-D8019 are shown) are
//! kept for every program.
//!
//! In-process engines (the interpreter, the JIT under `run` and `serve`,
//! whose users may look at any device) keep everything: `MachineUse::ALL`.

use crate::device::{BitArea, WordArea};

/// A set of the machine's parts a scan keeps up to date.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct MachineUse(u32);

/// A part of the machine and the devices by which a program or host uses it.
struct Part {
    part: MachineUse,
    bits: &'static [(BitArea, u32, u32)],
    words: &'static [(WordArea, u32, u32)],
}

/// Every part with its devices (first, last), as programs name them.
const PARTS: [Part; 5] = [
    Part {
        part: MachineUse::SYSTEM_RELAYS,
        bits: &[
            (BitArea::M, 8000, 8003),
            (BitArea::M, 8150, 8151),
            (BitArea::M, 8160, 8160),
            (BitArea::Sm, 0, 3),
        ],
        words: &[],
    },
    Part {
        part: MachineUse::CLOCK_RELAYS,
        bits: &[(BitArea::M, 8011, 8014)],
        words: &[],
    },
    Part {
        part: MachineUse::CALENDAR,
        bits: &[(BitArea::M, 8015, 8019)],
        words: &[(WordArea::D, 8013, 8019)],
    },
    Part {
        part: MachineUse::SCAN_TIME,
        bits: &[],
        words: &[(WordArea::D, 8010, 8012)],
    },
    Part {
        part: MachineUse::ALARMS,
        bits: &[(BitArea::Sm, 248, 249)],
        words: &[(WordArea::Sd, 249, 249)],
    },
];

impl MachineUse {
    /// Nothing beyond what every scan keeps.
    pub const NONE: MachineUse = MachineUse(0);
    /// M8000-M8003, M8150, M8151, M8160 and SM0-SM3, written at every scan.
    pub const SYSTEM_RELAYS: MachineUse = MachineUse(1);
    /// The clock relays M8011-M8014 (10 ms, 100 ms, 1 s, 1 min).
    pub const CLOCK_RELAYS: MachineUse = MachineUse(2);
    /// The calendar clock shown in D8013-D8019, with M8015-M8019.
    pub const CALENDAR: MachineUse = MachineUse(4);
    /// The scan-time registers D8010-D8012.
    pub const SCAN_TIME: MachineUse = MachineUse(8);
    /// The high-speed counters C235-C255 counting edges of X0-X7 at the
    /// input refresh.
    pub const HIGH_SPEED: MachineUse = MachineUse(16);
    /// The alarm monitor: SM248 and SD249 while SM249 is ON.
    pub const ALARMS: MachineUse = MachineUse(32);
    /// Every part: what an engine whose host may look at any device keeps.
    pub const ALL: MachineUse = MachineUse(63);

    /// The set as the `machine` argument of the begin- and end-scan entries.
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// The set an entry's `machine` argument names (unknown bits ignored).
    pub const fn from_bits(bits: u32) -> MachineUse {
        MachineUse(bits & MachineUse::ALL.0)
    }

    /// Are all of `other`'s parts in the set?
    pub const fn contains(self, other: MachineUse) -> bool {
        self.0 & other.0 == other.0
    }

    /// Both sets' parts.
    #[must_use]
    pub const fn with(self, other: MachineUse) -> MachineUse {
        MachineUse(self.0 | other.0)
    }

    /// The parts a program or host uses by naming bits `first..end` of
    /// `area`.
    pub fn of_bits(area: BitArea, first: u32, end: u32) -> MachineUse {
        PARTS.iter().fold(MachineUse::NONE, |uses, part| {
            let named = part
                .bits
                .iter()
                .any(|&(a, low, high)| a == area && first <= high && low < end);
            if named {
                uses.with(part.part)
            } else {
                uses
            }
        })
    }

    /// The parts a program or host uses by naming words `first..end` of
    /// `area`.
    pub fn of_words(area: WordArea, first: u32, end: u32) -> MachineUse {
        PARTS.iter().fold(MachineUse::NONE, |uses, part| {
            let named = part
                .words
                .iter()
                .any(|&(a, low, high)| a == area && first <= high && low < end);
            if named {
                uses.with(part.part)
            } else {
                uses
            }
        })
    }
}

impl MachineUse {
    /// The parts in the set, as the docs name them.
    pub fn names(self) -> impl Iterator<Item = &'static str> {
        [
            (MachineUse::SYSTEM_RELAYS, "special relays"),
            (MachineUse::CLOCK_RELAYS, "clock relays"),
            (MachineUse::CALENDAR, "calendar"),
            (MachineUse::SCAN_TIME, "scan time"),
            (MachineUse::HIGH_SPEED, "high-speed counters"),
            (MachineUse::ALARMS, "alarm monitor"),
        ]
        .into_iter()
        .filter(move |&(part, _)| self.contains(part))
        .map(|(_, name)| name)
    }
}

impl core::ops::BitOr for MachineUse {
    type Output = MachineUse;

    fn bitor(self, other: MachineUse) -> MachineUse {
        self.with(other)
    }
}

impl core::ops::BitOrAssign for MachineUse {
    fn bitor_assign(&mut self, other: MachineUse) {
        *self = self.with(other);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calendar::CalendarTime;
    use crate::memory::Memory;

    /// The devices of `part` in `mem`, in order.
    fn devices(mem: &Memory, part: &Part) -> Vec<i32> {
        let bits = part.bits.iter().flat_map(|&(area, low, high)| {
            (low..=high).map(move |n| i32::from(mem.view().bit(area, n).unwrap_or(false)))
        });
        let words = part
            .words
            .iter()
            .flat_map(|&(area, low, high)| (low..=high).map(move |n| i32::from(mem.view().word(area, n).unwrap_or(0))));
        bits.chain(words).collect()
    }

    #[test]
    fn a_scan_keeps_the_parts_it_is_asked_for_exactly_as_a_scan_keeping_all() {
        for bits in 0..=MachineUse::ALL.bits() {
            let uses = MachineUse::from_bits(bits);
            let (mut all, mut some) = (Memory::new_boxed(), Memory::new_boxed());
            for mem in [&mut all, &mut some] {
                assert!(mem.set_calendar(CalendarTime::at(2026, 12, 31, 23, 59, 58)));
                mem.sm[249] = 1;
                mem.s[903] = 1;
            }
            for (scan, elapsed) in [7u32, 600, 1200, 5, 59_000, 3, 86_400_000].into_iter().enumerate() {
                all.image().begin_scan_for(elapsed, MachineUse::ALL);
                some.image().begin_scan_for(elapsed, uses);
                for part in &PARTS {
                    if uses.contains(part.part) {
                        assert_eq!(devices(&all, part), devices(&some, part), "{uses:?}, scan {scan}");
                    }
                }
                all.image().end_scan_for(MachineUse::ALL);
                some.image().end_scan_for(uses);
                if uses.contains(MachineUse::ALARMS) {
                    assert_eq!((all.sm[248], all.sd[249]), (some.sm[248], some.sd[249]));
                }
                // The clock's own time runs whatever the program uses.
                assert_eq!(all.calendar(), some.calendar(), "{uses:?}, scan {scan}");
                assert_eq!(all.clock_ms, some.clock_ms);
            }
        }
    }

    #[test]
    fn a_scan_keeping_nothing_leaves_the_parts_alone() {
        let mut mem = Memory::new_boxed();
        mem.d[8013] = 77;
        mem.m[8000] = 0;
        for _ in 0..3 {
            mem.image().begin_scan_for(1500, MachineUse::NONE);
            mem.image().end_scan_for(MachineUse::NONE);
        }
        assert_eq!(
            (mem.d[8013], mem.d[8010], mem.m[8000], mem.m[8013], mem.sm[0]),
            (77, 0, 0, 0, 0)
        );
        assert_eq!(mem.calendar().second, 4, "1980-01-01 00:00:04.5");
        assert_eq!(mem.scan_count, 3);
    }

    #[test]
    fn devices_name_their_parts() {
        assert_eq!(MachineUse::of_bits(BitArea::M, 8000, 8001), MachineUse::SYSTEM_RELAYS);
        assert_eq!(MachineUse::of_bits(BitArea::M, 8013, 8014), MachineUse::CLOCK_RELAYS);
        assert_eq!(MachineUse::of_bits(BitArea::M, 8018, 8019), MachineUse::CALENDAR);
        assert_eq!(MachineUse::of_bits(BitArea::M, 0, 8000), MachineUse::NONE);
        assert_eq!(MachineUse::of_bits(BitArea::X, 8000, 8001), MachineUse::NONE);
        assert_eq!(MachineUse::of_words(WordArea::D, 8012, 8013), MachineUse::SCAN_TIME);
        assert_eq!(
            MachineUse::of_words(WordArea::D, 8010, 8020),
            MachineUse::SCAN_TIME | MachineUse::CALENDAR
        );
        assert_eq!(MachineUse::of_words(WordArea::Sd, 249, 250), MachineUse::ALARMS);
        // A whole area names every part in it.
        let all_m = MachineUse::of_bits(BitArea::M, 0, BitArea::M.count());
        assert_eq!(
            all_m,
            MachineUse::SYSTEM_RELAYS | MachineUse::CLOCK_RELAYS | MachineUse::CALENDAR
        );
        assert_eq!(MachineUse::from_bits(u32::MAX), MachineUse::ALL);
        assert!(MachineUse::ALL.contains(MachineUse::HIGH_SPEED));
        assert!(!MachineUse::CALENDAR.contains(MachineUse::ALL));
    }
}
