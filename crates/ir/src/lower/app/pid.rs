//! PID in the lowering: the operands are resolved and checked here; the
//! velocity form runs in the runtime's helper, which records its own
//! parameter errors (6730H ...) against the instruction's line.

use super::{Execution, Step};
use crate::Type;
use ladder_front::program::WordRef;
use ladder_runtime::helpers::Helper;
use ladder_runtime::Width;

/// PID S1 S2 S3 D (every scan).
pub fn pid(step: &mut Step, run: &Execution, s1: &WordRef, s2: &WordRef, s3: &WordRef, d: &WordRef) {
    let off = step.b().not(run.power);
    step.when(off, |step| {
        let instance = step.b().number(run.job);
        step.b().call(Helper::InstanceOff, vec![instance]);
    });
    step.skip_unless(run.power);
    let sv = step.count(s1);
    let pv = step.count(s2);
    let block_words = step.run_of(25);
    let block = step.resolve(s3, Width::Single, block_words, true);
    let mv = step.destination(d);
    step.commit();
    let sv = step.read_at(&sv, Width::Single);
    let sv = step.b().truncate(sv, Type::I32);
    let pv = step.read_at(&pv, Width::Single);
    let pv = step.b().truncate(pv, Type::I32);
    let (block, mv) = (step.l.place(&block), step.l.place(&mv));
    let instance = step.b().number(run.job);
    let line = step.line;
    let line = step.b().number(line);
    step.b().call(Helper::Pid, vec![instance, sv, pv, block, mv, line]);
}
