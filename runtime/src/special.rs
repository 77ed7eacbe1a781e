//! Special relays, special registers and operation-error codes with fixed meaning.

use crate::device::BitArea;

/// A special relay with a fixed meaning: an instruction flag or a mode bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SpecialBit {
    pub area: BitArea,
    pub number: u32,
}

impl SpecialBit {
    const fn m(number: u32) -> SpecialBit {
        SpecialBit {
            area: BitArea::M,
            number,
        }
    }

    const fn sm(number: u32) -> SpecialBit {
        SpecialBit {
            area: BitArea::Sm,
            number,
        }
    }

    /// How a programmer writes it (`M8020`, `SM152`).
    #[cfg(feature = "std")]
    pub fn name(self) -> String {
        self.area.device_name(self.number)
    }
}

/// M8020: the latest ADD/SUB gave 0.
pub const ZERO_FLAG: SpecialBit = SpecialBit::m(M_ZERO);
/// M8021: the latest ADD/SUB went below the smallest value.
pub const BORROW_FLAG: SpecialBit = SpecialBit::m(M_BORROW);
/// M8022: the latest ADD/SUB went above the largest value.
pub const CARRY_FLAG: SpecialBit = SpecialBit::m(M_CARRY);
/// SM152: SQR/DSQR dropped a fraction.
pub const SM_BORROW_FLAG: SpecialBit = SpecialBit::sm(152);
/// SM153: the result of SQR/DSQR, or the source of SUM/DSUM, is 0.
pub const SM_ZERO_FLAG: SpecialBit = SpecialBit::sm(153);
/// SM161: BCC and CRC work on the low byte of each word only (8-bit mode).
pub const SM_EIGHT_BIT_MODE: SpecialBit = SpecialBit::sm(161);
/// SM165: SORT2/DSORT2 sort in descending order.
pub const SM_DESCENDING: SpecialBit = SpecialBit::sm(165);
/// SM229: a SORT/SORT2/DSORT2 has completed.
pub const SM_SORT_DONE: SpecialBit = SpecialBit::sm(229);
/// SM248: some alarm state S900-S999 is ON (while SM249 is ON).
pub const SM_ALARM_ACTIVE: SpecialBit = SpecialBit::sm(248);
/// The alarm states ANS sets and ANR resets.
pub const FIRST_ALARM_STATE: u32 = 900;
pub const LAST_ALARM_STATE: u32 = 999;
/// SD249: the lowest alarm state that is ON (while SM249 is ON).
pub const SD_ALARM_LOWEST: u32 = 249;
/// SM249: alarm monitoring enabled (SM248 and SD249 follow S900-S999).
pub const SM_ALARM_MONITOR: SpecialBit = SpecialBit::sm(249);

/// SM0: always ON while running.
pub const SM_ALWAYS_ON: u32 = 0;
/// SM1: always OFF.
pub const SM_ALWAYS_OFF: u32 = 1;
/// SM2: ON during the first scan only.
pub const SM_FIRST_SCAN: u32 = 2;
/// SM3: OFF during the first scan only.
pub const SM_NOT_FIRST_SCAN: u32 = 3;

/// M relays that are always ON while running.
pub const M_ALWAYS_ON: [u32; 3] = [8000, 8151, 8160];
/// M relays that are always OFF.
pub const M_ALWAYS_OFF: [u32; 1] = [8001];
/// M relays that are ON during the first scan only.
pub const M_FIRST_SCAN: [u32; 2] = [8002, 8150];
/// M relays that are OFF during the first scan only.
pub const M_NOT_FIRST_SCAN: [u32; 1] = [8003];

/// Arithmetic flags of ADD/SUB (FX): zero, borrow, carry.
pub const M_ZERO: u32 = 8020;
pub const M_BORROW: u32 = 8021;
pub const M_CARRY: u32 = 8022;

/// M8029: the latest positioning, drum, ramp or display instruction has
/// completed (each execution writes it).
pub const M_EXECUTION_COMPLETE: u32 = 8029;
/// M8026: RAMP holds at its end value (OFF: it starts again).
pub const M_RAMP_HOLD: u32 = 8026;
/// M8161: ASCI, HEX and CCD handle one character per word (8-bit mode).
pub const M_EIGHT_BIT_MODE_FX: u32 = 8161;

/// M8029 as a flag of the instructions that write it.
pub const EXECUTION_COMPLETE: SpecialBit = SpecialBit::m(M_EXECUTION_COMPLETE);
/// M8026 as a mode of RAMP.
pub const RAMP_HOLD: SpecialBit = SpecialBit::m(M_RAMP_HOLD);
/// M8161 as a mode of ASCI, HEX, CCD.
pub const EIGHT_BIT_MODE_FX: SpecialBit = SpecialBit::m(M_EIGHT_BIT_MODE_FX);

/// M8067 turns ON when an instruction records an operation error.
pub const M_OPERATION_ERROR: u32 = 8067;
/// D8067 holds the code of the latest operation error.
pub const D_ERROR_CODE: u32 = 8067;
/// D8069 holds the source line of the instruction that failed.
pub const D_ERROR_LINE: u32 = 8069;

/// M8200+(n-200) ON makes the 32-bit counter Cn count down.
pub const M_COUNTER_DIRECTION_BASE: u32 = 8200;

/// Is M relay `n` one the runtime rewrites at every scan (a write by the
/// program would not last)?
pub fn is_system_m(n: u32) -> bool {
    M_ALWAYS_ON.contains(&n)
        || M_ALWAYS_OFF.contains(&n)
        || M_FIRST_SCAN.contains(&n)
        || M_NOT_FIRST_SCAN.contains(&n)
        || CLOCK_RELAYS.iter().any(|&(relay, _)| relay == n)
}

/// Is SM relay `n` one the runtime rewrites at every scan?
pub fn is_system_sm(n: u32) -> bool {
    n <= SM_NOT_FIRST_SCAN
}

/// Operation-error codes written to D8067 (seed: application instructions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum OperationError {
    /// 4084H: an input value is outside the range the instruction accepts
    /// (also used for division by zero).
    DataOutOfRange = 0x4084,
    /// 4085H: a device read by the instruction is outside its area.
    ReadOutOfRange = 0x4085,
    /// 4086H: a device written by the instruction is outside its area.
    WriteOutOfRange = 0x4086,
    /// 4087H: the instruction does not support the device type used.
    UnsupportedDevice = 0x4087,
    /// 4089H: too many application instructions of this kind.
    TooManyInstructions = 0x4089,
    /// 4093H: the two ends of a range are not the same device type.
    RangeNotSameDevice = 0x4093,
    /// 4094H: the two ends of a range are in the wrong order.
    RangeOrder = 0x4094,
    /// 6509H: FOR/NEXT loops repeated more than `LOOP_REPETITION_LIMIT`
    /// times in one scan; the loops stopped repeating for that scan.
    LoopWatchdog = 0x6509,
    /// 6730H: PID sampling time outside 1-32767 ms (the PID stops).
    PidSamplingTime = 0x6730,
    /// 6732H: PID input filter outside 0-99 % (the PID stops).
    PidInputFilter = 0x6732,
    /// 6733H: PID proportional gain outside 1-32767 % (the PID stops).
    PidProportionalGain = 0x6733,
    /// 6734H: PID integral time below 0 (the PID stops).
    PidIntegralTime = 0x6734,
    /// 6735H: PID derivative gain outside 0-200 % (the PID stops).
    PidDerivativeGain = 0x6735,
    /// 6736H: PID derivative time below 0 (the PID stops).
    PidDerivativeTime = 0x6736,
    /// 6748H: PID output upper limit below the lower one (they are
    /// exchanged; the PID goes on).
    PidLimitOrder = 0x6748,
    /// 6749H: PID alarm setting below 0 (that alarm is off; the PID goes on).
    PidAlarmSetting = 0x6749,
}

/// FOR/NEXT repetitions (a NEXT going back to its FOR) one scan allows, all
/// loops together.
pub const LOOP_REPETITION_LIMIT: u32 = 100_000;

/// The clock relays M8011, M8012, M8013, M8014 and their periods in ms: ON
/// while (t mod period) >= period / 2, t the accumulated reported time.
pub const CLOCK_RELAYS: [(u32, u32); 4] = [(8011, 10), (8012, 100), (8013, 1_000), (8014, 60_000)];
/// The longest clock period, a multiple of every other: t is kept modulo it.
pub const CLOCK_CYCLE_MS: u32 = 60_000;

impl OperationError {
    pub const ALL: [OperationError; 16] = [
        OperationError::DataOutOfRange,
        OperationError::ReadOutOfRange,
        OperationError::WriteOutOfRange,
        OperationError::UnsupportedDevice,
        OperationError::TooManyInstructions,
        OperationError::RangeNotSameDevice,
        OperationError::RangeOrder,
        OperationError::LoopWatchdog,
        OperationError::PidSamplingTime,
        OperationError::PidInputFilter,
        OperationError::PidProportionalGain,
        OperationError::PidIntegralTime,
        OperationError::PidDerivativeGain,
        OperationError::PidDerivativeTime,
        OperationError::PidLimitOrder,
        OperationError::PidAlarmSetting,
    ];

    pub const fn code(self) -> u16 {
        self as u16
    }

    /// The error with this code, if there is one.
    pub fn from_code(code: u32) -> Option<OperationError> {
        OperationError::ALL.into_iter().find(|e| u32::from(e.code()) == code)
    }
}
