//! The bit-level operations against Rust's integer arithmetic (the
//! semantics constant folding and the interpreter use), on edge values and
//! on seeded random ones; and the AIGER writer's header and encoding.

use super::aig::{value_of, Aig, Lit};
use super::words::{self, Word};

/// A word of fresh inputs.
fn input_word(aig: &mut Aig, width: u32) -> Word {
    (0..width).map(|_| aig.input()).collect()
}

fn assign(values: &mut Vec<bool>, value: i64, width: u32) {
    for i in 0..width {
        values.push((value >> i) & 1 == 1);
    }
}

fn read(nodes: &[bool], word: &[Lit]) -> i64 {
    let mut value = 0i64;
    for (i, &bit) in word.iter().enumerate() {
        if value_of(nodes, bit) {
            value |= 1 << i;
        }
    }
    let shift = 64 - word.len();
    (value << shift) >> shift
}

fn wrap(value: i64, width: u32) -> i64 {
    let shift = 64 - width;
    (value << shift) >> shift
}

/// Values worth trying: the edges of the width, then seeded random ones.
fn samples(width: u32, seed: u64) -> Vec<i64> {
    let max = (1i64 << (width - 1)) - 1;
    let mut values = vec![0, 1, -1, 2, -2, max, -max - 1, max - 1, -max, 7, -7, 100, -100];
    let mut state = seed;
    for _ in 0..24 {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        values.push(wrap((z ^ (z >> 31)) as i64, width));
    }
    values
}

#[test]
fn word_operations_compute_as_the_integers_do() {
    for width in [16u32, 32] {
        let mut aig = Aig::new();
        let a = input_word(&mut aig, width);
        let b = input_word(&mut aig, width);
        let add = words::add(&mut aig, &a, &b);
        let sub = words::sub(&mut aig, &a, &b);
        let mul = words::mul(&mut aig, &a, &b);
        let (div, rem) = words::divide_signed(&mut aig, &a, &b);
        let shl = words::shift(&mut aig, &a, &b, true, false);
        let shr = words::shift(&mut aig, &a, &b, false, true);
        let ushr = words::shift(&mut aig, &a, &b, false, false);
        let less = words::less_signed(&mut aig, &a, &b);
        let equal = words::equal(&mut aig, &a, &b);
        let ones = words::pop_count(&mut aig, &a);
        let zeros = words::leading_zeros(&mut aig, &a);
        let seed = 0x5EED ^ u64::from(width);
        for &x in &samples(width, seed) {
            for &y in &samples(width, seed.rotate_left(7)) {
                let mut inputs = Vec::new();
                assign(&mut inputs, x, width);
                assign(&mut inputs, y, width);
                let nodes = aig.simulate(&inputs, &[]);
                let r = |w: &[Lit]| read(&nodes, w);
                let case = format!("width {width}: {x} and {y}");
                assert_eq!(r(&add), wrap(x.wrapping_add(y), width), "add, {case}");
                assert_eq!(r(&sub), wrap(x.wrapping_sub(y), width), "sub, {case}");
                assert_eq!(r(&mul), wrap(x.wrapping_mul(y), width), "mul, {case}");
                if y != 0 {
                    let (q, m) = if width == 16 {
                        let (x, y) = (x as i16, y as i16);
                        (i64::from(x.wrapping_div(y)), i64::from(x.wrapping_rem(y)))
                    } else {
                        let (x, y) = (x as i32, y as i32);
                        (i64::from(x.wrapping_div(y)), i64::from(x.wrapping_rem(y)))
                    };
                    assert_eq!(r(&div), q, "div, {case}");
                    assert_eq!(r(&rem), m, "rem, {case}");
                }
                let amount = (y as u32) % width;
                if amount == y as u32 {
                    let unsigned = (x as u64) & ((1u64 << width) - 1);
                    assert_eq!(r(&shl), wrap(x << amount, width), "shl, {case}");
                    assert_eq!(r(&shr), wrap(x >> amount, width), "shr, {case}");
                    assert_eq!(r(&ushr), wrap((unsigned >> amount) as i64, width), "ushr, {case}");
                }
                assert_eq!(value_of(&nodes, less), x < y, "less, {case}");
                assert_eq!(value_of(&nodes, equal), x == y, "equal, {case}");
                let bits = (x as u64) & ((1u64 << width) - 1);
                assert_eq!(r(&ones), i64::from(bits.count_ones()), "pop count, {case}");
                assert_eq!(
                    r(&zeros),
                    i64::from(bits.leading_zeros() - (64 - width)),
                    "leading zeros, {case}"
                );
            }
        }
    }
}

#[test]
fn gates_fold_constants_and_are_shared() {
    let mut aig = Aig::new();
    let x = aig.input();
    let y = aig.input();
    assert_eq!(aig.and(x, Lit::FALSE), Lit::FALSE);
    assert_eq!(aig.and(x, Lit::TRUE), x);
    assert_eq!(aig.and(x, !x), Lit::FALSE);
    let g = aig.and(x, y);
    assert_eq!(aig.and(y, x), g, "the same gate, hashed");
    assert_eq!(aig.mux(Lit::TRUE, x, y), x);
    let count = aig.nodes.len();
    aig.or(x, y);
    aig.or(x, y);
    assert_eq!(aig.nodes.len(), count + 1, "one OR gate, built twice");
}

#[test]
fn latches_step_from_their_initial_values() {
    // A two-bit counter that counts while its input is ON.
    let mut aig = Aig::new();
    let enable = aig.input();
    let counter: Word = (0..2).map(|_| aig.latch(false)).collect();
    let one = words::constant(1, 2);
    let plus = words::add(&mut aig, &counter, &one);
    let next = words::mux(&mut aig, enable, &plus, &counter);
    for (&l, &n) in counter.iter().zip(&next) {
        aig.set_next(l, n);
    }
    let mut state = vec![false, false];
    for (scan, on) in [true, false, true, true, true].into_iter().enumerate() {
        let nodes = aig.simulate(&[on], &state);
        state = aig.latches.iter().map(|l| value_of(&nodes, l.next)).collect();
        let value = u32::from(state[0]) + 2 * u32::from(state[1]);
        let want = [1, 1, 2, 3, 0][scan];
        assert_eq!(value, want, "after scan {}", scan + 1);
    }
}

#[test]
fn wide_constants_and_comparisons_keep_their_sign() {
    // Property comparisons are made wider than 64 bits.
    let width = 66;
    let mut aig = Aig::new();
    let a = input_word(&mut aig, 16);
    let wide = words::resize(&a, width, true);
    for (value, number) in [(0i64, -5i64), (-7, -5), (-3, -5), (100, -1), (-1, -1), (-32768, 32767)] {
        let n = words::constant(number, width);
        assert_eq!(
            words::constant_value(&n[..63]).map(|v| wrap(v, 63)),
            Some(wrap(number, 63))
        );
        let less = words::less_signed(&mut aig, &wide, &n);
        let equal = words::equal(&mut aig, &wide, &n);
        let mut inputs = Vec::new();
        assign(&mut inputs, value, 16);
        let nodes = aig.simulate(&inputs, &[]);
        assert_eq!(value_of(&nodes, less), value < number, "{value} < {number}");
        assert_eq!(value_of(&nodes, equal), value == number, "{value} == {number}");
    }
}
