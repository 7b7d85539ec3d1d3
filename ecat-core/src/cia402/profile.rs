//! The trapezoidal profile generator of the profile modes (CiA 402-2 profile position, profile
//! velocity and homing: "the trajectory generator"; IEC 61800-7-201 §6.3 profile position mode,
//! Figure "trajectory generator"), and the limit functions every mode applies (0x607D software
//! position limit, 0x607F max profile velocity, 0x6072 max torque).
//!
//! **Arithmetic.** Integers only, no floating point: positions are `i64` counts with a sub-count
//! remainder in count·ns, velocities counts/s, accelerations counts/s². The braking distance is
//! solved with [`u64::isqrt`] (a fixed number of steps), so one update is bounded work with no
//! loop and no FPU (f32 would lose whole counts on moves longer than 2²⁴ counts; a Cortex-M4F
//! has no double-precision unit). Products that could overflow saturate; they saturate only
//! beyond any value a 32-bit object can hold.
//!
//! **Discrete ramps.** Per cycle of `dt` the velocity changes by at most `a·dt` (accelerating)
//! or `d·dt` (decelerating), at least 1 count/s so that every ramp ends. A position move never
//! runs faster than the speed from which the discrete braking sequence `v, v − d·dt, …` still
//! stops within the remaining distance, and arrives exactly on the target count.

/// Nanoseconds per second.
const NS_PER_S: i64 = 1_000_000_000;

// `max(..).min(..)` rather than `clamp`: `Ord::clamp` asserts min <= max, a panic path the
// compiler keeps although the bounds here are ordered by construction.

/// The ramp parameters of one move.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Ramps {
    /// The speed not to exceed, counts/s (PP: min(0x6081, 0x607F); PV: 0x607F).
    pub velocity: u32,
    /// counts/s² when speeding up (0x6083, homing: 0x609A).
    pub acceleration: u32,
    /// counts/s² when slowing down (0x6084, halt: 0x605D's ramp, homing: 0x609A).
    pub deceleration: u32,
}

/// The demand of a profile mode: position and velocity, advanced one cycle at a time.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Trajectory {
    /// Counts.
    position: i64,
    /// Count·ns not yet a whole count, |remainder| < 1 s.
    remainder: i64,
    /// Counts/s.
    velocity: i64,
}

impl Trajectory {
    /// At rest at 0.
    pub const fn new() -> Self {
        Self {
            position: 0,
            remainder: 0,
            velocity: 0,
        }
    }

    /// The demand position, counts.
    pub const fn position(&self) -> i64 {
        self.position
    }

    /// The demand velocity, counts/s.
    pub const fn velocity(&self) -> i64 {
        self.velocity
    }

    /// Whether the demand stands still.
    pub const fn standstill(&self) -> bool {
        self.velocity == 0
    }

    /// Takes over the actual `position` and `velocity` (entering a profile mode, or while the
    /// drive function is off: the demand follows the motor).
    pub fn follow(&mut self, position: i64, velocity: i64) {
        *self = Self {
            position,
            remainder: 0,
            velocity,
        };
    }

    /// Moves the coordinate system by `delta` counts (homing sets the home position).
    pub fn shift(&mut self, delta: i64) {
        self.position = self.position.saturating_add(delta);
    }

    /// One cycle towards `target` (absolute, counts) within `ramps`; true when the demand is at
    /// `target` and stands still.
    pub fn to_position(&mut self, target: i64, ramps: Ramps, dt_ns: u32) -> bool {
        let dt = i64::from(dt_ns.max(1));
        // The exact distance left, in count·ns: the whole counts less the sub-count remainder
        // already travelled.
        let remaining = target
            .saturating_sub(self.position)
            .saturating_mul(NS_PER_S)
            .saturating_sub(self.remainder);
        if remaining == 0 && self.velocity == 0 {
            return true;
        }
        let dir = if remaining < 0 { -1 } else { 1 };
        let speed = self.velocity * dir;
        let accelerate = step(ramps.acceleration, dt);
        let brake = step(ramps.deceleration, dt);
        let distance = remaining.unsigned_abs();
        // The velocity that covers `distance` in exactly one cycle.
        let one_cycle = i64::try_from(distance / dt.unsigned_abs()).unwrap_or(i64::MAX);
        let max = i64::from(ramps.velocity);
        let wanted = if speed < 0 {
            (speed + brake).min(0)
        } else {
            speed.saturating_add(accelerate).min(max)
        };
        let next = wanted
            .min(stopping_speed(one_cycle, brake))
            .max(speed - brake);
        let reaches = u64::try_from(next)
            .unwrap_or(0)
            .saturating_mul(dt.unsigned_abs())
            >= distance;
        if reaches && speed - brake <= one_cycle {
            // Arrives this cycle: exactly on the target, at the average speed of the cycle.
            self.position = target;
            self.remainder = 0;
            self.velocity = dir * one_cycle;
            return false;
        }
        self.velocity = next * dir;
        self.integrate(dt);
        false
    }

    /// One cycle towards the velocity `target` (counts/s, clamped into ±`ramps.velocity`):
    /// [`Ramps::acceleration`] while the speed grows, [`Ramps::deceleration`] while it falls
    /// (through zero when the sign changes). True when at `target`.
    pub fn to_velocity(&mut self, target: i64, ramps: Ramps, dt_ns: u32) -> bool {
        let dt = i64::from(dt_ns.max(1));
        let max = i64::from(ramps.velocity);
        let target = target.max(-max).min(max);
        let v = self.velocity;
        let slowing = v != 0 && (target.signum() != v.signum() || target.abs() < v.abs());
        self.velocity = if slowing {
            let floor = if target.signum() == v.signum() {
                target.abs()
            } else {
                0
            };
            v.signum() * (v.abs() - step(ramps.deceleration, dt)).max(floor)
        } else if target > v {
            v.saturating_add(step(ramps.acceleration, dt)).min(target)
        } else {
            v.saturating_sub(step(ramps.acceleration, dt)).max(target)
        };
        self.integrate(dt);
        self.velocity == target
    }

    /// One cycle of braking with `deceleration` (counts/s²); true at standstill.
    pub fn stop(&mut self, deceleration: u32, dt_ns: u32) -> bool {
        let ramps = Ramps {
            velocity: u32::MAX,
            acceleration: deceleration,
            deceleration,
        };
        self.to_velocity(0, ramps, dt_ns)
    }

    /// Advances the position by velocity × dt.
    fn integrate(&mut self, dt: i64) {
        let travel = self
            .velocity
            .saturating_mul(dt)
            .saturating_add(self.remainder);
        self.remainder = travel % NS_PER_S;
        self.position = self.position.saturating_add(travel / NS_PER_S);
    }
}

/// The velocity change of one cycle at `rate` counts/s², at least 1 count/s.
fn step(rate: u32, dt: i64) -> i64 {
    (i64::from(rate).saturating_mul(dt) / NS_PER_S).max(1)
}

/// The highest speed (counts/s) from which braking by `brake` per cycle stops within the
/// distance one cycle at `one_cycle` counts/s covers: the braking sequence `v, v − b, …, b`
/// covers `v(v + b)/(2b)` cycles' worth, so `v ≤ (√(b² + 8·b·w) − b)/2` with `w` = `one_cycle`.
fn stopping_speed(one_cycle: i64, brake: i64) -> i64 {
    let b = brake.unsigned_abs();
    let w = one_cycle.unsigned_abs();
    let radicand = b
        .saturating_mul(b)
        .saturating_add(b.saturating_mul(8).saturating_mul(w));
    let root = radicand.isqrt();
    i64::try_from((root.saturating_sub(b)) / 2).unwrap_or(i64::MAX)
}

/// `target` clamped into the software position limits 0x607D (active when `min < max`), and
/// whether it was outside (statusword bit 11, internal limit active).
pub(crate) fn clamp_position(limit: super::SoftwarePositionLimit, target: i64) -> (i64, bool) {
    if limit.min >= limit.max {
        return (target, false);
    }
    let clamped = target.max(i64::from(limit.min)).min(i64::from(limit.max));
    (clamped, clamped != target)
}

/// `velocity` clamped into ±0x607F max profile velocity, and whether it was outside.
pub(crate) fn clamp_velocity(velocity: i64, max: u32) -> (i64, bool) {
    let max = i64::from(max);
    let clamped = velocity.max(-max).min(max);
    (clamped, clamped != velocity)
}

/// `torque` (0.1 % of rated torque) clamped into ±0x6072 max torque, and whether it was outside.
pub fn clamp_torque(torque: i16, max: u16) -> (i16, bool) {
    let max = i16::try_from(max).unwrap_or(i16::MAX);
    let clamped = torque.max(-max).min(max);
    (clamped, clamped != torque)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: u32 = 1_000_000;

    #[test]
    fn a_short_move_lands_exactly() {
        let mut t = Trajectory::new();
        let ramps = Ramps {
            velocity: 100_000,
            acceleration: 1_000_000,
            deceleration: 1_000_000,
        };
        let mut n = 0;
        while !t.to_position(1_000, ramps, MS) {
            n += 1;
            assert!(n < 1_000);
            assert!(t.position() <= 1_000);
        }
        assert_eq!(t.position(), 1_000);
    }
}
