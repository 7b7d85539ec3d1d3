//! The dummy axis, cycle by cycle, through `Axis::step` on a dictionary value: each mode reaches
//! its target in a stated number of cycles, software limits, following error, fault injection
//! and reset, and the stop ramps of the option codes.

use ecat_axis::{
    Axis, AxisApp, AxisOd, Motor, RX_MAPPING, SUPPORTED_MODES, TORQUE_ACCELERATION, TX_MAPPING,
};
use ecat_core::cia402::objects;
use ecat_core::cia402::{SoftwarePositionLimit, State};
use ecat_core::coe::AbortCode;
use ecat_core::dictionary::ObjectHooks;
use ecat_core::sync_parameters::SyncParameters;
use ecat_embassy::Application;

const CSP: i8 = 8;
const CSV: i8 = 9;
const CST: i8 = 10;

/// Statusword bits: target reached, internal limit, drive follows command, following error.
const REACHED: u16 = 0x0400;
const LIMIT: u16 = 0x0800;
const FOLLOWS: u16 = 0x1000;
const FOLLOWING_ERROR: u16 = 0x2000;
/// Operation enabled + voltage enabled + remote.
const OPERATION_ENABLED: u16 = 0x0237;

fn cycle(axis: &mut Axis, od: &mut AxisOd, controlword: u16) {
    od.controlword = controlword;
    axis.step(od);
}

/// A fresh axis in Operation enabled in `mode` after three cycles (transitions 1, 2, 3+4).
fn enabled(mode: i8) -> (Axis, AxisOd) {
    let mut axis = Axis::new();
    let mut od = AxisOd {
        mode,
        ..AxisOd::default()
    };
    cycle(&mut axis, &mut od, 0x00);
    assert_eq!(od.statusword, 0x0250);
    cycle(&mut axis, &mut od, 0x06);
    assert_eq!(od.statusword, 0x0231);
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(axis.state(), State::OperationEnabled);
    assert_eq!(od.mode_display, mode);
    (axis, od)
}

/// Cycles with `controlword` until `done`, at most `limit` times; how many it took.
fn cycles_until(
    axis: &mut Axis,
    od: &mut AxisOd,
    controlword: u16,
    limit: u32,
    done: impl Fn(&AxisOd) -> bool,
) -> u32 {
    for n in 1..=limit {
        cycle(axis, od, controlword);
        if done(od) {
            return n;
        }
    }
    panic!("not done within {limit} cycles: {od:?}");
}

#[test]
fn the_dictionary_declares_the_cia402_objects_as_the_profile_defines_them() {
    assert_eq!(objects::check::<AxisOd>(), Ok(()));
    let od = AxisOd::default();
    assert_eq!(ecat_axis::INFO.device_type, 0x0002_0192);
    assert_eq!(ecat_axis::INFO.device_type & 0xFFFF, 402);
    assert_eq!(od.area.identity, ecat_axis::IDENTITY);
    assert_eq!(od.supported_modes, SUPPORTED_MODES);
    let bytes = |entries: &[ecat_core::pdo::MappingEntry]| {
        entries.iter().map(|e| u32::from(e.bit_len())).sum::<u32>() / 8
    };
    assert_eq!((bytes(&RX_MAPPING), bytes(&TX_MAPPING)), (13, 19));
    assert_eq!(
        (
            od.quick_stop_option,
            od.shutdown_option,
            od.disable_operation_option,
            od.fault_reaction_option
        ),
        (2, 0, 1, 2)
    );
}

#[test]
fn csp_reaches_the_target_in_distance_over_max_velocity_cycles() {
    // 10 000 counts at 1 000 000 counts/s with 1 ms cycles: 1 000 counts per cycle, 10 cycles.
    let (mut axis, mut od) = enabled(CSP);
    assert_eq!(od.statusword, OPERATION_ENABLED | REACHED | FOLLOWS);
    od.target_position = 10_000;
    for n in 1..=9 {
        cycle(&mut axis, &mut od, 0x0F);
        assert_eq!((od.position, od.velocity), (1_000 * n, 1_000_000));
        assert_eq!(od.following_error, 10_000 - 1_000 * n);
        assert_eq!(od.statusword, OPERATION_ENABLED | FOLLOWS);
    }
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.position, od.following_error), (10_000, 0));
    assert_eq!(od.statusword, OPERATION_ENABLED | REACHED | FOLLOWS);
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.position, od.velocity), (10_000, 0));
}

#[test]
fn the_cycle_time_comes_from_0x1c32_02() {
    // 2 ms cycles: 2 000 counts per cycle, 5 cycles.
    let (mut axis, mut od) = enabled(CSP);
    od.area.outputs.set(SyncParameters::CYCLE_TIME, 2_000_000);
    od.target_position = 10_000;
    let n = cycles_until(&mut axis, &mut od, 0x0F, 100, |od| {
        od.statusword & REACHED != 0
    });
    assert_eq!((n, od.position), (5, 10_000));
    // CSV over 250 µs cycles: 4 000 counts/s is exactly one count per cycle.
    let (mut axis, mut od) = enabled(CSV);
    od.area.outputs.set(SyncParameters::CYCLE_TIME, 250_000);
    od.target_velocity = 4_000;
    for n in 1..=8 {
        cycle(&mut axis, &mut od, 0x0F);
        assert_eq!(od.position, n);
    }
}

#[test]
fn csp_following_error_sets_bit_13_above_the_window() {
    let (mut axis, mut od) = enabled(CSP);
    od.following_error_window = 5_000;
    od.target_position = 10_000;
    // Errors after each cycle: 9 000, 8 000, ... 5 000 is inside the window.
    let bits: Vec<bool> = (0..6)
        .map(|_| {
            cycle(&mut axis, &mut od, 0x0F);
            od.statusword & FOLLOWING_ERROR != 0
        })
        .collect();
    assert_eq!(bits, [true, true, true, true, false, false]);
    // 0xFFFF_FFFF switches the check off.
    let (mut axis, mut od) = enabled(CSP);
    od.following_error_window = u32::MAX;
    od.target_position = i32::MAX;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(od.statusword & FOLLOWING_ERROR, 0);
    assert_eq!(od.following_error, i32::MAX - 1_000);
}

#[test]
fn csv_runs_at_target_velocity_plus_offset_within_the_speed_limit() {
    let (mut axis, mut od) = enabled(CSV);
    od.target_velocity = 4_000;
    od.velocity_offset = 1_000;
    for n in 1..=100 {
        cycle(&mut axis, &mut od, 0x0F);
        assert_eq!((od.velocity, od.position), (5_000, 5 * n));
        assert_eq!(od.statusword, OPERATION_ENABLED | REACHED | FOLLOWS);
    }
    od.target_velocity = 2_000_000;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.velocity, od.position), (1_000_000, 500 + 1_000));
    assert_eq!(od.statusword, OPERATION_ENABLED | LIMIT | FOLLOWS);
}

#[test]
fn cst_accelerates_with_the_torque_until_the_speed_limit() {
    // 10 % torque = 100 × 1 000 counts/s² = 100 counts/s per 1 ms cycle; limit 1 000 counts/s.
    let (mut axis, mut od) = enabled(CST);
    od.max_profile_velocity = 1_000;
    od.target_torque = 100;
    for n in 1..=10 {
        cycle(&mut axis, &mut od, 0x0F);
        assert_eq!((od.velocity, od.torque), (100 * n, 100));
        assert_eq!(od.statusword, OPERATION_ENABLED | REACHED | FOLLOWS);
    }
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.velocity, od.torque), (1_000, 0));
    assert_eq!(od.statusword, OPERATION_ENABLED | LIMIT | FOLLOWS);
    // Reversing the torque is allowed at the limit; offset 0x60B2 adds.
    od.target_torque = -150;
    od.torque_offset = 50;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.velocity, od.torque), (900, -100));
}

#[test]
fn software_position_limits_clamp_and_set_bit_11() {
    let limit = SoftwarePositionLimit {
        min: -1_500,
        max: 2_500,
    };
    let (mut axis, mut od) = enabled(CSP);
    od.position_limit = limit;
    od.target_position = 5_000;
    let n = cycles_until(&mut axis, &mut od, 0x0F, 10, |od| od.position == 2_500);
    assert_eq!(n, 3);
    assert_eq!(od.statusword, OPERATION_ENABLED | REACHED | LIMIT | FOLLOWS);
    od.target_position = 0;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(od.statusword & LIMIT, 0);

    let (mut axis, mut od) = enabled(CSV);
    od.position_limit = limit;
    od.target_velocity = -1_000_000;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.position, od.statusword & LIMIT), (-1_000, 0));
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.position, od.velocity), (-1_500, 0));
    assert_eq!(od.statusword & LIMIT, LIMIT);
}

#[test]
fn an_injected_fault_runs_the_fault_reaction_and_a_reset_edge_clears_it() {
    let (mut axis, mut od) = enabled(CSV);
    od.target_velocity = 5_000;
    cycle(&mut axis, &mut od, 0x0F);
    axis.inject_fault(0x2310);
    // Fault reaction 2: the quick stop ramp, 10 000 000 counts/s² = 10 000 counts/s per cycle.
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(axis.state(), State::FaultReactionActive);
    assert_eq!(
        (od.error_code, od.error_register, od.velocity),
        (0x2310, 1, 0)
    );
    assert_eq!(od.statusword, 0x021F | REACHED);
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((axis.state(), od.statusword), (State::Fault, 0x0218));
    // Enable operation does nothing in Fault; the edge of bit 7 resets and clears 0x603F.
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(axis.state(), State::Fault);
    cycle(&mut axis, &mut od, 0x8F);
    assert_eq!(
        (axis.state(), od.statusword),
        (State::SwitchOnDisabled, 0x0250)
    );
    assert_eq!((od.error_code, od.error_register), (0, 0));
    // A fault while bit 7 stays set is not reset by the held bit.
    axis.inject_fault(0x5000);
    cycle(&mut axis, &mut od, 0x80);
    cycle(&mut axis, &mut od, 0x80);
    assert_eq!((axis.state(), od.error_code), (State::Fault, 0x5000));
    cycle(&mut axis, &mut od, 0x00);
    cycle(&mut axis, &mut od, 0x80);
    assert_eq!((axis.state(), od.error_code), (State::SwitchOnDisabled, 0));
}

/// Quick stop from 10 000 counts/s: 0x6085 = 1 000 000 counts/s² (1 000 per cycle), 0x6084 =
/// 500 000 counts/s² (500 per cycle). Returns the velocities while the quick stop command is
/// held for `cycles` cycles, and the axis.
fn quick_stop(code: i16, cycles: usize) -> (Vec<i32>, Axis, AxisOd) {
    let (mut axis, mut od) = enabled(CSV);
    od.quick_stop_option = code;
    od.quick_stop_deceleration = 1_000_000;
    od.profile_deceleration = 500_000;
    od.target_velocity = 10_000;
    cycle(&mut axis, &mut od, 0x0F);
    let velocities = (0..cycles)
        .map(|_| {
            cycle(&mut axis, &mut od, 0x02);
            od.velocity
        })
        .collect();
    (velocities, axis, od)
}

#[test]
fn quick_stop_ramps_and_final_states_per_option_code() {
    let quick: Vec<i32> = (1..=10).map(|n| 10_000 - 1_000 * n).collect();
    let slow: Vec<i32> = (1..=20).map(|n| 10_000 - 500 * n).collect();
    // (code, ramp velocities, final state, final statusword)
    let cases: [(i16, &[i32], State, u16); 8] = [
        (1, &slow, State::SwitchOnDisabled, 0x0250),
        (2, &quick, State::SwitchOnDisabled, 0x0250),
        (3, &quick, State::SwitchOnDisabled, 0x0250),
        (4, &quick, State::SwitchOnDisabled, 0x0250),
        (5, &slow, State::QuickStopActive, 0x0617),
        (6, &quick, State::QuickStopActive, 0x0617),
        (7, &quick, State::QuickStopActive, 0x0617),
        (8, &quick, State::QuickStopActive, 0x0617),
    ];
    for (code, ramp, state, statusword) in cases {
        let (velocities, axis, od) = quick_stop(code, ramp.len() + 1);
        assert_eq!(velocities[..ramp.len()], *ramp, "code {code}");
        assert_eq!(
            (axis.state(), od.statusword),
            (state, statusword),
            "code {code}"
        );
    }
    // Code 0: the drive function is disabled at once, Switch on disabled the cycle after.
    let (velocities, axis, _) = quick_stop(0, 2);
    assert_eq!(velocities, [0, 0]);
    assert_eq!(axis.state(), State::SwitchOnDisabled);
}

#[test]
fn quick_stop_active_shows_target_reached_only_at_standstill_and_can_resume() {
    let (_, mut axis, mut od) = quick_stop(6, 5);
    assert_eq!(
        (axis.state(), od.statusword),
        (State::QuickStopActive, 0x0217)
    );
    for _ in 0..6 {
        cycle(&mut axis, &mut od, 0x02);
    }
    assert_eq!(od.statusword, 0x0617);
    // Transition 16: enable operation resumes CSV.
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(
        (axis.state(), od.velocity),
        (State::OperationEnabled, 10_000)
    );
}

#[test]
fn shutdown_ramps_down_then_goes_to_ready_to_switch_on() {
    let (mut axis, mut od) = enabled(CSV);
    od.shutdown_option = 1;
    od.profile_deceleration = 2_000_000;
    od.target_velocity = 10_000;
    cycle(&mut axis, &mut od, 0x0F);
    let n = cycles_until(&mut axis, &mut od, 0x06, 20, |od| od.velocity == 0);
    assert_eq!(n, 5);
    assert_eq!(axis.state(), State::OperationEnabled);
    cycle(&mut axis, &mut od, 0x06);
    assert_eq!(
        (axis.state(), od.statusword),
        (State::ReadyToSwitchOn, 0x0231)
    );
}

#[test]
fn unsupported_modes_are_refused_by_sdo_and_ignored_by_pdo() {
    let (mut axis, mut od) = enabled(CSV);
    let mut app = AxisApp;
    // 4 (profile torque) is not supported.
    assert_eq!(
        app.before_write(&od, 0x6060, 0, &[4]),
        Err(AbortCode::VALUE_RANGE)
    );
    assert_eq!(
        app.before_write(&od, 0x6060, 0, &[0]),
        Err(AbortCode::VALUE_RANGE)
    );
    assert_eq!(app.before_write(&od, 0x6060, 0, &[CST as u8]), Ok(()));
    assert_eq!(app.before_write(&od, 0x607A, 0, &[1, 0, 0, 0]), Ok(()));
    // Reserved homing methods are refused as well.
    for method in [0u8, 15, 16, 31, 32, 36, 38] {
        assert_eq!(
            app.before_write(&od, 0x6098, 0, &[method]),
            Err(AbortCode::VALUE_RANGE)
        );
    }
    assert_eq!(app.before_write(&od, 0x6098, 0, &[7]), Ok(()));
    // Through the RxPDO: the display keeps the running mode.
    od.mode = 4;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!(od.mode_display, CSV);
    // A supported mode switches on the fly.
    od.mode = CSP;
    od.target_position = 3;
    cycle(&mut axis, &mut od, 0x0F);
    assert_eq!((od.mode_display, od.position), (CSP, 3));
}

#[test]
fn leaving_op_commands_a_quick_stop() {
    let (mut axis, mut od) = enabled(CSV);
    od.target_velocity = 10_000;
    cycle(&mut axis, &mut od, 0x0F);
    axis.safe_state(&mut od);
    assert_eq!(od.controlword, 0x0002);
    axis.cycle(&mut od, None, &mut []);
    assert_eq!((axis.state(), od.velocity), (State::QuickStopActive, 0));
    axis.cycle(&mut od, None, &mut []);
    assert_eq!(axis.state(), State::SwitchOnDisabled);
}

#[test]
fn motor_ramps_end_and_positions_stay_exact() {
    let mut motor = Motor::new();
    motor.set_velocity(-5);
    // 1 count/s² over 1 ms rounds to 0: every ramp still takes at least 1 count/s per cycle.
    motor.decelerate(1, 1_000_000);
    assert_eq!(motor.velocity(), -4);
    // A deceleration of 0 stops at once.
    motor.decelerate(0, 1_000_000);
    assert!(motor.standstill());
    // 3 counts/s over 1 ms cycles: 1 count after 334 cycles, none lost to rounding.
    motor.set_velocity(3);
    for _ in 0..333 {
        motor.integrate(1_000_000);
    }
    assert_eq!(motor.position(), 0);
    motor.integrate(1_000_000);
    assert_eq!(motor.position(), 1);
    // Saturation instead of overflow.
    motor.set_velocity(i32::MAX);
    motor.accelerate(i64::MAX, u32::MAX);
    for _ in 0..10 {
        motor.integrate(u32::MAX);
    }
    assert_eq!((motor.velocity(), motor.position()), (i32::MAX, i32::MAX));
    assert_eq!(TORQUE_ACCELERATION, 1_000);
}
