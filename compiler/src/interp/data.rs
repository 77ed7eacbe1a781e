//! Application (data) instructions. Every operand is resolved before anything
//! is written: an out-of-range operand records 4085H (read) or 4086H (write)
//! and the instruction does nothing else.

use super::access::{resolve_word, write_place, BitPlace};
use crate::isa::DataOp;
use crate::program::{BitRef, DataInstruction, DataOperand, WordRef};
use ladder_runtime::place::MAX_BLOCK_UNITS;
use ladder_runtime::special::{M_BORROW, M_CARRY, M_ZERO};
use ladder_runtime::{Memory, OperationError, Place};

/// Executes one data instruction whose condition is ON.
pub fn execute(mem: &mut Memory, data: &DataInstruction, line: u32) {
    if let Err(error) = try_execute(mem, data) {
        mem.record_error(error, line);
    }
}

fn word(operand: &DataOperand) -> WordRef {
    match operand {
        DataOperand::Word(word) => *word,
        DataOperand::Bits(_) => unreachable!("checker gives word operands here"),
    }
}

fn bits(operand: &DataOperand) -> BitRef {
    match operand {
        DataOperand::Bits(bits) => *bits,
        DataOperand::Word(_) => unreachable!("checker gives bit operands here"),
    }
}

/// Resolves a source of `units` values.
fn source(mem: &Memory, operand: &DataOperand, wide: bool, units: u32) -> Result<Place, OperationError> {
    resolve_word(mem, word(operand), wide, units).ok_or(OperationError::ReadOutOfRange)
}

/// Resolves a destination of `units` values.
fn destination(mem: &Memory, operand: &DataOperand, wide: bool, units: u32) -> Result<Place, OperationError> {
    resolve_word(mem, word(operand), wide, units).ok_or(OperationError::WriteOutOfRange)
}

/// A destination twice the width: two units, except a digit group, which
/// holds only its own bits.
fn double_destination(mem: &Memory, operand: &DataOperand, wide: bool) -> Result<Place, OperationError> {
    let units = if matches!(word(operand), WordRef::Digits(..)) {
        1
    } else {
        2
    };
    destination(mem, operand, wide, units)
}

/// The three result bits of CMP/ZCP. The checker made sure all three exist
/// for a fixed address; an offset one must fit too.
fn bit_triple(mem: &mut Memory, operand: &DataOperand) -> Result<[BitPlace; 3], OperationError> {
    let BitRef::Device(area, address) = bits(operand) else {
        unreachable!("checker gives Y/M/S devices here")
    };
    let start = super::access::effective_index(mem, address);
    if start < 0 || start + 3 > i64::from(area.count()) {
        return Err(OperationError::WriteOutOfRange);
    }
    let start = start as u32;
    Ok([0, 1, 2].map(|i| BitPlace::Device(area, start + i)))
}

fn try_execute(mem: &mut Memory, data: &DataInstruction) -> Result<(), OperationError> {
    let wide = data.wide;
    let ops = &data.operands;
    match data.op {
        DataOp::Mov => {
            let s = source(mem, &ops[0], wide, 1)?;
            let d = destination(mem, &ops[1], wide, 1)?;
            let value = s.read(mem, wide);
            d.write(mem, wide, i64::from(value));
        }
        DataOp::BlockMov | DataOp::FillMov => {
            let n_place = source(mem, &ops[2], false, 1)?;
            let n = n_place.read(mem, false);
            if !(1..=MAX_BLOCK_UNITS as i32).contains(&n) {
                return Err(OperationError::DataOutOfRange);
            }
            let n = n as u32;
            let fill = data.op == DataOp::FillMov;
            let s = source(mem, &ops[0], wide, if fill { 1 } else { n })?;
            let d = destination(mem, &ops[1], wide, n)?;
            // Read everything first: overlapping blocks move as a whole.
            let values: Vec<i32> = (0..n)
                .map(|i| s.nth(if fill { 0 } else { i }, wide).read(mem, wide))
                .collect();
            for (i, value) in values.into_iter().enumerate() {
                d.nth(i as u32, wide).write(mem, wide, i64::from(value));
            }
        }
        DataOp::Add | DataOp::Sub => {
            let a = source(mem, &ops[0], wide, 1)?;
            let b = source(mem, &ops[1], wide, 1)?;
            let d = destination(mem, &ops[2], wide, 1)?;
            let (a, b) = (i64::from(a.read(mem, wide)), i64::from(b.read(mem, wide)));
            let exact = if data.op == DataOp::Add { a + b } else { a - b };
            let (min, max) = if wide {
                (i64::from(i32::MIN), i64::from(i32::MAX))
            } else {
                (-32768, 32767)
            };
            let wrapped = if wide {
                i64::from(exact as i32)
            } else {
                i64::from(exact as i16)
            };
            d.write(mem, wide, wrapped);
            mem.m[M_ZERO as usize] = (wrapped == 0) as u8;
            mem.m[M_BORROW as usize] = (exact < min) as u8;
            mem.m[M_CARRY as usize] = (exact > max) as u8;
        }
        DataOp::Mul => {
            let a = source(mem, &ops[0], wide, 1)?;
            let b = source(mem, &ops[1], wide, 1)?;
            let d = double_destination(mem, &ops[2], wide)?;
            let product = i64::from(a.read(mem, wide)) * i64::from(b.read(mem, wide));
            // The low half here, the high half in the next unit; a digit
            // group holds only its own low bits.
            d.write(mem, wide, product);
            if !matches!(d, Place::Digits(..)) {
                d.nth(1, wide).write(mem, wide, product >> if wide { 32 } else { 16 });
            }
        }
        DataOp::Div => {
            let a = source(mem, &ops[0], wide, 1)?;
            let b = source(mem, &ops[1], wide, 1)?;
            let d = double_destination(mem, &ops[2], wide)?;
            let (a, b) = (i64::from(a.read(mem, wide)), i64::from(b.read(mem, wide)));
            if b == 0 {
                return Err(OperationError::DataOutOfRange);
            }
            // Truncation toward zero; MIN / -1 wraps like the hardware.
            let (quotient, remainder) = (a / b, a % b);
            d.write(mem, wide, quotient);
            if !matches!(d, Place::Digits(..)) {
                d.nth(1, wide).write(mem, wide, remainder);
            }
        }
        DataOp::Inc | DataOp::Dec => {
            let d = destination(mem, &ops[0], wide, 1)?;
            let step = if data.op == DataOp::Inc { 1 } else { -1 };
            let value = i64::from(d.read(mem, wide)) + step;
            d.write(mem, wide, value);
        }
        DataOp::Cmp => {
            let a = source(mem, &ops[0], wide, 1)?;
            let b = source(mem, &ops[1], wide, 1)?;
            let results = bit_triple(mem, &ops[2])?;
            let (a, b) = (a.read(mem, wide), b.read(mem, wide));
            write_three(mem, results, [a > b, a == b, a < b]);
        }
        DataOp::ZoneCmp => {
            let low = source(mem, &ops[0], wide, 1)?;
            let high = source(mem, &ops[1], wide, 1)?;
            let s = source(mem, &ops[2], wide, 1)?;
            let results = bit_triple(mem, &ops[3])?;
            let (low, s) = (low.read(mem, wide), s.read(mem, wide));
            // A reversed zone is read as the single value `low` (FX).
            let high = high.read(mem, wide).max(low);
            write_three(mem, results, [s < low, (low..=high).contains(&s), s > high]);
        }
    }
    Ok(())
}

fn write_three(mem: &mut Memory, places: [BitPlace; 3], values: [bool; 3]) {
    for (place, value) in places.into_iter().zip(values) {
        write_place(mem, place, value);
    }
}
