//! The main demo end to end: ethercrab enables the CiA402 dummy axis over process data, homes it,
//! runs a PP move with a set of two set-points, CSP, CSV, a halt and a quick stop (issues: CiA402
//! dummy axis, #18). What the demo prints is checked here as numbers.

use ecat_examples::cia402::{CSP_DISTANCE, PP_TARGETS, Phase, State};
use ecat_examples::demo;

#[test]
fn ethercrab_enables_the_axis_moves_it_and_quick_stops_it() {
    let samples = demo::run(|_| {}).expect("the demo runs");
    let phase_end = |phase: Phase| {
        samples
            .iter()
            .rposition(|s| s.phase == phase)
            .map(|i| samples[i])
            .expect("the phase ran")
    };
    let enabled = samples
        .iter()
        .position(|s| s.state == Some(State::OperationEnabled))
        .expect("operation enabled");
    assert!(enabled < 10, "enabled after {enabled} cycles");

    // Homing: the drive reported homing attained + target reached in mode 6, and the position
    // was redefined (0x607C = 0 at the index pulse, a few counts before where it stopped).
    // (The sample that ended it is the first of PP.)
    let homing = samples
        .iter()
        .find(|s| s.phase == Phase::Pp)
        .copied()
        .expect("PP ran");
    assert_eq!(
        homing.statusword & 0x3400,
        0x1400,
        "{:#06x}",
        homing.statusword
    );
    assert!(
        homing.actual_position.abs() < 20.0,
        "{}",
        homing.actual_position
    );
    // PP: both set-points acknowledged (bit 12 rose twice) and the axis ended on the second.
    let pp: Vec<_> = samples.iter().filter(|s| s.phase == Phase::Pp).collect();
    let acknowledges = pp
        .windows(2)
        .filter(|w| w[0].statusword & 0x1000 == 0 && w[1].statusword & 0x1000 != 0)
        .count();
    assert_eq!(acknowledges, 2);
    let peak = pp
        .iter()
        .map(|s| s.actual_position)
        .fold(f64::MIN, f64::max);
    assert_eq!(
        peak,
        f64::from(PP_TARGETS[0]),
        "the first target is reached"
    );
    let pp_end = phase_end(Phase::Pp);
    assert_eq!(pp_end.actual_position, f64::from(PP_TARGETS[1]));

    let csp = phase_end(Phase::Csp);
    assert!(
        (csp.actual_position - f64::from(PP_TARGETS[1]) - CSP_DISTANCE).abs() <= 1.0,
        "the CSP move ends at its target: {}",
        csp.actual_position
    );
    // Two cycles at the peak speed of the cosine profile (π/2 · 200 000 counts / 1 s = 314 159
    // counts/s): 628 counts, plus the rounding of the command.
    let tracking = samples
        .iter()
        .filter(|s| s.phase == Phase::Csp)
        .map(|s| (s.commanded_position - s.actual_position).abs())
        .fold(0.0, f64::max);
    assert!(
        tracking < 630.0,
        "CSP follows within two cycles: {tracking}"
    );

    let csv = phase_end(Phase::Csv);
    assert_eq!(
        csv.actual_velocity, 120_000.0,
        "CSV holds the commanded velocity"
    );
    // Halt: the axis stops with the 0x605D ramp (0x6084) and stays Operation enabled.
    let halt = phase_end(Phase::Halt);
    assert_eq!(
        (halt.actual_velocity, halt.state),
        (0.0, Some(State::OperationEnabled))
    );

    let last = samples.last().expect("samples");
    assert_eq!(
        last.actual_velocity, 0.0,
        "stands still after the quick stop"
    );
    assert_eq!(
        last.state,
        Some(State::SwitchOnDisabled),
        "quick stop option 2"
    );
    let stop_cycles = samples
        .iter()
        .filter(|s| s.phase == Phase::QuickStop)
        .count();
    assert!(
        stop_cycles < 200,
        "the quick stop ramp took {stop_cycles} cycles"
    );
    assert!(
        samples.len() < 3_500,
        "the script took {} cycles",
        samples.len()
    );
}
