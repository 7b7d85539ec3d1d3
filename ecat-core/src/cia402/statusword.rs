//! The statusword 0x6041 (IEC 61800-7-201 §6.2.1.3, Table 29): the state pattern of
//! [`State::pattern`] plus the bits only the application knows.

use super::State;

/// Bit 4: voltage enabled (high voltage is applied to the drive).
pub const VOLTAGE_ENABLED: u16 = 1 << 4;
/// Bit 7: warning.
pub const WARNING: u16 = 1 << 7;
/// Bit 9: remote (the controlword is processed).
pub const REMOTE: u16 = 1 << 9;
/// Bit 10: target reached.
pub const TARGET_REACHED: u16 = 1 << 10;
/// Bit 11: internal limit active.
pub const INTERNAL_LIMIT: u16 = 1 << 11;
/// Bit 12 (operation mode specific): drive follows the command value (CSP, CSV, CST) or set-point
/// acknowledge (PP).
pub const FOLLOWS_COMMAND: u16 = 1 << 12;
/// Bit 13 (operation mode specific): following error (CSP, PP).
pub const FOLLOWING_ERROR: u16 = 1 << 13;
/// Bit 12 in profile position: set-point acknowledge.
pub const SET_POINT_ACKNOWLEDGE: u16 = 1 << 12;
/// Bit 12 in profile velocity: speed (1 = speed is 0, |0x606C| ≤ 0x606F for 0x6070 ms).
pub const SPEED_ZERO: u16 = 1 << 12;
/// Bit 13 in profile velocity: max slippage error (asynchronous motors only).
pub const MAX_SLIPPAGE_ERROR: u16 = 1 << 13;
/// Bit 12 in homing: homing attained.
pub const HOMING_ATTAINED: u16 = 1 << 12;
/// Bit 13 in homing: homing error.
pub const HOMING_ERROR: u16 = 1 << 13;

/// The statusword bits the application reports (Table 29).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StatusFlags {
    /// Bit 4.
    pub voltage_enabled: bool,
    /// Bit 7.
    pub warning: bool,
    /// Bit 9.
    pub remote: bool,
    /// Bit 10.
    pub target_reached: bool,
    /// Bit 11.
    pub internal_limit: bool,
    /// Bit 12.
    pub follows_command: bool,
    /// Bit 13.
    pub following_error: bool,
}

/// The statusword of `state` with `flags`. The state bits are exactly the pattern value of
/// Table 30, so bit 5 (quick stop, active low) is set in Ready to switch on, Switched on and
/// Operation enabled, clear in Quick stop active and clear where the pattern leaves it free.
pub fn statusword(state: State, flags: StatusFlags) -> u16 {
    let bits = [
        (flags.voltage_enabled, VOLTAGE_ENABLED),
        (flags.warning, WARNING),
        (flags.remote, REMOTE),
        (flags.target_reached, TARGET_REACHED),
        (flags.internal_limit, INTERNAL_LIMIT),
        (flags.follows_command, FOLLOWS_COMMAND),
        (flags.following_error, FOLLOWING_ERROR),
    ];
    bits.into_iter()
        .filter(|&(on, _)| on)
        .fold(state.pattern().1, |sw, (_, bit)| sw | bit)
}
