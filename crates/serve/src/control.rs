//! Running, stopping and stepping the soft PLC, and breakpoints: what the
//! commissioning engineer does at a PLC's RUN/STOP switch and in an
//! editor's debugger, decided by the scan thread between two scans.
//!
//! - STOP: no scans; every Y is turned OFF once (as an FX does in STOP),
//!   timers hold (no scan advances them); host writes still apply.
//! - RUN: as an FX switched from STOP to RUN, the devices that are not
//!   latched (`--latch`, FX3U's ranges by default) are cleared and the first
//!   scan is the first again (M8002 ON for it, D8011/D8012 since RUN); the
//!   inputs, forces, the clock and the modules' buffer memory stay. The
//!   first scan reports one period, not the time stopped. RUN also ends a
//!   pause.
//! - Pause: no scans; host writes apply at once, as in STOP (the program
//!   sees them at the next step).
//! - Step N: N scans, each reporting the configured period.
//! - A breakpoint is a condition over devices (`Y2 == 1`, `D0 > 100`,
//!   `M5 rises`); the scan thread pauses at the end of the scan in which it
//!   turns true.

use ladder_front::host_device::{parse_device, parse_value, HostDevice};
use ladder_runtime::Memory;

/// The most breakpoints at once.
pub const MOST_BREAKPOINTS: usize = 32;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relation {
    Equal,
    NotEqual,
    Less,
    LessOrEqual,
    Greater,
    GreaterOrEqual,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Condition {
    Compare(HostDevice, Relation, i32),
    /// The device's value turns from 0 to anything else.
    Rises(HostDevice),
    /// From anything else to 0.
    Falls(HostDevice),
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Breakpoint {
    pub id: u32,
    /// As the user wrote it.
    pub text: String,
    pub condition: Condition,
    /// The device's value after the previous scan (edges), and whether the
    /// condition held then (a condition pauses when it turns true).
    previous_value: Option<i32>,
    held: bool,
}

/// Where the scan thread stopped at a breakpoint.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Hit {
    pub id: u32,
    pub text: String,
    pub scan: u64,
}

/// The state of the RUN/STOP switch and the debugger.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Control {
    pub stopped: bool,
    pub paused: bool,
    /// Scans still to run while paused.
    pub steps: u32,
    pub breakpoints: Vec<Breakpoint>,
    pub hit: Option<Hit>,
    next_id: u32,
}

/// Parses `DEVICE OP VALUE` (`==`, `!=`, `<`, `<=`, `>`, `>=`; `=` is `==`)
/// or `DEVICE rises` / `DEVICE falls`. `D0:32 > 100000` compares a pair.
pub fn parse_condition(text: &str) -> Result<Condition, String> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let device = |name: &str| {
        let (name, double) = match name.strip_suffix(":32") {
            Some(bare) => (bare, true),
            None => (name, false),
        };
        parse_device(name, double)
    };
    // `D0>100` without spaces as well.
    let joined: String = words.concat();
    match words.as_slice() {
        [name, edge] if edge.eq_ignore_ascii_case("rises") => Ok(Condition::Rises(device(name)?)),
        [name, edge] if edge.eq_ignore_ascii_case("falls") => Ok(Condition::Falls(device(name)?)),
        _ => {
            const RELATIONS: [(&str, Relation); 7] = [
                ("==", Relation::Equal),
                ("!=", Relation::NotEqual),
                ("<=", Relation::LessOrEqual),
                (">=", Relation::GreaterOrEqual),
                ("<", Relation::Less),
                (">", Relation::Greater),
                ("=", Relation::Equal),
            ];
            let Some((at, symbol, relation)) = RELATIONS
                .iter()
                .filter_map(|&(symbol, relation)| joined.find(symbol).map(|at| (at, symbol, relation)))
                .min_by_key(|&(at, symbol, _)| (at, usize::MAX - symbol.len()))
            else {
                return Err(format!(
                    "`{text}` is not a condition: write DEVICE == VALUE (==, !=, <, <=, >, >=) or DEVICE rises/falls"
                ));
            };
            let (name, written) = (&joined[..at], &joined[at + symbol.len()..]);
            let device = device(name)?;
            let value = parse_value(written, device)?;
            // The device reads as a signed value: a value written above its
            // signed range is its bit pattern (H8F2A, 40000 == -25536) where
            // it is compared for equality, and a condition that no value of
            // the device can meet is refused rather than never pausing.
            let bits = device.bits();
            let (min, max) = if bits == 1 {
                (0i64, 1i64)
            } else {
                (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
            };
            let value = i64::from(value);
            let value = match relation {
                Relation::Equal | Relation::NotEqual if bits > 1 && value > max && value < (1i64 << bits) => {
                    value - (1i64 << bits)
                }
                Relation::Equal
                | Relation::NotEqual
                | Relation::Less
                | Relation::LessOrEqual
                | Relation::Greater
                | Relation::GreaterOrEqual => value,
            };
            let possible = match relation {
                Relation::Equal => (min..=max).contains(&value),
                Relation::NotEqual => true,
                Relation::Less => value > min,
                Relation::LessOrEqual => value >= min,
                Relation::Greater => value < max,
                Relation::GreaterOrEqual => value <= max,
            };
            if !possible {
                return Err(format!("`{}` can never hold: {name} reads {min}..{max}", text.trim()));
            }
            Ok(Condition::Compare(device, relation, value as i32))
        }
    }
}

impl Condition {
    fn device(&self) -> HostDevice {
        match *self {
            Condition::Compare(device, ..) | Condition::Rises(device) | Condition::Falls(device) => device,
        }
    }

    fn holds(&self, previous: Option<i32>, now: i32) -> bool {
        match *self {
            Condition::Compare(_, relation, value) => match relation {
                Relation::Equal => now == value,
                Relation::NotEqual => now != value,
                Relation::Less => now < value,
                Relation::LessOrEqual => now <= value,
                Relation::Greater => now > value,
                Relation::GreaterOrEqual => now >= value,
            },
            Condition::Rises(_) => previous == Some(0) && now != 0,
            Condition::Falls(_) => previous.is_some_and(|p| p != 0) && now == 0,
        }
    }
}

impl Control {
    /// RUN is RUN: it also ends a pause (and pending steps), as the switch
    /// on a PLC would.
    pub fn run(&mut self) {
        self.stopped = false;
        self.paused = false;
        self.steps = 0;
        self.hit = None;
    }

    /// A step was asked for while paused: it runs without waiting for the
    /// period.
    pub fn step_waiting(&self) -> bool {
        self.paused && self.steps > 0 && !self.stopped
    }

    pub fn add_breakpoint(&mut self, text: &str) -> Result<u32, String> {
        if self.breakpoints.len() >= MOST_BREAKPOINTS {
            return Err(format!("at most {MOST_BREAKPOINTS} breakpoints"));
        }
        let condition = parse_condition(text)?;
        self.next_id += 1;
        self.breakpoints.push(Breakpoint {
            id: self.next_id,
            text: text.trim().to_string(),
            condition,
            previous_value: None,
            held: false,
        });
        Ok(self.next_id)
    }

    /// Removes one breakpoint (`Some(id)`: false when there is none such) or all.
    pub fn remove_breakpoints(&mut self, id: Option<u32>) -> bool {
        match id {
            Some(id) => {
                let before = self.breakpoints.len();
                self.breakpoints.retain(|b| b.id != id);
                self.breakpoints.len() < before
            }
            None => {
                self.breakpoints.clear();
                true
            }
        }
    }

    /// After scan `scan` left `image`: pauses at the first breakpoint whose
    /// condition turned true. Every condition follows every scan, so an
    /// edge is never missed while another one holds.
    pub fn after_scan(&mut self, image: &Memory, scan: u64) {
        let mut first = None;
        for breakpoint in &mut self.breakpoints {
            let device = breakpoint.condition.device();
            let now = image.read_device(device.device, device.width).unwrap_or(0);
            let holds = breakpoint.condition.holds(breakpoint.previous_value, now);
            if holds && !breakpoint.held && first.is_none() {
                first = Some(Hit {
                    id: breakpoint.id,
                    text: breakpoint.text.clone(),
                    scan,
                });
            }
            breakpoint.previous_value = Some(now);
            breakpoint.held = holds;
        }
        if let Some(hit) = first {
            self.paused = true;
            self.steps = 0;
            self.hit = Some(hit);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conditions_read_as_written() {
        for text in [
            "Y2 == 1",
            "D0 > 100",
            "D0>100",
            "M5 rises",
            "X0 falls",
            "D10:32 >= 100000",
            "T0 = 1",
            "D0 != -5",
        ] {
            assert!(parse_condition(text).is_ok(), "{text}");
        }
        assert!(matches!(
            parse_condition("D0 <= 7"),
            Ok(Condition::Compare(_, Relation::LessOrEqual, 7))
        ));
        for bad in ["D0", "D0 >", "Q0 == 1", "D0 == x", "M5 jumps", ""] {
            assert!(parse_condition(bad).is_err(), "{bad}");
        }
        // Conditions no value of the device can meet.
        for never in [
            "D0 > 40000",
            "D0 > 32767",
            "D0 < -32768",
            "D0 == 65536",
            "Y0 > 1",
            "Y0 < 0",
            "Y0 == 2",
            "D0:32 > 2147483647",
        ] {
            assert!(parse_condition(never).is_err(), "{never}");
        }
        // A word's bit pattern, compared for equality.
        assert!(matches!(
            parse_condition("D0 == H8F2A"),
            Ok(Condition::Compare(_, Relation::Equal, -28886))
        ));
    }

    #[test]
    fn a_breakpoint_pauses_when_its_condition_turns_true() {
        let mut control = Control::default();
        control.add_breakpoint("M5 rises").unwrap();
        control.add_breakpoint("D0 > 2").unwrap();
        let mut image = Memory::new_boxed();
        control.after_scan(&image, 1);
        assert!(!control.paused);
        image.m[5] = 1;
        control.after_scan(&image, 2);
        assert_eq!(control.hit.as_ref().map(|h| (h.id, h.scan)), Some((1, 2)));
        control.paused = false;
        control.after_scan(&image, 3); // M5 still ON: no new edge
        assert!(!control.paused);
        image.d[0] = 3;
        control.after_scan(&image, 4);
        assert_eq!(control.hit.as_ref().map(|h| (h.id, h.scan)), Some((2, 4)));
        control.paused = false;
        control.after_scan(&image, 5); // still above 2: it held already
        assert!(!control.paused);
        assert!(control.remove_breakpoints(Some(1)));
        assert!(!control.remove_breakpoints(Some(1)));
        assert_eq!(control.breakpoints.len(), 1);
    }
}
