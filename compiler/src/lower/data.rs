//! Application instructions in the lowering. Each operand is checked in the
//! instruction's order; the first one out of range records its error (4085H
//! reading, 4086H writing) and the instruction does nothing else.

use super::Lowering;
use crate::ir::{BinOp, BlockId, Index, Inst, PlaceArg, Terminator, Type, Value};
use crate::isa::{CompareOp, DataOp};
use crate::program::{BitRef, DataInstruction, DataOperand, WordRef};
use ladder_runtime::device::{COUNTER_COUNT, FIRST_WIDE_COUNTER};
use ladder_runtime::place::{MAX_BLOCK_UNITS, PLACE_CONSTANT, PLACE_DIGITS, PLACE_WIDE_COUNTER};
use ladder_runtime::special::{M_BORROW, M_CARRY, M_ZERO};
use ladder_runtime::{BitArea, OperationError, WordArea};

/// A resolved word operand.
#[derive(Clone, Copy, Debug)]
pub(super) enum Operand {
    Constant(i64),
    Word(WordArea, Index),
    WideCounter(Index),
    Digits(BitArea, Index, u8),
}

/// How many values an operand covers.
#[derive(Clone, Copy, Debug)]
pub(super) enum Units {
    /// A count the checker already proved to fit at a fixed address.
    Checked(u32),
    /// A count known only at run time (BMOV/FMOV n), an I32.
    Dynamic(Value),
}

impl Lowering<'_> {
    /// Resolves a word operand: the operand, and an in-range test (a Bit)
    /// when the range is not known to hold at compile time.
    pub(super) fn resolve(&mut self, word: WordRef, wide: bool, units: Units) -> (Operand, Option<Value>) {
        let (address, first, len, per_unit) = match word {
            WordRef::Constant(value) => return (Operand::Constant(i64::from(value)), None),
            WordRef::Word(area, address) => (address, 0, area.count(), if wide { 2 } else { 1 }),
            WordRef::WideCounter(address) => (address, FIRST_WIDE_COUNTER, COUNTER_COUNT, 1),
            WordRef::Digits(area, address, digits) => (address, 0, area.count(), 4 * u32::from(digits)),
        };
        let statically_fine = address.offset.is_none() && matches!(units, Units::Checked(_));
        let (index, check) = if statically_fine {
            (Index::Fixed(address.index), None)
        } else {
            let index = match address.offset {
                Some(register) => self.offset_index(address.index, register),
                None => self.b.constant(Type::I32, i64::from(address.index)),
            };
            let units = match units {
                Units::Checked(n) => self.b.constant(Type::I32, i64::from(n)),
                Units::Dynamic(n) => n,
            };
            let per_unit = self.b.constant(Type::I32, i64::from(per_unit));
            let span = self.b.binary(BinOp::Mul, units, per_unit);
            let end = self.b.binary(BinOp::Add, index, span);
            let low = self.b.constant(Type::I32, i64::from(first));
            let high = self.b.constant(Type::I32, i64::from(len));
            let above_first = self.b.compare(CompareOp::Ge, index, low);
            let fits = self.b.compare(CompareOp::Le, end, high);
            (Index::Dynamic(index), Some(self.b.and(above_first, fits)))
        };
        let operand = match word {
            WordRef::Constant(_) => unreachable!("returned above"),
            WordRef::Word(area, _) => Operand::Word(area, index),
            WordRef::WideCounter(_) => Operand::WideCounter(index),
            WordRef::Digits(area, _, digits) => Operand::Digits(area, index, digits),
        };
        (operand, check)
    }

    /// Continues only if `check` holds; otherwise records `error` and goes to
    /// `after`.
    fn require(&mut self, check: Option<Value>, error: OperationError, line: u32, after: BlockId) {
        let Some(check) = check else { return };
        let pass = self.b.create_block();
        let fail = self.b.create_block();
        self.b.terminate(Terminator::Branch {
            condition: check,
            then: pass,
            otherwise: fail,
        });
        self.b.switch_to(fail);
        self.b.effect(Inst::RecordError { error, line });
        self.b.terminate(Terminator::Jump(after));
        self.b.switch_to(pass);
    }

    fn source(&mut self, operand: &DataOperand, wide: bool, units: Units, line: u32, after: BlockId) -> Operand {
        let (resolved, check) = self.resolve(word(operand), wide, units);
        self.require(check, OperationError::ReadOutOfRange, line, after);
        resolved
    }

    fn destination(&mut self, operand: &DataOperand, wide: bool, units: Units, line: u32, after: BlockId) -> Operand {
        let (resolved, check) = self.resolve(word(operand), wide, units);
        self.require(check, OperationError::WriteOutOfRange, line, after);
        resolved
    }

    /// A destination twice the width: two units, but a digit group holds
    /// only its own bits.
    fn double_destination(&mut self, operand: &DataOperand, wide: bool, line: u32, after: BlockId) -> Operand {
        let units = if matches!(word(operand), WordRef::Digits(..)) {
            1
        } else {
            2
        };
        self.destination(operand, wide, Units::Checked(units), line, after)
    }

    /// The three result bits of CMP/ZCP.
    fn bit_triple(&mut self, operand: &DataOperand, line: u32, after: BlockId) -> (BitArea, Index) {
        let DataOperand::Bits(BitRef::Device(area, address)) = operand else {
            unreachable!("the checker gives Y/M/S devices here")
        };
        let Some(register) = address.offset else {
            return (*area, Index::Fixed(address.index));
        };
        let index = self.offset_index(address.index, register);
        let zero = self.b.constant(Type::I32, 0);
        let last_start = self.b.constant(Type::I32, i64::from(area.count() - 3));
        let above_zero = self.b.compare(CompareOp::Ge, index, zero);
        let fits = self.b.compare(CompareOp::Le, index, last_start);
        let check = self.b.and(above_zero, fits);
        self.require(Some(check), OperationError::WriteOutOfRange, line, after);
        (*area, Index::Dynamic(index))
    }

    /// The instruction's body, entered when its condition holds. Failures
    /// jump to `after`.
    pub(super) fn data(&mut self, data: &DataInstruction, line: u32, after: BlockId) {
        let wide = data.wide;
        let ops = &data.operands;
        let one = Units::Checked(1);
        match data.op {
            DataOp::Mov => {
                let s = self.source(&ops[0], wide, one, line, after);
                let d = self.destination(&ops[1], wide, one, line, after);
                let value = self.read(&s, wide);
                self.write(&d, wide, value);
            }
            DataOp::BlockMov | DataOp::FillMov => {
                let n = self.source(&ops[2], false, one, line, after);
                let n = self.read(&n, false);
                let n = self.b.truncate(n, Type::I32);
                let one_unit = self.b.constant(Type::I32, 1);
                let most = self.b.constant(Type::I32, i64::from(MAX_BLOCK_UNITS));
                let at_least_one = self.b.compare(CompareOp::Ge, n, one_unit);
                let at_most = self.b.compare(CompareOp::Le, n, most);
                let n_ok = self.b.and(at_least_one, at_most);
                self.require(Some(n_ok), OperationError::DataOutOfRange, line, after);
                let fill = data.op == DataOp::FillMov;
                let source_units = if fill { one } else { Units::Dynamic(n) };
                let s = self.source(&ops[0], wide, source_units, line, after);
                let d = self.destination(&ops[1], wide, Units::Dynamic(n), line, after);
                let (source, destination) = (self.place(&s), self.place(&d));
                self.b.effect(Inst::BlockMove {
                    source,
                    destination,
                    count: n,
                    wide,
                    fill,
                });
            }
            DataOp::Add | DataOp::Sub => {
                let a = self.source(&ops[0], wide, one, line, after);
                let b = self.source(&ops[1], wide, one, line, after);
                let d = self.destination(&ops[2], wide, one, line, after);
                let (a, b) = (self.read(&a, wide), self.read(&b, wide));
                let op = if data.op == DataOp::Add { BinOp::Add } else { BinOp::Sub };
                let exact = self.b.binary(op, a, b);
                let wrapped = self.wrap(exact, wide);
                self.write(&d, wide, wrapped);
                let (min, max) = if wide {
                    (i64::from(i32::MIN), i64::from(i32::MAX))
                } else {
                    (-32768, 32767)
                };
                let zero = self.b.constant(Type::I64, 0);
                let min = self.b.constant(Type::I64, min);
                let max = self.b.constant(Type::I64, max);
                let flags = [
                    (M_ZERO, self.b.compare(CompareOp::Eq, wrapped, zero)),
                    (M_BORROW, self.b.compare(CompareOp::Lt, exact, min)),
                    (M_CARRY, self.b.compare(CompareOp::Gt, exact, max)),
                ];
                for (relay, value) in flags {
                    self.b.store_bit(BitArea::M, Index::Fixed(relay), value);
                }
            }
            DataOp::Mul => {
                let a = self.source(&ops[0], wide, one, line, after);
                let b = self.source(&ops[1], wide, one, line, after);
                let d = self.double_destination(&ops[2], wide, line, after);
                let (a, b) = (self.read(&a, wide), self.read(&b, wide));
                let product = self.b.binary(BinOp::Mul, a, b);
                self.write(&d, wide, product);
                if !matches!(d, Operand::Digits(..)) {
                    let half = self.b.constant(Type::I64, if wide { 32 } else { 16 });
                    let high = self.b.binary(BinOp::Shr, product, half);
                    let next = self.nth(&d, 1, wide);
                    self.write(&next, wide, high);
                }
            }
            DataOp::Div => {
                let a = self.source(&ops[0], wide, one, line, after);
                let b = self.source(&ops[1], wide, one, line, after);
                let d = self.double_destination(&ops[2], wide, line, after);
                let (a, b) = (self.read(&a, wide), self.read(&b, wide));
                let zero = self.b.constant(Type::I64, 0);
                let divisor_ok = self.b.compare(CompareOp::Ne, b, zero);
                self.require(Some(divisor_ok), OperationError::DataOutOfRange, line, after);
                let quotient = self.b.binary(BinOp::Div, a, b);
                self.write(&d, wide, quotient);
                if !matches!(d, Operand::Digits(..)) {
                    let remainder = self.b.binary(BinOp::Rem, a, b);
                    let next = self.nth(&d, 1, wide);
                    self.write(&next, wide, remainder);
                }
            }
            DataOp::Inc | DataOp::Dec => {
                let d = self.destination(&ops[0], wide, one, line, after);
                let value = self.read(&d, wide);
                let step = self.b.constant(Type::I64, 1);
                let op = if data.op == DataOp::Inc { BinOp::Add } else { BinOp::Sub };
                let stepped = self.b.binary(op, value, step);
                self.write(&d, wide, stepped);
            }
            DataOp::Cmp => {
                let a = self.source(&ops[0], wide, one, line, after);
                let b = self.source(&ops[1], wide, one, line, after);
                let (area, start) = self.bit_triple(&ops[2], line, after);
                let (a, b) = (self.read(&a, wide), self.read(&b, wide));
                let results = [CompareOp::Gt, CompareOp::Eq, CompareOp::Lt].map(|op| self.b.compare(op, a, b));
                self.write_triple(area, start, results);
            }
            DataOp::ZoneCmp => {
                let low = self.source(&ops[0], wide, one, line, after);
                let high = self.source(&ops[1], wide, one, line, after);
                let s = self.source(&ops[2], wide, one, line, after);
                let (area, start) = self.bit_triple(&ops[3], line, after);
                let (low, high, s) = (self.read(&low, wide), self.read(&high, wide), self.read(&s, wide));
                // A reversed zone counts as the single value `low`.
                let reversed = self.b.compare(CompareOp::Gt, low, high);
                let high = self.b.select(reversed, low, high);
                let below = self.b.compare(CompareOp::Lt, s, low);
                let above = self.b.compare(CompareOp::Gt, s, high);
                let outside = self.b.or(below, above);
                let inside = self.b.not(outside);
                self.write_triple(area, start, [below, inside, above]);
            }
        }
    }

    fn write_triple(&mut self, area: BitArea, start: Index, values: [Value; 3]) {
        for (unit, value) in values.into_iter().enumerate() {
            let index = self.index_plus(start, unit as u32);
            self.b.store_bit(area, index, value);
        }
    }

    /// `value` wrapped to the instruction's width, sign-extended again.
    fn wrap(&mut self, value: Value, wide: bool) -> Value {
        let narrow = self.b.truncate(value, if wide { Type::I32 } else { Type::I16 });
        self.b.extend(narrow, Type::I64, true)
    }

    fn index_plus(&mut self, index: Index, delta: u32) -> Index {
        match index {
            Index::Fixed(n) => Index::Fixed(n + delta),
            Index::Dynamic(_) if delta == 0 => index,
            Index::Dynamic(value) => {
                let delta = self.b.constant(Type::I32, i64::from(delta));
                Index::Dynamic(self.b.binary(BinOp::Add, value, delta))
            }
        }
    }

    /// The `unit`-th value from an operand.
    fn nth(&mut self, operand: &Operand, unit: u32, wide: bool) -> Operand {
        match *operand {
            Operand::Constant(_) => *operand,
            Operand::Word(area, index) => Operand::Word(area, self.index_plus(index, unit * if wide { 2 } else { 1 })),
            Operand::WideCounter(index) => Operand::WideCounter(self.index_plus(index, unit)),
            Operand::Digits(area, start, digits) => {
                Operand::Digits(area, self.index_plus(start, unit * 4 * u32::from(digits)), digits)
            }
        }
    }

    /// Reads an operand at the instruction's width as an I64: 16-bit words
    /// sign-extended, digit groups narrower than the width zero-extended.
    pub(super) fn read(&mut self, operand: &Operand, wide: bool) -> Value {
        match *operand {
            Operand::Constant(value) => self.b.constant(Type::I64, value),
            Operand::Word(area, index) if wide => {
                let low = self.b.push(Inst::LoadWord { area, index });
                let high_index = self.index_plus(index, 1);
                let high = self.b.push(Inst::LoadWord {
                    area,
                    index: high_index,
                });
                let low = self.b.extend(low, Type::I32, false);
                let high = self.b.extend(high, Type::I32, true);
                let sixteen = self.b.constant(Type::I32, 16);
                let high = self.b.binary(BinOp::Shl, high, sixteen);
                let joined = self.b.binary(BinOp::Or, high, low);
                self.b.extend(joined, Type::I64, true)
            }
            Operand::Word(area, index) => {
                let word = self.b.push(Inst::LoadWord { area, index });
                self.b.extend(word, Type::I64, true)
            }
            Operand::WideCounter(index) => {
                let value = self.b.push(Inst::LoadWideCounter { index });
                self.b.extend(value, Type::I64, true)
            }
            Operand::Digits(area, start, digits) => {
                let mut bits = self.b.constant(Type::I32, 0);
                for bit in 0..4 * u32::from(digits) {
                    let index = self.index_plus(start, bit);
                    let on = self.b.load_bit(area, index);
                    let on = self.b.extend(on, Type::I32, false);
                    let shift = self.b.constant(Type::I32, i64::from(bit));
                    let placed = self.b.binary(BinOp::Shl, on, shift);
                    bits = self.b.binary(BinOp::Or, bits, placed);
                }
                if wide {
                    self.b.extend(bits, Type::I64, true)
                } else {
                    let word = self.b.truncate(bits, Type::I16);
                    self.b.extend(word, Type::I64, true)
                }
            }
        }
    }

    /// Writes the low bits of an I64 that the operand holds.
    fn write(&mut self, operand: &Operand, wide: bool, value: Value) {
        match *operand {
            Operand::Constant(_) => {}
            Operand::Word(area, index) => {
                let low = self.b.truncate(value, Type::I16);
                self.b.effect(Inst::StoreWord {
                    area,
                    index,
                    value: low,
                });
                if wide {
                    let sixteen = self.b.constant(Type::I64, 16);
                    let high = self.b.binary(BinOp::Shr, value, sixteen);
                    let high = self.b.truncate(high, Type::I16);
                    let high_index = self.index_plus(index, 1);
                    self.b.effect(Inst::StoreWord {
                        area,
                        index: high_index,
                        value: high,
                    });
                }
            }
            Operand::WideCounter(index) => {
                let value = self.b.truncate(value, Type::I32);
                self.b.effect(Inst::StoreWideCounter { index, value });
            }
            Operand::Digits(area, start, digits) => {
                let one = self.b.constant(Type::I64, 1);
                let zero = self.b.constant(Type::I64, 0);
                for bit in 0..4 * u32::from(digits) {
                    let shift = self.b.constant(Type::I64, i64::from(bit));
                    let shifted = self.b.binary(BinOp::Shr, value, shift);
                    let masked = self.b.binary(BinOp::And, shifted, one);
                    let on = self.b.compare(CompareOp::Ne, masked, zero);
                    let index = self.index_plus(start, bit);
                    self.b.store_bit(area, index, on);
                }
            }
        }
    }

    /// An operand as the runtime's encoded place, for BMOV/FMOV.
    fn place(&mut self, operand: &Operand) -> PlaceArg {
        match *operand {
            Operand::Constant(value) => PlaceArg {
                kind: PLACE_CONSTANT,
                index: Index::Fixed(value as i32 as u32),
                digits: 0,
            },
            Operand::Word(area, index) => PlaceArg {
                kind: area as u32,
                index,
                digits: 0,
            },
            Operand::WideCounter(index) => PlaceArg {
                kind: PLACE_WIDE_COUNTER,
                index,
                digits: 0,
            },
            Operand::Digits(area, index, digits) => PlaceArg {
                kind: PLACE_DIGITS + area as u32,
                index,
                digits: u32::from(digits),
            },
        }
    }
}

fn word(operand: &DataOperand) -> WordRef {
    match operand {
        DataOperand::Word(word) => *word,
        DataOperand::Bits(_) => unreachable!("the checker gives word operands here"),
    }
}
