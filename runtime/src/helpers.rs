//! The functions compiled programs call (C ABI), declared once: the
//! `helpers!` table below gives each its name, parameters, what it writes
//! and its body. From it come the exported functions, the `Helper` enum the
//! compiler's IR names them by, their signatures for code generation, what
//! a call may write (for the compiler's analyses), and the symbol table of
//! the JIT. Tests check the cross-target shim and docs/runtime.md against it.
//!
//! Every helper takes the device image first; a null image is ignored (and
//! a helper that returns a value returns 0). Device numbers and places
//! outside their area are ignored by the methods they call.
//!
//! The reference interpreter does not call these: it implements the same
//! rules on its own, and the differential test compares the two.

use crate::capi::LadderMemory;
use crate::compiled::{self, SortJob, TableOp, Zone};
use crate::device::{BitArea, Width};
use crate::image::ImageMut;
use crate::layout::Array;
use crate::machine::MachineUse;
use crate::place::Place;
use crate::special::OperationError;

/// The C type of a helper parameter or result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    U32,
    I32,
    /// A place the helper reads (`Place::pack`), passed as a u32.
    SourcePlace,
    /// A place the helper writes (`Place::pack`), passed as a u32.
    DestinationPlace,
}

impl Param {
    /// Spelled as in C.
    pub fn c_type(self) -> &'static str {
        match self {
            Param::U32 | Param::SourcePlace | Param::DestinationPlace => "uint32_t",
            Param::I32 => "int32_t",
        }
    }
}

/// Parts of the image a helper may write besides its destination places.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Writes {
    /// Timer values, contacts and their bookkeeping.
    Timers,
    /// Counter values, contacts and their bookkeeping.
    Counters,
    /// The STL bookkeeping (`stl_pending_off`).
    StlBookkeeping,
    /// M8067, D8067, D8069.
    OperationError,
    /// Any bit of an area (flags such as SM229, alarm states).
    Bits(BitArea),
    /// Any device: the machine around the program (the clock and its
    /// registers, pulse outputs and their registers and flags).
    Image,
}

impl Writes {
    /// The bit areas a helper with this effect may write.
    pub fn bit_areas(self) -> &'static [BitArea] {
        match self {
            Writes::Timers => &[BitArea::TimerContact],
            Writes::Counters => &[BitArea::CounterContact],
            Writes::StlBookkeeping => &[],
            Writes::OperationError => &[BitArea::M],
            Writes::Bits(BitArea::X) => &[BitArea::X],
            Writes::Bits(BitArea::Y) => &[BitArea::Y],
            Writes::Bits(BitArea::M) => &[BitArea::M],
            Writes::Bits(BitArea::S) => &[BitArea::S],
            Writes::Bits(BitArea::Sm) => &[BitArea::Sm],
            Writes::Bits(BitArea::TimerContact) => &[BitArea::TimerContact],
            Writes::Bits(BitArea::CounterContact) => &[BitArea::CounterContact],
            Writes::Image => &BitArea::ALL,
        }
    }
}

/// A helper's declaration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HelperDecl {
    pub helper: Helper,
    pub name: &'static str,
    /// The parameters after the image pointer, with their names.
    pub params: &'static [(&'static str, Param)],
    pub returns: Option<Param>,
    pub writes: &'static [Writes],
    pub doc: &'static str,
}

impl HelperDecl {
    /// The C prototype: `void ladder_rt_x(LadderMemory *mem, uint32_t a)`.
    #[cfg(feature = "std")]
    pub fn c_prototype(&self) -> String {
        let params: Vec<String> = std::iter::once("LadderMemory *mem".to_string())
            .chain(
                self.params
                    .iter()
                    .map(|(name, param)| format!("{} {name}", param.c_type())),
            )
            .collect();
        format!(
            "{} {}({})",
            self.returns.map_or("void", Param::c_type),
            self.name,
            params.join(", ")
        )
    }
}

macro_rules! param_type {
    (u32) => {
        u32
    };
    (i32) => {
        i32
    };
    (source_place) => {
        u32
    };
    (destination_place) => {
        u32
    };
    (none) => {
        ()
    };
}

macro_rules! param_kind {
    (u32) => {
        Param::U32
    };
    (i32) => {
        Param::I32
    };
    (source_place) => {
        Param::SourcePlace
    };
    (destination_place) => {
        Param::DestinationPlace
    };
}

macro_rules! returns {
    (none) => {
        None
    };
    ($kind:ident) => {
        Some(param_kind!($kind))
    };
}

macro_rules! helpers {
    ($(
        #[doc = $doc:literal]
        $(#[doc = $more:literal])*
        $variant:ident = fn $name:ident($mem:ident $(, $param:ident: $kind:ident)*) -> $ret:ident
            writes [$($writes:tt)*] $body:block
    )*) => {
        /// The runtime helpers compiled code calls.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Helper {
            $( #[doc = $doc] $variant, )*
        }

        impl Helper {
            pub const ALL: &'static [Helper] = &[$(Helper::$variant),*];

            pub fn decl(self) -> &'static HelperDecl {
                match self {
                    $(Helper::$variant => {
                        const DECL: HelperDecl = HelperDecl {
                            helper: Helper::$variant,
                            name: stringify!($name),
                            params: &[$((stringify!($param), param_kind!($kind))),*],
                            returns: returns!($ret),
                            writes: {
                                #[allow(unused_imports)]
                                use Writes::*;
                                &[$($writes)*]
                            },
                            doc: concat!($doc $(, "\n", $more)*),
                        };
                        &DECL
                    })*
                }
            }

            /// The function's address, for a JIT to resolve its imports.
            pub fn address(self) -> *const u8 {
                match self {
                    $(Helper::$variant => $name as *const u8,)*
                }
            }
        }

        $(
            #[doc = $doc]
            $(#[doc = $more])*
            ///
            /// # Safety
            /// `mem` is null or the program's device image, not in use elsewhere.
            #[no_mangle]
            pub unsafe extern "C" fn $name(
                $mem: *mut LadderMemory $(, $param: param_type!($kind))*
            ) -> param_type!($ret) {
                // SAFETY: the caller passes the image it was given.
                match unsafe { ImageMut::from_raw($mem.cast()) } {
                    Some(mut image) => {
                        let $mem = &mut image;
                        $body
                    }
                    None => Default::default(),
                }
            }
        )*
    };
}

helpers! {
    /// `OUT Tn preset` with the rung result `coil` (0 or 1).
    TimerCoil = fn ladder_rt_timer_coil(mem, timer: u32, coil: u32, preset: i32) -> none
        writes [Timers] {
        mem.timer_coil(timer, coil != 0, preset)
    }

    /// `OUT Cn preset` with the rung result `coil` (0 or 1).
    CounterCoil = fn ladder_rt_counter_coil(mem, counter: u32, coil: u32, preset: i32) -> none
        writes [Counters] {
        mem.counter_coil(counter, coil != 0, preset)
    }

    /// `RST Tn`.
    ResetTimer = fn ladder_rt_reset_timer(mem, timer: u32) -> none writes [Timers] {
        mem.reset_timer(timer)
    }

    /// `RST Cn`.
    ResetCounter = fn ladder_rt_reset_counter(mem, counter: u32) -> none writes [Counters] {
        mem.reset_counter(counter)
    }

    /// A SET transfer out of the block of `state`.
    ScheduleStateOff = fn ladder_rt_schedule_state_off(mem, state: u32) -> none writes [StlBookkeeping] {
        mem.schedule_state_off(state)
    }

    /// A NEXT with repetitions left: 1 when the loop watchdog lets it repeat, else 0 (6509H recorded against `line`).
    LoopRepeat = fn ladder_rt_loop_repeat(mem, line: u32) -> i32 writes [OperationError] {
        i32::from(mem.loop_may_repeat(line))
    }

    /// BMOV: `n` units of `width` (1 = 16-bit, 2 = 32-bit) between checked places, as a whole.
    /// Overlapping blocks move as if every value were read before any is written.
    BlockMove = fn ladder_rt_block_move(
        mem, source: source_place, destination: destination_place, n: u32, width: u32
    ) -> none writes [] {
        if let (Some(source), Some(destination)) = (Place::unpack(source), Place::unpack(destination)) {
            compiled::block_move(mem, source, destination, n, width_of(width), false)
        }
    }

    /// FMOV: `value` into `n` units of `width` from a checked place.
    Fill = fn ladder_rt_fill(mem, destination: destination_place, n: u32, width: u32, value: i32) -> none
        writes [] {
        if let Some(destination) = Place::unpack(destination) {
            compiled::block_move(mem, Place::Constant(value), destination, n, width_of(width), true)
        }
    }

    /// SFTR (`left` 0) or SFTL (`left` 1): `n1` bits from a checked place shift by `n2`; `n2` bits from a checked source fill the vacated end.
    ShiftBits = fn ladder_rt_shift_bits(
        mem, source: source_place, destination: destination_place, n1: u32, n2: u32, left: u32
    ) -> none writes [] {
        if let (Some(source), Some(destination)) = (Place::unpack(source), Place::unpack(destination)) {
            compiled::shift_bits(mem, source, destination, n1, n2, left != 0)
        }
    }

    /// BTOW (`split` 0) or WTOB (`split` 1) of `n` bytes between checked word places.
    Bytes = fn ladder_rt_bytes(mem, source: source_place, destination: destination_place, n: u32, split: u32)
        -> none writes [] {
        if let (Some(source), Some(destination)) = (Place::unpack(source), Place::unpack(destination)) {
            compiled::bytes(mem, source, destination, n, split != 0)
        }
    }

    /// The number of the highest ON bit of `count` bits from a checked place, or -1 (ENCO).
    HighestOn = fn ladder_rt_highest_on(mem, source: source_place, count: u32) -> i32 writes [] {
        match Place::unpack(source) {
            Some(source) => compiled::highest_on(mem, source, count),
            None => -1,
        }
    }

    /// ZRST (`on` 0) or ZSET (`on` 1) of a checked zone from `first` to `last` (or `first` alone).
    Zone = fn ladder_rt_zone(mem, zone: u32, first: u32, last: u32, on: u32) -> none
        writes [Timers, Counters, Bits(BitArea::Y), Bits(BitArea::M), Bits(BitArea::S), Bits(BitArea::Sm)] {
        if let Some(zone) = Zone::from_code(zone) {
            compiled::zone(mem, zone, first, last, on != 0)
        }
    }

    /// MAX (`op` 0), MIN (1), MEAN (2) or WSUM (3) of `count` values of `width` from checked places.
    Table = fn ladder_rt_table(
        mem, op: u32, source: source_place, count: u32, width: u32, destination: destination_place
    ) -> none writes [] {
        if let (Some(op), Some(source), Some(destination)) =
            (TableOp::from_code(op), Place::unpack(source), Place::unpack(destination))
        {
            compiled::table(mem, op, source, count, width_of(width), destination)
        }
    }

    /// One scan of sort instruction `instance` with its input ON (`flags`: 1 row by row, 2 32-bit, 4 at once).
    /// The places and N1, N2, N3 are checked; SM165 decides the order of SORT2/DSORT2. Too many
    /// sorts in progress record 4089H against `line`.
    SortScan = fn ladder_rt_sort_scan(
        mem, instance: u32, source: source_place, destination: destination_place, rows: u32, columns: u32,
        key: u32, flags: u32, line: u32
    ) -> none writes [OperationError, Bits(BitArea::Sm)] {
        if let (Some(source), Some(destination)) = (Place::unpack(source), Place::unpack(destination)) {
            let row_major = flags & SORT_ROW_MAJOR != 0;
            let job = SortJob {
                source,
                destination,
                rows,
                columns,
                key,
                row_major,
                width: if flags & SORT_WIDE != 0 { Width::Double } else { Width::Single },
                descending: row_major && mem.get_u8(Array::Sm, crate::special::SM_DESCENDING.number) != 0,
                at_once: flags & SORT_AT_ONCE != 0,
            };
            compiled::sort_scan(mem, instance, &job, line)
        }
    }

    /// Sort instruction `instance` executed with its input OFF: its job ends.
    SortStop = fn ladder_rt_sort_stop(mem, instance: u32) -> none writes [] {
        compiled::sort_stop(mem, instance)
    }

    /// BCC: `method` (0 add, 1 subtract, 2 XOR) over `count` bytes into the low byte of a checked place.
    BlockCheck = fn ladder_rt_block_check(
        mem, method: u32, source: source_place, count: u32, destination: destination_place
    ) -> none writes [] {
        if let (Some(source), Some(destination)) = (Place::unpack(source), Place::unpack(destination)) {
            compiled::block_check(mem, method, source, count, destination)
        }
    }

    /// CRC: the CRC-16/MODBUS of `count` bytes from a checked place (SM161: low bytes only).
    Crc = fn ladder_rt_crc(mem, source: source_place, count: u32, destination: destination_place) -> none
        writes [] {
        if let (Some(source), Some(destination)) = (Place::unpack(source), Place::unpack(destination)) {
            compiled::crc(mem, source, count, destination)
        }
    }

    /// ANR: the lowest alarm state S900-S999 that is ON turns OFF.
    AlarmReset = fn ladder_rt_alarm_reset(mem) -> none writes [Bits(BitArea::S)] {
        compiled::alarm_reset(mem)
    }

    /// DSIN, DEXP, ...: function `function` (`RealFunction`) of the real number with bits `x`; the result's bits,
    /// or a NaN's when the argument or the result is out of range.
    RealFunction = fn ladder_rt_real_function(mem, function: u32, x: u32) -> i32 writes [] {
        let _ = mem;
        compiled::real_function(function, x)
    }

    /// DEBCD: the real number with bits `x` in scientific notation, the mantissa in the low word and the exponent
    /// in the high word.
    RealToDecimal = fn ladder_rt_real_to_decimal(mem, x: u32) -> i32 writes [] {
        let _ = mem;
        compiled::real_to_decimal(x)
    }

    /// DEBIN: the mantissa (low word) and exponent (high word) as a real number's bits, or a NaN's when out of range.
    DecimalToReal = fn ladder_rt_decimal_to_real(mem, decimal: u32) -> i32 writes [] {
        let _ = mem;
        compiled::decimal_to_real(decimal)
    }

    /// TWR: sets the clock from 7 words at a checked place; 1, or 0 when they are out of range.
    SetClock = fn ladder_rt_set_clock(mem, source: source_place) -> i32 writes [Image] {
        match Place::unpack(source) {
            Some(source) => i32::from(compiled::clock::set_clock(mem, source)),
            None => 0,
        }
    }

    /// TCMP: the time `hour`:`minute`:`second` against 3 words at a checked place; 1, or 0 out of range.
    TimeCompare = fn ladder_rt_time_compare(
        mem, hour: i32, minute: i32, second: i32, data: source_place, destination: destination_place
    ) -> i32 writes [] {
        match (Place::unpack(data), Place::unpack(destination)) {
            (Some(data), Some(destination)) => {
                let limit = [hour, minute, second].map(i64::from);
                i32::from(compiled::clock::time_compare(mem, limit, data, destination))
            }
            _ => 0,
        }
    }

    /// TZCP: the time at `data` against the zone from `low` to `high` (checked places); 1, or 0 out of range.
    TimeZone = fn ladder_rt_time_zone(
        mem, low: source_place, high: source_place, data: source_place, destination: destination_place
    ) -> i32 writes [] {
        match (Place::unpack(low), Place::unpack(high), Place::unpack(data), Place::unpack(destination)) {
            (Some(low), Some(high), Some(data), Some(destination)) => {
                i32::from(compiled::clock::time_zone(mem, low, high, data, destination))
            }
            _ => 0,
        }
    }

    /// TADD (`subtract` 0) or TSUB of times at checked places: `TIME_OK` | `TIME_ZERO` | `TIME_WRAPPED`, or 0
    /// out of range.
    TimeAdd = fn ladder_rt_time_add(
        mem, a: source_place, b: source_place, destination: destination_place, subtract: u32
    ) -> i32 writes [] {
        match (Place::unpack(a), Place::unpack(b), Place::unpack(destination)) {
            (Some(a), Some(b), Some(destination)) => compiled::clock::time_add(mem, a, b, destination, subtract != 0),
            _ => 0,
        }
    }

    /// HTOS: the seconds of the time at a checked place, or -1 when out of range or above `limit`.
    TimeToSeconds = fn ladder_rt_time_to_seconds(mem, source: source_place, limit: i32) -> i32 writes [] {
        match Place::unpack(source) {
            Some(source) => compiled::clock::time_to_seconds(mem, source, i64::from(limit)) as i32,
            None => -1,
        }
    }

    /// STOH: `seconds` as hours, minutes, seconds at a checked place; 1, or 0 out of range.
    SecondsToTime = fn ladder_rt_seconds_to_time(mem, seconds: i32, destination: destination_place) -> i32
        writes [] {
        match Place::unpack(destination) {
            Some(destination) => i32::from(compiled::clock::seconds_to_time(mem, i64::from(seconds), destination)),
            None => 0,
        }
    }

    /// HOUR (`wide` 0) / DHOUR instance `instance` with its rung ON: hours and seconds at a checked place, the
    /// alarm bit ON from `limit` hours.
    Hour = fn ladder_rt_hour(
        mem, instance: u32, limit: i32, hours: destination_place, alarm: destination_place, wide: u32
    ) -> none writes [] {
        if let (Some(hours), Some(alarm)) = (Place::unpack(hours), Place::unpack(alarm)) {
            compiled::clock::hour(mem, instance, i64::from(limit), hours, alarm, wide != 0)
        }
    }

    /// SER: count, first, last match of `key` and positions of the smallest and largest of `n` values of `width`
    /// at checked places.
    Search = fn ladder_rt_search(
        mem, table: source_place, n: u32, key: i32, destination: destination_place, width: u32
    ) -> none writes [] {
        if let (Some(table), Some(destination)) = (Place::unpack(table), Place::unpack(destination)) {
            compiled::handy::search(mem, table, n, i64::from(key), destination, width_of(width))
        }
    }

    /// ABSD: `n` outputs from the rising and falling points at checked places for the counter value `value`.
    AbsoluteDrum = fn ladder_rt_absolute_drum(
        mem, table: source_place, n: u32, value: i32, outputs: destination_place, width: u32
    ) -> none writes [] {
        if let (Some(table), Some(outputs)) = (Place::unpack(table), Place::unpack(outputs)) {
            compiled::handy::absolute_drum(mem, table, n, i64::from(value), outputs, width_of(width))
        }
    }

    /// INCD with the counters `counter`, `counter` + 1 (checked) and `power` the rung; M8029 at the end.
    IncrementalDrum = fn ladder_rt_incremental_drum(
        mem, table: source_place, n: u32, counter: u32, outputs: destination_place, power: u32
    ) -> none writes [Counters, Bits(BitArea::M)] {
        if let (Some(table), Some(outputs)) = (Place::unpack(table), Place::unpack(outputs)) {
            compiled::handy::incremental_drum(mem, table, n, counter, outputs, power != 0)
        }
    }

    /// An instruction that keeps an instance state ran with its rung OFF (RAMP, SEGL): it starts afresh.
    InstanceOff = fn ladder_rt_instance_off(mem, instance: u32) -> none writes [] {
        compiled::handy::instance_off(mem, instance)
    }

    /// RAMP instance `instance` with its rung ON: D and D+1 at a checked place; M8029 at the end.
    Ramp = fn ladder_rt_ramp(mem, instance: u32, from: i32, to: i32, target: destination_place, n: i32) -> none
        writes [Bits(BitArea::M)] {
        if let Some(target) = Place::unpack(target) {
            compiled::handy::ramp(mem, instance, i64::from(from), i64::from(to), target, i64::from(n))
        }
    }

    /// TTMR instance `instance`: D and D+1 at a checked place, `n` 0-2.
    TeachingTimer = fn ladder_rt_teaching_timer(mem, instance: u32, power: u32, target: destination_place, n: u32)
        -> none writes [] {
        if let Some(target) = Place::unpack(target) {
            compiled::handy::teaching_timer(mem, instance, power != 0, target, n)
        }
    }

    /// STMR instance `instance` on timer `timer` (checked) for `m` × 100 ms: four outputs at a checked place.
    SpecialTimer = fn ladder_rt_special_timer(
        mem, instance: u32, power: u32, timer: u32, m: i32, outputs: destination_place
    ) -> none writes [Timers] {
        if let Some(outputs) = Place::unpack(outputs) {
            compiled::handy::special_timer(mem, instance, power != 0, timer, i64::from(m), outputs)
        }
    }

    /// SEGD: the seven segments of the hex digit `digit`.
    Segments = fn ladder_rt_segments(mem, digit: u32) -> i32 writes [] {
        let _ = mem;
        compiled::handy::segments(digit)
    }

    /// SEGL instance `instance` with its rung ON: `sets` values (`first`, `second`), outputs at a checked place,
    /// mode `n`; 1, or 0 when a value is above 9999. M8029 at the end of a cycle.
    SegmentLatch = fn ladder_rt_segment_latch(
        mem, instance: u32, first: i32, second: i32, sets: u32, outputs: destination_place, n: u32
    ) -> i32 writes [Bits(BitArea::M)] {
        match Place::unpack(outputs) {
            Some(outputs) => {
                let values = [i64::from(first), i64::from(second)];
                i32::from(compiled::handy::segment_latch(mem, instance, values, sets, outputs, n))
            }
            None => 0,
        }
    }

    /// ASCI, HEX or CCD (`op`: `CharacterOp::code`, 0, 1, 2) of `n` characters between checked places (M8161:
    /// one per word); 1, or 0 when HEX met a character that is not a hex digit (or `op` is no operation).
    Characters = fn ladder_rt_characters(
        mem, op: u32, source: source_place, destination: destination_place, n: u32
    ) -> i32 writes [] {
        let op = compiled::handy::CharacterOp::from_code(op);
        match (op, Place::unpack(source), Place::unpack(destination)) {
            (Some(op), Some(source), Some(destination)) => {
                i32::from(compiled::handy::characters(mem, op, source, destination, n))
            }
            (None, _, _) | (_, None, _) | (_, _, None) => 0,
        }
    }

    /// DHSCS, DHSCR, DHSZ instance `instance` (`kind`: `HscCompare::code`, 1, 2, 3): registers (`power` 1) or
    /// withdraws the compare of counter `counter` with `low`, `high` and the checked destination.
    HighSpeedCompare = fn ladder_rt_high_speed_compare(
        mem, instance: u32, kind: u32, power: u32, counter: u32, low: i32, high: i32, destination: destination_place
    ) -> none writes [Image] {
        if let Some(kind) = crate::hsc::HscCompare::from_code(kind) {
            mem.high_speed_compare(instance, kind, power != 0, counter, [low, high], destination)
        }
    }

    /// SPD: the rising edges of X`input` over `period` ms into D, D+1, D+2 (a checked place, 32-bit when
    /// `width` is 2).
    Speed = fn ladder_rt_speed(mem, input: u32, period: i32, destination: destination_place, width: u32) -> none
        writes [] {
        if let Some(destination) = Place::unpack(destination) {
            compiled::highspeed::speed(mem, input, i64::from(period), destination, width_of(width))
        }
    }

    /// PLSY, PLSR, ... instance `instance` with its drive ON: `kind` (`PulseKind`) on output Y`output` (0-3),
    /// with the values of its operands and its direction output (a checked place, or 0). 0: operands
    /// with which it cannot start (4084H).
    PulseOutput = fn ladder_rt_pulse_output(
        mem, instance: u32, kind: u32, output: u32, frequency: i32, amount: i32, ramp: i32, creep: i32,
        near_point: u32, direction: destination_place
    ) -> i32 writes [Image] {
        match crate::pulse::PulseKind::from_code(kind) {
            Some(kind) => {
            let request = crate::pulse::PulseRequest {
                kind,
                output,
                frequency,
                amount,
                ramp_ms: ramp,
                creep,
                near_point: near_point != 0,
                direction,
            };
                i32::from(mem.pulse_output(instance, true, &request))
            }
            None => 0,
        }
    }

    /// A pulse instruction's drive is OFF: its output stops.
    PulseStop = fn ladder_rt_pulse_stop(mem, instance: u32) -> none writes [Image] {
        mem.pulse_stop(instance)
    }

    /// PWM instance `instance`: `width` ms ON of every `period` ms on a checked output while `power`.
    PulseWidth = fn ladder_rt_pulse_width(
        mem, instance: u32, power: u32, width: u32, period: u32, output: destination_place
    ) -> none writes [] {
        mem.pulse_width(instance, power != 0, width, period, output)
    }

    /// PID instance `instance` with its rung ON: set value `sv`, process value `pv`, the 25-word parameter block
    /// and the output at checked places; a parameter error is recorded against `line`.
    Pid = fn ladder_rt_pid(
        mem, instance: u32, sv: i32, pv: i32, block: source_place, mv: destination_place, line: u32
    ) -> none writes [OperationError] {
        if let (Some(block), Some(mv)) = (Place::unpack(block), Place::unpack(mv)) {
            compiled::pid::pid(mem, instance, i64::from(sv), i64::from(pv), block, mv, line)
        }
    }

    /// Records an operation error: M8067 ON, D8067 = `code`, D8069 = `line`.
    RecordError = fn ladder_rt_record_error(mem, code: u32, line: u32) -> none writes [OperationError] {
        if let Some(error) = OperationError::from_code(code) {
            mem.record_error(error, line)
        }
    }
}

/// `ladder_rt_sort_scan` flag: the table is laid out row by row (SORT2/DSORT2).
pub const SORT_ROW_MAJOR: u32 = 1;
/// `ladder_rt_sort_scan` flag: 32-bit values (DSORT2).
pub const SORT_WIDE: u32 = 2;
/// `ladder_rt_sort_scan` flag: sort at once (P forms).
pub const SORT_AT_ONCE: u32 = 4;

/// The width a helper's `width` argument names: 2 is 32-bit, else 16-bit.
fn width_of(width: u32) -> Width {
    if width == 2 {
        Width::Double
    } else {
        Width::Single
    }
}

/// A helper's `width` argument for `width`.
pub fn width_arg(width: Width) -> u32 {
    width.words()
}

/// Steps 1-2 of the scan, for the scan entry point of compiled objects,
/// which passes the layout table it was compiled for (null: the full
/// layout) and the parts of the machine the program and its host use
/// (`MachineUse::bits`). Returns 1 when the image has that layout and the
/// scan may go on; 0, doing nothing, for an image of another layout (or
/// none), whose devices the program's code would miss. The symbol carries
/// the layout rules' tag (`layout::TAGGED_BEGIN_SCAN`).
///
/// # Safety
/// `mem` is null or the program's device image.
#[export_name = "ladder_rt_begin_scan_v6_668580"]
pub unsafe extern "C" fn ladder_rt_begin_scan(
    mem: *mut LadderMemory,
    elapsed_ms: u32,
    layout: *const u32,
    machine: u32,
) -> u32 {
    // SAFETY: the caller passes the image it was given.
    match unsafe { ImageMut::from_raw(mem.cast()) } {
        Some(mut image) if image.has_layout(layout.cast()) => {
            image.begin_scan_for(elapsed_ms, MachineUse::from_bits(machine));
            1
        }
        _ => 0,
    }
}

/// Step 4 of the scan, for the scan entry point of compiled objects, after
/// the program ran on an image the begin-scan accepted; `machine` as there.
///
/// # Safety
/// `mem` is null or the program's device image.
#[export_name = "ladder_rt_end_scan_v6_668580"]
pub unsafe extern "C" fn ladder_rt_end_scan(mem: *mut LadderMemory, machine: u32) {
    // SAFETY: the caller passes the image it was given.
    if let Some(mut image) = unsafe { ImageMut::from_raw(mem.cast()) } {
        image.end_scan_for(MachineUse::from_bits(machine));
    }
}

/// Every symbol compiled code may import, with its address, for a JIT.
#[cfg(feature = "std")]
pub fn symbols() -> Vec<(&'static str, *const u8)> {
    Helper::ALL
        .iter()
        .map(|helper| (helper.decl().name, helper.address()))
        .chain([
            (crate::layout::TAGGED_BEGIN_SCAN, ladder_rt_begin_scan as *const u8),
            ("ladder_begin_scan", crate::capi::ladder_begin_scan as *const u8),
            (crate::layout::TAGGED_END_SCAN, ladder_rt_end_scan as *const u8),
            ("ladder_end_scan", crate::capi::ladder_end_scan as *const u8),
        ])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declarations_name_their_functions() {
        for &helper in Helper::ALL {
            let decl = helper.decl();
            assert_eq!(decl.helper, helper);
            assert!(decl.name.starts_with("ladder_rt_"), "{}", decl.name);
            assert!(!helper.address().is_null());
        }
        assert_eq!(
            Helper::TimerCoil.decl().c_prototype(),
            "void ladder_rt_timer_coil(LadderMemory *mem, uint32_t timer, uint32_t coil, int32_t preset)"
        );
    }

    /// As the module says: a helper given no image does nothing, and one
    /// that returns a value returns 0, even where its arguments alone would
    /// give another answer (a digit's segments, a real number's bits).
    #[test]
    fn null_images_are_ignored() {
        let null = core::ptr::null_mut();
        let one = 1.0f32.to_bits();
        let returned = unsafe {
            [
                ("ladder_rt_loop_repeat", ladder_rt_loop_repeat(null, 1)),
                ("ladder_rt_highest_on", ladder_rt_highest_on(null, 0, 16)),
                ("ladder_rt_real_function", ladder_rt_real_function(null, 0, one)),
                ("ladder_rt_real_to_decimal", ladder_rt_real_to_decimal(null, one)),
                ("ladder_rt_decimal_to_real", ladder_rt_decimal_to_real(null, 1)),
                ("ladder_rt_set_clock", ladder_rt_set_clock(null, 0)),
                ("ladder_rt_time_compare", ladder_rt_time_compare(null, 1, 2, 3, 0, 0)),
                ("ladder_rt_time_zone", ladder_rt_time_zone(null, 0, 0, 0, 0)),
                ("ladder_rt_time_add", ladder_rt_time_add(null, 0, 0, 0, 0)),
                ("ladder_rt_time_to_seconds", ladder_rt_time_to_seconds(null, 0, 9999)),
                ("ladder_rt_seconds_to_time", ladder_rt_seconds_to_time(null, 3661, 0)),
                ("ladder_rt_segments", ladder_rt_segments(null, 1)),
                (
                    "ladder_rt_segment_latch",
                    ladder_rt_segment_latch(null, 0, 1, 2, 1, 0, 0),
                ),
                ("ladder_rt_characters", ladder_rt_characters(null, 0, 0, 0, 1)),
                (
                    "ladder_rt_pulse_output",
                    ladder_rt_pulse_output(null, 0, 1, 0, 1000, 100, 0, 0, 0, 0),
                ),
            ]
        };
        for (name, value) in returned {
            assert_eq!(value, 0, "{name} with a null image");
        }
        // Every helper declared to return a value is among those above.
        let mut declared: Vec<&str> = Helper::ALL
            .iter()
            .filter(|helper| helper.decl().returns.is_some())
            .map(|helper| helper.decl().name)
            .collect();
        let mut called: Vec<&str> = returned.iter().map(|(name, _)| *name).collect();
        declared.sort_unstable();
        called.sort_unstable();
        assert_eq!(called, declared);
        // The scan's steps refuse a missing image as one of another layout.
        assert_eq!(unsafe { ladder_rt_begin_scan(null, 10, core::ptr::null(), 0) }, 0);
        // Helpers that return nothing write nothing: no image, nothing to
        // reach (a null dereference would crash the test).
        unsafe {
            ladder_rt_timer_coil(null, 0, 1, 5);
            ladder_rt_counter_coil(null, 0, 1, 5);
            ladder_rt_reset_timer(null, 0);
            ladder_rt_zone(null, 0, 0, 10, 1);
            ladder_rt_alarm_reset(null);
            ladder_rt_record_error(null, 0x4085, 3);
            ladder_rt_end_scan(null, 0);
        }
        // The same arguments on an image give other answers: the zeros above
        // are the null image's.
        let mut mem = crate::memory::Memory::new_boxed();
        let image = (&mut *mem as *mut crate::memory::Memory).cast();
        unsafe {
            assert_eq!(ladder_rt_loop_repeat(image, 1), 1);
            assert_ne!(ladder_rt_segments(image, 1), 0);
            assert_ne!(ladder_rt_real_to_decimal(image, one), 0);
            assert_eq!(ladder_rt_begin_scan(image, 10, core::ptr::null(), 0), 1);
        }
    }

    #[test]
    fn record_error_takes_known_codes_only() {
        let mut mem = crate::memory::Memory::new_boxed();
        let image = (&mut *mem as *mut crate::memory::Memory).cast();
        unsafe { ladder_rt_record_error(image, 0x1234, 9) };
        assert_eq!(mem.operation_error(), None);
        unsafe { ladder_rt_record_error(image, 0x4086, 9) };
        assert_eq!(mem.operation_error(), Some(0x4086));
    }
}
