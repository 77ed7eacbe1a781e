//! The transition system of one property as a binary AIGER file (the
//! format hardware model checkers read: ABC, nuXmv, IC3ref): inputs, then
//! latches, then AND gates, with one output that is ON in a bad state.
//! Only what the output depends on is written. AIGER 1.0 latches start at
//! 0, so a latch whose power-up value is 1 is written complemented.

use super::aig::{Lit, Node};
use super::system::System;

/// The file's bytes, with `input_names` (by input number) in its symbol
/// table where given.
pub fn write(system: &System, input_names: &[(u32, String)]) -> Vec<u8> {
    let aig = &system.aig;
    let cone = aig.cone(&[system.bad]);
    let mut number = vec![0u32; aig.nodes.len()];
    let mut complemented = vec![false; aig.nodes.len()];
    let mut next_var = 1u32;
    let mut inputs = Vec::new();
    for (n, node) in aig.nodes.iter().enumerate() {
        if let (true, Node::Input(i)) = (cone[n], node) {
            number[n] = next_var;
            next_var += 1;
            inputs.push(*i);
        }
    }
    let mut latches = Vec::new();
    for latch in &aig.latches {
        let n = latch.node as usize;
        if cone[n] {
            number[n] = next_var;
            complemented[n] = latch.init;
            next_var += 1;
            latches.push(*latch);
        }
    }
    let mut ands = Vec::new();
    for (n, node) in aig.nodes.iter().enumerate() {
        if let (true, Node::And(a, b)) = (cone[n], node) {
            number[n] = next_var;
            next_var += 1;
            ands.push((n, *a, *b));
        }
    }
    let map = |lit: Lit| -> u32 {
        let n = lit.node() as usize;
        if n == 0 {
            return lit.0 & 1;
        }
        2 * number[n] + (u32::from(lit.negated()) ^ u32::from(complemented[n]))
    };
    let max = next_var - 1;
    let mut out = format!("aig {max} {} {} 1 {}\n", inputs.len(), latches.len(), ands.len()).into_bytes();
    for latch in &latches {
        let next = map(latch.next) ^ u32::from(latch.init);
        out.extend(format!("{next}\n").as_bytes());
    }
    out.extend(format!("{}\n", map(system.bad)).as_bytes());
    for &(n, a, b) in &ands {
        let lhs = 2 * number[n];
        let (x, y) = (map(a), map(b));
        let (high, low) = if x >= y { (x, y) } else { (y, x) };
        leb128(&mut out, lhs - high);
        leb128(&mut out, high - low);
    }
    for (position, input) in inputs.iter().enumerate() {
        if let Some((_, name)) = input_names.iter().find(|(i, _)| i == input) {
            out.extend(format!("i{position} {name}\n").as_bytes());
        }
    }
    out.extend(b"o0 bad\nc\nwritten by ladderc verify: output 0 is ON after a scan that breaks the property\n");
    out
}

fn leb128(out: &mut Vec<u8>, mut value: u32) {
    while value >= 0x80 {
        out.push((value & 0x7f) as u8 | 0x80);
        value >>= 7;
    }
    out.push(value as u8);
}
