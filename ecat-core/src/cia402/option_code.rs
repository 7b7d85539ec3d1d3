//! The option codes that decide how the drive stops and which state follows
//! (IEC 61800-7-201 §6.2.3; CiA 402-2 objects 0x605A, 0x605B, 0x605C, 0x605E).
//!
//! Codes outside the ranges the standard defines (negative codes are manufacturer-specific) are
//! not implemented: a drive refuses them at the SDO write through the `min`/`max` its dictionary
//! declares ([`objects`](super::objects)); should one reach the state machine anyway it acts as
//! code 0 (disable the drive function).

use super::State;

/// How the drive brings the motor to a standstill.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ramp {
    /// Disable the drive function at once: no torque, the motor is free to rotate.
    Disable,
    /// Decelerate with the slow down ramp (profile deceleration 0x6084).
    SlowDown,
    /// Decelerate with the quick stop ramp (quick stop deceleration 0x6085).
    QuickStop,
    /// Decelerate at the current limit.
    CurrentLimit,
    /// Decelerate at the voltage limit.
    VoltageLimit,
}

/// A stop the motion layer executes: the ramp, and the state the PDS enters when the motor stands
/// still (or at once for [`Ramp::Disable`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reaction {
    /// The deceleration.
    pub ramp: Ramp,
    /// The state after the stop.
    pub then: State,
}

/// The four option codes, as the dictionary holds them (INTEGER16 each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OptionCodes {
    /// 0x605A quick stop option code, 0..=8.
    pub quick_stop: i16,
    /// 0x605B shutdown option code, 0..=1.
    pub shutdown: i16,
    /// 0x605C disable operation option code, 0..=1.
    pub disable_operation: i16,
    /// 0x605E fault reaction option code, 0..=4.
    pub fault_reaction: i16,
}

impl OptionCodes {
    /// The defaults of CiA 402-2: quick stop 2, shutdown 0, disable operation 1, fault reaction 2.
    pub const DEFAULT: Self = Self {
        quick_stop: 2,
        shutdown: 0,
        disable_operation: 1,
        fault_reaction: 2,
    };

    /// Transition 11 (0x605A): codes 0..4 stop and go on to Switch on disabled (transition 12);
    /// 5..8 stop with the ramp of code − 4 and stay in Quick stop active.
    pub const fn quick_stop(&self) -> Reaction {
        let (ramp, then) = match self.quick_stop {
            1 => (Ramp::SlowDown, State::SwitchOnDisabled),
            2 => (Ramp::QuickStop, State::SwitchOnDisabled),
            3 => (Ramp::CurrentLimit, State::SwitchOnDisabled),
            4 => (Ramp::VoltageLimit, State::SwitchOnDisabled),
            5 => (Ramp::SlowDown, State::QuickStopActive),
            6 => (Ramp::QuickStop, State::QuickStopActive),
            7 => (Ramp::CurrentLimit, State::QuickStopActive),
            8 => (Ramp::VoltageLimit, State::QuickStopActive),
            _ => (Ramp::Disable, State::SwitchOnDisabled),
        };
        Reaction { ramp, then }
    }

    /// Transition 8 (0x605B): 0 disables the drive function, 1 slows down first; then Ready to
    /// switch on.
    pub const fn shutdown(&self) -> Reaction {
        Reaction {
            ramp: slow_down_or_disable(self.shutdown),
            then: State::ReadyToSwitchOn,
        }
    }

    /// Transition 5 (0x605C): 0 disables the drive function, 1 slows down first; then Switched on.
    pub const fn disable_operation(&self) -> Reaction {
        Reaction {
            ramp: slow_down_or_disable(self.disable_operation),
            then: State::SwitchedOn,
        }
    }

    /// Transitions 13/14 (0x605E): 0 disable, 1 slow down, 2 quick stop, 3 current limit,
    /// 4 voltage limit; then Fault.
    pub const fn fault_reaction(&self) -> Reaction {
        let ramp = match self.fault_reaction {
            1 => Ramp::SlowDown,
            2 => Ramp::QuickStop,
            3 => Ramp::CurrentLimit,
            4 => Ramp::VoltageLimit,
            _ => Ramp::Disable,
        };
        Reaction {
            ramp,
            then: State::Fault,
        }
    }
}

impl Default for OptionCodes {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Code 1 of 0x605B/0x605C slows down with the slow down ramp; anything else disables.
const fn slow_down_or_disable(code: i16) -> Ramp {
    match code {
        1 => Ramp::SlowDown,
        _ => Ramp::Disable,
    }
}

/// The ramp of the halt function (controlword bit 8) by 0x605D halt option code (CiA 402-2
/// 0x605D; IEC 61800-7-201 §6.2.3): 1 slow down ramp (0x6084, the default), 2 quick stop ramp
/// (0x6085), 3 current limit, 4 voltage limit. The drive stays in Operation enabled. Other codes
/// (reserved, manufacturer-specific) act as 1.
pub const fn halt(code: i16) -> Ramp {
    match code {
        2 => Ramp::QuickStop,
        3 => Ramp::CurrentLimit,
        4 => Ramp::VoltageLimit,
        _ => Ramp::SlowDown,
    }
}
