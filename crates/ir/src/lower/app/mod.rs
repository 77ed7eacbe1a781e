//! Application instructions in the lowering, written apart from the
//! interpreter on purpose (the differential test compares the two).
//!
//! `Step` applies the operand rules once for every instruction: operands are
//! resolved first (computing their in-range tests); `commit` then branches
//! to 4085H if an operand that is read is out of range, else to 4086H if one
//! that is written is, and the instruction does nothing else. The shapes
//! (`map`, `modify`, ...) resolve, read, call the kernel with IR values and
//! write what it returns. Kernels live in one file per family.

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

use super::operand::{Operand, Units};
use super::Lowering;
use crate::CompareOp;
use crate::{BinOp, BlockId, Builder, Index, Inst, Terminator, Type, Value};
use ladder_front::isa::AppArgs;
use ladder_front::program::{Address, AppInstruction, BitRef, WordRef};
use ladder_runtime::special::SpecialBit;
use ladder_runtime::{OperationError, Width};

impl Lowering<'_> {
    /// The body of an application instruction: entered when its rung is ON,
    /// or every scan with `power` for instructions that run every scan;
    /// every failure continues at `after`.
    pub(super) fn app(&mut self, app: &AppInstruction, power: Value, line: u32, after: BlockId) {
        let mut step = Step {
            l: self,
            width: app.width,
            line,
            after,
            reads: Vec::new(),
            writes: Vec::new(),
        };
        let run = Execution {
            power,
            pulse: app.pulse_slot.is_some(),
            job: app.job.unwrap_or(0),
        };
        dispatch(&mut step, &app.args, &run);
    }
}

/// What an instruction that runs every scan needs to know of this one.
pub(super) struct Execution {
    /// A Bit: the rung's power (for a P form, its rising edge).
    pub power: Value,
    /// The P form.
    pub pulse: bool,
    /// Its job in the image (sorts).
    pub job: u32,
}

fn dispatch(step: &mut Step, args: &AppArgs, run: &Execution) {
    let flags = args.op().spec().writes;
    ladder_front::app_dispatch!(args, step, run, flags)
}

/// The operand step of one instruction.
pub(super) struct Step<'l, 'p> {
    pub l: &'l mut Lowering<'p>,
    /// The instruction's width.
    pub width: Width,
    /// The instruction's source line (what an operation error records).
    pub line: u32,
    after: BlockId,
    /// In-range tests of operands that are read, and of those written.
    reads: Vec<Value>,
    writes: Vec<Value>,
}

impl Step<'_, '_> {
    pub fn b(&mut self) -> &mut Builder {
        &mut self.l.b
    }

    /// Notes the in-range test of an operand the instruction reads.
    pub fn note_read_check(&mut self, check: Value) {
        self.note(Some(check), true);
    }

    /// The number an address names as an I32, its in-range test (from
    /// `first` up to `len`, exclusive) noted as an operand that is read — for
    /// a device named directly too: an operand whose range is narrower than
    /// its device class (STMR's T0-T199) compiles, and fails when it runs.
    pub fn address_number(&mut self, address: Address, first: u32, len: u32) -> Value {
        let Some(register) = address.index_register else {
            if !(first..len).contains(&address.index) {
                let outside = self.b().bit(false);
                self.note_read_check(outside);
            }
            return self.b().constant(Type::I32, i64::from(address.index));
        };
        let index = self.l.indexed(address.index, register);
        let b = self.b();
        let low = b.constant(Type::I32, i64::from(first));
        let last = b.constant(Type::I32, i64::from(len) - 1);
        let above = b.compare(CompareOp::Ge, index, low);
        let below = b.compare(CompareOp::Le, index, last);
        let within = b.and(above, below);
        self.note_read_check(within);
        index
    }

    /// A value at the instruction's width that decides how many units the
    /// other operands cover, resolved on its own (like `count_value`).
    /// A helper's I32 answer; 4084H unless it is not 0.
    pub fn require_ok(&mut self, answer: Value) {
        let zero = self.b().constant(Type::I32, 0);
        let ok = self.b().compare(CompareOp::Ne, answer, zero);
        self.require(ok, OperationError::DataOutOfRange);
    }

    /// A helper's I32 answer (0 for a helper without one).
    pub fn helper(&mut self, helper: ladder_runtime::helpers::Helper, args: Vec<Value>) -> Value {
        match self.b().call(helper, args) {
            Some(answer) => answer,
            None => self.b().constant(Type::I32, 0),
        }
    }

    pub fn source_value(&mut self, word: &WordRef) -> Value {
        let operand = self.source(word);
        self.commit();
        self.read(&operand)
    }

    /// Runs `then` only while `condition` holds, then goes on here.
    pub fn when(&mut self, condition: Value, then: impl FnOnce(&mut Step)) {
        let next = self.b().begin_if(condition);
        then(self);
        self.b().jump_to(next);
    }

    fn note(&mut self, check: Option<Value>, read: bool) {
        if let Some(check) = check {
            if read {
                self.reads.push(check);
            } else {
                self.writes.push(check);
            }
        }
    }

    /// `units` values of `width` from `word`; `read` says whether the
    /// instruction reads it (4085H out of range) or only writes it (4086H).
    pub fn resolve(&mut self, word: &WordRef, width: Width, units: Units, read: bool) -> Operand {
        let (operand, check) = self.l.resolve(*word, width, units);
        self.note(check, read);
        operand
    }

    pub fn source(&mut self, word: &WordRef) -> Operand {
        self.resolve(word, self.width, Units::Checked(1), true)
    }

    /// A 16-bit value (a count or a mode).
    pub fn count(&mut self, word: &WordRef) -> Operand {
        self.resolve(word, Width::Single, Units::Checked(1), true)
    }

    pub fn destination(&mut self, word: &WordRef) -> Operand {
        self.resolve(word, self.width, Units::Checked(1), false)
    }

    /// The first of `units` consecutive bits from `bit` (bits of words run
    /// on into the next word); `read` as for `resolve`.
    pub fn bits(&mut self, bit: &BitRef, units: Units, read: bool) -> Operand {
        let (address, len, scale, first_bit) = match *bit {
            BitRef::Device(area, address) => (address, area.count(), 1, 0),
            BitRef::WordBit(area, address, b) => (address, area.count(), 16, u32::from(b)),
        };
        let start = match address.index_register {
            None => Index::Fixed(address.index * scale + first_bit),
            Some(register) => {
                let index = self.l.indexed(address.index, register);
                let index = if scale == 1 {
                    index
                } else {
                    let sixteen = self.b().constant(Type::I32, 16);
                    let scaled = self.b().binary(BinOp::Mul, index, sixteen);
                    let bit = self.b().constant(Type::I32, i64::from(first_bit));
                    self.b().binary(BinOp::Add, scaled, bit)
                };
                Index::Dynamic(index)
            }
        };
        let limit = i64::from(len) * i64::from(scale);
        let check = match (start, units) {
            (Index::Fixed(first), Units::Checked(n)) => {
                (u64::from(first) + u64::from(n) > limit as u64).then(|| self.b().bit(false))
            }
            (start, units) => {
                let b = self.b();
                let first = match start {
                    Index::Fixed(n) => b.constant(Type::I32, i64::from(n)),
                    Index::Dynamic(v) => v,
                };
                let n = match units {
                    Units::Checked(n) => b.constant(Type::I32, i64::from(n)),
                    Units::Dynamic(n) => n,
                };
                let end = b.binary(BinOp::Add, first, n);
                let zero = b.constant(Type::I32, 0);
                let limit = b.constant(Type::I32, limit);
                let above_zero = b.compare(CompareOp::Ge, first, zero);
                let fits = b.compare(CompareOp::Le, end, limit);
                Some(b.and(above_zero, fits))
            }
        };
        self.note(check, read);
        match *bit {
            BitRef::Device(area, _) => Operand::Bit(area, start),
            BitRef::WordBit(area, ..) => Operand::WordBit(area, start),
        }
    }

    /// Continues only while `check` holds; otherwise records `error` and
    /// leaves the instruction.
    pub fn require(&mut self, check: Value, error: OperationError) {
        let (line, after) = (self.line, self.after);
        let b = self.b();
        let (pass, fail) = b.branch_to_new(check);
        b.switch_to(fail);
        b.effect(Inst::RecordError { error, line });
        b.terminate(Terminator::Jump(after));
        b.switch_to(pass);
    }

    /// Leaves the instruction without an error unless `condition` holds
    /// (N = 0: no processing).
    pub fn skip_unless(&mut self, condition: Value) {
        let after = self.after;
        let b = self.b();
        let go_on = b.create_block();
        b.terminate(Terminator::Branch {
            condition,
            then: go_on,
            otherwise: after,
        });
        b.switch_to(go_on);
    }

    /// The value of a 16-bit count operand as an I64, resolved on its own:
    /// counts are read first, as they decide how many units the other
    /// operands cover.
    pub fn count_value(&mut self, n: &WordRef) -> Value {
        let n = self.count(n);
        self.commit();
        self.read_at(&n, Width::Single)
    }

    /// Requires `low <= value <= high` (an I64), else 4084H.
    pub fn require_within(&mut self, value: Value, low: i64, high: i64) {
        let b = self.b();
        let low = b.constant(Type::I64, low);
        let high = b.constant(Type::I64, high);
        let above = b.compare(CompareOp::Ge, value, low);
        let below = b.compare(CompareOp::Le, value, high);
        let within = b.and(above, below);
        self.require(within, OperationError::DataOutOfRange);
    }

    fn all(&mut self, checks: Vec<Value>) -> Option<Value> {
        checks.into_iter().reduce(|a, b| self.l.b.and(a, b))
    }

    /// Ends resolution: 4085H if an operand that is read is out of range,
    /// else 4086H if one that is written is.
    pub fn commit(&mut self) {
        let reads = std::mem::take(&mut self.reads);
        if let Some(check) = self.all(reads) {
            self.require(check, OperationError::ReadOutOfRange);
        }
        let writes = std::mem::take(&mut self.writes);
        if let Some(check) = self.all(writes) {
            self.require(check, OperationError::WriteOutOfRange);
        }
    }

    /// `n` units the checker did not prove to fit (it checked the operand's
    /// first unit only): checked when the instruction runs, like a count
    /// known only then (constant operands fold the check away).
    pub fn run_of(&mut self, n: u32) -> Units {
        Units::Dynamic(self.b().constant(Type::I32, i64::from(n)))
    }

    /// The operand's value at the instruction's width, as an I64.
    pub fn read(&mut self, operand: &Operand) -> Value {
        self.l.read(operand, self.width)
    }

    pub fn read_at(&mut self, operand: &Operand, width: Width) -> Value {
        self.l.read(operand, width)
    }

    /// Writes the low bits of an I64 that the operand holds.
    pub fn write(&mut self, operand: &Operand, value: Value) {
        self.l.write(operand, self.width, value);
    }

    /// Writes a Bit value to a bit operand.
    pub fn write_bit(&mut self, operand: &Operand, on: Value) {
        let value = self.b().extend(on, Type::I64, false);
        self.l.write(operand, Width::Single, value);
    }

    fn values<const N: usize>(&mut self, operands: [Operand; N]) -> [Value; N] {
        operands.map(|operand| self.read(&operand))
    }

    /// D = kernel(S1, ..., Sn).
    pub fn map<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &WordRef,
        kernel: impl FnOnce(&mut Step, [Value; N]) -> Value,
    ) {
        let sources = sources.map(|s| self.source(s));
        let d = self.destination(d);
        self.commit();
        let values = self.values(sources);
        let value = kernel(self, values);
        self.write(&d, value);
    }

    /// D = kernel(S1, ..., Sn), and the instruction's flags in declaration
    /// order.
    pub fn map_flags<const N: usize, const F: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &WordRef,
        flags: &[SpecialBit],
        kernel: impl FnOnce(&mut Step, [Value; N]) -> (Value, [Value; F]),
    ) {
        let sources = sources.map(|s| self.source(s));
        let d = self.destination(d);
        self.commit();
        let values = self.values(sources);
        let (value, on) = kernel(self, values);
        self.write(&d, value);
        debug_assert_eq!(flags.len(), F, "the kernel returns every declared flag");
        for (flag, on) in flags.iter().zip(on) {
            self.b().store_bit(flag.area, Index::Fixed(flag.number), on);
        }
    }

    /// Bit D = kernel(S1, ..., Sn).
    pub fn map_bit<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &BitRef,
        kernel: impl FnOnce(&mut Step, [Value; N]) -> Value,
    ) {
        let sources = sources.map(|s| self.source(s));
        let d = self.bits(d, Units::Checked(1), false);
        self.commit();
        let values = self.values(sources);
        let on = kernel(self, values);
        self.write_bit(&d, on);
    }

    /// D = kernel(D).
    pub fn modify(&mut self, d: &WordRef, kernel: impl FnOnce(&mut Step, Value) -> Value) {
        let d = self.resolve(d, self.width, Units::Checked(1), true);
        self.commit();
        let value = self.read(&d);
        let value = kernel(self, value);
        self.write(&d, value);
    }

    /// (D, D+1 unit) = kernel(S1, ..., Sn); a digit group holds only its own
    /// bits of the first unit.
    pub fn map_double<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &WordRef,
        kernel: impl FnOnce(&mut Step, [Value; N]) -> [Value; 2],
    ) {
        let sources = sources.map(|s| self.source(s));
        let units = if matches!(d, WordRef::Digits(..)) { 1 } else { 2 };
        let d = self.resolve(d, self.width, Units::Checked(units), false);
        self.commit();
        let values = self.values(sources);
        let [low, high] = kernel(self, values);
        self.write(&d, low);
        if units == 2 {
            let next = self.l.nth(&d, 1, self.width);
            self.write(&next, high);
        }
    }

    /// D, D+1, D+2 = kernel(S1, ..., Sn).
    pub fn map_bits<const N: usize>(
        &mut self,
        sources: [&WordRef; N],
        d: &BitRef,
        kernel: impl FnOnce(&mut Step, [Value; N]) -> [Value; 3],
    ) {
        let sources = sources.map(|s| self.source(s));
        let d = self.bits(d, Units::Checked(3), false);
        self.commit();
        let values = self.values(sources);
        let results = kernel(self, values);
        for (unit, value) in (0..).zip(results) {
            let target = self.l.nth(&d, unit, self.width);
            self.write_bit(&target, value);
        }
    }
}
