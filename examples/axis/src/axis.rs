//! The process-data cycle of the axis: the CiA 402 state machine decides, the simulated motor
//! moves (the structure of the SSC `CiA402_Application`/`CiA402_DummyMotionControl`).
//!
//! The profile modes (PP, PV, HM) run `ecat_core::cia402`'s trajectory generator and the motor
//! follows its demand exactly; the cyclic modes (CSP, CSV, CST) drive the motor directly. The
//! halt bit (controlword bit 8) stops every mode with the 0x605D ramp; the stop ramps of the
//! option codes, 0x607D (not while homing), 0x607F and 0x6072 apply in every mode.

use ecat_core::cia402::controlword::HALT;
use ecat_core::cia402::homing::{Homing, HomingInputs, HomingParameters};
use ecat_core::cia402::inputs::digital_inputs;
use ecat_core::cia402::pp::{PpParameters, ProfilePosition};
use ecat_core::cia402::profile::{Trajectory, clamp_torque};
use ecat_core::cia402::pv::{ProfileVelocity, PvParameters};
use ecat_core::cia402::statusword::StatusFlags;
use ecat_core::cia402::touch_probe::{ProbeInput, TouchProbes};
use ecat_core::cia402::{
    Mode, Motion, OptionCodes, PowerDriveSystem, Ramp, SoftwarePositionLimit, State, halt, mode,
    statusword,
};
use ecat_embassy::Application;

use crate::motor::{Machine, Motor, TORQUE_ACCELERATION, saturate};
use crate::{AxisApp, AxisOd};

/// The cycle time when 0x1C32:02 is 0 (no cycle configured): 1 ms.
pub const DEFAULT_CYCLE_NS: u32 = 1_000_000;

/// The controlword [`Axis::safe_state`](Application::safe_state) leaves in the dictionary:
/// quick stop (IEC 61800-7-201 Table 28).
const QUICK_STOP: u16 = 0x0002;

/// What one cycle of motion reports into the statusword and the actual values.
#[derive(Debug, Default)]
struct Report {
    target_reached: bool,
    internal_limit: bool,
    follows_command: bool,
    following_error: bool,
    /// 0x60F4.
    error: i32,
    /// 0x6077.
    torque: i16,
}

/// One axis: the [`Application`] of the drive (its cycle, safe state and SDO checks,
/// [`AxisApp`]).
#[derive(Debug, Clone, Default)]
pub struct Axis {
    pds: PowerDriveSystem,
    motor: Motor,
    fault: Option<u16>,
    /// The demand of the profile modes.
    trajectory: Trajectory,
    pp: ProfilePosition,
    pv: ProfileVelocity,
    homing: Homing,
    probes: TouchProbes,
    /// The mode followed in the previous cycle (`None`: not Operation enabled).
    following: Option<i8>,
    /// The switches and the index pulse.
    machine: Machine,
    /// Physical position = reported position − `origin` (homing moves the origin).
    origin: i64,
    /// The physical position of the previous cycle.
    physical: i64,
    /// The touch probe 2 input (an application input).
    probe2: bool,
    /// An index pulse passed in the previous cycle's motion.
    index: bool,
    /// The controlword of the previous cycle (a mode entered with bit 4 rising starts at once).
    controlword: u16,
}

impl Axis {
    /// An axis at power on: Not ready to switch on, motor at rest at 0, on [`Machine::DEFAULT`].
    pub const fn new() -> Self {
        Self {
            pds: PowerDriveSystem::new(),
            motor: Motor::new(),
            fault: None,
            trajectory: Trajectory::new(),
            pp: ProfilePosition::new(),
            pv: ProfileVelocity::new(),
            homing: Homing::new(),
            probes: TouchProbes::new(),
            following: None,
            machine: Machine::DEFAULT,
            origin: 0,
            physical: 0,
            probe2: false,
            index: false,
            controlword: 0,
        }
    }

    /// The same axis on `machine`.
    pub const fn with_machine(mut self, machine: Machine) -> Self {
        self.machine = machine;
        self
    }

    /// The machine's physical position of the motor (where the switches are).
    pub const fn physical_position(&self) -> i64 {
        self.physical
    }

    /// Sets the touch probe 2 input (touch probe 1 is wired to the home switch).
    pub fn set_probe_input(&mut self, level: bool) {
        self.probe2 = level;
    }

    /// The PDS state.
    pub const fn state(&self) -> State {
        self.pds.state()
    }

    /// The simulated motor.
    pub const fn motor(&self) -> &Motor {
        &self.motor
    }

    /// An application fault with CiA 301 error code `code` (e.g. 0x2310 continuous over
    /// current): the next cycle stores it in 0x603F and starts the fault reaction (transition
    /// 13). A fault reset (transition 15) clears 0x603F.
    pub fn inject_fault(&mut self, code: u16) {
        self.fault = Some(code);
    }

    /// One cycle over the dictionary: the body of [`Application::cycle`].
    pub fn step(&mut self, od: &mut AxisOd) {
        let dt = match cycle_time(od) {
            0 => DEFAULT_CYCLE_NS,
            configured => configured,
        };
        let options = OptionCodes {
            quick_stop: od.quick_stop_option,
            shutdown: od.shutdown_option,
            disable_operation: od.disable_operation_option,
            fault_reaction: od.fault_reaction_option,
        };
        if let Some(code) = self.fault.take() {
            od.error_code = code;
            self.pds.fault(&options);
        }
        let step = self
            .pds
            .update(od.controlword, &options, self.motor.standstill());
        if step.transitions.contains(15) {
            od.error_code = 0;
        }
        od.error_register = u8::from(od.error_code != 0);
        od.mode_display = mode::display(od.mode, od.mode_display, od.supported_modes);
        let following = (step.motion == Motion::Follow).then_some(od.mode_display);
        if following != self.following {
            self.enter();
            self.following = following;
        }
        let mut report = match step.motion {
            Motion::Off | Motion::Stop(Ramp::Disable) => self.halt(dt, false),
            Motion::Hold => self.halt(dt, true),
            Motion::Stop(ramp) => self.stop(od, ramp, dt),
            Motion::Follow if od.controlword & HALT != 0 && !self.profile_mode(od) => {
                self.stop(od, halt(od.halt_option), dt)
            }
            Motion::Follow => self.follow(od, dt),
        };
        if following != Some(Mode::Homing.code()) {
            report.internal_limit |= self.enforce(od.position_limit);
        }
        if !matches!(step.motion, Motion::Follow) || !self.profile_mode(od) {
            self.trajectory.follow(
                i64::from(self.motor.position()),
                i64::from(self.motor.velocity()),
            );
        }
        self.sense(od);
        self.publish(od, &report);
        self.controlword = od.controlword;
    }

    /// Whether the active mode runs the trajectory generator (PP, PV, HM).
    fn profile_mode(&self, od: &AxisOd) -> bool {
        matches!(
            Mode::from_code(od.mode_display),
            Some(Mode::ProfilePosition | Mode::ProfileVelocity | Mode::Homing)
        )
    }

    /// A new mode is followed (or Operation enabled ended): the demand takes the motor's
    /// position and velocity, set-points are dropped; bit 4 counts as rising when it was 0 in
    /// the previous cycle.
    fn enter(&mut self) {
        let position = i64::from(self.motor.position());
        self.trajectory
            .follow(position, i64::from(self.motor.velocity()));
        self.pp.enter(position, self.controlword);
        self.pv = ProfileVelocity::new();
        self.homing.enter(self.controlword);
    }

    /// The switches into 0x60FD, the touch probes into 0x60B9..0x60BD.
    fn sense(&mut self, od: &mut AxisOd) {
        let physical = i64::from(self.motor.position()) - self.origin;
        let (negative, positive, home) = self.machine.switches(physical);
        let index = self.machine.index_passed(self.physical, physical);
        self.physical = physical;
        self.index = index;
        od.digital_inputs = digital_inputs(negative, positive, home);
        let position = self.motor.position();
        self.probes.update(
            od.touch_probe_function,
            [
                ProbeInput {
                    input: home,
                    index,
                    position,
                },
                ProbeInput {
                    input: self.probe2,
                    index,
                    position,
                },
            ],
        );
        od.touch_probe_status = self.probes.status();
        let [first, second] = [self.probes.positions(0), self.probes.positions(1)];
        od.probe1_positive = first.positive;
        od.probe1_negative = first.negative;
        od.probe2_positive = second.positive;
        od.probe2_negative = second.negative;
    }

    /// The deceleration of `ramp`: 0x6084 for the slow down ramp, 0x6085 for the quick stop
    /// ramp and for the current and voltage limits (the dummy motor has neither).
    fn deceleration(od: &AxisOd, ramp: Ramp) -> u32 {
        match ramp {
            Ramp::SlowDown => od.profile_deceleration,
            _ => od.quick_stop_deceleration,
        }
    }

    /// No torque (the unpowered dummy motor has no inertia and stops at once), or holding at
    /// standstill with `target_reached`.
    fn halt(&mut self, dt: u32, target_reached: bool) -> Report {
        self.motor.set_velocity(0);
        self.motor.integrate(dt);
        Report {
            target_reached,
            ..Report::default()
        }
    }

    /// Decelerates with the ramp: 0x6084 for the slow down ramp, 0x6085 for the quick stop ramp
    /// and for the current and voltage limits (the dummy motor has neither). Target reached once
    /// at standstill.
    fn stop(&mut self, od: &AxisOd, ramp: Ramp, dt: u32) -> Report {
        self.motor.decelerate(Self::deceleration(od, ramp), dt);
        self.motor.integrate(dt);
        Report {
            target_reached: self.motor.standstill(),
            ..Report::default()
        }
    }

    /// Operation enabled: the active mode (0x6061); no supported mode holds the motor.
    fn follow(&mut self, od: &AxisOd, dt: u32) -> Report {
        match Mode::from_code(od.mode_display) {
            Some(Mode::ProfilePosition) => self.pp(od, dt),
            Some(Mode::ProfileVelocity) => self.pv(od, dt),
            Some(Mode::Homing) => self.hm(od, dt),
            Some(Mode::CyclicSyncPosition) => self.csp(od, dt),
            Some(Mode::CyclicSyncVelocity) => self.csv(od, dt),
            Some(Mode::CyclicSyncTorque) => self.cst(od, dt),
            _ => self.halt(dt, false),
        }
    }

    /// The motor follows the demand of the trajectory generator.
    fn drive(&mut self) {
        self.motor.move_to(
            saturate(self.trajectory.position()),
            saturate(self.trajectory.velocity()),
        );
    }

    /// PP ([`ProfilePosition`]): bit 10 target reached, 12 set-point acknowledge, 13 following
    /// error (demand − actual beyond 0x6065; the ideal motor never lags).
    fn pp(&mut self, od: &AxisOd, dt: u32) -> Report {
        let parameters = PpParameters {
            target: od.target_position,
            profile_velocity: od.profile_velocity,
            acceleration: od.profile_acceleration,
            deceleration: od.profile_deceleration,
            max_velocity: od.max_profile_velocity,
            limit: od.position_limit,
            window: od.position_window,
            window_time: od.position_window_time,
            halt_deceleration: Self::deceleration(od, halt(od.halt_option)),
        };
        let actual = i64::from(self.motor.position());
        let status = self.pp.update(
            od.controlword,
            &parameters,
            actual,
            &mut self.trajectory,
            dt,
        );
        self.drive();
        let error = self.trajectory.position() - i64::from(self.motor.position());
        Report {
            target_reached: status.target_reached,
            internal_limit: status.internal_limit,
            follows_command: status.set_point_acknowledge,
            following_error: od.following_error_window != u32::MAX
                && error.unsigned_abs() > u64::from(od.following_error_window),
            error: saturate(error),
            torque: 0,
        }
    }

    /// PV ([`ProfileVelocity`]): bit 10 target reached, 11 limited, 12 speed zero.
    fn pv(&mut self, od: &AxisOd, dt: u32) -> Report {
        let parameters = PvParameters {
            target: od.target_velocity,
            acceleration: od.profile_acceleration,
            deceleration: od.profile_deceleration,
            max_velocity: od.max_profile_velocity,
            window: od.velocity_window,
            window_time: od.velocity_window_time,
            threshold: od.velocity_threshold,
            threshold_time: od.velocity_threshold_time,
            halt_deceleration: Self::deceleration(od, halt(od.halt_option)),
        };
        let status = self
            .pv
            .update(od.controlword, &parameters, &mut self.trajectory, dt);
        self.drive();
        Report {
            target_reached: status.target_reached,
            internal_limit: status.internal_limit,
            follows_command: status.speed_zero,
            ..Report::default()
        }
    }

    /// HM ([`Homing`]) against the machine's switches and index pulse: bit 10 target reached,
    /// 12 homing attained, 13 homing error. The reference moves the reported position.
    fn hm(&mut self, od: &AxisOd, dt: u32) -> Report {
        let parameters = HomingParameters {
            method: od.homing_method,
            switch_speed: od.homing_speeds.switch_search,
            zero_speed: od.homing_speeds.zero_search,
            acceleration: od.homing_acceleration,
            home_offset: od.home_offset,
            max_velocity: od.max_profile_velocity,
            halt_deceleration: Self::deceleration(od, halt(od.halt_option)),
        };
        let physical = i64::from(self.motor.position()) - self.origin;
        let (negative_limit, positive_limit, home_switch) = self.machine.switches(physical);
        let inputs = HomingInputs {
            negative_limit,
            positive_limit,
            home_switch,
            index_pulse: self.index,
        };
        let status = self.homing.update(
            od.controlword,
            &parameters,
            inputs,
            &mut self.trajectory,
            dt,
        );
        self.origin += status.shift;
        self.drive();
        Report {
            target_reached: status.target_reached,
            follows_command: status.attained,
            following_error: status.error,
            ..Report::default()
        }
    }

    /// CSP: moves to the target position (clamped into 0x607D), at most at 0x607F. The
    /// following error is target − actual; bit 13 when it exceeds 0x6065 (no time window 0x6066:
    /// at once). Target reached when at the target.
    fn csp(&mut self, od: &AxisOd, dt: u32) -> Report {
        let (target, clamped) = clamp(od.position_limit, od.target_position);
        let max = i64::from(od.max_profile_velocity);
        let distance = i64::from(target) - i64::from(self.motor.position());
        let needed = distance.saturating_mul(1_000_000_000) / i64::from(dt.max(1));
        if needed.abs() <= max {
            self.motor.move_to(target, saturate(needed));
        } else {
            self.motor.set_velocity(saturate(needed.clamp(-max, max)));
            self.motor.integrate(dt);
        }
        let error = i64::from(target) - i64::from(self.motor.position());
        Report {
            target_reached: error == 0,
            internal_limit: clamped,
            follows_command: true,
            following_error: od.following_error_window != u32::MAX
                && error.unsigned_abs() > u64::from(od.following_error_window),
            error: saturate(error),
            torque: 0,
        }
    }

    /// CSV: runs at target velocity + 0x60B1, limited to 0x607F. Target reached when running at
    /// the commanded velocity.
    fn csv(&mut self, od: &AxisOd, dt: u32) -> Report {
        let commanded = i64::from(od.target_velocity) + i64::from(od.velocity_offset);
        let max = i64::from(od.max_profile_velocity);
        self.motor
            .set_velocity(saturate(commanded.clamp(-max, max)));
        self.motor.integrate(dt);
        Report {
            target_reached: i64::from(self.motor.velocity()) == commanded,
            internal_limit: commanded.abs() > max,
            follows_command: true,
            ..Report::default()
        }
    }

    /// CST: target torque + 0x60B2 accelerates the load by [`TORQUE_ACCELERATION`] per 0.1 %;
    /// at the speed limit 0x607F no torque is applied in that direction. Target reached when
    /// the commanded torque is applied.
    fn cst(&mut self, od: &AxisOd, dt: u32) -> Report {
        let (commanded, torque_limited) = clamp_torque(
            od.target_torque.saturating_add(od.torque_offset),
            od.max_torque,
        );
        let max = i64::from(od.max_profile_velocity);
        let velocity = i64::from(self.motor.velocity());
        let at_limit = (commanded > 0 && velocity >= max) || (commanded < 0 && velocity <= -max);
        let torque = if at_limit { 0 } else { commanded };
        self.motor
            .accelerate(i64::from(torque) * TORQUE_ACCELERATION, dt);
        let limited = i64::from(self.motor.velocity()).clamp(-max, max);
        self.motor.set_velocity(saturate(limited));
        self.motor.integrate(dt);
        Report {
            target_reached: !at_limit,
            internal_limit: at_limit || torque_limited,
            follows_command: true,
            torque,
            ..Report::default()
        }
    }

    /// Stops the motor at a software position limit it crossed; whether it did.
    fn enforce(&mut self, limit: SoftwarePositionLimit) -> bool {
        let (position, clamped) = clamp(limit, self.motor.position());
        if clamped {
            self.motor.stop_at(position);
        }
        clamped
    }

    /// The actual values and the statusword into the dictionary.
    fn publish(&self, od: &mut AxisOd, report: &Report) {
        od.position = self.motor.position();
        od.velocity = self.motor.velocity();
        od.torque = report.torque;
        od.following_error = report.error;
        let flags = StatusFlags {
            voltage_enabled: true,
            warning: false,
            remote: true,
            target_reached: report.target_reached,
            internal_limit: report.internal_limit,
            follows_command: report.follows_command,
            following_error: report.following_error,
        };
        od.statusword = statusword(self.pds.state(), flags);
    }
}

/// 0x1C32:02, the cycle time.
fn cycle_time(od: &AxisOd) -> u32 {
    od.area
        .outputs
        .get(ecat_core::sync_parameters::SyncParameters::CYCLE_TIME)
}

/// `position` clamped into the software position limits (active when min < max), and whether
/// it was outside.
fn clamp(limit: SoftwarePositionLimit, position: i32) -> (i32, bool) {
    if limit.min >= limit.max {
        return (position, false);
    }
    let clamped = position.clamp(limit.min, limit.max);
    (clamped, clamped != position)
}

impl Application<AxisOd> for Axis {
    fn object_hooks(&mut self) -> impl ecat_core::dictionary::ObjectHooks<AxisOd> + '_ {
        AxisApp
    }

    fn cycle(&mut self, od: &mut AxisOd, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        self.step(od);
    }

    /// Leaving OP commands a quick stop: the drive stops with the 0x605A reaction while the
    /// MainDevice's controlword no longer arrives.
    fn safe_state(&mut self, od: &mut AxisOd) {
        od.controlword = QUICK_STOP;
    }
}
