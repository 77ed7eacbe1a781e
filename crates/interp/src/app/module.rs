//! Special-function modules: FROM and TO move words between a unit's buffer
//! memory (`Un\Gm`, in the image) and the program's devices. A module's own
//! behaviour is the host's to simulate.

use super::{Outcome, Step};
use ladder_front::program::WordRef;
use ladder_runtime::device::{buffer_word, BUFFER_UNITS, BUFFER_WORDS_PER_UNIT};
use ladder_runtime::{OperationError, Place, WordArea};

/// The buffer words of unit `unit` from word `first`, `words` long;
/// `None` (4084H) outside unit 0-7 or past G32766.
fn buffer(unit: i64, first: i64, words: i64) -> Option<Place> {
    let fits = (0..i64::from(BUFFER_UNITS)).contains(&unit)
        && first >= 0
        && words >= 1
        && first + words <= i64::from(BUFFER_WORDS_PER_UNIT);
    fits.then(|| Place::Word(WordArea::Buffer, buffer_word(unit as u32, first as u32)))
}

/// FROM m1 m2 D n (`from` true) or TO m1 m2 S n: n units of the
/// instruction's width between buffer words m2.. of unit m1 and the
/// program's devices. n 1-32767.
pub fn transfer(step: &mut Step, m1: &WordRef, m2: &WordRef, other: &WordRef, n: &WordRef, from: bool) -> Outcome {
    let width = step.width;
    // DFROM/DTO read m1, m2 and n as pairs, as every operand of a D form.
    let unit = step.source_value(m1)?;
    let first = step.source_value(m2)?;
    let n = step.source_value(n)?;
    let Some(buffer) = buffer(unit, first, n * i64::from(width.words())) else {
        return Err(OperationError::DataOutOfRange);
    };
    let device = step.resolve(other, width, n as u32, !from);
    step.commit()?;
    let Some(device) = device else { return Ok(()) };
    let (source, destination) = if from { (buffer, device) } else { (device, buffer) };
    let values: Vec<i64> = (0..n as u32)
        .map(|unit| step.read_at(source.nth(unit, width), width))
        .collect();
    for (unit, value) in (0..).zip(values) {
        step.write_at(destination.nth(unit, width), width, value);
    }
    Ok(())
}
