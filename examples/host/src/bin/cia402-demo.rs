//! The CiA402 dummy axis, driven by a real MainDevice: the axis runs on the real ecat runners on
//! the host executor behind an emulated ESC; ethercrab (in-process, no NIC, no root) finds it,
//! reads its identity and dictionary over SDO, brings it to OP, enables the drive through the
//! CiA402 state machine, homes it (method 7: home cam and index pulse), makes a profile position
//! move with a set of two set-points, moves it in cyclic synchronous position mode with a smooth
//! profile, then in cyclic synchronous velocity mode, halts it and quick-stops it. Time is virtual
//! (1 ms per cycle); the run takes well under a second of wall time and writes a plot (plotters,
//! SVG) of commanded against actual motion, the following error and the drive's state.
//!
//! ```text
//! cargo run --release -p ecat-examples --bin cia402-demo [-- --plot FILE]
//! cargo run --release -p ecat-examples --bin cia402-demo -- --iface IFNAME   # serve it instead
//! ```

use std::process::ExitCode;

use ecat_examples::cia402::{Phase, State, state_name};
use ecat_examples::demo::{self, Sample};
use ecat_examples::{bridge, plot};
use plotters::style::RGBColor;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.as_slice() {
        [flag, iface] if flag == "--iface" => bridge::serve(&bridge::Options {
            iface: iface.clone(),
            devices: vec!["cia402".to_owned()],
            pcap: None,
            la_requests: false,
            chained: false,
            out: None,
        })
        .map(|_| ()),
        [flag, path] if flag == "--plot" => run(path),
        [] => run("cia402-demo.svg"),
        _ => Err("usage: cia402-demo [--plot FILE | --iface IFNAME]".to_owned()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("cia402-demo: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(plot_path: &str) -> Result<(), String> {
    let samples = demo::run(|line| println!("{line}"))?;
    write_plot(plot_path, &samples)?;
    println!("plot of commanded vs actual motion: {plot_path}");
    Ok(())
}

fn write_plot(path: &str, samples: &[Sample]) -> Result<(), String> {
    let col = |f: fn(&Sample) -> f64| samples.iter().map(f).collect::<Vec<f64>>();
    let t = col(|s| s.ms);
    let (cp, ap) = (col(|s| s.commanded_position), col(|s| s.actual_position));
    let (cv, av) = (col(|s| s.commanded_velocity), col(|s| s.actual_velocity));
    // The MainDevice's view in the cyclic modes (the command it sent against the position it
    // read back), and the drive's own 0x60F4.
    let tracking: Vec<f64> = samples
        .iter()
        .map(|s| match s.phase {
            Phase::Csp => s.commanded_position - s.actual_position,
            _ => f64::NAN,
        })
        .collect();
    let drive_error = col(|s| s.following_error);
    let commanded = RGBColor(214, 39, 40);
    let actual = RGBColor(31, 119, 180);
    let figure = plot::Figure {
        title: "ecat CiA 402 dummy axis driven by ethercrab (1 ms cycles, virtual time)",
        x: &t,
        x_label: "time (ms)",
        panels: vec![
            plot::Panel {
                title: "Position",
                unit: "counts",
                series: vec![
                    plot::Series {
                        name: "commanded (PP: set-point target)",
                        colour: commanded,
                        values: &cp,
                        dashed: true,
                    },
                    plot::Series {
                        name: "actual 0x6064",
                        colour: actual,
                        values: &ap,
                        dashed: false,
                    },
                ],
                weight: 3,
            },
            plot::Panel {
                title: "Velocity",
                unit: "counts/s",
                series: vec![
                    plot::Series {
                        name: "commanded",
                        colour: commanded,
                        values: &cv,
                        dashed: true,
                    },
                    plot::Series {
                        name: "actual 0x606C",
                        colour: actual,
                        values: &av,
                        dashed: false,
                    },
                ],
                weight: 3,
            },
            plot::Panel {
                title: "Following error",
                unit: "counts",
                series: vec![
                    plot::Series {
                        name: "CSP: command − actual seen by the MainDevice (one exchange)",
                        colour: RGBColor(148, 103, 189),
                        values: &tracking,
                        dashed: false,
                    },
                    plot::Series {
                        name: "0x60F4 reported by the drive",
                        colour: RGBColor(44, 160, 44),
                        values: &drive_error,
                        dashed: false,
                    },
                ],
                weight: 2,
            },
        ],
        phases: spans(samples, |s| Some(s.phase))
            .into_iter()
            .filter_map(|(from, to, phase)| {
                let colour = match phase {
                    Phase::Homing => RGBColor(255, 205, 120),
                    Phase::Pp => RGBColor(160, 210, 255),
                    Phase::Csp => RGBColor(190, 235, 190),
                    Phase::Csv => RGBColor(215, 200, 240),
                    Phase::Halt => RGBColor(255, 235, 130),
                    Phase::QuickStop => RGBColor(250, 175, 175),
                    Phase::Enable | Phase::Done => return None,
                };
                Some(plot::Span {
                    from,
                    to,
                    label: phase.name(),
                    colour,
                })
            })
            .collect(),
        states: spans(samples, |s| s.state)
            .into_iter()
            .map(|(from, to, state)| plot::Span {
                from,
                to,
                label: state_name(Some(state)),
                colour: match state {
                    State::OperationEnabled => RGBColor(46, 139, 87),
                    State::QuickStopActive => RGBColor(205, 92, 60),
                    State::Fault | State::FaultReactionActive => RGBColor(178, 34, 34),
                    State::SwitchOnDisabled => RGBColor(120, 120, 120),
                    _ => RGBColor(100, 140, 180),
                },
            })
            .collect(),
    };
    let svg = plot::svg(&figure)?;
    std::fs::write(path, svg).map_err(|e| format!("cannot write {path}: {e}"))
}

/// The runs of equal `key` over the samples: (first ms, last ms + 1, key).
fn spans<K: PartialEq + Copy>(
    samples: &[Sample],
    key: impl Fn(&Sample) -> Option<K>,
) -> Vec<(f64, f64, K)> {
    let mut out: Vec<(f64, f64, K)> = Vec::new();
    for s in samples {
        let Some(k) = key(s) else { continue };
        match out.last_mut() {
            Some(last) if last.2 == k => last.1 = s.ms + 1.0,
            _ => out.push((s.ms, s.ms + 1.0, k)),
        }
    }
    out
}
