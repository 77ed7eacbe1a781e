//! The C API as a C host calls it.

use super::*;

#[test]
fn device_kinds_round_trip() {
    for kind in 0..12 {
        for number in [0, 199, 200, 255] {
            let Some(device) = basic_device(kind, number) else {
                panic!("kind {kind}")
            };
            assert_eq!(c_device(device), (c_device(device).0, number));
            assert_eq!(c_device(device).0 as u32, kind);
        }
    }
    for kind in [LadderDevice::V, LadderDevice::Z] {
        for number in 0..INDEX_REGISTER_COUNT {
            let device = basic_device(kind as u32, number).expect("an index register");
            assert_eq!(c_device(device), (kind, number));
        }
    }
    assert_eq!(
        basic_device(12, 3),
        Some(Basic::Word(WordArea::Index, 7)),
        "V3 is word 7"
    );
    assert_eq!(
        basic_device(13, 3),
        Some(Basic::Word(WordArea::Index, 6)),
        "Z3 is word 6"
    );
    let mut mem = Memory::new_boxed();
    let past_z7 = basic_device(13, 8).expect("a device kind");
    assert!(mem.write_basic(past_z7, 1).is_err(), "Z8 does not exist");
    assert_eq!(
        basic_device(14, 32_767 + 10),
        Some(Basic::Word(WordArea::Buffer, 32_777)),
        "U1\\G10"
    );
    assert_eq!(basic_device(15, 0), None);
}

#[test]
fn init_checks_storage() {
    let mut storage = vec![0u32; LADDER_MEMORY_SIZE / 4];
    let bytes = LADDER_MEMORY_SIZE;
    unsafe {
        assert!(ladder_init(core::ptr::null_mut(), bytes).is_null());
        assert!(ladder_init(storage.as_mut_ptr().cast(), bytes - 1).is_null());
        assert!(ladder_init(storage.as_mut_ptr().cast::<u8>().add(1).cast(), bytes - 4).is_null());
        assert!(!ladder_init(storage.as_mut_ptr().cast(), bytes).is_null());
    }
}

#[test]
fn read_write_force_scan() {
    let mut storage = vec![0u32; LADDER_MEMORY_SIZE / 4];
    unsafe {
        let mem = ladder_init(storage.as_mut_ptr().cast(), LADDER_MEMORY_SIZE);
        assert_eq!(ladder_set_input(mem, 8, true), LadderStatus::Ok);
        let mut value = 7;
        assert_eq!(
            ladder_read(mem, LadderDevice::X as u32, 8, &mut value),
            LadderStatus::Ok
        );
        assert_eq!(value, 0, "X changes at the next input refresh, not before");
        assert_eq!(
            ladder_write(mem, LadderDevice::Cn as u32, 210, 100_000),
            LadderStatus::Ok
        );
        assert_eq!(
            ladder_write(mem, LadderDevice::D as u32, 8512, 1),
            LadderStatus::OutOfRange
        );
        assert_eq!(
            ladder_write(mem, LadderDevice::D as u32, 0, 70_000),
            LadderStatus::BadValue
        );
        assert_eq!(ladder_write(mem, LadderDevice::D as u32, 0, 65_535), LadderStatus::Ok);
        assert_eq!(ladder_write(mem, LadderDevice::M as u32, 0, 2), LadderStatus::BadValue);
        assert_eq!(ladder_write(mem, 99, 0, 1), LadderStatus::BadArgument);
        assert_eq!(ladder_force(mem, LadderDevice::Y as u32, 1, true), LadderStatus::Ok);
        assert_eq!(
            ladder_force(mem, LadderDevice::D as u32, 1, true),
            LadderStatus::NotForceable
        );
        assert_eq!(
            ladder_force(mem, LadderDevice::S as u32, 1, true),
            LadderStatus::NotForceable
        );
        assert_eq!(ladder_force(mem, 99, 1, true), LadderStatus::BadArgument);
        assert_eq!(ladder_unforce(mem, 99, 1), LadderStatus::BadArgument);
        ladder_begin_scan(mem, 10);
        ladder_end_scan(mem);
        assert_eq!(
            ladder_read(mem, LadderDevice::X as u32, 8, &mut value),
            LadderStatus::Ok
        );
        assert_eq!(value, 1);
        assert_eq!(
            ladder_read(mem, LadderDevice::D as u32, 0, &mut value),
            LadderStatus::Ok
        );
        assert_eq!(value, -1, "65535 is the word HFFFF");
        assert_eq!(
            ladder_read(mem, LadderDevice::Cn as u32, 210, &mut value),
            LadderStatus::Ok
        );
        assert_eq!(value, 100_000);
        assert_eq!(ladder_get_output(mem, 1), 1);
        assert_eq!(ladder_get_output(mem, 256), -1);
        assert_eq!(ladder_scan_count(mem), 1);
        assert_eq!(ladder_operation_error(mem), 0);
    }
}

#[test]
fn a_null_image_is_never_touched() {
    let null = core::ptr::null_mut();
    let mut value = 0;
    unsafe {
        assert_eq!(ladder_set_input(null, 0, true), LadderStatus::BadArgument);
        assert_eq!(ladder_write(null, 0, 0, 1), LadderStatus::BadArgument);
        assert_eq!(ladder_read(null, 0, 0, &mut value), LadderStatus::BadArgument);
        assert_eq!(ladder_force(null, 0, 0, true), LadderStatus::BadArgument);
        assert_eq!(ladder_unforce(null, 0, 0), LadderStatus::BadArgument);
        assert_eq!(ladder_get_output(null, 0), -1);
        assert_eq!(ladder_operation_error(null), 0);
        assert_eq!(ladder_operation_error_line(null), 0);
        assert_eq!(ladder_scan_count(null), 0);
        ladder_begin_scan(null, 10);
        ladder_end_scan(null);
        ladder_clear_operation_error(null);
    }
}

/// A compact image: what it holds behaves as in the full image; what it
/// does not is NOT_IN_IMAGE; storage never initialised is refused.
#[test]
fn compact_images_through_the_c_api() {
    use crate::layout::LayoutBuilder;
    let layout = LayoutBuilder::new()
        .include_bits(BitArea::X, 0, 2)
        .include_bits(BitArea::Y, 0, 2)
        .include_words(WordArea::D, 100, 102)
        .include_bits(BitArea::M, 8067, 8068)
        .include_words(WordArea::D, 8067, 8070)
        .build();
    let table: *const u32 = layout.words().as_ptr();
    let size = layout.size as usize;
    let mut storage = vec![0u32; size / 4];
    let mut value = 0;
    unsafe {
        let raw = storage.as_mut_ptr().cast::<c_void>();
        assert_eq!(
            ladder_set_input(raw.cast(), 0, true),
            LadderStatus::BadArgument,
            "never initialised"
        );
        assert!(ladder_init_layout(raw, size - 4, table).is_null(), "too small");
        assert!(ladder_init_layout(raw, size, core::ptr::null()).is_null());
        let mem = ladder_init_layout(raw, size, table);
        assert!(!mem.is_null());
        assert_eq!(ladder_set_input(mem, 1, true), LadderStatus::Ok);
        assert_eq!(ladder_set_input(mem, 2, true), LadderStatus::NotInImage);
        assert_eq!(ladder_set_input(mem, 256, true), LadderStatus::OutOfRange);
        assert_eq!(ladder_write(mem, LadderDevice::D as u32, 101, -7), LadderStatus::Ok);
        assert_eq!(
            ladder_write(mem, LadderDevice::D as u32, 5, 1),
            LadderStatus::NotInImage
        );
        assert_eq!(
            ladder_write(mem, LadderDevice::D as u32, 9000, 1),
            LadderStatus::OutOfRange
        );
        assert_eq!(
            ladder_read(mem, LadderDevice::D as u32, 101, &mut value),
            LadderStatus::Ok
        );
        assert_eq!(value, -7);
        assert_eq!(
            ladder_read(mem, LadderDevice::M as u32, 0, &mut value),
            LadderStatus::NotInImage
        );
        assert_eq!(
            ladder_write_real(mem, LadderDevice::D as u32, 100, 1.5),
            LadderStatus::Ok
        );
        let mut real = 0.0f32;
        assert_eq!(
            ladder_read_real(mem, LadderDevice::D as u32, 100, &mut real),
            LadderStatus::Ok
        );
        assert_eq!(real, 1.5);
        assert_eq!(
            ladder_read_real(mem, LadderDevice::D as u32, 101, &mut real),
            LadderStatus::NotInImage,
            "D102 is not in the image"
        );
        assert_eq!(ladder_force(mem, LadderDevice::Y as u32, 1, true), LadderStatus::Ok);
        assert_eq!(
            ladder_force(mem, LadderDevice::Y as u32, 7, true),
            LadderStatus::NotInImage
        );
        assert_eq!(
            ladder_add_pulses(mem, 3, 2),
            LadderStatus::Ok,
            "taken, and nothing counts them"
        );
        // The scan of a program with this layout runs; one built for
        // the full layout (or another table) is refused and does nothing.
        assert_eq!(
            crate::helpers::ladder_rt_begin_scan(mem, 10, core::ptr::null(), u32::MAX),
            0
        );
        assert_eq!(crate::helpers::ladder_rt_begin_scan(mem, 10, table, u32::MAX), 1);
        ladder_end_scan(mem);
        assert_eq!(
            ladder_read(mem, LadderDevice::X as u32, 1, &mut value),
            LadderStatus::Ok
        );
        assert_eq!(value, 1);
        assert_eq!(ladder_get_output(mem, 1), 1, "forced ON");
        assert_eq!(ladder_get_output(mem, 7), -1);
        assert_eq!(ladder_scan_count(mem), 1);
        assert_eq!(ladder_layout_misses(mem), 0);
        // A full image refuses the compact program's scan the same way.
        let mut full = vec![0u32; LADDER_MEMORY_SIZE / 4];
        let full = ladder_init(full.as_mut_ptr().cast(), LADDER_MEMORY_SIZE);
        assert_eq!(crate::helpers::ladder_rt_begin_scan(full, 10, table, u32::MAX), 0);
        assert_eq!(
            crate::helpers::ladder_rt_begin_scan(full, 10, core::ptr::null(), u32::MAX),
            1
        );
    }
}
