//! Application instructions in the reference interpreter.
//!
//! `Step` is the one place that applies the operand rules of docs/language.md:
//! every operand is resolved first; if one that is read lies outside its area
//! the instruction records 4085H, else if one that is written does, 4086H,
//! and either way it does nothing else. `execute` dispatches to a shape
//! (`map`, `modify`, ...) that resolves, reads, calls the instruction's
//! kernel with values, and writes what the kernel returns. The kernels live
//! in one file per family and see values only.
//!
//! Nothing here uses the IR, the code generator or the runtime's helpers for
//! compiled code: this is the specification the native engines are tested
//! against.

mod alarm;
mod arithmetic;
mod check;
mod clock;
mod compare;
mod convert;
mod float;
mod handy;
mod highspeed;
mod logic;
mod module;
mod moves;
mod pid;
mod shift;
mod table;
mod zone;

use super::access::{bit_place, effective_index, resolve_word, write_place};
use ladder_front::isa::app::Runs;
use ladder_front::isa::AppArgs;
use ladder_front::program::{AppInstruction, BitRef, WordRef};
use ladder_runtime::{Memory, OperationError, Place, Width};

/// Runs one application instruction with its rung's `power` (for a P form,
/// ON only in the scan the rung rose): instructions that run while ON do
/// nothing without it; the others (ANS, SORT) see it. An operation error is
/// recorded against `line`.
pub fn execute(mem: &mut Memory, app: &AppInstruction, power: bool, line: u32) {
    match app.args.op().spec().runs {
        Runs::WhenOn if !power => return,
        Runs::WhenOn | Runs::EveryScan => {}
    }
    let mut step = Step {
        mem,
        width: app.width,
        read_failed: false,
        write_failed: false,
    };
    let run = Execution {
        power,
        pulse: app.pulse_slot.is_some(),
        job: app.job.unwrap_or(0),
    };
    if let Err(error) = dispatch(&mut step, &app.args, &run) {
        step.mem.record_error(error, line);
    }
}

/// What an instruction that runs every scan needs to know of this one.
pub struct Execution {
    pub power: bool,
    /// The P form.
    pub pulse: bool,
    /// Its job in the image (sorts).
    pub job: u32,
}

type Outcome = Result<(), OperationError>;

fn dispatch(step: &mut Step, args: &AppArgs, run: &Execution) -> Outcome {
    let flags = args.op().spec().writes;
    ladder_front::app_dispatch!(args, step, run, flags)
}

/// `value` wrapped to `width` and sign-extended: what a device of that width
/// holds after the value is written.
pub fn wrap(value: i64, width: Width) -> i64 {
    match width {
        Width::Single => i64::from(value as i16),
        Width::Double => i64::from(value as i32),
    }
}

/// The operand step of one execution.
pub struct Step<'m> {
    pub mem: &'m mut Memory,
    /// The instruction's width.
    pub width: Width,
    read_failed: bool,
    write_failed: bool,
}

impl Step<'_> {
    /// Notes an operand that is read and lies outside its area (4085H at
    /// `commit`).
    pub fn fail_read(&mut self) {
        self.read_failed = true;
    }

    fn mark(&mut self, read: bool) {
        if read {
            self.read_failed = true;
        } else {
            self.write_failed = true;
        }
    }

    /// `units` values of `width` from `word`; `read` says whether the
    /// instruction reads the operand (4085H) or only writes it (4086H).
    pub fn resolve(&mut self, word: &WordRef, width: Width, units: u32, read: bool) -> Option<Place> {
        let place = resolve_word(self.mem, *word, width, units);
        if place.is_none() {
            self.mark(read);
        }
        place
    }

    /// A value read at the instruction's width.
    pub fn source(&mut self, word: &WordRef) -> Option<Place> {
        self.resolve(word, self.width, 1, true)
    }

    /// A 16-bit value (a count or a mode).
    pub fn count(&mut self, word: &WordRef) -> Option<Place> {
        self.resolve(word, Width::Single, 1, true)
    }

    /// A value written at the instruction's width.
    pub fn destination(&mut self, word: &WordRef) -> Option<Place> {
        self.resolve(word, self.width, 1, false)
    }

    /// The first of `n` consecutive bits from `bit` (bits of words run on
    /// into the next word); `read` as for `resolve`.
    pub fn bits(&mut self, bit: &BitRef, n: u32, read: bool) -> Option<Place> {
        let (address, len) = match *bit {
            BitRef::Device(area, address) => (address, area.count()),
            BitRef::WordBit(area, address, _) => (address, area.count()),
        };
        let index = effective_index(self.mem, address);
        let place = (index >= 0 && index < i64::from(len)).then(|| bit_place(*bit, index as u32));
        let place = place.filter(|&start| {
            // The last bit of the run is still in the area.
            let last = start.nth(n.saturating_sub(1), self.width);
            match last {
                Place::Bit(_, i) => i < len,
                Place::WordBit(_, b) => b / 16 < len,
                Place::Constant(_) | Place::Word(..) | Place::WideCounter(_) | Place::Digits(..) => false,
            }
        });
        if place.is_none() {
            self.mark(read);
        }
        place
    }

    /// The value of a 16-bit count operand, resolved on its own: counts are
    /// read first, as they decide how many units the other operands cover.
    pub fn count_value(&mut self, n: &WordRef) -> Result<i64, OperationError> {
        let place = self.count(n);
        self.commit()?;
        Ok(place.map_or(0, |p| self.read_at(p, Width::Single)))
    }

    /// A value at the instruction's width that decides how many units the
    /// other operands cover, resolved on its own (like `count_value`).
    pub fn source_value(&mut self, word: &WordRef) -> Result<i64, OperationError> {
        let place = self.source(word);
        self.commit()?;
        Ok(place.map_or(0, |p| self.read(p)))
    }

    /// Ends resolution: the error of the first operand out of range (reads
    /// before writes), if any.
    pub fn commit(&self) -> Outcome {
        if self.read_failed {
            Err(OperationError::ReadOutOfRange)
        } else if self.write_failed {
            Err(OperationError::WriteOutOfRange)
        } else {
            Ok(())
        }
    }

    /// The value at the instruction's width.
    pub fn read(&self, place: Place) -> i64 {
        i64::from(place.read(self.mem, self.width))
    }

    pub fn read_at(&self, place: Place, width: Width) -> i64 {
        i64::from(place.read(self.mem, width))
    }

    /// Writes the low bits of `value` that the place holds at `width`.
    pub fn write_at(&mut self, place: Place, width: Width, value: i64) {
        place.write(self.mem, width, value);
    }

    /// Sets special relays `flags` to `on`, in order.
    pub fn write_flags(&mut self, flags: &[ladder_runtime::special::SpecialBit], on: &[bool]) {
        for (flag, &on) in flags.iter().zip(on) {
            self.mem.set_bit(flag.area, flag.number, on);
        }
    }

    /// Writes the low bits of `value` that the place holds.
    pub fn write(&mut self, place: Place, value: i64) {
        place.write(self.mem, self.width, value);
    }

    fn sources<const N: usize>(&mut self, sources: [&WordRef; N]) -> [Option<Place>; N] {
        sources.map(|word| self.source(word))
    }

    fn values<const N: usize>(&self, places: [Option<Place>; N]) -> [i64; N] {
        places.map(|place| place.map_or(0, |p| self.read(p)))
    }

    /// D = kernel(S1, ..., Sn).
    pub fn map<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &WordRef,
        kernel: impl FnOnce([i64; N], Width) -> Result<i64, OperationError>,
    ) -> Outcome {
        self.map_flags::<N, 0>(sources, d, &[], |values, width| Ok((kernel(values, width)?, [])))
    }

    /// D = kernel(S1, ..., Sn), and the instruction's flags (`flags`, in
    /// declaration order) from the kernel.
    pub fn map_flags<const N: usize, const F: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &WordRef,
        flags: &[ladder_runtime::special::SpecialBit],
        kernel: impl FnOnce([i64; N], Width) -> Result<(i64, [bool; F]), OperationError>,
    ) -> Outcome {
        let places = self.sources(sources);
        let d = self.destination(d);
        self.commit()?;
        let (value, on) = kernel(self.values(places), self.width)?;
        if let Some(d) = d {
            self.write(d, value);
        }
        debug_assert_eq!(flags.len(), F, "the kernel returns every declared flag");
        for (flag, on) in flags.iter().zip(on) {
            self.mem.set_bit(flag.area, flag.number, on);
        }
        Ok(())
    }

    /// Bit D = kernel(S1, ..., Sn).
    pub fn map_bit<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &BitRef,
        kernel: impl FnOnce([i64; N], Width) -> Result<bool, OperationError>,
    ) -> Outcome {
        let places = self.sources(sources);
        let d = self.bits(d, 1, false);
        self.commit()?;
        let on = kernel(self.values(places), self.width)?;
        if let Some(d) = d {
            write_place(self.mem, d, on);
        }
        Ok(())
    }

    /// D = kernel(D).
    pub fn modify(&mut self, d: &WordRef, kernel: impl FnOnce(i64, Width) -> i64) -> Outcome {
        let place = self.resolve(d, self.width, 1, true);
        self.commit()?;
        if let Some(place) = place {
            let value = kernel(self.read(place), self.width);
            self.write(place, value);
        }
        Ok(())
    }

    /// (D, D+1 unit) = kernel(S1, ..., Sn), for results twice the width; a
    /// digit group holds only its own bits of the first unit.
    pub fn map_double<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &WordRef,
        kernel: impl FnOnce([i64; N], Width) -> Result<[i64; 2], OperationError>,
    ) -> Outcome {
        let places = self.sources(sources);
        let units = if matches!(d, WordRef::Digits(..)) { 1 } else { 2 };
        let d = self.resolve(d, self.width, units, false);
        self.commit()?;
        let [low, high] = kernel(self.values(places), self.width)?;
        if let Some(d) = d {
            self.write(d, low);
            if units == 2 {
                self.write(d.nth(1, self.width), high);
            }
        }
        Ok(())
    }

    /// D, D+1, D+2 = kernel(S1, ..., Sn).
    pub fn map_bits<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &BitRef,
        kernel: impl FnOnce([i64; N]) -> [bool; 3],
    ) -> Outcome {
        let places = self.sources(sources);
        let d = self.bits(d, 3, false);
        self.commit()?;
        let values = kernel(self.values(places));
        if let Some(d) = d {
            for (unit, on) in (0..).zip(values) {
                write_place(self.mem, d.nth(unit, self.width), on);
            }
        }
        Ok(())
    }
}
