//! Signed division by a constant as a multiplication, as C compilers do it
//! (Hacker's Delight, 2nd ed., 10-1). Without its optimiser Cranelift
//! emits `idiv` for every `sdiv` and `srem` (tens of cycles each); a timer
//! of 10 or 100 ms resolution divides its elapsed time at every scan, and
//! `DIV` with a K operand divides by a constant too.

use cranelift_codegen::ir::{types, InstBuilder, Value};
use cranelift_frontend::FunctionBuilder;

/// The multiplier and shift that divide by a constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Magic {
    /// As a `bits`-wide two's-complement number.
    multiplier: i64,
    shift: u32,
}

/// The magic numbers for dividing `bits`-wide signed numbers by `divisor`
/// (2 or more, below 2^(bits-1)).
fn magic(divisor: u64, bits: u32) -> Magic {
    let half = 1u128 << (bits - 1);
    let d = u128::from(divisor);
    let anc = half - 1 - half % d;
    let mut p = bits - 1;
    let (mut q1, mut r1) = (half / anc, half % anc);
    let (mut q2, mut r2) = (half / d, half % d);
    loop {
        p += 1;
        q1 *= 2;
        r1 *= 2;
        if r1 >= anc {
            q1 += 1;
            r1 -= anc;
        }
        q2 *= 2;
        r2 *= 2;
        if r2 >= d {
            q2 += 1;
            r2 -= d;
        }
        let delta = d - r2;
        if !(q1 < delta || (q1 == delta && r1 == 0)) {
            break;
        }
    }
    let m = q2 + 1;
    // Below 2^bits; at or above 2^(bits-1) it is negative in `bits`.
    let multiplier = if m >= half {
        m as i128 - (1i128 << bits)
    } else {
        m as i128
    };
    Magic {
        multiplier: multiplier as i64,
        shift: p - bits,
    }
}

/// The width of the types handled here.
fn bits(ty: types::Type) -> Option<u32> {
    match ty {
        types::I32 => Some(32),
        types::I64 => Some(64),
        _ => None,
    }
}

/// `n / divisor`, truncating, when the divisor is a constant it handles (2
/// or more, on `i32` and `i64`); `None` leaves the division to `sdiv`.
pub fn quotient(builder: &mut FunctionBuilder, n: Value, divisor: i64) -> Option<Value> {
    let ty = builder.func.dfg.value_type(n);
    let bits = bits(ty)?;
    if divisor < 2 || (bits == 32 && divisor > i64::from(i32::MAX)) {
        return None;
    }
    let Magic { multiplier, shift } = magic(divisor as u64, bits);
    let ins = builder.ins();
    let m = ins.iconst(ty, multiplier);
    let mut q = builder.ins().smulhi(n, m);
    if multiplier < 0 {
        q = builder.ins().iadd(q, n);
    }
    if shift > 0 {
        q = builder.ins().sshr_imm_s(q, i64::from(shift));
    }
    // Toward zero: one more for a negative quotient.
    let sign = builder.ins().ushr_imm_s(q, i64::from(bits - 1));
    Some(builder.ins().iadd(q, sign))
}

/// `n % divisor` (the dividend's sign), as `quotient` handles it.
pub fn remainder(builder: &mut FunctionBuilder, n: Value, divisor: i64) -> Option<Value> {
    let q = quotient(builder, n, divisor)?;
    let ty = builder.func.dfg.value_type(n);
    let d = builder.ins().iconst(ty, divisor);
    let product = builder.ins().imul(q, d);
    Some(builder.ins().isub(n, product))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The emitted sequence, evaluated in Rust.
    fn divide(n: i64, divisor: u64, bits: u32) -> i64 {
        let Magic { multiplier, shift } = magic(divisor, bits);
        let high = ((i128::from(n) * i128::from(multiplier)) >> bits) as i64;
        let mut q = if multiplier < 0 { high + n } else { high };
        q >>= shift;
        let sign = ((q as u64) >> 63) as i64;
        let sign = if bits == 32 { i64::from(q < 0) } else { sign };
        q + sign
    }

    #[test]
    fn matches_division_for_every_kind_of_divisor_and_dividend() {
        let mut divisors: Vec<u64> = (2..=1100).collect();
        for k in 1..63 {
            divisors.extend([(1u64 << k) - 1, 1 << k, (1 << k) + 1]);
        }
        divisors.extend([i32::MAX as u64, i64::MAX as u64, 641, 6_700_417, 274_177]);
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for bits in [32u32, 64] {
            let (min, max) = if bits == 32 {
                (i64::from(i32::MIN), i64::from(i32::MAX))
            } else {
                (i64::MIN, i64::MAX)
            };
            for &d in divisors.iter().filter(|&&d| d >= 2 && d as i128 <= max as i128) {
                let mut dividends = vec![0, 1, -1, min, min + 1, max, max - 1, d as i64, -(d as i64)];
                dividends.extend([(d as i64).wrapping_sub(1), 1 - d as i64, (d as i64).wrapping_add(1)]);
                for _ in 0..64 {
                    let n = next() as i64;
                    dividends.push(if bits == 32 { i64::from(n as i32) } else { n });
                    dividends.push(if bits == 32 {
                        i64::from((n % 100_000) as i32)
                    } else {
                        n % 100_000
                    });
                }
                for n in dividends.into_iter().filter(|n| (min..=max).contains(n)) {
                    assert_eq!(divide(n, d, bits), n / d as i64, "{n} / {d} in {bits} bits");
                }
            }
        }
    }
}
