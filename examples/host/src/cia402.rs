//! The MainDevice's side of a CiA402 drive, as the demo drives one: where the drive's objects sit in
//! the process image (read from its PDO configuration over SDO), the controlword sequence that
//! enables it, and a motion script (homing, a profile position move with a set of two set-points,
//! a smooth CSP move, a CSV segment, a halt, a quick stop).
//!
//! The drive's own side (state machine, statusword, modes) is `ecat_core::cia402`; this module
//! reuses its statusword decoding and mode numbers.

use std::collections::HashMap;
use std::ops::Deref;

pub use ecat_core::cia402::State;
use ecat_core::cia402::controlword::{FAULT_RESET, HALT, NEW_SET_POINT};
use ecat_core::cia402::statusword::{
    HOMING_ATTAINED, HOMING_ERROR, SET_POINT_ACKNOWLEDGE, TARGET_REACHED,
};
use ecat_core::cia402::{Command as ControlCommand, Mode};
use ethercrab::SubDeviceRef;
use ethercrab::error::Error;

/// The names of the modes set in a 0x6502 value.
pub fn mode_names(supported: u32) -> String {
    let names: Vec<&str> = (1..=10i8)
        .filter_map(Mode::from_code)
        .filter(|m| supported & m.supported_bit() != 0)
        .map(|m| match m {
            Mode::ProfilePosition => "PP",
            Mode::ProfileVelocity => "PV",
            Mode::ProfileTorque => "PT",
            Mode::Homing => "HM",
            Mode::CyclicSyncPosition => "CSP",
            Mode::CyclicSyncVelocity => "CSV",
            Mode::CyclicSyncTorque => "CST",
        })
        .collect();
    names.join(", ")
}

/// A short name of a PDS state.
pub fn state_name(state: Option<State>) -> &'static str {
    match state {
        Some(State::NotReadyToSwitchOn) => "not ready",
        Some(State::SwitchOnDisabled) => "switch on disabled",
        Some(State::ReadyToSwitchOn) => "ready to switch on",
        Some(State::SwitchedOn) => "switched on",
        Some(State::OperationEnabled) => "operation enabled",
        Some(State::QuickStopActive) => "quick stop active",
        Some(State::FaultReactionActive) => "fault reaction",
        Some(State::Fault) => "fault",
        None => "?",
    }
}

/// Where one mapped object sits in an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Slot {
    byte: usize,
    bits: u8,
}

/// The byte offsets of the mapped objects in the output and input images, as the drive's PDO
/// assignment (0x1C12/0x1C13) and mappings (0x16xx/0x1Axx) say.
#[derive(Debug, Clone)]
pub struct Pdo {
    outputs_at: HashMap<u16, Slot>,
    inputs_at: HashMap<u16, Slot>,
    /// Output image bytes.
    pub outputs: usize,
    /// Input image bytes.
    pub inputs: usize,
}

/// What the MainDevice sends each cycle.
#[derive(Debug, Clone, Copy, Default)]
pub struct Command {
    /// 0x6040.
    pub controlword: u16,
    /// 0x6060.
    pub mode: i8,
    /// 0x607A, counts.
    pub target_position: i32,
    /// 0x60FF, counts/s.
    pub target_velocity: i32,
    /// 0x6081, counts/s.
    pub profile_velocity: u32,
    /// 0x6083, counts/s².
    pub profile_acceleration: u32,
    /// 0x6084, counts/s².
    pub profile_deceleration: u32,
}

/// What the drive reports each cycle.
#[derive(Debug, Clone, Copy, Default)]
pub struct Feedback {
    /// 0x6041.
    pub statusword: u16,
    /// 0x6061.
    pub mode: i8,
    /// 0x6064, counts.
    pub position: i32,
    /// 0x606C, counts/s.
    pub velocity: i32,
    /// 0x60F4, counts (0 when not mapped).
    pub following_error: i32,
}

impl Pdo {
    /// Reads the PDO configuration of `sub` (expedited SDO uploads, as ethercrab does itself).
    pub async fn read<S: Deref<Target = ethercrab::SubDevice>>(
        sub: &SubDeviceRef<'_, S>,
    ) -> Result<Self, Error> {
        let (outputs_at, outputs) = Self::image(sub, 0x1C12).await?;
        let (inputs_at, inputs) = Self::image(sub, 0x1C13).await?;
        Ok(Self {
            outputs_at,
            inputs_at,
            outputs,
            inputs,
        })
    }

    async fn image<S: Deref<Target = ethercrab::SubDevice>>(
        sub: &SubDeviceRef<'_, S>,
        assignment: u16,
    ) -> Result<(HashMap<u16, Slot>, usize), Error> {
        let mut slots = HashMap::new();
        let mut bit = 0usize;
        let pdos: u8 = sub.sdo_read(assignment, 0).await?;
        for n in 1..=pdos {
            let pdo: u16 = sub.sdo_read(assignment, n).await?;
            let entries: u8 = sub.sdo_read(pdo, 0).await?;
            for e in 1..=entries {
                let entry: u32 = sub.sdo_read(pdo, e).await?;
                let (index, bits) = ((entry >> 16) as u16, entry as u8);
                if index != 0 && bit.is_multiple_of(8) {
                    slots.insert(
                        index,
                        Slot {
                            byte: bit / 8,
                            bits,
                        },
                    );
                }
                bit += usize::from(bits);
            }
        }
        Ok((slots, bit.div_ceil(8)))
    }

    /// Writes `command` into the output image.
    pub fn write(&self, image: &mut [u8], command: Command) {
        let values = [
            (0x6040, i64::from(command.controlword)),
            (0x6060, i64::from(command.mode)),
            (0x607A, i64::from(command.target_position)),
            (0x60FF, i64::from(command.target_velocity)),
            (0x6081, i64::from(command.profile_velocity)),
            (0x6083, i64::from(command.profile_acceleration)),
            (0x6084, i64::from(command.profile_deceleration)),
        ];
        for (index, value) in values {
            if let Some(slot) = self.outputs_at.get(&index) {
                let bytes = value.to_le_bytes();
                let n = usize::from(slot.bits / 8);
                if let Some(dst) = image.get_mut(slot.byte..slot.byte + n) {
                    dst.copy_from_slice(&bytes[..n]);
                }
            }
        }
    }

    /// Reads the feedback from the input image.
    pub fn read_feedback(&self, image: &[u8]) -> Feedback {
        let get = |index: u16| -> i64 {
            let Some(slot) = self.inputs_at.get(&index) else {
                return 0;
            };
            let n = usize::from(slot.bits / 8);
            let mut bytes = [0u8; 8];
            if let Some(src) = image.get(slot.byte..slot.byte + n) {
                bytes[..n].copy_from_slice(src);
            }
            let shift = 64 - 8 * n as u32;
            (i64::from_le_bytes(bytes) << shift) >> shift
        };
        Feedback {
            statusword: get(0x6041) as u16,
            mode: get(0x6061) as i8,
            position: get(0x6064) as i32,
            velocity: get(0x606C) as i32,
            following_error: get(0x60F4) as i32,
        }
    }
}

/// The stages of the demo's motion script.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Walking the drive to "operation enabled".
    Enable,
    /// Homing (mode 6) with the method the demo wrote to 0x6098.
    Homing,
    /// Profile position (mode 1): two set-points, the second buffered (set of set-points).
    Pp,
    /// A smooth position move in cyclic synchronous position mode.
    Csp,
    /// A velocity segment in cyclic synchronous velocity mode.
    Csv,
    /// Halt (controlword bit 8) while in CSV: the drive stops with its 0x605D ramp.
    Halt,
    /// Quick stop until the drive stands still.
    QuickStop,
    /// Finished.
    Done,
}

impl Phase {
    /// Every phase that moves the axis, in order.
    pub const MOTION: [Phase; 6] = [
        Phase::Homing,
        Phase::Pp,
        Phase::Csp,
        Phase::Csv,
        Phase::Halt,
        Phase::QuickStop,
    ];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Enable => "enable",
            Phase::Homing => "homing",
            Phase::Pp => "PP",
            Phase::Csp => "CSP",
            Phase::Csv => "CSV",
            Phase::Halt => "halt",
            Phase::QuickStop => "quick stop",
            Phase::Done => "done",
        }
    }
}

/// Commanded motion at one instant (NaN where the drive generates the profile itself).
#[derive(Debug, Clone, Copy, Default)]
pub struct Setpoint {
    /// Counts.
    pub position: f64,
    /// Counts/s.
    pub velocity: f64,
}

/// The PP set-points: 60 000 counts, then 20 000 (buffered while the first runs), at
/// 200 000 counts/s with 2 000 000 counts/s² ramps.
pub const PP_TARGETS: [i32; 2] = [60_000, 20_000];
const PP_VELOCITY: u32 = 200_000;
const PP_ACCELERATION: u32 = 2_000_000;
/// The CSP move: distance in counts and duration in s (a cosine velocity profile: smooth
/// acceleration and deceleration).
pub const CSP_DISTANCE: f64 = 200_000.0;
const CSP_TIME: f64 = 1.0;
/// The CSV segment: ramp to this velocity (counts/s) in CSV_RAMP s, hold until CSV_TIME.
pub const CSV_VELOCITY: f64 = 120_000.0;
const CSV_RAMP: f64 = 0.3;
const CSV_TIME: f64 = 0.7;
/// How long the halt bit is held, s.
const HALT_TIME: f64 = 0.12;
/// How long CSV runs again after the halt, before the quick stop, s.
const RESUME_TIME: f64 = 0.1;

/// The motion script: what to command next, from the drive's state and feedback.
#[derive(Debug, Clone)]
pub struct Profile {
    phase: Phase,
    /// Time in the current phase, s.
    t: f64,
    start: f64,
    setpoint: Setpoint,
    command: Command,
    /// PP: set-points sent so far; homing: the drive reported "in progress".
    progress: usize,
    /// PP: the set-point the drive runs to (for the plot).
    shown: usize,
    /// CSV: the segment after the halt.
    resumed: bool,
}

impl Default for Profile {
    fn default() -> Self {
        Self::new()
    }
}

impl Profile {
    /// The script at its start.
    pub fn new() -> Self {
        Self {
            phase: Phase::Enable,
            t: 0.0,
            start: 0.0,
            setpoint: Setpoint::default(),
            command: Command {
                mode: Mode::Homing.code(),
                profile_velocity: PP_VELOCITY,
                profile_acceleration: PP_ACCELERATION,
                profile_deceleration: PP_ACCELERATION,
                ..Command::default()
            },
            progress: 0,
            shown: 0,
            resumed: false,
        }
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// What to send this cycle.
    pub fn command(&self) -> Command {
        self.command
    }

    /// The commanded motion of the last step.
    pub fn commanded(&self) -> Setpoint {
        self.setpoint
    }

    /// Advances the script by one cycle of `dt` seconds, given what the drive reported.
    pub fn step(&mut self, state: Option<State>, feedback: Feedback, dt: f64) {
        self.t += dt;
        match self.phase {
            Phase::Enable => self.enable(state, feedback),
            Phase::Homing => self.homing(feedback),
            Phase::Pp => self.pp(feedback),
            Phase::Csp => self.csp(),
            Phase::Csv => self.csv(dt),
            Phase::Halt => {
                self.command.controlword = ControlCommand::EnableOperation.controlword() | HALT;
                self.setpoint = Setpoint {
                    position: f64::NAN,
                    velocity: f64::NAN,
                };
                if self.t >= HALT_TIME {
                    self.resumed = true;
                    self.command.controlword = ControlCommand::EnableOperation.controlword();
                    self.next(Phase::Csv);
                }
            }
            Phase::QuickStop => {
                self.command.controlword = ControlCommand::QuickStop.controlword();
                self.setpoint = Setpoint {
                    position: f64::NAN,
                    velocity: f64::NAN,
                };
                let stopped = feedback.velocity == 0;
                // Option codes 0..4 end in Switch on disabled; 5..8 stay in Quick stop active.
                let off = state == Some(State::SwitchOnDisabled)
                    || (state == Some(State::QuickStopActive) && self.t > 0.3);
                if stopped && off && self.t > 0.05 {
                    self.next(Phase::Done);
                }
            }
            Phase::Done => {}
        }
    }

    fn next(&mut self, phase: Phase) {
        self.phase = phase;
        self.t = 0.0;
        self.progress = 0;
    }

    fn enable(&mut self, state: Option<State>, feedback: Feedback) {
        // Hold the actual position, so enabling does not jump.
        self.command.target_position = feedback.position;
        self.start = f64::from(feedback.position);
        self.setpoint = Setpoint {
            position: f64::NAN,
            velocity: f64::NAN,
        };
        self.command.controlword = match state {
            Some(State::Fault) => FAULT_RESET,
            Some(State::ReadyToSwitchOn) => ControlCommand::SwitchOn.controlword(),
            Some(State::SwitchedOn) => ControlCommand::EnableOperation.controlword(),
            Some(State::OperationEnabled) => {
                self.next(Phase::Homing);
                ControlCommand::EnableOperation.controlword()
            }
            _ => ControlCommand::Shutdown.controlword(),
        };
    }

    /// Homing: bit 4 up in mode 6; done when the drive shows mode 6 with homing attained and
    /// target reached after having shown "in progress" (bits 13, 12, 10 all 0).
    fn homing(&mut self, feedback: Feedback) {
        self.command.mode = Mode::Homing.code();
        self.command.controlword = ControlCommand::EnableOperation.controlword() | NEW_SET_POINT;
        self.setpoint = Setpoint {
            position: f64::NAN,
            velocity: f64::NAN,
        };
        if feedback.mode != Mode::Homing.code() {
            return;
        }
        let bits = feedback.statusword & (HOMING_ERROR | HOMING_ATTAINED | TARGET_REACHED);
        if bits == 0 {
            self.progress = 1;
        } else if self.progress == 1 && bits == HOMING_ATTAINED | TARGET_REACHED {
            self.command.controlword = ControlCommand::EnableOperation.controlword();
            self.next(Phase::Pp);
        }
    }

    /// PP: each set-point with a rising edge of bit 4 (bit 5 = 0: the second one buffered),
    /// bit 4 dropped when the drive acknowledges (bit 12); done at target reached with no
    /// set-point pending.
    fn pp(&mut self, feedback: Feedback) {
        self.command.mode = Mode::ProfilePosition.code();
        let acknowledged = feedback.statusword & SET_POINT_ACKNOWLEDGE != 0;
        let enable = ControlCommand::EnableOperation.controlword();
        let raised = self.command.controlword & NEW_SET_POINT != 0;
        if feedback.mode != Mode::ProfilePosition.code() {
            self.command.controlword = enable;
        } else if raised && acknowledged {
            self.command.controlword = enable;
            self.progress += 1;
        } else if !raised && !acknowledged && self.progress < PP_TARGETS.len() {
            if let Some(&target) = PP_TARGETS.get(self.progress) {
                self.command.target_position = target;
                self.command.controlword = enable | NEW_SET_POINT;
            }
        } else if !raised
            && self.progress == PP_TARGETS.len()
            && feedback.statusword & TARGET_REACHED != 0
            && !acknowledged
        {
            self.start = f64::from(feedback.position);
            self.command.target_position = feedback.position;
            self.next(Phase::Csp);
        }
        // The plot shows the set-point the drive runs to: the first until the axis is there.
        let shown = PP_TARGETS.get(self.shown).copied().unwrap_or_default();
        if feedback.position == shown && self.shown + 1 < self.progress.max(1) {
            self.shown += 1;
        }
        self.setpoint = Setpoint {
            position: if self.progress == 0 && self.command.controlword & NEW_SET_POINT == 0 {
                f64::NAN
            } else {
                f64::from(PP_TARGETS.get(self.shown).copied().unwrap_or_default())
            },
            velocity: f64::NAN,
        };
    }

    fn csp(&mut self) {
        let s = (self.t / CSP_TIME).min(1.0);
        let shape = (1.0 - (std::f64::consts::PI * s).cos()) / 2.0;
        let speed = std::f64::consts::PI * (std::f64::consts::PI * s).sin() / 2.0;
        self.setpoint = Setpoint {
            position: self.start + CSP_DISTANCE * shape,
            velocity: if s < 1.0 {
                CSP_DISTANCE / CSP_TIME * speed
            } else {
                0.0
            },
        };
        self.command.mode = Mode::CyclicSyncPosition.code();
        self.command.controlword = ControlCommand::EnableOperation.controlword();
        self.command.target_position = self.setpoint.position.round() as i32;
        if self.t >= CSP_TIME + 0.1 {
            self.start = self.setpoint.position;
            self.next(Phase::Csv);
        }
    }

    fn csv(&mut self, dt: f64) {
        if self.resumed {
            // After the halt: the velocity command again (CSV has no ramp of its own), then the
            // quick stop.
            self.command.target_velocity = CSV_VELOCITY as i32;
            self.setpoint = Setpoint {
                position: f64::NAN,
                velocity: CSV_VELOCITY,
            };
            if self.t >= RESUME_TIME {
                self.next(Phase::QuickStop);
            }
            return;
        }
        let ramp = (self.t / CSV_RAMP).min(1.0);
        let velocity = CSV_VELOCITY * ramp;
        // The position the commanded velocity integrates to, for the plot.
        self.start += velocity * dt;
        self.setpoint = Setpoint {
            position: self.start,
            velocity,
        };
        self.command.mode = Mode::CyclicSyncVelocity.code();
        self.command.target_velocity = velocity.round() as i32;
        if self.t >= CSV_TIME {
            self.next(Phase::Halt);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_enable_sequence_follows_the_state() {
        let mut p = Profile::new();
        let fb = Feedback::default();
        p.step(Some(State::SwitchOnDisabled), fb, 0.001);
        assert_eq!(p.command().controlword, 0x06);
        p.step(Some(State::ReadyToSwitchOn), fb, 0.001);
        assert_eq!(p.command().controlword, 0x07);
        p.step(Some(State::SwitchedOn), fb, 0.001);
        assert_eq!(p.command().controlword, 0x0F);
        p.step(Some(State::OperationEnabled), fb, 0.001);
        assert_eq!(p.phase(), Phase::Homing);
    }

    #[test]
    fn homing_then_two_set_points_with_the_handshake() {
        let mut p = Profile::new();
        let on = Some(State::OperationEnabled);
        p.step(on, Feedback::default(), 0.001);
        let hm = |statusword| Feedback {
            statusword,
            mode: 6,
            ..Feedback::default()
        };
        // Attained + reached before "in progress" was seen: an old result, not this run.
        p.step(on, hm(0x1637), 0.001);
        assert_eq!((p.phase(), p.command().controlword), (Phase::Homing, 0x1F));
        p.step(on, hm(0x0237), 0.001);
        p.step(on, hm(0x1637), 0.001);
        assert_eq!(p.phase(), Phase::Pp);
        let pp = |statusword| Feedback {
            statusword,
            mode: 1,
            ..Feedback::default()
        };
        p.step(on, pp(0x0237), 0.001);
        assert_eq!(
            (p.command().controlword, p.command().target_position),
            (0x1F, 60_000)
        );
        p.step(on, pp(0x1237), 0.001);
        assert_eq!(p.command().controlword, 0x0F);
        p.step(on, pp(0x0237), 0.001);
        assert_eq!(
            (p.command().controlword, p.command().target_position),
            (0x1F, 20_000)
        );
        p.step(on, pp(0x1237), 0.001);
        p.step(on, pp(0x1237), 0.001);
        assert_eq!((p.command().controlword, p.phase()), (0x0F, Phase::Pp));
        p.step(on, pp(0x0637), 0.001);
        assert_eq!(p.phase(), Phase::Csp);
    }

    #[test]
    fn the_csp_move_is_smooth_and_ends_at_the_distance() {
        let mut p = Profile::new();
        p.next(Phase::Csp);
        let mut last = 0.0;
        for _ in 0..1000 {
            p.step(Some(State::OperationEnabled), Feedback::default(), 0.001);
            let step = p.commanded().position - last;
            assert!(
                (0.0..=CSP_DISTANCE / CSP_TIME * 1.6 * 0.001).contains(&step),
                "{step}"
            );
            last = p.commanded().position;
        }
        assert!((last - CSP_DISTANCE).abs() < 1.0, "{last}");
    }

    #[test]
    fn mode_names_follow_0x6502_bits() {
        assert_eq!(mode_names(0x0000_0380), "CSP, CSV, CST");
        assert_eq!(mode_names(0x0000_0001), "PP");
    }
}
