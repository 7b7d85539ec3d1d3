//! The profile modes of the dummy axis, cycle by cycle through `Axis::step` on a dictionary value
//! (1 ms cycles, virtual time): profile position with the set-point handshake and a buffered
//! set of set-points, profile velocity with its window bits, homing against the simulated
//! machine's cam and index pulse, halt and touch probe — each reaching its target in a stated
//! number of cycles with the mode bits checked every cycle — and the whole sequence of the
//! issue (homing, PP with buffered set-points, PV, halt, quick stop) with its exact statusword
//! sequence.

use ecat_axis::{Axis, AxisOd, Machine};
use ecat_core::cia402::State;

const PP: i8 = 1;
const PV: i8 = 3;
const HM: i8 = 6;
const CSV: i8 = 9;

/// Statusword: Operation enabled + voltage enabled + remote, and the mode bits.
const ENABLED_SW: u16 = 0x0237;
const REACHED: u16 = 1 << 10;
const LIMIT: u16 = 1 << 11;
const B12: u16 = 1 << 12;
const B13: u16 = 1 << 13;

/// Controlword: enable operation, new set-point / homing start (4), change set immediately (5),
/// relative (6), halt (8).
const EN: u16 = 0x000F;
const NEW: u16 = 1 << 4;
const IMMEDIATE: u16 = 1 << 5;
const HALT: u16 = 1 << 8;

fn cycle(axis: &mut Axis, od: &mut AxisOd, controlword: u16) -> u16 {
    od.controlword = controlword;
    axis.step(od);
    od.statusword
}

/// The profile parameters of these tests: 100 c/cycle, 2 c/cycle² ramps; homing at 50 and
/// 10 c/cycle with 5 c/cycle² and home offset 1 000, method 7.
fn dictionary(mode: i8) -> AxisOd {
    let mut od = AxisOd {
        mode,
        ..AxisOd::default()
    };
    od.profile_velocity = 100_000;
    od.profile_acceleration = 2_000_000;
    od.profile_deceleration = 2_000_000;
    od.homing_method = 7;
    od.homing_speeds.switch_search = 50_000;
    od.homing_speeds.zero_search = 10_000;
    od.homing_acceleration = 5_000_000;
    od.home_offset = 1_000;
    od
}

/// A fresh axis in Operation enabled in `mode` after three cycles (transitions 1, 2, 3+4).
fn enabled(mode: i8) -> (Axis, AxisOd) {
    let mut axis = Axis::new();
    let mut od = dictionary(mode);
    assert_eq!(cycle(&mut axis, &mut od, 0x00), 0x0250);
    assert_eq!(cycle(&mut axis, &mut od, 0x06), 0x0231);
    cycle(&mut axis, &mut od, EN);
    assert_eq!(axis.state(), State::OperationEnabled);
    (axis, od)
}

/// The statusword run-length encoded: (value, cycles).
fn runs(words: &[u16]) -> Vec<(u16, u32)> {
    let mut out: Vec<(u16, u32)> = Vec::new();
    for &w in words {
        match out.last_mut() {
            Some((last, n)) if *last == w => *n += 1,
            _ => out.push((w, 1)),
        }
    }
    out
}

#[test]
fn the_dictionary_offers_the_profile_modes_and_objects() {
    let od = AxisOd::default();
    // PP (bit 0), PV (bit 2), HM (bit 5), CSP, CSV, CST (bits 7..9).
    assert_eq!(od.supported_modes, 0x0000_03A5);
    assert_eq!(ecat_core::cia402::objects::check::<AxisOd>(), Ok(()));
    assert_eq!((od.halt_option, od.homing_method), (1, 37));
    let bytes = |entries: &[ecat_core::pdo::MappingEntry]| {
        entries.iter().map(|e| u32::from(e.bit_len())).sum::<u32>() / 8
    };
    assert_eq!(
        (
            bytes(&ecat_axis::RX_PROFILE_MAPPING),
            bytes(&ecat_axis::TX_PROFILE_MAPPING)
        ),
        (25, 31)
    );
}

#[test]
fn pp_reaches_the_target_in_stated_cycles_with_the_handshake_every_cycle() {
    let (mut axis, mut od) = enabled(PP);
    assert_eq!(od.statusword, ENABLED_SW | REACHED);
    od.target_position = 10_000;
    // Edge: acknowledged at once.
    assert_eq!(cycle(&mut axis, &mut od, EN | NEW), ENABLED_SW | B12);
    assert_eq!(cycle(&mut axis, &mut od, EN | NEW), ENABLED_SW | B12);
    // Bit 4 low: acknowledge low, moving, not reached, every cycle until the target.
    // 10 000 counts at 100 c/cycle with 2 c/cycle² ramps: 50 cycles up (2 550 counts), 49
    // cruising, 50 down (2 450), 1 landing; 2 of them spent above.
    let mut n = 2;
    loop {
        let sw = cycle(&mut axis, &mut od, EN);
        n += 1;
        if sw & REACHED != 0 {
            assert_eq!(sw, ENABLED_SW | REACHED);
            break;
        }
        assert_eq!(sw, ENABLED_SW, "cycle {n}");
        assert!(od.velocity <= 100_000 && od.position <= 10_000);
    }
    assert_eq!((n, od.position, od.velocity), (151, 10_000, 0));
}

#[test]
fn pp_buffers_a_set_of_set_points_and_holds_the_acknowledge_while_full() {
    let (mut axis, mut od) = enabled(PP);
    od.target_position = 3_000;
    assert_eq!(cycle(&mut axis, &mut od, EN | NEW), ENABLED_SW | B12);
    assert_eq!(cycle(&mut axis, &mut od, EN), ENABLED_SW);
    od.target_position = 1_000;
    assert_eq!(cycle(&mut axis, &mut od, EN | NEW), ENABLED_SW | B12);
    let mut words = Vec::new();
    while words.len() < 400 {
        words.push(cycle(&mut axis, &mut od, EN));
    }
    // Full buffer: acknowledge held until the first target (3 000) is reached and the second
    // starts, then low; reached at 1 000.
    let r = runs(&words);
    assert_eq!(
        r.iter().map(|&(w, _)| w).collect::<Vec<_>>(),
        [ENABLED_SW | B12, ENABLED_SW, ENABLED_SW | REACHED]
    );
    assert_eq!(od.position, 1_000);
    // 3 000 counts at 2 c/cycle², peak below 100 c/cycle: 2·√1 500 ≈ 77.5 cycles, the buffered
    // set-point starting in the 78th; 2 000 counts back: 2·√1 000 ≈ 63.2 cycles, the landing,
    // and the standstill cycle before bit 10 (position window 0, time 0): 66.
    assert_eq!((r[0].1, r[1].1), (78, 66));
}

#[test]
fn pp_change_set_immediately_turns_around_at_once() {
    let (mut axis, mut od) = enabled(PP);
    od.target_position = 10_000;
    cycle(&mut axis, &mut od, EN | NEW | IMMEDIATE);
    for _ in 0..60 {
        cycle(&mut axis, &mut od, EN | IMMEDIATE);
    }
    let v = od.velocity;
    od.target_position = 0;
    assert_eq!(
        cycle(&mut axis, &mut od, EN | NEW | IMMEDIATE),
        ENABLED_SW | B12
    );
    assert_eq!(od.velocity, v - 2_000);
}

#[test]
fn pv_reaches_the_target_velocity_in_stated_cycles() {
    let (mut axis, mut od) = enabled(PV);
    // Standing: speed zero (bit 12) and reached for target 0.
    assert_eq!(od.statusword, ENABLED_SW | REACHED | B12);
    od.target_velocity = -30_000;
    let mut words = Vec::new();
    for _ in 0..20 {
        words.push(cycle(&mut axis, &mut od, EN));
    }
    // 2 000 c/s per cycle: 15 cycles to −30 000; speed zero gone at once (|v| > 100).
    assert_eq!(runs(&words), [(ENABLED_SW, 14), (ENABLED_SW | REACHED, 6)]);
    assert_eq!(od.velocity, -30_000);
    // Above 0x607F: clamped, bit 11.
    od.target_velocity = 2_000_000;
    let n = (1..)
        .find(|_| cycle(&mut axis, &mut od, EN) & REACHED != 0)
        .unwrap();
    assert_eq!((n, od.velocity), (515, 1_000_000));
    assert_eq!(od.statusword, ENABLED_SW | REACHED | LIMIT);
}

#[test]
fn homing_method_7_finds_the_index_below_the_cam_in_stated_cycles() {
    let (mut axis, mut od) = enabled(HM);
    assert_eq!(od.statusword, ENABLED_SW | REACHED);
    let mut words = Vec::new();
    loop {
        let sw = cycle(&mut axis, &mut od, EN | NEW);
        words.push(sw);
        if sw & (B12 | REACHED) == B12 | REACHED {
            break;
        }
        assert!(words.len() < 2_000);
    }
    // In progress, attained while braking, completed; the reference (the index at 4 500,
    // below the cam at 5 000..8 000) reads 0x607C = 1 000. 191 cycles: 10 ramping up to
    // 50 c/cycle (275 counts) and 95 at 50 c/cycle to the cam at 5 000; 12 turning to
    // −10 c/cycle (about 150 counts into the cam); 15 back to 4 999 where the cam releases;
    // 50 at 10 c/cycle to the index at 4 500 (and the cycle that sees it). Attained for the one
    // braking cycle (10 → 5 → 0 c/cycle at 5 c/cycle²), then completed.
    assert_eq!(
        runs(&words),
        [
            (ENABLED_SW, 191),
            (ENABLED_SW | B12, 1),
            (ENABLED_SW | B12 | REACHED, 1)
        ]
    );
    // The reference is the position of the cycle that saw the pulse (one cycle's resolution:
    // 4 495 at 10 c/cycle downwards); it reads 1 000.
    assert_eq!(
        axis.physical_position() - i64::from(od.position),
        4_495 - 1_000
    );
    // 0x60FD: the home switch is bit 2, off here.
    assert_eq!(od.digital_inputs, 0);
}

#[test]
fn homing_into_a_limit_without_a_cam_is_an_error() {
    let mut axis = Axis::new().with_machine(Machine {
        home: (i64::MAX, i64::MAX),
        positive_limit: 2_000,
        negative_limit: -2_000,
        ..Machine::DEFAULT
    });
    let mut od = dictionary(HM);
    cycle(&mut axis, &mut od, 0x00);
    cycle(&mut axis, &mut od, 0x06);
    cycle(&mut axis, &mut od, EN);
    let mut words = Vec::new();
    while words.last() != Some(&(ENABLED_SW | B13 | REACHED)) {
        words.push(cycle(&mut axis, &mut od, EN | NEW));
        assert!(words.len() < 2_000);
    }
    let states: Vec<u16> = runs(&words).iter().map(|&(w, _)| w).collect();
    assert_eq!(
        states,
        [ENABLED_SW, ENABLED_SW | B13, ENABLED_SW | B13 | REACHED]
    );
    // Both limits were hit: 0x60FD bit 0 now.
    assert_eq!(od.digital_inputs, 0b001);
}

#[test]
fn halt_stops_csv_with_the_0x605d_ramp_and_stays_enabled() {
    let (mut axis, mut od) = enabled(CSV);
    od.target_velocity = 20_000;
    cycle(&mut axis, &mut od, EN);
    od.halt_option = 2; // quick stop ramp 0x6085: 10 000 c/s per cycle
    assert_eq!(cycle(&mut axis, &mut od, EN | HALT), ENABLED_SW);
    assert_eq!(od.velocity, 10_000);
    assert_eq!(cycle(&mut axis, &mut od, EN | HALT), ENABLED_SW | REACHED);
    assert_eq!((od.velocity, axis.state()), (0, State::OperationEnabled));
}

#[test]
fn the_touch_probe_latches_the_home_switch_edges() {
    let (mut axis, mut od) = enabled(PV);
    // Probe 1 on its input (the home switch), both edges, first event.
    od.touch_probe_function = 0x0031;
    od.target_velocity = 100_000;
    for _ in 0..200 {
        cycle(&mut axis, &mut od, EN);
    }
    // 100 c/cycle after 50 ramp cycles; the cam is 5 000..8 000.
    assert_eq!(od.touch_probe_status, 0x0007);
    assert_eq!((od.probe1_positive, od.probe1_negative), (5_050, 8_050));
}

/// The sequence of the issue: homing, a PP move with a buffered set of set-points, a PV
/// segment, a halt and a quick stop, with every statusword asserted.
#[test]
fn homing_pp_set_of_set_points_pv_halt_and_quick_stop() {
    let (mut axis, mut od) = enabled(HM);
    let mut words = Vec::new();
    // Homing: method 7.
    while words
        .last()
        .is_none_or(|&w| w & (B12 | REACHED) != B12 | REACHED)
    {
        words.push(cycle(&mut axis, &mut od, EN | NEW));
    }
    words.push(cycle(&mut axis, &mut od, EN));
    // PP: 6 000 then 2 000, the second buffered.
    od.mode = PP;
    od.target_position = 6_000;
    words.push(cycle(&mut axis, &mut od, EN | NEW));
    words.push(cycle(&mut axis, &mut od, EN));
    od.target_position = 2_000;
    words.push(cycle(&mut axis, &mut od, EN | NEW));
    while words.last().is_none_or(|&w| w & REACHED == 0) {
        words.push(cycle(&mut axis, &mut od, EN));
    }
    assert_eq!(od.position, 2_000);
    // PV: to 40 000 c/s, then halt (0x605D = 1: profile deceleration).
    od.mode = PV;
    od.target_velocity = 40_000;
    for _ in 0..40 {
        words.push(cycle(&mut axis, &mut od, EN));
    }
    for _ in 0..25 {
        words.push(cycle(&mut axis, &mut od, EN | HALT));
    }
    // Released: back to 40 000, then quick stop (0x605A = 2: 0x6085, then Switch on disabled).
    for _ in 0..25 {
        words.push(cycle(&mut axis, &mut od, EN));
    }
    for _ in 0..6 {
        words.push(cycle(&mut axis, &mut od, 0x0002));
    }
    assert_eq!(axis.state(), State::SwitchOnDisabled);
    let r = runs(&words);
    let expected: &[(u16, u32)] = &[
        // Homing: in progress, attained, completed (one more cycle with bit 4 low).
        (ENABLED_SW, 191),
        (ENABLED_SW | B12, 1),
        (ENABLED_SW | B12 | REACHED, 2),
        // PP, entered with bit 4 rising: the first set-point acknowledged, released; the
        // second buffered: acknowledge held while the axis runs ~5 000 counts to 6 000
        // (2·√2 500 = 100 cycles + 2), then 4 000 back to 2 000 (2·√2 000 ≈ 89.4, landing,
        // standstill), reached.
        (ENABLED_SW | B12, 1),
        (ENABLED_SW, 1),
        (ENABLED_SW | B12, 102),
        (ENABLED_SW, 92),
        (ENABLED_SW | REACHED, 1),
        // PV: 40 000 c/s at 2 000 c/s per cycle, reached in the 20th cycle (window 100, 0 ms).
        (ENABLED_SW, 19),
        (ENABLED_SW | REACHED, 21),
        // Halt (0x605D = 1: 0x6084): 20 cycles to standstill, then reached + speed zero.
        (ENABLED_SW, 19),
        (ENABLED_SW | REACHED | B12, 6),
        // Released: 20 cycles back to 40 000, reached.
        (ENABLED_SW, 19),
        (ENABLED_SW | REACHED, 6),
        // Quick stop (0x605A = 2): Quick stop active braking at 0x6085 (10 000 c/s per cycle),
        // target reached at standstill, then Switch on disabled (transition 12).
        (0x0217, 3),
        (0x0217 | REACHED, 1),
        (0x0250, 2),
    ];
    assert_eq!(r, expected);
}

/// The statusword after one cycle of `controlword` from a fresh axis in `state` (reached
/// through the public API, quick stop option 6 so that Quick stop active stays) in `mode`,
/// standing at 0 with every target 0.
fn statusword_after(state: State, mode: i8, controlword: u16) -> u16 {
    let mut axis = Axis::new();
    let mut od = dictionary(mode);
    od.quick_stop_option = 6;
    let path: &[u16] = match state {
        State::SwitchOnDisabled => &[0x00],
        State::ReadyToSwitchOn => &[0x00, 0x06],
        State::SwitchedOn => &[0x00, 0x06, 0x07],
        State::OperationEnabled => &[0x00, 0x06, 0x0F],
        State::QuickStopActive => &[0x00, 0x06, 0x0F, 0x02, 0x02],
        _ => unreachable!(),
    };
    for &cw in path {
        cycle(&mut axis, &mut od, cw);
    }
    assert_eq!(axis.state(), state);
    // The command bits of the state, plus the edge under test.
    let base = path.last().copied().unwrap_or(0);
    cycle(&mut axis, &mut od, base | controlword)
}

/// (state, controlword edge, mode) → statusword, byte-exact: the mode bits appear only in
/// Operation enabled (Quick stop active reports target reached at standstill); bit 4 rising
/// acknowledges a PP set-point (already at its target 0: reached too) and starts homing method
/// 7 (in progress: 13/12/10 = 000), not while halted; halt clears "drive follows the command" in
/// the cyclic modes and reports target reached at standstill; PV shows speed zero (bit 12)
/// whenever it stands.
#[test]
fn statusword_table_by_state_edge_and_mode() {
    const CSP: i8 = 8;
    const CST: i8 = 10;
    let modes = [PP, PV, HM, CSP, CSV, CST];
    // Per state and edge: the statusword in each of the six modes.
    let table: &[(State, u16, [u16; 6])] = &[
        (State::SwitchOnDisabled, 0, [0x0250; 6]),
        (State::SwitchOnDisabled, NEW, [0x0250; 6]),
        (State::ReadyToSwitchOn, 0, [0x0231; 6]),
        (State::ReadyToSwitchOn, HALT, [0x0231; 6]),
        (State::SwitchedOn, NEW, [0x0233; 6]),
        (
            State::OperationEnabled,
            0,
            [0x0637, 0x1637, 0x0637, 0x1637, 0x1637, 0x1637],
        ),
        (
            State::OperationEnabled,
            NEW,
            [0x1637, 0x1637, 0x0237, 0x1637, 0x1637, 0x1637],
        ),
        (
            State::OperationEnabled,
            HALT,
            [0x0637, 0x1637, 0x0637, 0x0637, 0x0637, 0x0637],
        ),
        (
            State::OperationEnabled,
            NEW | HALT,
            [0x1637, 0x1637, 0x0637, 0x0637, 0x0637, 0x0637],
        ),
        (State::QuickStopActive, 0, [0x0617; 6]),
        (State::QuickStopActive, NEW, [0x0617; 6]),
    ];
    for &(state, edge, expected) in table {
        let got = modes.map(|mode| statusword_after(state, mode, edge));
        assert_eq!(got, expected, "{state:?} with {edge:#06x}");
    }
}

/// SM3 starts after three buffers of the larger RxPDO set, so that assigning 0x1601 (25 bytes)
/// instead of 0x1600 (13) in PREOP cannot make SM2 overlap SM3; SM2's default length stays the
/// default assignment's.
#[test]
fn the_sync_managers_leave_room_for_the_profile_pdo_set() {
    let sms = ecat_core::sii::sync_managers(&ecat_axis::DEVICE, &AxisOd::default());
    let (outputs, inputs) = (&sms[2], &sms[3]);
    assert_eq!((outputs.length, inputs.length), (13, 19));
    // 13 + 25 bytes of RxPDO mapping objects, three buffers, 8-aligned.
    assert_eq!(inputs.start - outputs.start, (3 * 38u16).div_ceil(8) * 8);
}
