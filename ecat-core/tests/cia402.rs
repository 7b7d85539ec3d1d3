//! The CiA 402 profile: the PDS state machine as a table over every state and command, the stop
//! paths of every option code, the fault reset edge, the statusword, the modes of operation and
//! the standard-object check (IEC 61800-7-201 §6.2).

use State::*;
use ecat_core::cia402::mode::{self, Mode};
use ecat_core::cia402::objects::{self, Mismatch, SoftwarePositionLimit};
use ecat_core::cia402::statusword as sw;
use ecat_core::cia402::{
    Command, Motion, OptionCodes, PowerDriveSystem, Ramp, State, StatusFlags, Transitions,
    statusword,
};
use ecat_core::coe::AbortCode;
use proptest::prelude::*;

/// The option codes of the table: quick stop 6 (quick stop ramp, stay), shutdown 1 (slow down),
/// disable operation 0 (disable), fault reaction 2 (quick stop ramp).
const TABLE_OPTIONS: OptionCodes = OptionCodes {
    quick_stop: 6,
    shutdown: 1,
    disable_operation: 0,
    fault_reaction: 2,
};

/// Remote and voltage enabled, as a drive on the bus reports them.
const FLAGS: StatusFlags = StatusFlags {
    voltage_enabled: true,
    warning: false,
    remote: true,
    target_reached: false,
    internal_limit: false,
    follows_command: false,
    following_error: false,
};

/// The commands of the table: name, controlword, whether bit 7 was set in the cycle before.
const COMMANDS: [(&str, u16, bool); 9] = [
    ("shutdown", 0x06, false),
    ("switch on", 0x07, false),
    ("switch on + enable operation", 0x0F, false),
    ("enable operation", 0x0F, false),
    ("disable voltage", 0x00, false),
    ("quick stop", 0x02, false),
    ("disable operation", 0x07, false),
    ("fault reset edge", 0x80, false),
    ("fault reset held", 0x80, true),
];

fn update(pds: &mut PowerDriveSystem, cw: u16, standstill: bool) -> ecat_core::cia402::Step {
    pds.update(cw, &TABLE_OPTIONS, standstill)
}

/// A PDS in `target` (Quick stop active: stopped, staying), through the public API only; the last
/// update before the return had bit 7 set when `held`.
fn reach(target: State, held: bool) -> PowerDriveSystem {
    let bit7 = if held { 0x80 } else { 0 };
    let mut pds = PowerDriveSystem::new();
    let path: &[u16] = match target {
        NotReadyToSwitchOn => return pds,
        SwitchOnDisabled => &[0x00],
        ReadyToSwitchOn => &[0x00, 0x06],
        SwitchedOn => &[0x00, 0x06, 0x07],
        OperationEnabled | FaultReactionActive | Fault => &[0x00, 0x06, 0x0F],
        QuickStopActive => &[0x00, 0x06, 0x0F, 0x02],
    };
    for &cw in path {
        update(&mut pds, cw, false);
    }
    let last = path.last().copied().unwrap_or(0);
    match target {
        QuickStopActive => {
            update(&mut pds, 0x02, true);
        }
        FaultReactionActive | Fault => pds.fault(&TABLE_OPTIONS),
        _ => {}
    }
    update(&mut pds, last | bit7, target == Fault);
    assert_eq!(pds.state(), target, "reach {target:?}");
    pds
}

fn transitions(list: &[u8]) -> Transitions {
    Transitions(list.iter().fold(0, |acc, n| acc | 1 << n))
}

/// `(state, transitions, motion)` after each command of [`COMMANDS`], per starting state.
#[rustfmt::skip]
fn expected(state: State) -> [(State, &'static [u8], Motion); 9] {
    use Motion::*;
    let sod = (SwitchOnDisabled, &[][..], Off);
    match state {
        NotReadyToSwitchOn => [(SwitchOnDisabled, &[1][..], Off); 9],
        SwitchOnDisabled => [(ReadyToSwitchOn, &[2], Off), sod, sod, sod, sod, sod, sod, sod, sod],
        ReadyToSwitchOn => [
            (ReadyToSwitchOn, &[], Off), (SwitchedOn, &[3], Off),
            (OperationEnabled, &[3, 4], Follow), (OperationEnabled, &[3, 4], Follow),
            (SwitchOnDisabled, &[7], Off), (SwitchOnDisabled, &[7], Off),
            (SwitchedOn, &[3], Off), (ReadyToSwitchOn, &[], Off), (ReadyToSwitchOn, &[], Off),
        ],
        SwitchedOn => [
            (ReadyToSwitchOn, &[6], Off), (SwitchedOn, &[], Off),
            (OperationEnabled, &[4], Follow), (OperationEnabled, &[4], Follow),
            (SwitchOnDisabled, &[10], Off), (SwitchOnDisabled, &[10], Off),
            (SwitchedOn, &[], Off), (SwitchedOn, &[], Off), (SwitchedOn, &[], Off),
        ],
        OperationEnabled => [
            (OperationEnabled, &[], Stop(Ramp::SlowDown)), (OperationEnabled, &[], Stop(Ramp::Disable)),
            (OperationEnabled, &[], Follow), (OperationEnabled, &[], Follow),
            (SwitchOnDisabled, &[9], Off), (QuickStopActive, &[11], Stop(Ramp::QuickStop)),
            (OperationEnabled, &[], Stop(Ramp::Disable)), (OperationEnabled, &[], Follow),
            (OperationEnabled, &[], Follow),
        ],
        QuickStopActive => [
            (QuickStopActive, &[], Hold), (QuickStopActive, &[], Hold),
            (OperationEnabled, &[16], Follow), (OperationEnabled, &[16], Follow),
            (SwitchOnDisabled, &[12], Off), (QuickStopActive, &[], Hold),
            (QuickStopActive, &[], Hold), (QuickStopActive, &[], Hold), (QuickStopActive, &[], Hold),
        ],
        FaultReactionActive => [(FaultReactionActive, &[], Stop(Ramp::QuickStop)); 9],
        Fault => [
            (Fault, &[], Off), (Fault, &[], Off), (Fault, &[], Off), (Fault, &[], Off),
            (Fault, &[], Off), (Fault, &[], Off), (Fault, &[], Off),
            (SwitchOnDisabled, &[15], Off), (Fault, &[], Off),
        ],
    }
}

/// The statusword of each state with [`FLAGS`] (Table 30 pattern + bits 4 and 9).
fn expected_statusword(state: State) -> u16 {
    match state {
        NotReadyToSwitchOn => 0x0210,
        SwitchOnDisabled => 0x0250,
        ReadyToSwitchOn => 0x0231,
        SwitchedOn => 0x0233,
        OperationEnabled => 0x0237,
        QuickStopActive => 0x0217,
        FaultReactionActive => 0x021F,
        Fault => 0x0218,
    }
}

#[test]
fn every_state_times_every_command() {
    for from in State::ALL {
        for ((name, cw, held), (state, taken, motion)) in COMMANDS.into_iter().zip(expected(from)) {
            let mut pds = reach(from, held);
            let step = update(&mut pds, cw, false);
            let case = format!("{from:?} × {name} (0x{cw:04X})");
            assert_eq!(pds.state(), state, "{case}");
            assert_eq!(step.transitions, transitions(taken), "{case}");
            assert_eq!(step.motion, motion, "{case}");
            assert_eq!(
                statusword(pds.state(), FLAGS),
                expected_statusword(state),
                "{case}"
            );
        }
    }
}

#[test]
fn quick_stop_option_codes_decide_ramp_and_final_state() {
    let cases: [(i16, Ramp, State, u8); 9] = [
        (0, Ramp::Disable, SwitchOnDisabled, 12),
        (1, Ramp::SlowDown, SwitchOnDisabled, 12),
        (2, Ramp::QuickStop, SwitchOnDisabled, 12),
        (3, Ramp::CurrentLimit, SwitchOnDisabled, 12),
        (4, Ramp::VoltageLimit, SwitchOnDisabled, 12),
        (5, Ramp::SlowDown, QuickStopActive, 0),
        (6, Ramp::QuickStop, QuickStopActive, 0),
        (7, Ramp::CurrentLimit, QuickStopActive, 0),
        (8, Ramp::VoltageLimit, QuickStopActive, 0),
    ];
    for (code, ramp, then, transition) in cases {
        let options = OptionCodes {
            quick_stop: code,
            ..OptionCodes::DEFAULT
        };
        let mut pds = reach(OperationEnabled, false);
        let step = pds.update(0x02, &options, false);
        assert_eq!(
            (pds.state(), step.motion),
            (QuickStopActive, Motion::Stop(ramp)),
            "code {code}"
        );
        assert_eq!(step.transitions, transitions(&[11]));
        if ramp != Ramp::Disable {
            // Still moving: the stop goes on.
            let step = pds.update(0x02, &options, false);
            assert_eq!(
                (pds.state(), step.motion),
                (QuickStopActive, Motion::Stop(ramp))
            );
            assert!(step.transitions.is_empty());
        }
        let step = pds.update(0x02, &options, true);
        assert_eq!(pds.state(), then, "code {code}");
        let (taken, motion) = match then {
            SwitchOnDisabled => (transitions(&[transition]), Motion::Off),
            _ => (Transitions::default(), Motion::Hold),
        };
        assert_eq!(
            (step.transitions, step.motion),
            (taken, motion),
            "code {code}"
        );
    }
}

#[test]
fn enable_operation_leaves_quick_stop_only_for_the_staying_codes_after_the_stop() {
    // Codes 5..8: transition 16 once the stop is done, not during it.
    let stay = OptionCodes {
        quick_stop: 5,
        ..OptionCodes::DEFAULT
    };
    let mut pds = reach(OperationEnabled, false);
    pds.update(0x02, &stay, false);
    pds.update(0x0F, &stay, false);
    assert_eq!(pds.state(), QuickStopActive);
    pds.update(0x0F, &stay, true); // the stop completes; the command waits for the next cycle
    let step = pds.update(0x0F, &stay, true);
    assert_eq!(
        (pds.state(), step.transitions),
        (OperationEnabled, transitions(&[16]))
    );
    // Code 1: no transition 16, the stop runs on into Switch on disabled.
    let leave = OptionCodes {
        quick_stop: 1,
        ..OptionCodes::DEFAULT
    };
    let mut pds = reach(OperationEnabled, false);
    pds.update(0x02, &leave, false);
    let step = pds.update(0x0F, &leave, false);
    assert_eq!(
        (pds.state(), step.motion),
        (QuickStopActive, Motion::Stop(Ramp::SlowDown))
    );
}

#[test]
fn shutdown_and_disable_operation_option_codes() {
    // (controlword, options, ramp, final state, transition)
    let cases = [
        (
            0x06,
            OptionCodes {
                shutdown: 0,
                ..OptionCodes::DEFAULT
            },
            Ramp::Disable,
            ReadyToSwitchOn,
            8,
        ),
        (
            0x06,
            OptionCodes {
                shutdown: 1,
                ..OptionCodes::DEFAULT
            },
            Ramp::SlowDown,
            ReadyToSwitchOn,
            8,
        ),
        (
            0x07,
            OptionCodes {
                disable_operation: 0,
                ..OptionCodes::DEFAULT
            },
            Ramp::Disable,
            SwitchedOn,
            5,
        ),
        (
            0x07,
            OptionCodes {
                disable_operation: 1,
                ..OptionCodes::DEFAULT
            },
            Ramp::SlowDown,
            SwitchedOn,
            5,
        ),
    ];
    for (cw, options, ramp, then, transition) in cases {
        let mut pds = reach(OperationEnabled, false);
        let step = pds.update(cw, &options, false);
        assert_eq!(
            (pds.state(), step.motion),
            (OperationEnabled, Motion::Stop(ramp))
        );
        if ramp == Ramp::SlowDown {
            let step = pds.update(cw, &options, false);
            assert_eq!(
                (pds.state(), step.motion),
                (OperationEnabled, Motion::Stop(ramp))
            );
        }
        let step = pds.update(cw, &options, true);
        assert_eq!(pds.state(), then, "0x{cw:02X} {options:?}");
        assert_eq!(
            (step.transitions, step.motion),
            (transitions(&[transition]), Motion::Off)
        );
    }
}

#[test]
fn disable_voltage_and_quick_stop_replace_a_running_shutdown_ramp() {
    let options = OptionCodes {
        shutdown: 1,
        ..OptionCodes::DEFAULT
    };
    let mut pds = reach(OperationEnabled, false);
    pds.update(0x06, &options, false);
    let step = pds.update(0x02, &options, false);
    assert_eq!(
        (pds.state(), step.motion),
        (QuickStopActive, Motion::Stop(Ramp::QuickStop))
    );
    assert_eq!(step.transitions, transitions(&[11]));

    let mut pds = reach(OperationEnabled, false);
    pds.update(0x06, &options, false);
    let step = pds.update(0x00, &options, false);
    assert_eq!((pds.state(), step.motion), (SwitchOnDisabled, Motion::Off));
    assert_eq!(step.transitions, transitions(&[9]));
    assert_eq!(pds.pending(), None);
}

#[test]
fn fault_reaction_option_codes() {
    let ramps = [
        Ramp::Disable,
        Ramp::SlowDown,
        Ramp::QuickStop,
        Ramp::CurrentLimit,
        Ramp::VoltageLimit,
    ];
    for (code, ramp) in (0..).zip(ramps) {
        let options = OptionCodes {
            fault_reaction: code,
            ..OptionCodes::DEFAULT
        };
        let mut pds = reach(OperationEnabled, false);
        pds.fault(&options);
        assert_eq!(pds.state(), FaultReactionActive);
        let step = pds.update(0x0F, &options, false);
        if ramp == Ramp::Disable {
            assert_eq!((pds.state(), step.transitions), (Fault, transitions(&[14])));
            continue;
        }
        assert_eq!(
            (pds.state(), step.motion),
            (FaultReactionActive, Motion::Stop(ramp)),
            "code {code}"
        );
        let step = pds.update(0x0F, &options, true);
        assert_eq!(
            (pds.state(), step.transitions, step.motion),
            (Fault, transitions(&[14]), Motion::Off)
        );
    }
}

#[test]
fn a_fault_enters_fault_reaction_from_every_state_but_the_fault_states() {
    for from in State::ALL {
        let mut pds = reach(from, false);
        pds.fault(&OptionCodes::DEFAULT);
        let expected = if from == Fault {
            Fault
        } else {
            FaultReactionActive
        };
        assert_eq!(pds.state(), expected, "from {from:?}");
    }
}

#[test]
fn fault_reset_acts_on_the_rising_edge_of_bit_7_only() {
    let options = OptionCodes::DEFAULT;
    let mut pds = reach(Fault, false);
    assert_eq!(
        pds.update(0x80, &options, true).transitions,
        transitions(&[15])
    );
    assert_eq!(pds.state(), SwitchOnDisabled);
    // A new fault while bit 7 is still held: no second reset.
    pds.fault(&options);
    pds.update(0x80, &options, true);
    assert_eq!(pds.state(), Fault);
    for _ in 0..3 {
        assert!(pds.update(0x80, &options, true).transitions.is_empty());
        assert_eq!(pds.state(), Fault);
    }
    // Bit 7 falls, then rises again: the next edge resets.
    pds.update(0x00, &options, true);
    assert_eq!(pds.state(), Fault);
    pds.update(0x86, &options, true); // bit 7 with other bits set is still the edge
    assert_eq!(pds.state(), SwitchOnDisabled);
}

#[test]
fn controlword_commands_follow_the_masks_of_table_28() {
    let cases: [(u16, Option<Command>); 12] = [
        (0x0000, Some(Command::DisableVoltage)),
        (0x000D, Some(Command::DisableVoltage)), // bit 1 clear wins over every other bit
        (0x0002, Some(Command::QuickStop)),
        (0x000B, Some(Command::QuickStop)),
        (0x0006, Some(Command::Shutdown)),
        (0x000E, Some(Command::Shutdown)), // bit 3 is not part of shutdown
        (0x0007, Some(Command::SwitchOn)),
        (0x0077, Some(Command::SwitchOn)), // mode-specific bits 4..6 are ignored
        (0x000F, Some(Command::EnableOperation)),
        (0x017F, Some(Command::EnableOperation)), // halt (bit 8) is not a device control bit
        (0x0080, None),
        (0x008F, None),
    ];
    for (cw, command) in cases {
        assert_eq!(Command::decode(cw), command, "0x{cw:04X}");
    }
}

#[test]
fn statusword_flags_set_exactly_their_bit() {
    let base = statusword(OperationEnabled, StatusFlags::default());
    assert_eq!(base, 0x0027);
    let bits = [
        (
            StatusFlags {
                voltage_enabled: true,
                ..Default::default()
            },
            0x0010,
        ),
        (
            StatusFlags {
                warning: true,
                ..Default::default()
            },
            0x0080,
        ),
        (
            StatusFlags {
                remote: true,
                ..Default::default()
            },
            0x0200,
        ),
        (
            StatusFlags {
                target_reached: true,
                ..Default::default()
            },
            0x0400,
        ),
        (
            StatusFlags {
                internal_limit: true,
                ..Default::default()
            },
            0x0800,
        ),
        (
            StatusFlags {
                follows_command: true,
                ..Default::default()
            },
            0x1000,
        ),
        (
            StatusFlags {
                following_error: true,
                ..Default::default()
            },
            0x2000,
        ),
    ];
    for (flags, bit) in bits {
        assert_eq!(
            statusword(OperationEnabled, flags),
            0x0027 | bit,
            "{flags:?}"
        );
    }
    assert_eq!((sw::VOLTAGE_ENABLED, sw::FOLLOWING_ERROR), (0x0010, 0x2000));
}

#[test]
fn each_state_pattern_identifies_only_its_state() {
    for state in State::ALL {
        for flags in [StatusFlags::default(), FLAGS] {
            assert_eq!(
                State::from_statusword(statusword(state, flags)),
                Some(state)
            );
        }
        let value = state.pattern().1;
        let matching: Vec<State> = State::ALL
            .into_iter()
            .filter(|s| value & s.pattern().0 == s.pattern().1)
            .collect();
        assert_eq!(matching, [state]);
    }
    assert_eq!(State::from_statusword(0x0001), None);
}

#[test]
fn unknown_option_codes_disable_the_drive_function() {
    let odd = OptionCodes {
        quick_stop: -1,
        shutdown: 2,
        disable_operation: -5,
        fault_reaction: 5,
    };
    assert_eq!(odd.quick_stop().ramp, Ramp::Disable);
    assert_eq!(odd.quick_stop().then, SwitchOnDisabled);
    assert_eq!(odd.shutdown().ramp, Ramp::Disable);
    assert_eq!(odd.disable_operation().ramp, Ramp::Disable);
    assert_eq!(odd.fault_reaction().ramp, Ramp::Disable);
}

/// CSP, CSV and CST: 0x6502 = 0x0000_0380.
const CSX: u32 = 0x0000_0380;

#[test]
fn modes_are_checked_against_0x6502() {
    for (code, supported) in [
        (8, true),
        (9, true),
        (10, true),
        (1, false),
        (3, false),
        (0, false),
        (-1, false),
        (-128, false),
    ] {
        assert_eq!(mode::is_supported(code, CSX), supported, "mode {code}");
    }
    assert!(mode::is_supported(32, 1 << 31));
    assert_eq!(mode::check_write(&[8], CSX), Ok(()));
    assert_eq!(mode::check_write(&[1], CSX), Err(AbortCode::VALUE_RANGE));
    assert_eq!(mode::check_write(&[0], CSX), Err(AbortCode::VALUE_RANGE));
    assert_eq!(mode::check_write(&[0xFF], CSX), Err(AbortCode::VALUE_RANGE));
    // A wrong length is the dictionary's to refuse (0x06070012), not the mode check's.
    assert_eq!(mode::check_write(&[8, 0], CSX), Ok(()));
    assert_eq!(mode::check_write(&[1, 0], CSX), Ok(()));
}

#[test]
fn mode_display_follows_only_supported_modes() {
    assert_eq!(mode::display(8, 0, CSX), 8);
    assert_eq!(mode::display(9, 8, CSX), 9);
    assert_eq!(mode::display(1, 9, CSX), 9);
    assert_eq!(mode::display(0, 10, CSX), 10);
}

#[test]
fn mode_codes_and_bits() {
    let modes = [
        (Mode::ProfilePosition, 1, 0x001),
        (Mode::ProfileVelocity, 3, 0x004),
        (Mode::ProfileTorque, 4, 0x008),
        (Mode::Homing, 6, 0x020),
        (Mode::CyclicSyncPosition, 8, 0x080),
        (Mode::CyclicSyncVelocity, 9, 0x100),
        (Mode::CyclicSyncTorque, 10, 0x200),
    ];
    for (mode, code, bit) in modes {
        assert_eq!(
            (mode.code(), mode.supported_bit(), Mode::from_code(code)),
            (code, bit, Some(mode))
        );
    }
    for code in [0, 2, 5, 7, 11, -1] {
        assert_eq!(Mode::from_code(code), None);
    }
}

// --- the standard-object check --------------------------------------------------------------

/// A dictionary with the required objects and 0x607D, all as CiA 402-2 declares them.
struct Good {
    error_code: u16,
    controlword: u16,
    statusword: u16,
    mode: i8,
    mode_display: i8,
    limit: SoftwarePositionLimit,
    supported: u32,
}

ecat_core::dictionary! {
    minimal Good {
        0x603F => var(error_code, RO | TXPDO, "Error code");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword");
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
        0x607D => record(limit: SoftwarePositionLimit, "Software position limit") {
            1 => min, RW, "Min position limit";
            2 => max, RW, "Max position limit";
        };
        0x6502 => var(supported, RO, "Supported drive modes", default = CSX);
    }
}

/// 0x6041 as UNSIGNED32.
struct Bad {
    error_code: u16,
    controlword: u16,
    statusword: u32,
    mode: i8,
    mode_display: i8,
    supported: u32,
}

ecat_core::dictionary! {
    minimal Bad {
        0x603F => var(error_code, RO | TXPDO, "Error code");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword"); // UNSIGNED32: wrong
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
        0x6502 => var(supported, RO, "Supported drive modes");
    }
}

/// 0x6040 read-only.
struct ReadOnlyControl {
    error_code: u16,
    controlword: u16,
}

ecat_core::dictionary! {
    minimal ReadOnlyControl {
        0x603F => var(error_code, RO | TXPDO, "Error code");
        0x6040 => var(controlword, RO | RXPDO, "Controlword");
    }
}

/// 0x603F not TxPDO-mappable.
struct Unmapped {
    error_code: u16,
}

ecat_core::dictionary! {
    minimal Unmapped {
        0x603F => var(error_code, RO, "Error code");
    }
}

/// Without 0x6502.
struct Partial {
    error_code: u16,
    controlword: u16,
    statusword: u16,
    mode: i8,
    mode_display: i8,
}

ecat_core::dictionary! {
    minimal Partial {
        0x603F => var(error_code, RO | TXPDO, "Error code");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword");
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
    }
}

#[test]
fn standard_objects_are_checked_for_presence_type_access_and_mapping() {
    assert_eq!(objects::check::<Good>(), Ok(()));
    assert_eq!(
        objects::check::<Bad>(),
        Err((0x6041, 0, Mismatch::DataType))
    );
    assert_eq!(
        objects::check::<ReadOnlyControl>(),
        Err((0x6040, 0, Mismatch::Access))
    );
    assert_eq!(
        objects::check::<Unmapped>(),
        Err((0x603F, 0, Mismatch::Mapping))
    );
    assert_eq!(
        objects::check::<Partial>(),
        Err((0x6502, 0, Mismatch::Missing))
    );
    assert_eq!(objects::check::<()>(), Err((0x603F, 0, Mismatch::Missing)));
    let good = Good::default();
    let _ = (
        good.error_code,
        good.controlword,
        good.statusword,
        good.mode,
        good.mode_display,
    );
    assert_eq!(
        (good.limit, good.supported),
        (SoftwarePositionLimit { min: 0, max: 0 }, CSX)
    );
    let _ = (
        Bad::default(),
        ReadOnlyControl::default(),
        Unmapped::default(),
        Partial::default(),
    );
}

// --- fuzz ------------------------------------------------------------------------------------

#[derive(Debug, Clone)]
enum Input {
    Cycle { controlword: u16, standstill: bool },
    Fault,
}

fn input() -> impl Strategy<Value = Input> {
    prop_oneof![
        4 => (any::<u16>(), any::<bool>()).prop_map(|(controlword, standstill)| Input::Cycle { controlword, standstill }),
        // Controlwords near the commands, so that every state is visited often.
        4 => (prop::sample::select(vec![0x00u16, 0x02, 0x06, 0x07, 0x0F, 0x80, 0x86]), any::<bool>())
            .prop_map(|(controlword, standstill)| Input::Cycle { controlword, standstill }),
        1 => Just(Input::Fault),
    ]
}

fn options() -> impl Strategy<Value = OptionCodes> {
    (-2i16..10, -2i16..3, -2i16..3, -2i16..6).prop_map(
        |(quick_stop, shutdown, disable_operation, fault_reaction)| OptionCodes {
            quick_stop,
            shutdown,
            disable_operation,
            fault_reaction,
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any controlword sequence with faults injected: no panic, the statusword always shows
    /// exactly the state the PDS is in, transitions stay within 0..=16, and transition 15 only
    /// happens on a rising edge of bit 7.
    #[test]
    fn arbitrary_controlwords_and_faults(options in options(), inputs in prop::collection::vec(input(), 0..64), flags in any::<[bool; 7]>()) {
        let [voltage_enabled, warning, remote, target_reached, internal_limit, follows_command, following_error] = flags;
        let flags = StatusFlags { voltage_enabled, warning, remote, target_reached, internal_limit, follows_command, following_error };
        let mut pds = PowerDriveSystem::new();
        let mut previous = 0u16;
        for input in inputs {
            match input {
                Input::Fault => pds.fault(&options),
                Input::Cycle { controlword, standstill } => {
                    let step = pds.update(controlword, &options, standstill);
                    prop_assert_eq!(step.transitions.0 & !0x1_FFFF, 0);
                    if step.transitions.contains(15) {
                        prop_assert!(controlword & 0x80 != 0 && previous & 0x80 == 0);
                    }
                    prop_assert_eq!(step.motion == Motion::Follow, pds.state() == OperationEnabled && pds.pending().is_none());
                    previous = controlword;
                }
            }
            let word = statusword(pds.state(), flags);
            prop_assert_eq!(State::from_statusword(word), Some(pds.state()));
        }
    }
}
