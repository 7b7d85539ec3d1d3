//! The simulated motor: an ideal velocity source with a torque input for CST. Position is the
//! integral of velocity over the cycle time, kept exact with a sub-count remainder.

/// Nanoseconds per second.
const NS_PER_S: i64 = 1_000_000_000;

/// Acceleration in counts/s² per 0.1 % of rated torque (the simulated load's inertia).
pub const TORQUE_ACCELERATION: i64 = 1_000;

/// The state of the simulated motor.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Motor {
    /// Counts.
    position: i32,
    /// Counts·ns not yet a whole count, |remainder| < 1 s.
    remainder: i64,
    /// Counts/s.
    velocity: i32,
}

impl Motor {
    /// A motor at rest at position 0.
    pub const fn new() -> Self {
        Self {
            position: 0,
            remainder: 0,
            velocity: 0,
        }
    }

    /// Position in counts.
    pub const fn position(&self) -> i32 {
        self.position
    }

    /// Velocity in counts/s.
    pub const fn velocity(&self) -> i32 {
        self.velocity
    }

    /// Whether the motor stands still.
    pub const fn standstill(&self) -> bool {
        self.velocity == 0
    }

    /// Runs at `velocity` from now on (an ideal velocity loop).
    pub fn set_velocity(&mut self, velocity: i32) {
        self.velocity = velocity;
    }

    /// Changes the velocity by `acceleration` (counts/s²) over `dt_ns`.
    pub fn accelerate(&mut self, acceleration: i64, dt_ns: u32) {
        let delta = acceleration.saturating_mul(i64::from(dt_ns)) / NS_PER_S;
        self.velocity = saturate(i64::from(self.velocity).saturating_add(delta));
    }

    /// Decelerates towards standstill by `deceleration` (counts/s²) over `dt_ns`, by at least
    /// 1 count/s so that every ramp ends; 0 stops at once.
    pub fn decelerate(&mut self, deceleration: u32, dt_ns: u32) {
        let step = u64::from(deceleration).saturating_mul(u64::from(dt_ns)) / 1_000_000_000;
        let step = i64::try_from(step).unwrap_or(i64::MAX).max(1);
        let speed = i64::from(self.velocity.unsigned_abs());
        let slower = if deceleration == 0 {
            0
        } else {
            (speed - step).max(0)
        };
        self.velocity = saturate(slower) * self.velocity.signum();
    }

    /// Advances the position by velocity × `dt_ns`.
    pub fn integrate(&mut self, dt_ns: u32) {
        let travel = i64::from(self.velocity)
            .saturating_mul(i64::from(dt_ns))
            .saturating_add(self.remainder);
        self.remainder = travel % NS_PER_S;
        self.position = saturate(i64::from(self.position).saturating_add(travel / NS_PER_S));
    }

    /// Arrives exactly at `position` within this cycle, moving at `velocity`.
    pub fn move_to(&mut self, position: i32, velocity: i32) {
        self.position = position;
        self.remainder = 0;
        self.velocity = velocity;
    }

    /// Moves the coordinate system by `delta` counts (homing): the motor stays where it is.
    pub fn shift(&mut self, delta: i64) {
        self.position = saturate(i64::from(self.position).saturating_add(delta));
    }

    /// Stops at `position` (a hard limit): velocity 0, no sub-count remainder.
    pub fn stop_at(&mut self, position: i32) {
        self.move_to(position, 0);
    }
}

/// `value` clamped into `i32`.
pub(crate) fn saturate(value: i64) -> i32 {
    i32::try_from(value).unwrap_or(if value < 0 { i32::MIN } else { i32::MAX })
}

/// The simulated machine around the motor: limit switches, a home cam and the encoder's index
/// pulse, at physical positions (counts from where the motor was at power on; homing moves the
/// reported position, not these).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Machine {
    /// The negative limit switch is active at or below this position.
    pub negative_limit: i64,
    /// The positive limit switch is active at or above this position.
    pub positive_limit: i64,
    /// The home switch is active from `.0` to `.1` (inclusive).
    pub home: (i64, i64),
    /// Counts per revolution: one index pulse per period.
    pub index_period: i64,
    /// Where the index pulses sit within a period.
    pub index_phase: i64,
}

impl Machine {
    /// Limits at ±100 000 counts, a home cam from 5 000 to 8 000, 4 000 counts per revolution
    /// with the index at 500 (…, 500, 4 500, 8 500, …).
    pub const DEFAULT: Self = Self {
        negative_limit: -100_000,
        positive_limit: 100_000,
        home: (5_000, 8_000),
        index_period: 4_000,
        index_phase: 500,
    };

    /// Negative limit, positive limit and home switch at physical `position`.
    pub const fn switches(&self, position: i64) -> (bool, bool, bool) {
        (
            position <= self.negative_limit,
            position >= self.positive_limit,
            position >= self.home.0 && position <= self.home.1,
        )
    }

    /// Whether the motor passed an index pulse moving from `before` to `now`: a pulse in
    /// `(before, now]` moving up, in `[now, before)` moving down.
    pub fn index_passed(&self, before: i64, now: i64) -> bool {
        let period = self.index_period.max(1);
        // `checked_`: no division-overflow panic path (the period is positive anyway).
        let revolution = |x: i64| {
            x.saturating_sub(self.index_phase)
                .checked_div_euclid(period)
                .unwrap_or(0)
        };
        match now.cmp(&before) {
            core::cmp::Ordering::Greater => revolution(now) != revolution(before),
            core::cmp::Ordering::Less => revolution(now - 1) != revolution(before - 1),
            core::cmp::Ordering::Equal => false,
        }
    }
}

impl Default for Machine {
    fn default() -> Self {
        Self::DEFAULT
    }
}
