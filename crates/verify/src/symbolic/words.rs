//! Words as vectors of literals (bit 0 first) and the integer operations
//! of the IR on them: two's-complement arithmetic that wraps as the PLC's
//! does, signed comparisons, shifts by the low bits of the amount (as
//! machine code does), and signed division truncating toward zero.

use super::aig::{Aig, Lit};

pub type Word = Vec<Lit>;

/// `value` in `width` bits: its low bits, sign-extended past 64.
pub fn constant(value: i64, width: u32) -> Word {
    (0..width)
        .map(|i| Lit::constant((value >> i.min(63)) & 1 == 1))
        .collect()
}

/// Its value when every bit is a constant.
pub fn constant_value(word: &[Lit]) -> Option<i64> {
    let mut value = 0i64;
    for (i, &bit) in word.iter().enumerate() {
        if bit == Lit::TRUE {
            value |= 1 << i;
        } else if bit != Lit::FALSE {
            return None;
        }
    }
    Some(value)
}

/// `word` to `width` bits: sign- or zero-extended, or truncated.
pub fn resize(word: &[Lit], width: u32, signed: bool) -> Word {
    let fill = if signed {
        word.last().copied().unwrap_or(Lit::FALSE)
    } else {
        Lit::FALSE
    };
    (0..width as usize)
        .map(|i| word.get(i).copied().unwrap_or(fill))
        .collect()
}

pub fn bitwise(a: &[Lit], b: &[Lit], mut op: impl FnMut(Lit, Lit) -> Lit) -> Word {
    a.iter().zip(b).map(|(&x, &y)| op(x, y)).collect()
}

pub fn mux(aig: &mut Aig, condition: Lit, if_true: &[Lit], if_false: &[Lit]) -> Word {
    if_true
        .iter()
        .zip(if_false)
        .map(|(&t, &f)| aig.mux(condition, t, f))
        .collect()
}

/// `a + b + carry`, wrapped to the width of `a`, and the carry out.
pub fn add_carry(aig: &mut Aig, a: &[Lit], b: &[Lit], carry: Lit) -> (Word, Lit) {
    let mut carry = carry;
    let mut sum = Vec::with_capacity(a.len());
    for (&x, &y) in a.iter().zip(b) {
        let half = aig.xor(x, y);
        sum.push(aig.xor(half, carry));
        let both = aig.and(x, y);
        let through = aig.and(half, carry);
        carry = aig.or(both, through);
    }
    (sum, carry)
}

pub fn add(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> Word {
    add_carry(aig, a, b, Lit::FALSE).0
}

pub fn sub(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> Word {
    let nb: Word = b.iter().map(|&l| !l).collect();
    add_carry(aig, a, &nb, Lit::TRUE).0
}

pub fn neg(aig: &mut Aig, a: &[Lit]) -> Word {
    let zero = constant(0, a.len() as u32);
    sub(aig, &zero, a)
}

/// The low bits of `a * b` (the same for signed and unsigned).
pub fn mul(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> Word {
    let width = a.len();
    let mut product = constant(0, width as u32);
    for (i, &bit) in b.iter().enumerate() {
        if bit == Lit::FALSE {
            continue;
        }
        let mut partial = vec![Lit::FALSE; width];
        for j in 0..width - i.min(width) {
            partial[i + j] = aig.and(a[j], bit);
        }
        product = add(aig, &product, &partial);
    }
    product
}

/// Unsigned quotient and remainder (the divisor is never zero).
pub fn divide_unsigned(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> (Word, Word) {
    let width = a.len();
    let divisor = resize(b, width as u32 + 1, false);
    let mut remainder = constant(0, width as u32 + 1);
    let mut quotient = vec![Lit::FALSE; width];
    for i in (0..width).rev() {
        // remainder = remainder * 2 + a[i]
        remainder.pop();
        remainder.insert(0, a[i]);
        let (difference, no_borrow) = {
            let nd: Word = divisor.iter().map(|&l| !l).collect();
            add_carry(aig, &remainder, &nd, Lit::TRUE)
        };
        quotient[i] = no_borrow;
        remainder = mux(aig, no_borrow, &difference, &remainder);
    }
    remainder.pop();
    (quotient, remainder)
}

/// Signed quotient (toward zero) and remainder (the dividend's sign),
/// wrapping as `wrapping_div` does for the lowest number by -1.
pub fn divide_signed(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> (Word, Word) {
    let (sa, sb) = (a[a.len() - 1], b[b.len() - 1]);
    let na = neg(aig, a);
    let nb = neg(aig, b);
    let abs_a = mux(aig, sa, &na, a);
    let abs_b = mux(aig, sb, &nb, b);
    let (q, r) = divide_unsigned(aig, &abs_a, &abs_b);
    let q_negative = aig.xor(sa, sb);
    let nq = neg(aig, &q);
    let nr = neg(aig, &r);
    (mux(aig, q_negative, &nq, &q), mux(aig, sa, &nr, &r))
}

/// Shift by the amount's low bits (modulo the width, as machine code
/// shifts): left, arithmetic right or logical right.
pub fn shift(aig: &mut Aig, a: &[Lit], amount: &[Lit], left: bool, arithmetic: bool) -> Word {
    let width = a.len();
    let fill = if arithmetic { a[width - 1] } else { Lit::FALSE };
    let mut value = a.to_vec();
    let mut step = 1usize;
    for &bit in amount {
        if step >= width {
            break;
        }
        let shifted: Word = (0..width)
            .map(|i| {
                if left {
                    if i >= step {
                        value[i - step]
                    } else {
                        Lit::FALSE
                    }
                } else if i + step < width {
                    value[i + step]
                } else {
                    fill
                }
            })
            .collect();
        value = mux(aig, bit, &shifted, &value);
        step *= 2;
    }
    value
}

pub fn equal(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> Lit {
    let bits: Vec<Lit> = a.iter().zip(b).map(|(&x, &y)| aig.iff(x, y)).collect();
    aig.and_all(bits)
}

/// `a < b`, signed.
pub fn less_signed(aig: &mut Aig, a: &[Lit], b: &[Lit]) -> Lit {
    let width = a.len() as u32 + 1;
    let difference = sub(aig, &resize(a, width, true), &resize(b, width, true));
    difference[difference.len() - 1]
}

/// The number of one bits, as a word of `a`'s width.
pub fn pop_count(aig: &mut Aig, a: &[Lit]) -> Word {
    let width = a.len() as u32;
    let mut total = constant(0, width);
    for &bit in a {
        let mut one = constant(0, width);
        one[0] = bit;
        total = add(aig, &total, &one);
    }
    total
}

/// The number of leading zero bits, as a word of `a`'s width.
pub fn leading_zeros(aig: &mut Aig, a: &[Lit]) -> Word {
    let width = a.len() as u32;
    // From the lowest bit up: the count is width - 1 - i for the highest
    // one bit i, width when there is none.
    let mut count = constant(i64::from(width), width);
    for (i, &bit) in a.iter().enumerate() {
        let here = constant(i64::from(width) - 1 - i as i64, width);
        count = mux(aig, bit, &here, &count);
    }
    count
}
