//! Digital inputs 0x60FD (CiA 402-2 0x60FD): bit 0 negative limit switch, bit 1 positive limit
//! switch, bit 2 home switch, bit 3 interlock, 4..15 reserved, 16..31 manufacturer-specific.

/// Bit 0: negative limit switch.
pub const NEGATIVE_LIMIT: u32 = 1 << 0;
/// Bit 1: positive limit switch.
pub const POSITIVE_LIMIT: u32 = 1 << 1;
/// Bit 2: home switch.
pub const HOME_SWITCH: u32 = 1 << 2;
/// Bit 3: interlock.
pub const INTERLOCK: u32 = 1 << 3;

/// The 0x60FD value of the three switches (interlock and manufacturer bits 0).
pub const fn digital_inputs(negative_limit: bool, positive_limit: bool, home: bool) -> u32 {
    (negative_limit as u32) | (positive_limit as u32) << 1 | (home as u32) << 2
}
