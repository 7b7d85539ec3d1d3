//! The CiA402 dummy axis, driven by a real MainDevice: the axis runs on the real ecat runners on
//! the host executor behind an emulated ESC; ethercrab (in-process, no NIC, no root) finds it,
//! reads its identity and dictionary over SDO, brings it to OP, enables the drive through the
//! CiA402 state machine, moves it in cyclic synchronous position mode with a smooth profile, then
//! in cyclic synchronous velocity mode, then quick-stops it. Time is virtual (1 ms per cycle); the
//! run takes a few seconds of wall time and writes a plot of commanded against actual motion.
//!
//! ```text
//! cargo run --release -p ecat-examples --bin cia402-demo [-- --plot FILE]
//! cargo run --release -p ecat-examples --bin cia402-demo -- --iface IFNAME   # serve it instead
//! ```

use std::process::ExitCode;

use ecat_examples::demo::{self, Sample};
use ecat_examples::{bridge, plot};

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
    let svg = plot::svg(
        &t,
        "time (ms)",
        &[
            plot::Panel {
                title: "Position",
                unit: "counts",
                series: vec![
                    plot::Series {
                        name: "commanded",
                        colour: "#d62728",
                        values: &cp,
                        dashed: true,
                    },
                    plot::Series {
                        name: "actual",
                        colour: "#1f77b4",
                        values: &ap,
                        dashed: false,
                    },
                ],
            },
            plot::Panel {
                title: "Velocity",
                unit: "counts/s",
                series: vec![
                    plot::Series {
                        name: "commanded",
                        colour: "#d62728",
                        values: &cv,
                        dashed: true,
                    },
                    plot::Series {
                        name: "actual",
                        colour: "#1f77b4",
                        values: &av,
                        dashed: false,
                    },
                ],
            },
        ],
    );
    std::fs::write(path, svg).map_err(|e| format!("cannot write {path}: {e}"))
}
