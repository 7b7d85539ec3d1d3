//! Profile position mode (mode 1; CiA 402-2 / IEC 61800-7-201 §6.3 "profile position mode";
//! ETG.6010 §6 lists it among the modes an EtherCAT drive may offer).
//!
//! **Set-point handshake** (controlword bit 4 new set-point, statusword bit 12 set-point
//! acknowledge): a rising edge of bit 4 while bit 12 is 0 takes 0x607A (with 0x6081, 0x6083,
//! 0x6084) and sets bit 12 in the same cycle; bit 12 returns to 0 once bit 4 is 0 *and* the
//! drive can take another set-point. A rising edge while bit 12 is 1 is ignored.
//!
//! **Single set-point / set of set-points** (bit 5 change set immediately): with bit 5 = 1 the
//! new set-point replaces the one in progress at once (the move is re-planned from the current
//! position and velocity); with bit 5 = 0 it is buffered and started when the current one
//! reaches its target. The buffer holds one set-point: while it is full, bit 12 stays 1 (even
//! with bit 4 = 0) and further edges are ignored; it drops when the buffered set-point starts.
//! With bit 9 (change on set-point) set as well, the move does not stop at the first target: it
//! passes it at the first set-point's profile velocity and continues to the buffered one (only
//! when both lie in the same direction; otherwise it stops at the first target).
//!
//! **Absolute / relative** (bit 6): a relative target is added to the preceding target (0x60F2
//! positioning option code 0, "relative to the preceding (internal absolute) target"); the first
//! relative set-point after entering the mode is relative to the demand position then.
//!
//! **Target reached** (bit 10): the last set-point is done (demand at target, standstill) and
//! the actual position is within 0x6067 position window of it for 0x6068 position window time;
//! while halted (bit 8), bit 10 is set once the axis stands still. A new set-point clears it.
//!
//! **Limits**: the target is clamped into 0x607D (bit 11 while the set-point in progress was
//! clamped); the profile velocity is capped at 0x607F.
//!
//! Sources: CiA 402-2 object 0x6040/0x6041 PP bit definitions as drive manuals restate them
//! (Synapticon SOMANET "Setting set-points"; Bonfiglioli ACTIVE Cube CM-PROFINET p. 89: bits 4, 5,
//! 6, 8, 9, 10, 12) — reached through the search tool; the buffer-full behaviour of bit 12 is the
//! one of the CiA 402-2 "set of set-points" timing figure.

use super::SoftwarePositionLimit;
use super::controlword::{
    CHANGE_ON_SET_POINT, CHANGE_SET_IMMEDIATELY, HALT, NEW_SET_POINT, RELATIVE,
};
use super::profile::{Ramps, Trajectory, clamp_position};

/// The objects profile position reads each cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PpParameters {
    /// 0x607A target position, counts.
    pub target: i32,
    /// 0x6081 profile velocity, counts/s.
    pub profile_velocity: u32,
    /// 0x6083 profile acceleration, counts/s².
    pub acceleration: u32,
    /// 0x6084 profile deceleration, counts/s².
    pub deceleration: u32,
    /// 0x607F max profile velocity, counts/s.
    pub max_velocity: u32,
    /// 0x607D software position limit.
    pub limit: SoftwarePositionLimit,
    /// 0x6067 position window, counts (0xFFFF_FFFF: the window is off, reached = demand done).
    pub window: u32,
    /// 0x6068 position window time, ms.
    pub window_time: u16,
    /// The deceleration of the halt ramp (0x605D resolved by the drive), counts/s².
    pub halt_deceleration: u32,
}

/// The mode-specific statusword bits of one cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PpStatus {
    /// Bit 10.
    pub target_reached: bool,
    /// Bit 12.
    pub set_point_acknowledge: bool,
    /// Bit 11 (the set-point in progress was clamped into 0x607D).
    pub internal_limit: bool,
}

/// One accepted set-point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct SetPoint {
    /// Absolute, clamped into 0x607D.
    target: i64,
    /// min(0x6081, 0x607F) when taken.
    velocity: u32,
    acceleration: u32,
    deceleration: u32,
    /// Controlword bit 9 when taken.
    change_on_set_point: bool,
    /// Whether the target was clamped.
    clamped: bool,
}

/// The profile position function of one axis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ProfilePosition {
    active: Option<SetPoint>,
    buffered: Option<SetPoint>,
    acknowledge: bool,
    /// Bit 4 of the previous cycle.
    new_set_point: bool,
    /// The preceding target, the base of relative set-points.
    base: i64,
    /// Time the actual position has been inside the position window, ns.
    in_window: u32,
}

impl ProfilePosition {
    /// No set-point, relative moves based at 0.
    pub const fn new() -> Self {
        Self {
            active: None,
            buffered: None,
            acknowledge: false,
            new_set_point: false,
            base: 0,
            in_window: 0,
        }
    }

    /// Entering the mode (or leaving Operation enabled): set-points are dropped, relative moves
    /// are based at the demand `position`; a bit 4 already set needs a new rising edge.
    pub fn enter(&mut self, position: i64, controlword: u16) {
        *self = Self {
            base: position,
            new_set_point: controlword & NEW_SET_POINT != 0,
            ..Self::new()
        };
    }

    /// Whether a set-point waits in the buffer.
    pub const fn buffered(&self) -> bool {
        self.buffered.is_some()
    }

    /// One cycle in Operation enabled: the handshake, then one step of `trajectory`;
    /// `actual` is 0x6064 for the position window.
    pub fn update(
        &mut self,
        controlword: u16,
        p: &PpParameters,
        actual: i64,
        trajectory: &mut Trajectory,
        dt_ns: u32,
    ) -> PpStatus {
        self.handshake(controlword, p, trajectory.position());
        let halted = controlword & HALT != 0;
        let done = if halted {
            trajectory.stop(p.halt_deceleration, dt_ns)
        } else {
            self.follow(trajectory, dt_ns)
        };
        if !halted && done && self.buffered.is_none() {
            let target = self.active.map_or(trajectory.position(), |s| s.target);
            let inside = target.abs_diff(actual) <= u64::from(p.window);
            self.in_window = if inside {
                self.in_window.saturating_add(dt_ns)
            } else {
                0
            };
        } else {
            self.in_window = 0;
        }
        let window_time = u32::from(p.window_time).saturating_mul(1_000_000);
        let settled = self.in_window > 0 && self.in_window >= window_time.max(1);
        PpStatus {
            target_reached: if halted { done } else { settled },
            set_point_acknowledge: self.acknowledge,
            internal_limit: self.active.is_some_and(|s| s.clamped),
        }
    }

    /// Bit 4's rising edge takes a set-point; bit 12 follows the buffer.
    fn handshake(&mut self, controlword: u16, p: &PpParameters, demand: i64) {
        let bit4 = controlword & NEW_SET_POINT != 0;
        let edge = bit4 && !self.new_set_point;
        self.new_set_point = bit4;
        if edge && !self.acknowledge {
            let base = if controlword & RELATIVE != 0 {
                self.base
            } else {
                0
            };
            let (target, clamped) =
                clamp_position(p.limit, base.saturating_add(i64::from(p.target)));
            let set_point = SetPoint {
                target,
                velocity: p.profile_velocity.min(p.max_velocity),
                acceleration: p.acceleration,
                deceleration: p.deceleration,
                change_on_set_point: controlword & CHANGE_ON_SET_POINT != 0,
                clamped,
            };
            self.base = target;
            self.in_window = 0;
            let immediately = controlword & CHANGE_SET_IMMEDIATELY != 0;
            let idle = self.active.is_none_or(|s| s.target == demand);
            if immediately || idle {
                self.active = Some(set_point);
                self.buffered = None;
            } else {
                self.buffered = Some(set_point);
            }
            self.acknowledge = true;
        } else if !bit4 && self.buffered.is_none() {
            self.acknowledge = false;
        }
    }

    /// One step towards the active set-point; true when all set-points are done.
    fn follow(&mut self, trajectory: &mut Trajectory, dt_ns: u32) -> bool {
        let Some(current) = self.active else {
            return trajectory.stop(u32::MAX, dt_ns);
        };
        let ramps = Ramps {
            velocity: current.velocity,
            acceleration: current.acceleration,
            deceleration: current.deceleration,
        };
        let before = trajectory.position();
        let blend = self.buffered.filter(|next| {
            current.change_on_set_point
                && (current.target - before).signum() == (next.target - current.target).signum()
        });
        let arrived = match blend {
            Some(next) => {
                trajectory.to_position(next.target, ramps, dt_ns);
                let dir = (current.target - before).signum();
                (trajectory.position() - current.target) * dir >= 0
            }
            None => trajectory.to_position(current.target, ramps, dt_ns),
        };
        if arrived && let Some(next) = self.buffered.take() {
            self.active = Some(next);
            return false;
        }
        arrived && self.buffered.is_none() && trajectory.standstill()
    }
}
