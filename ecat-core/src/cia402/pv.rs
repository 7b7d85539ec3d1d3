//! Profile velocity mode (mode 3; CiA 402-2 / IEC 61800-7-201 §6.5 "profile velocity mode").
//!
//! The demand ramps to 0x60FF target velocity (clamped into ±0x607F, bit 11 while clamped) with
//! 0x6083 profile acceleration while the speed grows and 0x6084 profile deceleration while it
//! falls. Statusword bits:
//!
//! - bit 10 target reached: |0x60FF − 0x606C| ≤ 0x606D velocity window, continuously for
//!   0x606E velocity window time (ms); with halt (bit 8) set: the axis stands still.
//! - bit 12 speed: 1 while |0x606C| ≤ 0x606F velocity threshold has held for 0x6070 velocity
//!   threshold time (ms) — "speed is 0" —, 0 as soon as it is above the threshold.
//! - bit 13 max slippage error: defined for asynchronous (induction) motors, whose slip 0x60F8
//!   bounds; a synchronous servo has no slip, so this implementation reports 0.

use super::controlword::HALT;
use super::profile::{Ramps, Trajectory, clamp_velocity};

/// The objects profile velocity reads each cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PvParameters {
    /// 0x60FF target velocity, counts/s.
    pub target: i32,
    /// 0x6083 profile acceleration, counts/s².
    pub acceleration: u32,
    /// 0x6084 profile deceleration, counts/s².
    pub deceleration: u32,
    /// 0x607F max profile velocity, counts/s.
    pub max_velocity: u32,
    /// 0x606D velocity window, counts/s.
    pub window: u16,
    /// 0x606E velocity window time, ms.
    pub window_time: u16,
    /// 0x606F velocity threshold, counts/s.
    pub threshold: u16,
    /// 0x6070 velocity threshold time, ms.
    pub threshold_time: u16,
    /// The deceleration of the halt ramp (0x605D resolved by the drive), counts/s².
    pub halt_deceleration: u32,
}

/// The mode-specific statusword bits of one cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PvStatus {
    /// Bit 10.
    pub target_reached: bool,
    /// Bit 11 (0x60FF clamped into ±0x607F).
    pub internal_limit: bool,
    /// Bit 12 (speed is 0).
    pub speed_zero: bool,
}

/// The profile velocity function of one axis: the two window timers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ProfileVelocity {
    /// Time inside the velocity window, ns.
    in_window: u32,
    /// Time at or below the velocity threshold, ns.
    below_threshold: u32,
}

impl ProfileVelocity {
    /// Both timers at 0.
    pub const fn new() -> Self {
        Self {
            in_window: 0,
            below_threshold: 0,
        }
    }

    /// One cycle in Operation enabled; `actual` is 0x606C after the previous cycle.
    pub fn update(
        &mut self,
        controlword: u16,
        p: &PvParameters,
        trajectory: &mut Trajectory,
        dt_ns: u32,
    ) -> PvStatus {
        let (target, internal_limit) = clamp_velocity(i64::from(p.target), p.max_velocity);
        let halted = controlword & HALT != 0;
        let standstill = if halted {
            trajectory.stop(p.halt_deceleration, dt_ns)
        } else {
            let ramps = Ramps {
                velocity: p.max_velocity,
                acceleration: p.acceleration,
                deceleration: p.deceleration,
            };
            trajectory.to_velocity(target, ramps, dt_ns);
            trajectory.standstill()
        };
        let actual = trajectory.velocity();
        let inside = target.abs_diff(actual) <= u64::from(p.window);
        self.in_window = timer(self.in_window, inside, dt_ns);
        let below = actual.unsigned_abs() <= u64::from(p.threshold);
        self.below_threshold = timer(self.below_threshold, below, dt_ns);
        PvStatus {
            target_reached: if halted {
                standstill
            } else {
                elapsed(self.in_window, p.window_time)
            },
            internal_limit,
            speed_zero: elapsed(self.below_threshold, p.threshold_time),
        }
    }
}

/// A condition timer: `ns` plus this cycle while `holds`, 0 otherwise.
pub(crate) fn timer(ns: u32, holds: bool, dt_ns: u32) -> u32 {
    if holds { ns.saturating_add(dt_ns) } else { 0 }
}

/// Whether a timer that runs has run for `ms` (0 ms: as soon as it runs).
pub(crate) fn elapsed(ns: u32, ms: u16) -> bool {
    ns > 0 && ns >= u32::from(ms).saturating_mul(1_000_000)
}
