//! Conversions: SWAP, ENCO, DECO, BTOW, WTOB, DIS, UNI, BCD, BIN.

use super::{Outcome, Step};
use ladder_front::program::{Element, WordRef};
use ladder_runtime::{OperationError, Place, Width};

/// The high and low byte of each 16-bit word change places.
pub fn swap(d: i64, width: Width) -> i64 {
    let words = match width {
        Width::Single => 1,
        Width::Double => 2,
    };
    (0..words).fold(0, |swapped, word| {
        let value = (d >> (16 * word)) & 0xFFFF;
        let turned = ((value & 0xFF) << 8) | (value >> 8);
        swapped | (turned << (16 * word))
    })
}

/// How many bits an element run may have: 2^8 for bit devices, 2^4 (one
/// word) for words.
fn exponent_limit(element: &Element) -> i64 {
    match element {
        Element::Bits(_) => 8,
        Element::Word(_) => 4,
    }
}

/// Where an element run starts, and whether it could be resolved: `units`
/// bits from a bit device, or a 16-bit word.
fn element_place(step: &mut Step, element: &Element, units: u32, read: bool) -> Option<Place> {
    match element {
        Element::Bits(bit) => step.bits(bit, units, read),
        Element::Word(word) => step.resolve(word, Width::Single, 1, read),
    }
}

/// The value of `count` bits of an element: bit devices one by one from the
/// start, or the low bits of a word.
fn element_bits(step: &Step, element: &Element, place: Place, count: u32) -> Vec<bool> {
    match element {
        Element::Bits(_) => (0..count)
            .map(|unit| step.read_at(place.nth(unit, Width::Single), Width::Single) != 0)
            .collect(),
        Element::Word(_) => {
            let word = step.read_at(place, Width::Single);
            (0..count).map(|bit| (word >> bit) & 1 != 0).collect()
        }
    }
}

/// ENCO S N D: of the 2^N bits from S, the number of the highest ON one.
/// N = 0 does nothing; N outside 1-8 (bit devices) or 1-4 (words), or no ON
/// bit, is 4084H.
pub fn encode(step: &mut Step, s: &Element, n: &WordRef, d: &WordRef) -> Outcome {
    let n = step.count_value(n)?;
    if n == 0 {
        return Ok(());
    }
    if !(1..=exponent_limit(s)).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let bits = 1u32 << n;
    let source = element_place(step, s, bits, true);
    let destination = step.destination(d);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let on = element_bits(step, s, source, bits);
    let highest = on.iter().rposition(|&b| b).ok_or(OperationError::DataOutOfRange)?;
    step.write(destination, highest as i64);
    Ok(())
}

/// DECO S N D: of the 2^N bits from D, the one numbered by the low N bits of
/// S turns ON and the others OFF (a word D is written whole). N = 0 does
/// nothing; N outside 1-8 (bit devices) or 1-4 (a word) is 4084H.
pub fn decode(step: &mut Step, s: &Element, n: &WordRef, d: &Element) -> Outcome {
    let n = step.count_value(n)?;
    if n == 0 {
        return Ok(());
    }
    if !(1..=exponent_limit(d)).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    let n = n as u32;
    let outputs = match d {
        Element::Bits(_) => 1u32 << n,
        Element::Word(_) => 16,
    };
    let source = element_place(step, s, n, true);
    let destination = element_place(step, d, outputs, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let number = element_bits(step, s, source, n)
        .iter()
        .enumerate()
        .fold(0u32, |value, (bit, &on)| value | (u32::from(on) << bit));
    match d {
        Element::Bits(_) => {
            for unit in 0..outputs {
                step.write(destination.nth(unit, Width::Single), i64::from(unit == number));
            }
        }
        Element::Word(_) => step.write(destination, 1 << number),
    }
    Ok(())
}

/// BTOW (`split` false): the low bytes of N words from S, two to a word
/// from D (low byte first; an odd last byte gets a high byte of 0). WTOB
/// (`split` true): N bytes of the words from S, low byte first, into N words
/// from D (high bytes 0). N = 0 does nothing; N < 0 is 4084H. Everything is
/// read before anything is written, so overlapping ranges are fine.
pub fn bytes(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef, split: bool) -> Outcome {
    let n = step.count_value(n)?;
    if n < 0 {
        return Err(OperationError::DataOutOfRange);
    }
    if n == 0 {
        return Ok(());
    }
    let n = n as u32;
    let words = n.div_ceil(2);
    let (inputs, outputs) = if split { (words, n) } else { (n, words) };
    let source = step.resolve(s, Width::Single, inputs, true);
    let destination = step.resolve(d, Width::Single, outputs, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let input: Vec<i64> = (0..inputs).map(|i| step.read(source.nth(i, Width::Single))).collect();
    let output: Vec<i64> = if split {
        (0..n as usize)
            .map(|j| (input[j / 2] >> (8 * (j % 2))) & 0xFF)
            .collect()
    } else {
        (0..words as usize)
            .map(|i| {
                let low = input[2 * i] & 0xFF;
                let high = input.get(2 * i + 1).map_or(0, |w| w & 0xFF);
                low | (high << 8)
            })
            .collect()
    };
    for (unit, value) in (0..).zip(output) {
        step.write(destination.nth(unit, Width::Single), value);
    }
    Ok(())
}

/// The count of DIS and UNI: 0-4, else 4084H.
fn nibble_count(step: &mut Step, n: &WordRef) -> Result<u32, OperationError> {
    let n = step.count_value(n)?;
    if !(0..=4).contains(&n) {
        return Err(OperationError::DataOutOfRange);
    }
    Ok(n as u32)
}

/// DIS S D N: 4-bit digit k of S into word D+k, for k below N (N = 0 does
/// nothing).
pub fn distribute(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = nibble_count(step, n)?;
    if n == 0 {
        return Ok(());
    }
    let source = step.source(s);
    let destination = step.resolve(d, Width::Single, n, false);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let value = step.read(source);
    for k in 0..n {
        step.write(destination.nth(k, Width::Single), (value >> (4 * k)) & 0xF);
    }
    Ok(())
}

/// UNI S D N: the low 4 bits of word S+k as digit k of D, for k below N;
/// the digits above are 0 (N = 0 does nothing).
pub fn unite(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) -> Outcome {
    let n = nibble_count(step, n)?;
    if n == 0 {
        return Ok(());
    }
    let source = step.resolve(s, Width::Single, n, true);
    let destination = step.destination(d);
    step.commit()?;
    let (Some(source), Some(destination)) = (source, destination) else {
        return Ok(());
    };
    let value = (0..n).fold(0, |value, k| {
        value | ((step.read(source.nth(k, Width::Single)) & 0xF) << (4 * k))
    });
    step.write(destination, value);
    Ok(())
}

/// The largest value BCD converts: 4 or 8 decimal digits.
fn bcd_limit(width: Width) -> i64 {
    match width {
        Width::Single => 9_999,
        Width::Double => 99_999_999,
    }
}

/// BCD S D: binary to BCD; S outside 0..=9999 (99999999) is 4084H.
pub fn bcd([s]: [i64; 1], width: Width) -> Result<i64, OperationError> {
    if !(0..=bcd_limit(width)).contains(&s) {
        return Err(OperationError::DataOutOfRange);
    }
    let digits = s.to_string();
    Ok(digits
        .bytes()
        .fold(0, |bcd, digit| (bcd << 4) | i64::from(digit - b'0')))
}

/// BIN S D: BCD to binary; a 4-bit digit above 9 is 4084H.
pub fn bin([s]: [i64; 1], width: Width) -> Result<i64, OperationError> {
    let bits = s as u64 & (u64::MAX >> (64 - width.bits()));
    let mut value = 0;
    for position in (0..width.bits() / 4).rev() {
        let digit = (bits >> (4 * position)) & 0xF;
        if digit > 9 {
            return Err(OperationError::DataOutOfRange);
        }
        value = value * 10 + digit as i64;
    }
    Ok(value)
}
