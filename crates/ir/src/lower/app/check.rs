//! Check codes: BCC, CRC, through the runtime's helpers.

use super::Step;
use crate::lower::operand::Units;
use crate::{BinOp, Index, Type, Value};
use ladder_front::program::WordRef;
use ladder_runtime::helpers::Helper;
use ladder_runtime::special::SM_EIGHT_BIT_MODE;
use ladder_runtime::Width;

/// The words that hold `bytes` (an I32) bytes: one each in 8-bit mode
/// (SM161), two each otherwise.
fn words_for(step: &mut Step, bytes: Value) -> Value {
    let eight_bit = step
        .b()
        .load_bit(SM_EIGHT_BIT_MODE.area, Index::Fixed(SM_EIGHT_BIT_MODE.number));
    let b = step.b();
    let one = b.constant(Type::I32, 1);
    let rounded = b.binary(BinOp::Add, bytes, one);
    let pairs = b.binary(BinOp::Shr, rounded, one);
    b.select(eight_bit, bytes, pairs)
}

/// BCC S1 S2 S3 D: S1 outside 0-2 or S3 outside 0-32767 records 4084H.
pub fn block_check(step: &mut Step, s1: &WordRef, s2: &WordRef, s3: &WordRef, d: &WordRef) {
    let method = step.count(s1);
    let count = step.count(s3);
    step.commit();
    let method = step.read_at(&method, Width::Single);
    let count = step.read_at(&count, Width::Single);
    step.require_within(method, 0, 2);
    step.require_within(count, 0, i64::from(i16::MAX));
    let count = step.b().truncate(count, Type::I32);
    let words = words_for(step, count);
    let source = step.resolve(s2, Width::Single, Units::Dynamic(words), true);
    let destination = step.destination(d);
    step.commit();
    let method = step.b().truncate(method, Type::I32);
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    step.b()
        .call(Helper::BlockCheck, vec![method, source, count, destination]);
}

/// CRC S D N: N outside 1-256 records 4084H; in 8-bit mode D is two words.
pub fn crc(step: &mut Step, s: &WordRef, d: &WordRef, n: &WordRef) {
    let count = step.count_value(n);
    step.require_within(count, 1, 256);
    let count = step.b().truncate(count, Type::I32);
    let words = words_for(step, count);
    let source = step.resolve(s, Width::Single, Units::Dynamic(words), true);
    let eight_bit = step
        .b()
        .load_bit(SM_EIGHT_BIT_MODE.area, Index::Fixed(SM_EIGHT_BIT_MODE.number));
    let b = step.b();
    let two = b.constant(Type::I32, 2);
    let one = b.constant(Type::I32, 1);
    let units = b.select(eight_bit, two, one);
    let destination = step.resolve(d, Width::Single, Units::Dynamic(units), false);
    step.commit();
    let (source, destination) = (step.l.place(&source), step.l.place(&destination));
    step.b().call(Helper::Crc, vec![source, count, destination]);
}
