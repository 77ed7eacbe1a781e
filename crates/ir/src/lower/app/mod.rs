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
use crate::{BinOp, BlockId, Builder, Index, Inst, Terminator, Type, Value};
use ladder_front::isa::{AppArgs, CompareOp};
use ladder_front::program::{Address, AppInstruction, BitRef, WordRef};
use ladder_runtime::hsc::HscCompare;
use ladder_runtime::pulse::PulseKind;
use ladder_runtime::real::RealFunction;
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
    match args {
        AppArgs::Mov { s, d } => step.map([s], d, moves::mov),
        AppArgs::BlockMov { s, d, n } => moves::block_move(step, s, d, n),
        AppArgs::FillMov { s, d, n } => moves::fill_move(step, s, d, n),
        AppArgs::Add { s1, s2, d } => step.map_flags([s1, s2], d, flags, arithmetic::add),
        AppArgs::Sub { s1, s2, d } => step.map_flags([s1, s2], d, flags, arithmetic::sub),
        AppArgs::Mul { s1, s2, d } => step.map_double([s1, s2], d, arithmetic::mul),
        AppArgs::Div { s1, s2, d } => step.map_double([s1, s2], d, arithmetic::div),
        AppArgs::Inc { d } => step.modify(d, arithmetic::inc),
        AppArgs::Dec { d } => step.modify(d, arithmetic::dec),
        AppArgs::Cmp { s1, s2, d } => step.map_bits([s1, s2], d, compare::cmp),
        AppArgs::ZoneCmp { s1, s2, s, d } => step.map_bits([s1, s2, s], d, compare::zcp),
        AppArgs::Neg { d } => step.modify(d, arithmetic::neg),
        AppArgs::Sqr { s, d } => step.map_flags([s], d, flags, arithmetic::sqr),
        AppArgs::Wand { s1, s2, d } => step.map([s1, s2], d, logic::wand),
        AppArgs::Wor { s1, s2, d } => step.map([s1, s2], d, logic::wor),
        AppArgs::Wxor { s1, s2, d } => step.map([s1, s2], d, logic::wxor),
        AppArgs::Cml { s, d } => step.map([s], d, logic::cml),
        AppArgs::Bon { s, n, d } => step.map_bit([s, n], d, logic::bon),
        AppArgs::Sum { s, d } => step.map_flags([s], d, flags, logic::sum),
        AppArgs::Swap { d } => step.modify(d, convert::swap),
        AppArgs::Encode { s, n, d } => convert::encode(step, s, n, d),
        AppArgs::Decode { s, n, d } => convert::decode(step, s, n, d),
        AppArgs::BytesToWords { s, d, n } => convert::bytes(step, s, d, n, false),
        AppArgs::WordsToBytes { s, d, n } => convert::bytes(step, s, d, n, true),
        AppArgs::Distribute { s, d, n } => convert::distribute(step, s, d, n),
        AppArgs::Unite { s, d, n } => convert::unite(step, s, d, n),
        AppArgs::OctalMove { s, d } => moves::octal_move(step, s, d),
        AppArgs::ZoneReset { d1, d2 } => zone::reset(step, d1, d2),
        AppArgs::ZoneSet { d1, d2 } => zone::set(step, d1, d2),
        AppArgs::Max { s1, s2, d } => table::extreme(step, s1, s2, d, true),
        AppArgs::Min { s1, s2, d } => table::extreme(step, s1, s2, d, false),
        AppArgs::Limit { s1, s2, s3, d } => step.map([s1, s2, s3], d, table::limit),
        AppArgs::Mean { s, d, n } => table::mean(step, s, d, n),
        AppArgs::Wsum { s, d, n } => table::sum(step, s, d, n),
        AppArgs::Sort { s, n1, n2, d, n3 } => table::sort(step, run, [s, n1, n2, d, n3], false),
        AppArgs::Sort2 { s, n1, n2, d, n3 } => table::sort(step, run, [s, n1, n2, d, n3], true),
        AppArgs::Bcc { s1, s2, s3, d } => check::block_check(step, s1, s2, s3, d),
        AppArgs::Crc { s, d, n } => check::crc(step, s, d, n),
        AppArgs::Ans { s, n, d } => alarm::set(step, run, s, n, d),
        AppArgs::Anr {} => alarm::reset(step),
        AppArgs::Xch { d1, d2 } => moves::exchange(step, d1, d2),
        AppArgs::Alt { d } => logic::alternate(step, d),
        AppArgs::Bcd { s, d } => step.map([s], d, convert::bcd),
        AppArgs::Bin { s, d } => step.map([s], d, convert::bin),
        AppArgs::Ror { d, n } => shift::rotate(step, d, n, true),
        AppArgs::Rol { d, n } => shift::rotate(step, d, n, false),
        AppArgs::ShiftRight { s, d, n1, n2 } => shift::shift_bits(step, s, d, n1, n2, false),
        AppArgs::ShiftLeft { s, d, n1, n2 } => shift::shift_bits(step, s, d, n1, n2, true),
        AppArgs::RealCmp { s1, s2, d } => float::compare(step, &[s1, s2], d),
        AppArgs::RealZoneCmp { s1, s2, s, d } => float::compare(step, &[s1, s2, s], d),
        AppArgs::RealMov { s, d } => float::map(step, [s], d, flags, float::mov),
        AppArgs::RealAdd { s1, s2, d } => float::map(step, [s1, s2], d, flags, float::add),
        AppArgs::RealSub { s1, s2, d } => float::map(step, [s1, s2], d, flags, float::sub),
        AppArgs::RealMul { s1, s2, d } => float::map(step, [s1, s2], d, flags, float::mul),
        AppArgs::RealDiv { s1, s2, d } => float::map(step, [s1, s2], d, flags, float::div),
        AppArgs::RealSqr { s, d } => float::map(step, [s], d, flags, float::sqr),
        AppArgs::RealNeg { d } => float::neg(step, d),
        AppArgs::Flt { s, d } => float::flt(step, s, d),
        AppArgs::Int { s, d } => float::int(step, s, d, flags),
        AppArgs::RealToDecimal { s, d } => float::to_decimal(step, s, d),
        AppArgs::DecimalToReal { s, d } => float::from_decimal(step, s, d),
        AppArgs::Sin { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Sin)),
        AppArgs::Cos { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Cos)),
        AppArgs::Tan { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Tan)),
        AppArgs::Asin { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Asin)),
        AppArgs::Acos { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Acos)),
        AppArgs::Atan { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Atan)),
        AppArgs::Rad { s, d } => float::map(step, [s], d, flags, float::angle(true)),
        AppArgs::Deg { s, d } => float::map(step, [s], d, flags, float::angle(false)),
        AppArgs::Exp { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Exp)),
        AppArgs::Loge { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Ln)),
        AppArgs::Log10 { s, d } => float::map(step, [s], d, flags, float::apply(RealFunction::Log10)),
        AppArgs::Trd { d } => clock::read(step, d),
        AppArgs::Twr { s } => clock::write(step, s),
        AppArgs::Tcmp { s1, s2, s3, s, d } => clock::compare(step, [s1, s2, s3], s, d),
        AppArgs::Tzcp { s1, s2, s, d } => clock::zone(step, s1, s2, s, d),
        AppArgs::Tadd { s1, s2, d } => clock::add(step, s1, s2, d, false, flags),
        AppArgs::Tsub { s1, s2, d } => clock::add(step, s1, s2, d, true, flags),
        AppArgs::Htos { s, d } => clock::to_seconds(step, s, d),
        AppArgs::Stoh { s, d } => clock::to_time(step, s, d),
        AppArgs::Hour { s, d1, d2 } => clock::hour(step, run.job, s, d1, d2),
        AppArgs::Ser { s1, s2, d, n } => handy::search(step, s1, s2, d, n),
        AppArgs::Absd { s1, s2, d, n } => handy::absolute_drum(step, s1, s2, d, n),
        AppArgs::Incd { s1, s2, d, n } => handy::incremental_drum(step, run, s1, s2, d, n),
        AppArgs::Ttmr { d, n } => handy::teaching_timer(step, run, d, n),
        AppArgs::Stmr { s, m, d } => handy::special_timer(step, run, s, m, d),
        AppArgs::Ramp { s1, s2, d, n } => handy::ramp(step, run, s1, s2, d, n),
        AppArgs::Segd { s, d } => handy::segment_decode(step, s, d),
        AppArgs::Segl { s, d, n } => handy::segment_latch(step, run, s, d, n),
        AppArgs::Asci { s, d, n } => handy::characters(step, 0, s, d, n),
        AppArgs::Hex { s, d, n } => handy::characters(step, 1, s, d, n),
        AppArgs::Ccd { s, d, n } => handy::characters(step, 2, s, d, n),
        AppArgs::Hscs { s1, s2, d } => highspeed::compare(step, run, HscCompare::Set, &[s1], s2, d),
        AppArgs::Hscr { s1, s2, d } => highspeed::compare(step, run, HscCompare::Reset, &[s1], s2, d),
        AppArgs::Hsz { s1, s2, s, d } => highspeed::compare(step, run, HscCompare::Zone, &[s1, s2], s, d),
        AppArgs::Spd { s1, s2, d } => highspeed::speed(step, s1, s2, d),
        AppArgs::Plsy { s1, s2, d } => highspeed::pulse(
            step,
            run,
            &pulse_operands(PulseKind::Plsy, d, [Some(s1), Some(s2), None, None], None, None, None),
        ),
        AppArgs::Plsr { s1, s2, s3, d } => highspeed::pulse(
            step,
            run,
            &pulse_operands(
                PulseKind::Plsr,
                d,
                [Some(s1), Some(s2), Some(s3), None],
                None,
                None,
                None,
            ),
        ),
        AppArgs::Plsv { s, d1, d2 } => highspeed::pulse(
            step,
            run,
            &pulse_operands(PulseKind::Plsv, d1, [Some(s), None, None, None], None, None, Some(d2)),
        ),
        AppArgs::Drvi { s1, s2, d1, d2 } => highspeed::pulse(
            step,
            run,
            &pulse_operands(
                PulseKind::Drvi,
                d1,
                [Some(s2), Some(s1), None, None],
                None,
                None,
                Some(d2),
            ),
        ),
        AppArgs::Drva { s1, s2, d1, d2 } => highspeed::pulse(
            step,
            run,
            &pulse_operands(
                PulseKind::Drva,
                d1,
                [Some(s2), Some(s1), None, None],
                None,
                None,
                Some(d2),
            ),
        ),
        AppArgs::Zrn { s1, s2, s3, d } => highspeed::pulse(
            step,
            run,
            &pulse_operands(
                PulseKind::Zrn,
                d,
                [Some(s1), None, None, Some(s2)],
                Some(s3),
                None,
                None,
            ),
        ),
        AppArgs::Dszr { s1, s2, d1, d2 } => highspeed::pulse(
            step,
            run,
            &pulse_operands(
                PulseKind::Dszr,
                d1,
                [None, None, None, None],
                Some(s1),
                Some(s2),
                Some(d2),
            ),
        ),
        AppArgs::Pwm { s1, s2, d } => highspeed::pulse_width(step, run, s1, s2, d),
        AppArgs::From { m1, m2, d, n } => module::transfer(step, m1, m2, d, n, true),
        AppArgs::To { m1, m2, s, n } => module::transfer(step, m1, m2, s, n, false),
        AppArgs::Pid { s1, s2, s3, d } => pid::pid(step, run, s1, s2, s3, d),
    }
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
        let b = self.b();
        let body = b.create_block();
        let next = b.create_block();
        b.terminate(Terminator::Branch {
            condition,
            then: body,
            otherwise: next,
        });
        b.switch_to(body);
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
        let pass = b.create_block();
        let fail = b.create_block();
        b.terminate(Terminator::Branch {
            condition: check,
            then: pass,
            otherwise: fail,
        });
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

/// The operands of a pulse instruction: frequency, amount, ramp, creep
/// (in that order), near point, zero signal, output and direction.
fn pulse_operands<'a>(
    kind: PulseKind,
    output: &'a BitRef,
    [frequency, amount, ramp, creep]: [Option<&'a WordRef>; 4],
    near_point: Option<&'a BitRef>,
    zero_signal: Option<&'a BitRef>,
    direction: Option<&'a BitRef>,
) -> highspeed::PulseOperands<'a> {
    highspeed::PulseOperands {
        kind,
        frequency,
        amount,
        ramp,
        creep,
        near_point,
        zero_signal,
        output,
        direction,
    }
}
