//! Homing mode (mode 6; CiA 402-2 / IEC 61800-7-201 §6.4 "homing mode"; ETG.6010 lists the same
//! methods): 0x6098 homing method, 0x6099:01 speed during search for switch, 0x6099:02 speed
//! during search for zero, 0x609A homing acceleration, 0x607C home offset.
//!
//! The application provides the inputs each cycle ([`HomingInputs`]: negative and positive limit
//! switch, home switch, index pulse); the positions are those of the demand (one cycle's
//! resolution; a drive with a latch unit passes the index pulse of the cycle it latched in).
//!
//! **Methods** ([`Method::of`]): every method is a reference *edge* of one switch, approached in
//! a final direction either leaving the switch (active → inactive) or entering it, optionally
//! followed by the first index pulse in that direction:
//!
//! | method | switch | first search | final approach | index |
//! |---|---|---|---|---|
//! | 1 / 17 | negative limit | − | + leaving | yes / no |
//! | 2 / 18 | positive limit | + | − leaving | yes / no |
//! | 3 / 19 | home (active on the + side) | + | − leaving | yes / no |
//! | 4 / 20 | home (active on the + side) | + | + entering | yes / no |
//! | 5 / 21 | home (active on the − side) | − | + leaving | yes / no |
//! | 6 / 22 | home (active on the − side) | − | − entering | yes / no |
//! | 7 / 23 | home cam, + limit reverses | + | − leaving (lower edge) | yes / no |
//! | 8 / 24 | home cam, + limit reverses | + | + entering (lower edge) | yes / no |
//! | 9 / 25 | home cam, + limit reverses | + | − entering (upper edge) | yes / no |
//! | 10 / 26 | home cam, + limit reverses | + | + leaving (upper edge) | yes / no |
//! | 11 / 27 | home cam, − limit reverses | − | + leaving (upper edge) | yes / no |
//! | 12 / 28 | home cam, − limit reverses | − | − entering (upper edge) | yes / no |
//! | 13 / 29 | home cam, − limit reverses | − | + entering (lower edge) | yes / no |
//! | 14 / 30 | home cam, − limit reverses | − | − leaving (lower edge) | yes / no |
//! | 33 / 34 | — | — | − / + | yes |
//! | 35, 37 | current position is the home position | | | |
//!
//! 15, 16, 31, 32, 36 and other codes are reserved: starting them is a homing error.
//!
//! **Sequence**: outside the switch, search at 0x6099:01 in the first search direction until it
//! is active; for a leaving approach then move at 0x6099:02 in the final direction until it is
//! inactive; for an entering approach first back off against the final direction until it is
//! inactive, then move in the final direction until it is active again; then, with index, on to
//! the first index pulse. Starting on the switch skips the search. A limit switch met in the
//! direction of motion reverses the search of methods 7–14 once; any other limit switch met is
//! a homing error. At the reference the position is redefined so that the reference reads 0x607C
//! home offset ("the zero position is offset from the home position by adding the home offset",
//! CiA 402-2 0x607C as restated in the Elmo DS 402 implementation guide, §9.2), and the axis
//! brakes with 0x609A.
//!
//! **Statusword** (bits 13 homing error, 12 homing attained, 10 target reached):
//! in progress 0/0/0, interrupted or not started 0/0/1, attained but target not reached 0/1/0,
//! completed 0/1/1, error while moving 1/0/0, error at standstill 1/0/1. Controlword bit 4
//! starts on its rising edge; its falling edge and the halt bit (8, with the 0x605D ramp)
//! interrupt.

use super::controlword::{HALT, HOMING_START};
use super::profile::{Ramps, Trajectory};

/// The objects homing reads.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HomingParameters {
    /// 0x6098 homing method.
    pub method: i8,
    /// 0x6099:01 speed during search for switch, counts/s.
    pub switch_speed: u32,
    /// 0x6099:02 speed during search for zero, counts/s.
    pub zero_speed: u32,
    /// 0x609A homing acceleration, counts/s².
    pub acceleration: u32,
    /// 0x607C home offset, counts.
    pub home_offset: i32,
    /// 0x607F max profile velocity, counts/s (caps both speeds).
    pub max_velocity: u32,
    /// The deceleration of the halt ramp (0x605D resolved by the drive), counts/s².
    pub halt_deceleration: u32,
}

/// The switches and the index pulse as the application reads them this cycle (the bits of
/// 0x60FD digital inputs, and the encoder's zero pulse).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HomingInputs {
    /// 0x60FD bit 0.
    pub negative_limit: bool,
    /// 0x60FD bit 1.
    pub positive_limit: bool,
    /// 0x60FD bit 2.
    pub home_switch: bool,
    /// An index (zero) pulse occurred this cycle.
    pub index_pulse: bool,
}

/// The mode-specific statusword bits of one cycle, and the coordinate change of this cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HomingStatus {
    /// Bit 10.
    pub target_reached: bool,
    /// Bit 12.
    pub attained: bool,
    /// Bit 13.
    pub error: bool,
    /// Counts added to the position this cycle (the reference became 0x607C): the application
    /// shifts its actual position by as much.
    pub shift: i64,
}

/// The switch a method references.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Switch {
    /// 0x60FD bit 0.
    NegativeLimit,
    /// 0x60FD bit 1.
    PositiveLimit,
    /// 0x60FD bit 2.
    Home,
    /// No switch: the index pulse alone (33, 34).
    None,
}

/// A homing method as the sequence executes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Method {
    /// The reference switch.
    pub switch: Switch,
    /// The first search direction, ±1.
    pub search: i8,
    /// Whether a limit switch in the search direction reverses it (7–14).
    pub reverse_at_limit: bool,
    /// The final approach direction, ±1.
    pub approach: i8,
    /// Whether the final approach leaves the switch (else enters it).
    pub leaving: bool,
    /// Whether the index pulse after the edge is the reference.
    pub index: bool,
}

impl Method {
    /// The method with code `code` (0x6098), `Some(None)` for 35 and 37 (current position),
    /// `None` for a reserved code.
    pub const fn of(code: i8) -> Option<Option<Self>> {
        let index = code <= 14 || code >= 33;
        let base = if code > 16 && code <= 30 {
            code - 16
        } else {
            code
        };
        let (switch, search, reverse_at_limit, approach, leaving) = match base {
            1 => (Switch::NegativeLimit, -1, false, 1, true),
            2 => (Switch::PositiveLimit, 1, false, -1, true),
            3 => (Switch::Home, 1, false, -1, true),
            4 => (Switch::Home, 1, false, 1, false),
            5 => (Switch::Home, -1, false, 1, true),
            6 => (Switch::Home, -1, false, -1, false),
            7 => (Switch::Home, 1, true, -1, true),
            8 => (Switch::Home, 1, true, 1, false),
            9 => (Switch::Home, 1, true, -1, false),
            10 => (Switch::Home, 1, true, 1, true),
            11 => (Switch::Home, -1, true, 1, true),
            12 => (Switch::Home, -1, true, -1, false),
            13 => (Switch::Home, -1, true, 1, false),
            14 => (Switch::Home, -1, true, -1, true),
            33 => (Switch::None, -1, false, -1, true),
            34 => (Switch::None, 1, false, 1, true),
            35 | 37 => return Some(None),
            _ => return None,
        };
        Some(Some(Self {
            switch,
            search,
            reverse_at_limit,
            approach,
            leaving,
            index,
        }))
    }
}

/// Where the sequence is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Not started since entering the mode, or interrupted.
    Idle,
    /// Fast search for the switch in `dir`; `reversed` after a limit switch turned it.
    Search { dir: i8, reversed: bool },
    /// Slow, against the final direction, until the switch is inactive (entering approaches).
    BackOff,
    /// Slow, in the final direction, until the switch is at the final level.
    Approach,
    /// Slow, in the final direction, until the index pulse.
    Index,
    /// The reference is set; braking.
    Attained,
    /// A homing error; braking.
    Error,
}

/// The homing function of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Homing {
    phase: Phase,
    method: Option<Method>,
    /// Bit 4 of the previous cycle.
    start: bool,
}

impl Default for Homing {
    fn default() -> Self {
        Self::new()
    }
}

impl Homing {
    /// Not started.
    pub const fn new() -> Self {
        Self {
            phase: Phase::Idle,
            method: None,
            start: false,
        }
    }

    /// Entering the mode: not started; a bit 4 already set needs a new rising edge.
    pub fn enter(&mut self, controlword: u16) {
        *self = Self {
            start: controlword & HOMING_START != 0,
            ..Self::new()
        };
    }

    /// One cycle in Operation enabled.
    pub fn update(
        &mut self,
        controlword: u16,
        p: &HomingParameters,
        inputs: HomingInputs,
        trajectory: &mut Trajectory,
        dt_ns: u32,
    ) -> HomingStatus {
        let bit4 = controlword & HOMING_START != 0;
        let rising = bit4 && !self.start;
        self.start = bit4;
        let halted = controlword & HALT != 0;
        let mut shift = 0;
        if rising && !halted {
            shift = self.begin(p, inputs, trajectory);
        } else if (!bit4 || halted) && self.running() {
            self.phase = Phase::Idle;
        }
        if self.running() {
            shift = self.advance(inputs, p, trajectory);
        }
        let ramps = Ramps {
            velocity: p.zero_speed.max(p.switch_speed).min(p.max_velocity),
            acceleration: p.acceleration,
            deceleration: p.acceleration,
        };
        let standstill = match self.phase {
            Phase::Search { dir, .. } => {
                let speed = i64::from(p.switch_speed.min(p.max_velocity));
                trajectory.to_velocity(i64::from(dir) * speed, ramps, dt_ns);
                false
            }
            Phase::BackOff | Phase::Approach | Phase::Index => {
                let dir = self.method.map_or(0, |m| match self.phase {
                    Phase::BackOff => -m.approach,
                    _ => m.approach,
                });
                let speed = i64::from(p.zero_speed.min(p.max_velocity));
                trajectory.to_velocity(i64::from(dir) * speed, ramps, dt_ns);
                false
            }
            Phase::Idle if halted => trajectory.stop(p.halt_deceleration, dt_ns),
            Phase::Idle | Phase::Attained | Phase::Error => trajectory.stop(p.acceleration, dt_ns),
        };
        HomingStatus {
            target_reached: standstill,
            attained: self.phase == Phase::Attained,
            error: self.phase == Phase::Error,
            shift,
        }
    }

    const fn running(&self) -> bool {
        matches!(
            self.phase,
            Phase::Search { .. } | Phase::BackOff | Phase::Approach | Phase::Index
        )
    }

    /// Starts the method of 0x6098: the first phase from where the switch is; 35/37 finish at
    /// once. Returns the coordinate shift.
    fn begin(&mut self, p: &HomingParameters, inputs: HomingInputs, t: &mut Trajectory) -> i64 {
        match Method::of(p.method) {
            None => {
                self.phase = Phase::Error;
                self.method = None;
                0
            }
            Some(None) => {
                self.method = None;
                self.phase = Phase::Attained;
                reference(t, p)
            }
            Some(Some(method)) => {
                self.method = Some(method);
                let on = level(method.switch, inputs);
                self.phase = match (method.switch, on, method.leaving) {
                    (Switch::None, _, _) => Phase::Index,
                    (_, false, _) => Phase::Search {
                        dir: method.search,
                        reversed: false,
                    },
                    (_, true, true) => Phase::Approach,
                    (_, true, false) => Phase::BackOff,
                };
                0
            }
        }
    }

    /// The phase transitions of this cycle's inputs; the shift when the reference is found.
    fn advance(&mut self, inputs: HomingInputs, p: &HomingParameters, t: &mut Trajectory) -> i64 {
        let Some(m) = self.method else {
            self.phase = Phase::Error;
            return 0;
        };
        let on = level(m.switch, inputs);
        let dir = match self.phase {
            Phase::Search { dir, .. } => dir,
            Phase::BackOff => -m.approach,
            _ => m.approach,
        };
        // A limit switch in the direction of motion that is not the reference.
        let blocked = match dir {
            1 => inputs.positive_limit && m.switch != Switch::PositiveLimit,
            _ => inputs.negative_limit && m.switch != Switch::NegativeLimit,
        };
        let mut found = false;
        self.phase = match self.phase {
            Phase::Search { .. } if on && m.leaving => Phase::Approach,
            Phase::Search { .. } if on => Phase::BackOff,
            Phase::Search { dir, reversed } if blocked && m.reverse_at_limit && !reversed => {
                Phase::Search {
                    dir: -dir,
                    reversed: true,
                }
            }
            Phase::BackOff if !on => Phase::Approach,
            Phase::Approach if on != m.leaving => {
                if m.index {
                    Phase::Index
                } else {
                    found = true;
                    Phase::Attained
                }
            }
            Phase::Index if inputs.index_pulse => {
                found = true;
                Phase::Attained
            }
            _ if blocked => Phase::Error,
            phase => phase,
        };
        if found { reference(t, p) } else { 0 }
    }
}

/// The level of the reference switch.
const fn level(switch: Switch, inputs: HomingInputs) -> bool {
    match switch {
        Switch::NegativeLimit => inputs.negative_limit,
        Switch::PositiveLimit => inputs.positive_limit,
        Switch::Home => inputs.home_switch,
        Switch::None => false,
    }
}

/// Makes the demand position the home offset; the shift.
fn reference(t: &mut Trajectory, p: &HomingParameters) -> i64 {
    let shift = i64::from(p.home_offset) - t.position();
    t.shift(shift);
    shift
}
