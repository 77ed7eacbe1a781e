//! Special relays, special registers and operation-error codes with fixed meaning.

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
    M_ALWAYS_ON.contains(&n) || M_ALWAYS_OFF.contains(&n) || M_FIRST_SCAN.contains(&n) || M_NOT_FIRST_SCAN.contains(&n)
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
}

impl OperationError {
    pub const fn code(self) -> u16 {
        self as u16
    }
}
