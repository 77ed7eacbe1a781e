//! The device image as bytes: a digest every engine computes the same way,
//! and the names of the fields and devices behind a byte offset, to report
//! where two images differ (and to write `expect` lines for it).

use ladder_runtime::capi::LadderDevice;
use ladder_runtime::layout::{Layout, FULL, HEADER_SIZE, SEGMENTS};
use ladder_runtime::Memory;
use std::mem::offset_of;

/// The runtime's digest of the image after its header
/// (`ladder_runtime::image::digest`; `testsuite/differential/driver.c`
/// computes the same).
pub fn digest(mem: &Memory) -> u64 {
    mem.digest()
}

/// `digest` of an image's bytes, whatever its layout.
pub fn digest_bytes(bytes: &[u8]) -> u64 {
    ladder_runtime::image::digest(bytes)
}

/// The bytes of an image with `layout` holding what `mem` holds (header
/// zero): what a compact image must be when the full one is `mem`.
pub fn project(mem: &Memory, layout: &Layout) -> Vec<u8> {
    let full = bytemuck::bytes_of(mem);
    let mut bytes = vec![0u8; layout.size as usize];
    let scalars = HEADER_SIZE..ladder_runtime::layout::ARRAYS_START;
    bytes[scalars.clone()].copy_from_slice(&full[scalars]);
    for (run, segment) in layout.runs.iter().zip(SEGMENTS) {
        if run.count == 0 {
            continue;
        }
        let length = run.count as usize * segment.array.size();
        let from = FULL
            .offset(segment.array, run.first)
            .expect("the full layout holds every device");
        bytes[run.offset as usize..run.offset as usize + length].copy_from_slice(&full[from..from + length]);
    }
    bytes
}

/// The full image with what a compact image's `bytes` hold, and zero
/// elsewhere (to name the devices where two compact images differ).
pub fn expand(bytes: &[u8], layout: &Layout) -> Box<Memory> {
    let mut mem = Memory::new_boxed();
    let full = bytemuck::bytes_of_mut(&mut *mem);
    let scalars = HEADER_SIZE..ladder_runtime::layout::ARRAYS_START;
    full[scalars.clone()].copy_from_slice(&bytes[scalars]);
    for (run, segment) in layout.runs.iter().zip(SEGMENTS) {
        if run.count == 0 {
            continue;
        }
        let length = run.count as usize * segment.array.size();
        let to = FULL
            .offset(segment.array, run.first)
            .expect("the full layout holds every device");
        full[to..to + length].copy_from_slice(&bytes[run.offset as usize..run.offset as usize + length]);
    }
    mem
}

/// A field of the image: its name, where it starts, the size of one
/// element, and the device kind (and first number) its elements are.
struct Field {
    name: &'static str,
    start: usize,
    element: usize,
    device: Option<(LadderDevice, u32)>,
}

fn fields() -> Vec<Field> {
    let field = |name, start, element, device| Field {
        name,
        start,
        element,
        device,
    };
    vec![
        field("header", offset_of!(Memory, header), 4, None),
        field("forced_count", offset_of!(Memory, forced_count), 4, None),
        field("stl_pending_any", offset_of!(Memory, stl_pending_any), 4, None),
        field("elapsed_ms", offset_of!(Memory, elapsed_ms), 4, None),
        field("scan_count", offset_of!(Memory, scan_count), 4, None),
        field("clock_ms", offset_of!(Memory, clock_ms), 4, None),
        field("loop_repetitions", offset_of!(Memory, loop_repetitions), 4, None),
        field("calendar_seconds", offset_of!(Memory, calendar_seconds), 4, None),
        field("calendar_ms", offset_of!(Memory, calendar_ms), 4, None),
        field("calendar_flags", offset_of!(Memory, calendar_flags), 4, None),
        field("layout_misses", offset_of!(Memory, layout_misses), 4, None),
        field("x", offset_of!(Memory, x), 1, Some((LadderDevice::X, 0))),
        field("y", offset_of!(Memory, y), 1, Some((LadderDevice::Y, 0))),
        field("m", offset_of!(Memory, m), 1, Some((LadderDevice::M, 0))),
        field("s", offset_of!(Memory, s), 1, Some((LadderDevice::S, 0))),
        field("sm", offset_of!(Memory, sm), 1, Some((LadderDevice::Sm, 0))),
        field(
            "timer_contact",
            offset_of!(Memory, timer_contact),
            1,
            Some((LadderDevice::Ts, 0)),
        ),
        field(
            "counter_contact",
            offset_of!(Memory, counter_contact),
            1,
            Some((LadderDevice::Cs, 0)),
        ),
        field("d", offset_of!(Memory, d), 2, Some((LadderDevice::D, 0))),
        field("sd", offset_of!(Memory, sd), 2, Some((LadderDevice::Sd, 0))),
        field("r", offset_of!(Memory, r), 2, Some((LadderDevice::R, 0))),
        field(
            "timer_value",
            offset_of!(Memory, timer_value),
            2,
            Some((LadderDevice::Tn, 0)),
        ),
        field(
            "counter_value",
            offset_of!(Memory, counter_value),
            2,
            Some((LadderDevice::Cn, 0)),
        ),
        field(
            "wide_counter_value",
            offset_of!(Memory, wide_counter_value),
            4,
            Some((LadderDevice::Cn, 200)),
        ),
        // Z0, V0, Z1, V1, ...: interleaved, so no single device kind.
        field("index", offset_of!(Memory, index), 2, None),
        field("timer_remainder_ms", offset_of!(Memory, timer_remainder_ms), 2, None),
        field("timer_coil_was_on", offset_of!(Memory, timer_coil_was_on), 1, None),
        field("counter_coil_was_on", offset_of!(Memory, counter_coil_was_on), 1, None),
        field("stl_pending_off", offset_of!(Memory, stl_pending_off), 1, None),
        field("stl_block_active", offset_of!(Memory, stl_block_active), 1, None),
        field("edge_slot", offset_of!(Memory, edge_slot), 1, None),
        field("sort_state", offset_of!(Memory, sort_state), 1, None),
        field("sort_scans", offset_of!(Memory, sort_scans), 1, None),
        field("input_image", offset_of!(Memory, input_image), 1, None),
        field("output_image", offset_of!(Memory, output_image), 1, None),
        field("force_x", offset_of!(Memory, force_x), 1, None),
        field("force_y", offset_of!(Memory, force_y), 1, None),
        field("force_m", offset_of!(Memory, force_m), 1, None),
        field("force_timer", offset_of!(Memory, force_timer), 1, None),
        field("force_counter", offset_of!(Memory, force_counter), 1, None),
        field("pulses_pending", offset_of!(Memory, pulses_pending), 4, None),
        field("input_edges", offset_of!(Memory, input_edges), 4, None),
        // Four words per instance: phase, a, b, c.
        field("instance", offset_of!(Memory, instance), 4, None),
        field("pulse_owner", offset_of!(Memory, pulse_owner), 4, None),
        field("pulse_remainder", offset_of!(Memory, pulse_remainder), 4, None),
        field("buffer", offset_of!(Memory, buffer), 2, Some((LadderDevice::U, 0))),
    ]
}

/// One differing element of two images.
#[derive(Clone, Debug)]
pub struct Difference {
    /// `d[12]`, `timer_remainder_ms[3]`.
    pub place: String,
    /// The device, when the element is one (`D12`, `CN200`).
    pub device: Option<(LadderDevice, u32)>,
    /// The element in the expected image (sign-extended) and in the other.
    pub expected: i64,
    pub actual: i64,
}

/// The elements where `actual` differs from `expected`, in image order.
pub fn differences(expected: &Memory, actual: &Memory) -> Vec<Difference> {
    let (a, b) = (bytemuck::bytes_of(expected), bytemuck::bytes_of(actual));
    let fields = fields();
    let mut out: Vec<Difference> = Vec::new();
    for offset in (0..a.len()).filter(|&i| a[i] != b[i]) {
        let Some(field) = fields.iter().rev().find(|f| f.start <= offset) else {
            continue;
        };
        let index = (offset - field.start) / field.element;
        let place = format!("{}[{index}]", field.name);
        if out.last().is_some_and(|d| d.place == place) {
            continue;
        }
        let element_start = field.start + index * field.element;
        let value = |bytes: &[u8]| -> i64 {
            let raw = &bytes[element_start..element_start + field.element];
            match field.element {
                2 => i64::from(i16::from_ne_bytes([raw[0], raw[1]])),
                4 => i64::from(i32::from_ne_bytes([raw[0], raw[1], raw[2], raw[3]])),
                _ => i64::from(raw[0]),
            }
        };
        out.push(Difference {
            place,
            device: field.device.map(|(kind, first)| (kind, first + index as u32)),
            expected: value(a),
            actual: value(b),
        });
    }
    out
}
