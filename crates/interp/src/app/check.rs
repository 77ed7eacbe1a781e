//! Check codes: BCC, CRC.

use super::{Outcome, Step};
use ladder_front::program::WordRef;
use ladder_runtime::special::SM_EIGHT_BIT_MODE;
use ladder_runtime::{OperationError, Place, Width};

/// In 8-bit mode (SM161 ON) each word holds one byte (its low byte);
/// otherwise two, low byte first.
fn eight_bit(step: &Step) -> bool {
    step.mem.sm[SM_EIGHT_BIT_MODE.number as usize] != 0
}

/// The words that hold `bytes` bytes.
fn words_for(bytes: u32, eight_bit: bool) -> u32 {
    if eight_bit {
        bytes
    } else {
        bytes.div_ceil(2)
    }
}

fn bytes_from(step: &Step, start: Place, bytes: u32, eight_bit: bool) -> Vec<u8> {
    (0..bytes)
        .map(|k| {
            let (unit, shift) = if eight_bit { (k, 0) } else { (k / 2, 8 * (k % 2)) };
            (step.read_at(start.nth(unit, Width::Single), Width::Single) >> shift) as u8
        })
        .collect()
}

/// BCC S1 S2 S3 D: the block check code of S3 bytes from S2 by method S1
/// (0 the sum, 1 zero minus the sum, 2 the exclusive OR) into the low byte of
/// D; D's high byte stays. S1 outside 0-2 or S3 outside 0-32767 is 4084H.
pub fn block_check(step: &mut Step, s1: &WordRef, s2: &WordRef, s3: &WordRef, d: &WordRef) -> Outcome {
    let method = step.count(s1);
    let count = step.count(s3);
    step.commit()?;
    let [method, count] = [method, count].map(|place| place.map_or(0, |p| step.read_at(p, Width::Single)));
    if !(0..=2).contains(&method) || count < 0 {
        return Err(OperationError::DataOutOfRange);
    }
    let (count, eight_bit) = (count as u32, eight_bit(step));
    let source = step.resolve(s2, Width::Single, words_for(count, eight_bit), true);
    let destination = step.destination(d);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let bytes = bytes_from(step, source, count, eight_bit);
    let sum = bytes.iter().fold(0u32, |sum, &b| sum + u32::from(b));
    let code = match method {
        0 => sum,
        1 => 0u32.wrapping_sub(sum),
        _ => bytes.iter().fold(0u32, |code, &b| code ^ u32::from(b)),
    } & 0xFF;
    let high = step.read(destination) & !0xFF;
    step.write(destination, high | i64::from(code));
    Ok(())
}

/// CRC S D N: the CRC-16 of N bytes from S with the generator polynomial
/// X16+X15+X2+1, reflected, starting from FFFFH (CRC-16/MODBUS). In 16-bit
/// mode D holds the CRC; in 8-bit mode D its low byte and D+1 its high byte.
/// N outside 1-256 is 4084H.
pub fn crc(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let count = step.count_value(n)?;
    if !(1..=256).contains(&count) {
        return Err(OperationError::DataOutOfRange);
    }
    let (count, eight_bit) = (count as u32, eight_bit(step));
    let source = step.resolve(s, Width::Single, words_for(count, eight_bit), true);
    let destination = step.resolve(d, Width::Single, if eight_bit { 2 } else { 1 }, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let mut crc: u16 = 0xFFFF;
    for byte in bytes_from(step, source, count, eight_bit) {
        crc ^= u16::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xA001 } else { crc >> 1 };
        }
    }
    if eight_bit {
        step.write(destination, i64::from(crc & 0xFF));
        step.write(destination.nth(1, Width::Single), i64::from(crc >> 8));
    } else {
        step.write(destination, i64::from(crc));
    }
    Ok(())
}
