//! Modes of operation (IEC 61800-7-201 §6.2.2; CiA 402-2 0x6060 modes of operation, 0x6061
//! modes of operation display, 0x6502 supported drive modes).
//!
//! A mode is supported when bit `mode − 1` of 0x6502 is set. An SDO write of an unsupported mode
//! to 0x6060 is refused with 0x06090030 "value range of parameter exceeded" ([`check_write`]):
//! the value is outside the set the device accepts, whatever its state. (0x08000022 "present
//! device state" would suit a mode the device supports but cannot switch to now; this profile
//! switches modes in every state, so it has no such case.) A mode that arrives through an RxPDO
//! bypasses the SDO check: [`display`] then keeps the previous mode.

use crate::coe::AbortCode;
use crate::dictionary::Value;

/// The modes of Table 31 this profile knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// 1: profile position.
    ProfilePosition,
    /// 3: profile velocity.
    ProfileVelocity,
    /// 4: profile torque.
    ProfileTorque,
    /// 6: homing.
    Homing,
    /// 8: cyclic synchronous position.
    CyclicSyncPosition,
    /// 9: cyclic synchronous velocity.
    CyclicSyncVelocity,
    /// 10: cyclic synchronous torque.
    CyclicSyncTorque,
}

impl Mode {
    /// The mode with code `code` (0x6060/0x6061 value), `None` for 0 ("no mode"), reserved and
    /// manufacturer-specific codes.
    pub const fn from_code(code: i8) -> Option<Self> {
        match code {
            1 => Some(Self::ProfilePosition),
            3 => Some(Self::ProfileVelocity),
            4 => Some(Self::ProfileTorque),
            6 => Some(Self::Homing),
            8 => Some(Self::CyclicSyncPosition),
            9 => Some(Self::CyclicSyncVelocity),
            10 => Some(Self::CyclicSyncTorque),
            _ => None,
        }
    }

    /// The code of the mode.
    pub const fn code(self) -> i8 {
        match self {
            Self::ProfilePosition => 1,
            Self::ProfileVelocity => 3,
            Self::ProfileTorque => 4,
            Self::Homing => 6,
            Self::CyclicSyncPosition => 8,
            Self::CyclicSyncVelocity => 9,
            Self::CyclicSyncTorque => 10,
        }
    }

    /// The bit of the mode in 0x6502 (Table 33: bit = mode − 1).
    pub const fn supported_bit(self) -> u32 {
        1 << (self.code() - 1)
    }
}

/// Whether `code` is a mode the device supports according to `supported` (0x6502): a positive
/// code whose bit `code − 1` is set. 0 and negative (manufacturer-specific) codes never are.
pub const fn is_supported(code: i8, supported: u32) -> bool {
    match code {
        1..=32 => supported & (1 << (code - 1)) != 0,
        _ => false,
    }
}

/// The check of an SDO download `data` to 0x6060 against `supported` (0x6502), for
/// `ObjectHooks::before_write`: a wrong length is left to the dictionary's own decoding, an
/// unsupported mode is [`AbortCode::VALUE_RANGE`].
pub fn check_write(data: &[u8], supported: u32) -> Result<(), AbortCode> {
    match i8::decode(data) {
        Ok(code) if !is_supported(code, supported) => Err(AbortCode::VALUE_RANGE),
        _ => Ok(()),
    }
}

/// The mode the drive runs after this cycle, for 0x6061: the requested 0x6060 when supported
/// (a change takes effect at once, in any state: §6.2.2 leaves the switching instant to the
/// drive, and the MainDevice watches 0x6061 to see it), otherwise the `current` one.
pub const fn display(requested: i8, current: i8, supported: u32) -> i8 {
    if is_supported(requested, supported) {
        requested
    } else {
        current
    }
}
