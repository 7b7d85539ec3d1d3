//! The main demo end to end: ethercrab enables the CiA402 dummy axis over process data and moves
//! it (issue: CiA402 dummy axis). What the demo prints is checked here as numbers.

use ecat_examples::cia402::{Phase, State};
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

    let csp = phase_end(Phase::Csp);
    assert!(
        (csp.actual_position - 200_000.0).abs() <= 1.0,
        "the CSP move ends at its target: {}",
        csp.actual_position
    );
    let tracking = samples
        .iter()
        .filter(|s| s.phase == Phase::Csp)
        .map(|s| (s.commanded_position - s.actual_position).abs())
        .fold(0.0, f64::max);
    assert!(
        tracking < 500.0,
        "CSP follows within two cycles: {tracking}"
    );

    let csv = phase_end(Phase::Csv);
    assert_eq!(
        csv.actual_velocity, 120_000.0,
        "CSV holds the commanded velocity"
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
