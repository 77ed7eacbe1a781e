//! The compact footprint of single instructions: what a declared reach
//! holds, and that a count known only at run time still holds the area.

use super::compact_layout;
use ladder_front::check::compile_source;

use ladder_front::source::SourceFile;
use ladder_runtime::layout::{Array, Layout};

fn layout(text: &str) -> Layout {
    let (program, diagnostics) = compile_source(&SourceFile::new("t.il", text));
    let program = program.unwrap_or_else(|| panic!("{text}: {diagnostics:?}"));
    compact_layout(&program, &crate::lower_and_optimize(&program), &[])
}

/// The devices of `array` the layout holds among `numbers`.
fn held(layout: &Layout, array: Array, numbers: impl IntoIterator<Item = u32>) -> Vec<u32> {
    numbers
        .into_iter()
        .filter(|&n| layout.offset(array, n).is_some())
        .collect()
}

#[test]
fn a_block_move_holds_its_runs_not_the_area() {
    let image = layout("LD X0\nBMOV D300 D310 K5\n");
    assert_eq!(held(&image, Array::D, 298..318), (300..315).collect::<Vec<_>>());
    assert_eq!(held(&image, Array::D, [0, 7999]), Vec::<u32>::new());
    // 32-bit units, digit groups.
    let image = layout("LD X0\nDFMOV K1 D300 K3\nFMOV K0 K2M100 K2\n");
    assert_eq!(held(&image, Array::D, 299..308), (300..306).collect::<Vec<_>>());
    assert_eq!(held(&image, Array::M, 99..118), (100..116).collect::<Vec<_>>());
}

#[test]
fn a_count_read_at_run_time_holds_the_whole_area() {
    let image = layout("LD X0\nBMOV D300 D310 D1\n");
    assert_eq!(held(&image, Array::D, [0, 300, 4000, 7999]), vec![0, 300, 4000, 7999]);
    let image = layout("LD X0\nTO K0 K0 D300 D1\n");
    assert_eq!(held(&image, Array::D, [0, 300, 7999]), vec![0, 300, 7999]);
}

#[test]
fn fixed_reaches_hold_their_words() {
    let image = layout("LD X0\nTRD D300\n");
    assert_eq!(held(&image, Array::D, 299..309), (300..307).collect::<Vec<_>>());
    let image = layout("LD X0\nPID D10 D11 D400 D12\n");
    assert_eq!(held(&image, Array::D, [9, 10, 424, 425]), vec![10, 424]);
}

/// Reads and writes past the operand's own unit that the kind alone
/// missed: TO's source run, SEGL's second set, CRC's pair under M8161.
#[test]
fn reaches_beyond_a_single_operand_are_held() {
    let image = layout("LD X0\nTO K0 K0 D300 K4\n");
    assert_eq!(held(&image, Array::D, 300..305), vec![300, 301, 302, 303]);
    let image = layout("LD X0\nSEGL D300 Y0 K4\n");
    assert_eq!(held(&image, Array::D, 300..302), vec![300, 301]);
    assert_eq!(held(&image, Array::Y, 0..13), (0..12).collect::<Vec<_>>());
    let image = layout("LD X0\nCRC D300 D310 K2\n");
    assert_eq!(held(&image, Array::D, [300, 301, 310, 311]), vec![300, 301, 310, 311]);
}

#[test]
fn bit_runs_count_bits() {
    // One run per segment: M100 to M215, not the rest of M.
    let image = layout("LD X0\nSFTL M100 M200 K16 K4\n");
    assert_eq!(held(&image, Array::M, [99, 100, 215, 216, 8000]), vec![100, 215]);
    let image = layout("LD X0\nSFTL X0 Y0 K16 K4\n");
    assert_eq!(held(&image, Array::Y, [0, 15, 16]), vec![0, 15]);
    let image = layout("LD X0\nALT M100\n");
    assert_eq!(held(&image, Array::M, 99..102), vec![100]);
    // DECO's compiled code turns ON one bit by a run-time index: all of M,
    // in one piece, whatever the declaration says.
    let image = layout("LD X0\nDECO D300 K3 M200\n");
    assert_eq!(held(&image, Array::M, [0, 200, 8511]), vec![0, 200, 8511]);
    let image = layout("LD X0\nENCO M100 K4 D301\n");
    assert_eq!(held(&image, Array::M, 99..117), (100..116).collect::<Vec<_>>());
    // A word in a bit-or-word position is the word, whatever N.
    let image = layout("LD X0\nDECO D300 D302 D301\n");
    assert_eq!(held(&image, Array::D, 299..304), vec![300, 301, 302]);
}

/// Setting the clock with MOV while M8015 is ON, as on an FX: the calendar
/// reads all of D8013-D8019 when M8015 turns OFF.
#[test]
fn one_clock_register_holds_the_clock_block() {
    let image = layout("LD X0\nOUT M8015\nLD X1\nMOV K5 D8016\n");
    assert_eq!(held(&image, Array::D, 8013..8020), (8013..8020).collect::<Vec<_>>());
    assert_eq!(held(&image, Array::M, 8015..8020), (8015..8020).collect::<Vec<_>>());
    let image = layout("LD X0\nOUT Y0\n");
    assert_eq!(held(&image, Array::D, 8013..8020), Vec::<u32>::new());
}

#[test]
fn a_zone_of_word_bits_holds_the_words_between_across_segments() {
    let image = layout("LD X0\nZSET D7998.0 D8001.F\n");
    // (D8000 up holds D8067 and D8069, the operation error, too.)
    assert_eq!(held(&image, Array::D, 7996..8002), (7998..8002).collect::<Vec<_>>());
}

/// A run of 32-bit counters with a large constant count ends at the last
/// counter (found by the differential test: the footprint walked toward
/// u32::MAX and overflowed).
#[test]
fn a_long_run_of_counters_ends_at_the_last_counter() {
    let image = layout("LD X0\nDFMOV K1 C200 K32767\nLD X1\nDSORT2 C200 K2147483647 K2147483647 D0 K1\n");
    assert_eq!(held(&image, Array::WideCounterValue, [200, 255]), vec![200, 255]);
}

/// A bit run of 2^n from a word bit with n past 31 (DECO refuses it at run
/// time) holds the word area, without overflowing on the way.
#[test]
fn a_huge_run_of_word_bits_holds_the_words() {
    let image = layout("LD X0\nDECO D0 K40 D1.1\n");
    assert_eq!(held(&image, Array::D, [1, 7999]), vec![1, 7999]);
}

/// The machine parts an instruction declares (`machine [...]`), and only
/// those: TRD and TWR hold the clock, the time arithmetic of the same
/// family does not; pulse outputs hold their channel state without the
/// input counting of the high-speed counters.
#[test]
fn declared_machine_parts_are_held_and_only_they() {
    let clock: Vec<u32> = (8013..8020).collect();
    for program in ["LD X0\nTRD D300\n", "LD X0\nTWR D300\n"] {
        assert_eq!(held(&layout(program), Array::D, 8013..8020), clock, "{program}");
    }
    for program in ["LD X0\nTCMP K1 K2 K3 D300 M0\n", "LD X0\nHTOS D300 D310\n"] {
        assert_eq!(
            held(&layout(program), Array::D, 8013..8020),
            Vec::<u32>::new(),
            "{program}"
        );
    }
    let pulses = layout("LD X0\nPLSY K100 K10 Y0\n");
    assert!(pulses.whole(Array::PulseOwner).is_some());
    assert_eq!(held(&pulses, Array::M, [8029]), vec![8029]);
    assert!(pulses.whole(Array::InputEdges).is_none());
    let speed = layout("LD X0\nSPD X1 K100 D300\n");
    assert!(speed.whole(Array::InputEdges).is_some());
    assert!(speed.whole(Array::PulseOwner).is_none());
}
