//! The CiA 402 profile modes of `ecat_core::cia402`: profile position (set-point handshake,
//! single set-point, set of set-points, change on set-point, relative, halt, limits), profile
//! velocity (velocity window, speed zero, halt), homing (every method against a simulated
//! machine, the statusword table, errors, interruption), the halt option codes, the touch probe
//! and the profile generator. Time is virtual: 1 ms cycles.

use ecat_core::cia402::homing::{Homing, HomingInputs, HomingParameters, Method, Switch};
use ecat_core::cia402::inputs::digital_inputs;
use ecat_core::cia402::pp::{PpParameters, ProfilePosition};
use ecat_core::cia402::profile::{Ramps, Trajectory, clamp_torque};
use ecat_core::cia402::pv::{ProfileVelocity, PvParameters};
use ecat_core::cia402::touch_probe::{ProbeInput, TouchProbes};
use ecat_core::cia402::{Ramp, SoftwarePositionLimit, halt};
use proptest::prelude::*;

const MS: u32 = 1_000_000;

/// `bit` when `on`.
fn flag(on: bool, bit: u16) -> u16 {
    if on { bit } else { 0 }
}

/// Statusword bits 10 (target reached), 11 (internal limit), 12, 13.
const REACHED: u16 = 1 << 10;
const LIMIT: u16 = 1 << 11;
const B12: u16 = 1 << 12;
const B13: u16 = 1 << 13;

/// Controlword: enable operation + new set-point (bit 4), change set immediately (5), relative
/// (6), halt (8), change on set-point (9).
const ENABLED: u16 = 0x000F;
const NEW: u16 = 1 << 4;
const IMMEDIATE: u16 = 1 << 5;
const RELATIVE: u16 = 1 << 6;
const HALT: u16 = 1 << 8;
const ON_SET_POINT: u16 = 1 << 9;

/// 10 counts per cycle at most, 1 count/cycle² ramps.
const PP: PpParameters = PpParameters {
    target: 0,
    profile_velocity: 10_000,
    acceleration: 1_000_000,
    deceleration: 1_000_000,
    max_velocity: 1_000_000,
    limit: SoftwarePositionLimit { min: 0, max: 0 },
    window: 0,
    window_time: 0,
    halt_deceleration: 2_000_000,
};

struct PpAxis {
    pp: ProfilePosition,
    t: Trajectory,
}

impl PpAxis {
    fn new() -> Self {
        let mut pp = ProfilePosition::new();
        pp.enter(0, ENABLED);
        Self {
            pp,
            t: Trajectory::new(),
        }
    }

    /// One cycle: the mode bits 10..13.
    fn cycle(&mut self, cw: u16, p: &PpParameters) -> u16 {
        let actual = self.t.position();
        let s = self.pp.update(cw, p, actual, &mut self.t, MS);
        flag(s.target_reached, REACHED)
            | flag(s.internal_limit, LIMIT)
            | flag(s.set_point_acknowledge, B12)
    }

    /// Cycles with `cw` until bit 10; the number of cycles.
    fn until_reached(&mut self, cw: u16, p: &PpParameters, limit: u32) -> u32 {
        for n in 1..=limit {
            if self.cycle(cw, p) & REACHED != 0 {
                return n;
            }
        }
        panic!("not reached in {limit} cycles at {}", self.t.position());
    }
}

fn pp_to(target: i32) -> PpParameters {
    PpParameters { target, ..PP }
}

#[test]
fn pp_handshake_acknowledges_on_the_edge_and_releases_when_bit_4_drops() {
    let mut axis = PpAxis::new();
    // Nothing commanded: at rest, target reached.
    assert_eq!(axis.cycle(ENABLED, &pp_to(1_000)), REACHED);
    // Rising edge of bit 4: taken and acknowledged in the same cycle; bit 10 drops.
    assert_eq!(axis.cycle(ENABLED | NEW, &pp_to(1_000)), B12);
    // Bit 4 held: acknowledge stays; a changed 0x607A is not taken without an edge.
    assert_eq!(axis.cycle(ENABLED | NEW, &pp_to(-5_000)), B12);
    // Bit 4 dropped: acknowledge drops in the same cycle.
    assert_eq!(axis.cycle(ENABLED, &pp_to(-5_000)), 0);
    // 1 000 counts, 10 c/cycle, 1 c/cycle² ramps: 10 cycles up (55 counts), 89 cruising, 10
    // down; the three cycles above moved 1 + 2 + 3.
    let n = axis.until_reached(ENABLED, &pp_to(-5_000), 1_000);
    assert_eq!((n, axis.t.position()), (108, 1_000));
    assert_eq!(axis.cycle(ENABLED, &pp_to(-5_000)), REACHED);
}

#[test]
fn pp_single_set_point_replaces_the_move_in_progress() {
    let mut axis = PpAxis::new();
    axis.cycle(ENABLED | NEW | IMMEDIATE, &pp_to(1_000));
    for _ in 0..30 {
        assert_eq!(axis.cycle(ENABLED | IMMEDIATE, &pp_to(1_000)), 0);
    }
    // A new target behind the axis: taken at once, the axis brakes and turns.
    assert_eq!(axis.cycle(ENABLED | NEW | IMMEDIATE, &pp_to(100)), B12);
    let before = axis.t.velocity();
    axis.cycle(ENABLED | IMMEDIATE, &pp_to(100));
    assert!(axis.t.velocity() < before);
    axis.until_reached(ENABLED | IMMEDIATE, &pp_to(100), 1_000);
    assert_eq!(axis.t.position(), 100);
}

#[test]
fn pp_set_of_set_points_buffers_one_and_holds_the_acknowledge_while_full() {
    let mut axis = PpAxis::new();
    assert_eq!(axis.cycle(ENABLED | NEW, &pp_to(500)), B12);
    assert_eq!(axis.cycle(ENABLED, &pp_to(500)), 0);
    // The second set-point is buffered: acknowledged, and the acknowledge stays with bit 4 = 0.
    assert_eq!(axis.cycle(ENABLED | NEW, &pp_to(800)), B12);
    assert_eq!(axis.cycle(ENABLED, &pp_to(800)), B12);
    // A third edge while the buffer is full is ignored.
    assert_eq!(axis.cycle(ENABLED | NEW, &pp_to(-9_999)), B12);
    assert!(axis.pp.buffered());
    // At 500 the buffered set-point starts and the acknowledge drops; the axis stopped at 500.
    let mut stopped_at_500 = false;
    let mut n = 0;
    while axis.cycle(ENABLED, &pp_to(0)) & B12 != 0 {
        stopped_at_500 |= axis.t.position() == 500 && axis.t.standstill();
        n += 1;
        assert!(n < 1_000);
    }
    assert!(stopped_at_500);
    assert!(!axis.pp.buffered());
    axis.until_reached(ENABLED, &pp_to(0), 1_000);
    assert_eq!(axis.t.position(), 800);
}

#[test]
fn pp_change_on_set_point_passes_the_first_target_without_stopping() {
    let mut axis = PpAxis::new();
    axis.cycle(ENABLED | NEW | ON_SET_POINT, &pp_to(500));
    axis.cycle(ENABLED | ON_SET_POINT, &pp_to(500));
    axis.cycle(ENABLED | NEW | ON_SET_POINT, &pp_to(800));
    let mut min_speed_after_start = i64::MAX;
    let mut n = 0;
    while axis.cycle(ENABLED | ON_SET_POINT, &pp_to(0)) & REACHED == 0 {
        if axis.t.position() > 100 && axis.t.position() < 700 {
            min_speed_after_start = min_speed_after_start.min(axis.t.velocity());
        }
        n += 1;
        assert!(n < 1_000);
    }
    assert_eq!(axis.t.position(), 800);
    assert_eq!(min_speed_after_start, 10_000);
}

#[test]
fn pp_relative_targets_add_to_the_preceding_target() {
    let mut axis = PpAxis::new();
    axis.cycle(ENABLED | NEW | RELATIVE, &pp_to(300));
    axis.until_reached(ENABLED | RELATIVE, &pp_to(300), 1_000);
    axis.cycle(ENABLED | NEW | RELATIVE, &pp_to(-100));
    axis.until_reached(ENABLED | RELATIVE, &pp_to(-100), 1_000);
    assert_eq!(axis.t.position(), 200);
}

#[test]
fn pp_clamps_the_target_into_0x607d_with_bit_11() {
    let mut axis = PpAxis::new();
    let p = PpParameters {
        limit: SoftwarePositionLimit {
            min: -100,
            max: 400,
        },
        ..pp_to(1_000)
    };
    assert_eq!(axis.cycle(ENABLED | NEW, &p), B12 | LIMIT);
    axis.until_reached(ENABLED, &p, 1_000);
    assert_eq!(axis.t.position(), 400);
    assert_eq!(axis.cycle(ENABLED, &p), REACHED | LIMIT);
}

#[test]
fn pp_halt_stops_with_the_halt_ramp_then_resumes() {
    let mut axis = PpAxis::new();
    axis.cycle(ENABLED | NEW, &pp_to(1_000));
    for _ in 0..20 {
        axis.cycle(ENABLED, &pp_to(1_000));
    }
    assert_eq!(axis.t.velocity(), 10_000);
    // Halt ramp 2 c/cycle²: 10 → 8 → 6 → 4 → 2 → 0 c/cycle, bit 10 at standstill.
    let bits: Vec<u16> = (0..6)
        .map(|_| axis.cycle(ENABLED | HALT, &pp_to(1_000)))
        .collect();
    assert_eq!(bits, [0, 0, 0, 0, REACHED, REACHED]);
    // Halt released: the move continues to its target.
    assert_eq!(axis.cycle(ENABLED, &pp_to(1_000)), 0);
    axis.until_reached(ENABLED, &pp_to(1_000), 1_000);
    assert_eq!(axis.t.position(), 1_000);
}

#[test]
fn pp_position_window_delays_target_reached_by_0x6068() {
    let mut axis = PpAxis::new();
    let p = PpParameters {
        window: 5,
        window_time: 3,
        ..pp_to(100)
    };
    axis.cycle(ENABLED | NEW, &p);
    let mut trace = Vec::new();
    while trace.len() < 60 {
        trace.push((axis.t.position(), axis.cycle(ENABLED, &p) & REACHED));
    }
    let arrived = trace.iter().position(|&(x, _)| x == 100).unwrap();
    let reached = trace.iter().position(|&(_, r)| r != 0).unwrap();
    // Arrival cycle, the standstill cycle, then 3 ms inside the window.
    assert_eq!(reached - arrived, 3);
}

const PV: PvParameters = PvParameters {
    target: 0,
    acceleration: 1_000_000,
    deceleration: 2_000_000,
    max_velocity: 50_000,
    window: 500,
    window_time: 2,
    threshold: 1_500,
    threshold_time: 1,
    halt_deceleration: 5_000_000,
};

/// PV bits 10/11/12 of one cycle.
fn pv_cycle(pv: &mut ProfileVelocity, t: &mut Trajectory, cw: u16, target: i32) -> u16 {
    let s = pv.update(cw, &PvParameters { target, ..PV }, t, MS);
    flag(s.target_reached, REACHED) | flag(s.internal_limit, LIMIT) | flag(s.speed_zero, B12)
}

#[test]
fn pv_window_threshold_and_halt_bits_cycle_by_cycle() {
    let mut pv = ProfileVelocity::new();
    let mut t = Trajectory::new();
    // 0 → 5 000 c/s at 1 000 c/s per cycle. Speed zero while |v| ≤ 1 500 for 1 ms (the first
    // cycle at 1 000 c/s), target reached once |5 000 − v| ≤ 500 held for 2 ms (5 000 from the
    // fifth cycle on).
    let bits: Vec<u16> = (0..8)
        .map(|_| pv_cycle(&mut pv, &mut t, ENABLED, 5_000))
        .collect();
    assert_eq!(bits, [B12, 0, 0, 0, 0, REACHED, REACHED, REACHED]);
    assert_eq!(t.velocity(), 5_000);
    // Above 0x607F: clamped with bit 11; reached at 50 000.
    let n = (1..)
        .find(|_| pv_cycle(&mut pv, &mut t, ENABLED, 90_000) & REACHED != 0)
        .unwrap();
    assert_eq!((n, t.velocity()), (46, 50_000));
    assert_eq!(pv_cycle(&mut pv, &mut t, ENABLED, 90_000), REACHED | LIMIT);
    // Halt: 5 000 c/s per cycle to standstill in 10 cycles, bit 10 at standstill, speed zero
    // 1 ms after reaching the threshold.
    let bits: Vec<u16> = (0..11)
        .map(|_| pv_cycle(&mut pv, &mut t, ENABLED | HALT, 40_000))
        .collect();
    assert_eq!(&bits[..9], &[0; 9]);
    assert_eq!(bits[9], REACHED | B12);
    assert_eq!(t.velocity(), 0);
    // Reversing: the deceleration ramp applies down to 0, then the acceleration ramp.
    pv_cycle(&mut pv, &mut t, ENABLED, 3_000);
    pv_cycle(&mut pv, &mut t, ENABLED, 3_000);
    assert_eq!(t.velocity(), 2_000);
    pv_cycle(&mut pv, &mut t, ENABLED, -3_000);
    assert_eq!(t.velocity(), 0);
    pv_cycle(&mut pv, &mut t, ENABLED, -3_000);
    assert_eq!(t.velocity(), -1_000);
}

#[test]
fn the_halt_option_code_selects_the_ramp() {
    assert_eq!(
        [0, 1, 2, 3, 4, 5, -1].map(halt),
        [
            Ramp::SlowDown,
            Ramp::SlowDown,
            Ramp::QuickStop,
            Ramp::CurrentLimit,
            Ramp::VoltageLimit,
            Ramp::SlowDown,
            Ramp::SlowDown
        ]
    );
}

#[test]
fn the_torque_limit_clamps_with_bit_11() {
    assert_eq!(clamp_torque(1_500, 1_000), (1_000, true));
    assert_eq!(clamp_torque(-1_500, 1_000), (-1_000, true));
    assert_eq!(clamp_torque(999, 1_000), (999, false));
}

/// A machine for homing: switches and index pulses at physical positions.
#[derive(Clone, Copy)]
struct Machine {
    /// Negative limit active at or below, positive at or above.
    limits: (i64, i64),
    /// Home switch active inside (inclusive).
    home: (i64, i64),
    /// Index pulses at 500 + k·1 000.
    index: bool,
}

/// A cam between the limits.
const CAM: Machine = Machine {
    limits: (-10_000, 10_000),
    home: (2_000, 3_000),
    index: true,
};
/// A home switch active on the positive side of 2 000.
const POSITIVE_SIDE: Machine = Machine {
    home: (2_000, i64::MAX),
    ..CAM
};
/// A home switch active on the negative side of 2 000.
const NEGATIVE_SIDE: Machine = Machine {
    home: (i64::MIN, 2_000),
    ..CAM
};

impl Machine {
    fn inputs(&self, before: i64, now: i64) -> HomingInputs {
        // A pulse at x = 500 + k·1 000 crossed: x in (before, now] moving up, [now, before)
        // moving down.
        let pulse = |x: i64| (x - 500).div_euclid(1_000);
        let crossed = match now.cmp(&before) {
            std::cmp::Ordering::Greater => pulse(now) != pulse(before),
            std::cmp::Ordering::Less => pulse(now - 1) != pulse(before - 1),
            std::cmp::Ordering::Equal => false,
        };
        HomingInputs {
            negative_limit: now <= self.limits.0,
            positive_limit: now >= self.limits.1,
            home_switch: (self.home.0..=self.home.1).contains(&now),
            index_pulse: self.index && crossed,
        }
    }
}

const HM: HomingParameters = HomingParameters {
    method: 0,
    switch_speed: 20_000,
    zero_speed: 1_000,
    acceleration: 500_000,
    home_offset: 7,
    max_velocity: 1_000_000,
    halt_deceleration: 1_000_000,
};

struct HomingRun {
    /// The physical position where the reference was taken.
    reference: i64,
    /// The distinct (bit 13, 12, 10) states in order.
    states: Vec<u16>,
    cycles: u32,
    /// The final physical position.
    end: i64,
}

/// Homes with `method` from physical `start` on `machine` until bit 10 with 12 or 13.
fn home(machine: Machine, method: i8, start: i64) -> HomingRun {
    let p = HomingParameters { method, ..HM };
    let mut hm = Homing::new();
    hm.enter(ENABLED);
    let mut t = Trajectory::new();
    t.follow(start, 0);
    let mut origin = 0i64; // physical = demand − origin
    let mut before = start;
    let mut states = Vec::new();
    let mut reference = None;
    for cycle in 1..=20_000 {
        let now = t.position() - origin;
        let inputs = machine.inputs(before, now);
        before = now;
        let s = hm.update(ENABLED | NEW, &p, inputs, &mut t, MS);
        if s.shift != 0 || (s.attained && reference.is_none()) {
            origin += s.shift;
            reference = Some(now);
            // The reference now reads 0x607C.
            assert_eq!(now + origin, i64::from(HM.home_offset));
        }
        let bits = flag(s.error, B13) | flag(s.attained, B12) | flag(s.target_reached, REACHED);
        if states.last() != Some(&bits) {
            states.push(bits);
        }
        if s.target_reached && (s.attained || s.error) {
            return HomingRun {
                reference: reference.unwrap_or(i64::MIN),
                states,
                cycles: cycle,
                end: t.position() - origin,
            };
        }
    }
    panic!("method {method} from {start} did not end: {states:?}");
}

#[test]
fn every_homing_method_finds_its_reference() {
    // (machine, method, start, reference)
    let table: &[(Machine, i8, i64, i64)] = &[
        (CAM, 1, 0, -9_500),
        (CAM, 2, 0, 9_500),
        (POSITIVE_SIDE, 3, 0, 1_500),
        (POSITIVE_SIDE, 3, 5_000, 1_500),
        (POSITIVE_SIDE, 4, 0, 2_500),
        (POSITIVE_SIDE, 4, 5_000, 2_500),
        (NEGATIVE_SIDE, 5, 5_000, 2_500),
        (NEGATIVE_SIDE, 5, 0, 2_500),
        (NEGATIVE_SIDE, 6, 5_000, 1_500),
        (NEGATIVE_SIDE, 6, 0, 1_500),
        (CAM, 7, 0, 1_500),
        (CAM, 7, 2_500, 1_500),
        (CAM, 7, 5_000, 1_500),
        (CAM, 8, 0, 2_500),
        (CAM, 8, 5_000, 2_500),
        (CAM, 9, 0, 2_500),
        (CAM, 9, 5_000, 2_500),
        (CAM, 10, 0, 3_500),
        (CAM, 10, 5_000, 3_500),
        (CAM, 11, 5_000, 3_500),
        (CAM, 11, 0, 3_500),
        (CAM, 12, 5_000, 2_500),
        (CAM, 12, 0, 2_500),
        (CAM, 13, 5_000, 2_500),
        (CAM, 13, 0, 2_500),
        (CAM, 14, 5_000, 1_500),
        (CAM, 14, 2_500, 1_500),
        (CAM, 14, 0, 1_500),
        (CAM, 17, 0, -9_999),
        (CAM, 18, 0, 9_999),
        (POSITIVE_SIDE, 19, 0, 1_999),
        (POSITIVE_SIDE, 20, 0, 2_000),
        (NEGATIVE_SIDE, 21, 5_000, 2_001),
        (NEGATIVE_SIDE, 22, 5_000, 2_000),
        (CAM, 23, 0, 1_999),
        (CAM, 24, 0, 2_000),
        (CAM, 25, 0, 3_000),
        (CAM, 26, 0, 3_001),
        (CAM, 27, 5_000, 3_001),
        (CAM, 28, 5_000, 3_000),
        (CAM, 29, 5_000, 2_000),
        (CAM, 30, 5_000, 1_999),
        (CAM, 33, 0, -500),
        (CAM, 34, 0, 500),
        (CAM, 35, 1_234, 1_234),
        (CAM, 37, -77, -77),
    ];
    for &(machine, method, start, reference) in table {
        let run = home(machine, method, start);
        assert_eq!(
            (method, start, run.reference),
            (method, start, reference),
            "method {method} from {start}: {:?}",
            run.states
        );
        // In progress (0/0/0), attained (0/1/0), completed (0/1/1); 35 and 37 complete at once.
        let expected: &[u16] = if matches!(method, 35 | 37) {
            &[B12 | REACHED]
        } else {
            &[0, B12, B12 | REACHED]
        };
        assert_eq!(run.states, expected, "method {method} from {start}");
    }
}

#[test]
fn homing_sets_the_reference_to_the_home_offset() {
    let run = home(CAM, 34, 0);
    // The demand reads 7 (0x607C) at the reference, 500 physical (`home` checks the shift);
    // the axis brakes at 500 c/s per cycle and stops one count beyond the pulse. 503 cycles:
    // 2 ramping up (1.5 counts), 499 at 1 count per cycle, 2 braking.
    assert_eq!(run.reference, 500);
    assert_eq!(run.end, 501);
    assert_eq!(run.cycles, 503);
}

#[test]
fn homing_errors_report_bit_13_and_stop() {
    // No home switch anywhere: method 3 searches into the positive limit.
    let nowhere = Machine {
        home: (i64::MAX, i64::MAX),
        ..CAM
    };
    let run = home(nowhere, 3, 0);
    assert_eq!(run.states, [0, B13, B13 | REACHED]);
    // A cam method reverses once at the limit, then fails at the other.
    let run = home(nowhere, 7, 0);
    assert_eq!(run.states, [0, B13, B13 | REACHED]);
    assert!(run.end < -10_000);
    // Reserved methods are an error at once, at standstill.
    for method in [0, 15, 16, 31, 32, 36, 38, -1] {
        assert_eq!(Method::of(method), None);
        assert_eq!(home(CAM, method, 0).states, [B13 | REACHED]);
    }
}

#[test]
fn homing_is_not_started_without_an_edge_and_interrupted_by_halt_or_bit_4() {
    let mut hm = Homing::new();
    hm.enter(ENABLED | NEW);
    let mut t = Trajectory::new();
    let p = HomingParameters { method: 34, ..HM };
    let none = HomingInputs::default();
    let bits = |s: ecat_core::cia402::homing::HomingStatus| {
        flag(s.error, B13) | flag(s.attained, B12) | flag(s.target_reached, REACHED)
    };
    // Bit 4 already set when the mode was entered: not started (0/0/1).
    assert_eq!(
        bits(hm.update(ENABLED | NEW, &p, none, &mut t, MS)),
        REACHED
    );
    assert_eq!(bits(hm.update(ENABLED, &p, none, &mut t, MS)), REACHED);
    // Rising edge: in progress.
    assert_eq!(bits(hm.update(ENABLED | NEW, &p, none, &mut t, MS)), 0);
    assert_eq!(t.velocity(), 500);
    // Halt: interrupted, braking at the halt ramp (1 000 c/s per cycle): standstill at once.
    assert_eq!(
        bits(hm.update(ENABLED | NEW | HALT, &p, none, &mut t, MS)),
        REACHED
    );
    // Release of halt does not resume: a new edge is needed.
    assert_eq!(
        bits(hm.update(ENABLED | NEW, &p, none, &mut t, MS)),
        REACHED
    );
    assert_eq!(bits(hm.update(ENABLED, &p, none, &mut t, MS)), REACHED);
    assert_eq!(bits(hm.update(ENABLED | NEW, &p, none, &mut t, MS)), 0);
    // Bit 4 dropped: interrupted.
    hm.update(ENABLED | NEW, &p, none, &mut t, MS);
    assert_eq!(bits(hm.update(ENABLED, &p, none, &mut t, MS)), 0);
    assert_eq!(bits(hm.update(ENABLED, &p, none, &mut t, MS)), REACHED);
}

#[test]
fn the_method_table_matches_the_standard_figures() {
    let m = |code| Method::of(code).flatten().unwrap();
    assert_eq!(m(1).switch, Switch::NegativeLimit);
    assert_eq!(m(18).switch, Switch::PositiveLimit);
    assert!(m(14).index && !m(30).index);
    assert_eq!((m(7).approach, m(7).leaving), (-1, true));
    assert_eq!((m(12).search, m(12).reverse_at_limit), (-1, true));
    assert_eq!(Method::of(35), Some(None));
    assert_eq!(Method::of(37), Some(None));
}

#[test]
fn digital_inputs_put_the_switches_in_bits_0_to_2() {
    assert_eq!(digital_inputs(true, false, false), 0b001);
    assert_eq!(digital_inputs(false, true, true), 0b110);
}

/// Probe 1 on `input` (or the index), probe 2 on `input2`; both store `position` (probe 2 its
/// negation).
fn probe2(input: bool, index: bool, input2: bool, position: i32) -> [ProbeInput; 2] {
    [
        ProbeInput {
            input,
            index,
            position,
        },
        ProbeInput {
            input: input2,
            index,
            position: -position,
        },
    ]
}

fn probe(input: bool, index: bool, position: i32) -> [ProbeInput; 2] {
    probe2(input, index, false, position)
}

#[test]
fn touch_probe_first_event_latches_once_until_rearmed() {
    let mut tp = TouchProbes::new();
    // Probe 1: enabled, first event, input, both edges (0x0031).
    tp.update(0x0031, probe(false, false, 0));
    assert_eq!(tp.status(), 0x0001);
    tp.update(0x0031, probe(true, false, 100));
    assert_eq!((tp.status(), tp.positions(0).positive), (0x0003, 100));
    tp.update(0x0031, probe(false, false, 150));
    assert_eq!((tp.status(), tp.positions(0).negative), (0x0007, 150));
    // Further edges are ignored in first-event mode.
    tp.update(0x0031, probe(true, false, 200));
    assert_eq!((tp.status(), tp.positions(0).positive), (0x0007, 100));
    // Re-arming the positive edge (bit 4 0 → 1) clears bit 1 and takes the next edge.
    tp.update(0x0021, probe(false, false, 210));
    tp.update(0x0031, probe(false, false, 220));
    assert_eq!(tp.status(), 0x0005);
    tp.update(0x0031, probe(true, false, 230));
    assert_eq!((tp.status(), tp.positions(0).positive), (0x0007, 230));
    // Disabled: the status byte clears, the positions stay.
    tp.update(0x0000, probe(false, false, 240));
    assert_eq!((tp.status(), tp.positions(0).positive), (0, 230));
}

#[test]
fn touch_probe_continuous_on_the_index_and_probe_2() {
    let mut tp = TouchProbes::new();
    // Probe 1 continuous on the index pulse, positive edge (0x17); probe 2 enabled, first event,
    // on its input, negative edge (0x21).
    let f = 0x2117;
    tp.update(f, probe2(false, false, true, 0));
    assert_eq!(tp.status(), 0x0101);
    tp.update(f, probe2(false, true, true, 10));
    assert_eq!((tp.status(), tp.positions(0).positive), (0x0103, 10));
    tp.update(f, probe2(false, false, false, 20));
    assert_eq!((tp.status(), tp.positions(1).negative), (0x0503, -20));
    // Continuous: the next index pulse overwrites; probe 2 (first event) keeps its first edge.
    tp.update(f, probe2(false, true, true, 30));
    tp.update(f, probe2(false, false, false, 40));
    assert_eq!(tp.status(), 0x0503);
    assert_eq!(
        (tp.positions(0).positive, tp.positions(1).negative),
        (30, -20)
    );
    // The probe 1 input is not its source: its edges store nothing.
    tp.update(f, probe2(true, false, false, 50));
    assert_eq!(tp.positions(0).positive, 30);
    assert_eq!(tp.positions(2), Default::default());
}

proptest! {
    /// Any move lands exactly on its target, never above the profile velocity, never changing
    /// the velocity by more than the ramps allow per cycle, in a bounded number of cycles.
    #[test]
    fn moves_land_exactly_within_the_ramps(
        target in -200_000i64..200_000,
        velocity in 1_000u32..200_000,
        acceleration in 100_000u32..10_000_000,
        deceleration in 100_000u32..10_000_000,
    ) {
        let ramps = Ramps { velocity, acceleration, deceleration };
        let mut t = Trajectory::new();
        let step = |rate: u32| i64::from(rate / 1_000).max(1);
        let mut n = 0;
        let mut last = 0i64;
        while !t.to_position(target, ramps, MS) {
            let v = t.velocity();
            prop_assert!(v.abs() <= i64::from(velocity));
            let change = (v - last).abs();
            prop_assert!(change <= step(acceleration).max(step(deceleration)) + 1,
                "change {change} at {n}");
            last = v;
            n += 1;
            prop_assert!(n < 500_000);
        }
        prop_assert_eq!(t.position(), target);
    }
}
