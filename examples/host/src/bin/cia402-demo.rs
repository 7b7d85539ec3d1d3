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

use ecat_emu::harness;
use ecat_emu::line::Line;
use ecat_emu::master::TestMaster;
use ecat_emu::real_master;
use ecat_examples::cia402::{Feedback, Pdo, Phase, Profile, State, mode_names, state_name};
use ecat_examples::{bridge, catalog, plot};
use embassy_futures::select::{Either, select};
use embassy_time::{Duration, MockDriver};
use ethercrab::{MainDevice, SubDeviceGroup, Timeouts};

/// One cycle of virtual time.
const CYCLE: Duration = Duration::from_millis(1);

type Group = SubDeviceGroup<2, 64, ethercrab::DefaultLock, ethercrab::subdevice_group::Op>;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.as_slice() {
        [flag, iface] if flag == "--iface" => bridge::serve(&bridge::Options {
            iface: iface.clone(),
            devices: vec!["cia402".to_owned()],
            pcap: None,
        }),
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
    let axis = catalog::device("cia402").ok_or("no cia402 device")?;
    let outcome = std::rc::Rc::new(std::cell::RefCell::new(Err("did not run".to_owned())));
    let result = outcome.clone();
    harness::serve(vec![axis], move |escs| async move {
        let masters: Vec<TestMaster> = escs.iter().cloned().map(TestMaster::new).collect();
        let line = Line::new(escs);
        let (main, transport) = real_master::main_device(
            move |frame: &mut [u8]| line.process(frame),
            Timeouts::default(),
            real_master::config(),
        );
        let scenario = async {
            let mut demo = Demo {
                main,
                masters,
                samples: Vec::new(),
            };
            demo.run().await
        };
        *result.borrow_mut() = match select(transport, scenario).await {
            Either::First(()) => Err("the transport stopped".to_owned()),
            Either::Second(outcome) => outcome,
        };
    });
    let samples = outcome.replace(Err(String::new()))?;
    write_plot(plot_path, &samples)?;
    println!("plot of commanded vs actual motion: {plot_path}");
    Ok(())
}

/// One cycle's record.
#[derive(Debug, Clone, Copy)]
struct Sample {
    ms: f64,
    commanded_position: f64,
    actual_position: f64,
    commanded_velocity: f64,
    actual_velocity: f64,
}

struct Demo {
    main: &'static MainDevice<'static>,
    masters: Vec<TestMaster>,
    samples: Vec<Sample>,
}

impl Demo {
    async fn run(&mut self) -> Result<Vec<Sample>, String> {
        let now = || embassy_time::Instant::now().as_micros() * 1_000;
        let group = self
            .main
            .init_single_group::<2, 64>(now)
            .await
            .map_err(|e| format!("scan: {e}"))?;
        let sub = group.subdevice(self.main, 0).map_err(|e| e.to_string())?;
        let id = sub.identity();
        println!(
            "found {:?} at {:#06x}: vendor {:#010x}, product {:#010x}, revision {}, serial {:#010x}",
            sub.name(),
            sub.configured_address(),
            id.vendor_id,
            id.product_id,
            id.revision,
            id.serial
        );
        let sdo = |e: ethercrab::error::Error| format!("SDO: {e}");
        let vendor: u32 = sub.sdo_read(0x1018, 1).await.map_err(sdo)?;
        let name: heapless::String<64> = sub.sdo_read(0x1008, 0).await.map_err(sdo)?;
        let modes: u32 = sub.sdo_read(0x6502, 0).await.map_err(sdo)?;
        println!(
            "PREOP: 0x1018:01 = {vendor:#010x}, 0x1008 = {name:?}, 0x6502 = {modes:#010x} ({})",
            mode_names(modes)
        );
        let pdo = Pdo::read(&sub).await.map_err(sdo)?;
        // OP follows the first valid outputs, so the cyclic frames start before it (ethercrab's
        // `into_op` would wait without sending any).
        let group = group
            .into_safe_op(self.main)
            .await
            .map_err(|e| format!("to SAFEOP: {e}"))?;
        println!(
            "SAFEOP: {} output bytes, {} input bytes",
            pdo.outputs, pdo.inputs
        );
        let group: Group = group
            .request_into_op(self.main)
            .await
            .map_err(|e| format!("requesting OP: {e}"))?;
        let mut profile = Profile::new();
        let mut cycles = 0u32;
        let mut op = false;
        let mut last_phase = Phase::Enable;
        while profile.phase() != Phase::Done {
            let (all_op, state, feedback) = self.exchange(&group, &pdo, &profile).await?;
            if all_op && !op {
                println!("OP after {cycles} cycles");
                op = true;
            }
            profile.step(state, feedback, CYCLE.as_micros() as f64 / 1e6);
            self.samples.push(Sample {
                ms: f64::from(cycles),
                commanded_position: profile.commanded().position,
                actual_position: f64::from(feedback.position),
                commanded_velocity: profile.commanded().velocity,
                actual_velocity: f64::from(feedback.velocity),
            });
            let phase = profile.phase();
            if cycles.is_multiple_of(250) || phase != last_phase {
                println!(
                    "t={:>5} ms  {:<9} {:<20} statusword {:#06x}  position {:>7}  velocity {:>7}",
                    cycles,
                    phase.name(),
                    state_name(state),
                    feedback.statusword,
                    feedback.position,
                    feedback.velocity
                );
                last_phase = phase;
            }
            cycles += 1;
            if cycles > 20_000 {
                return Err(format!("stuck in {}", profile.phase().name()));
            }
        }
        let worst = self
            .samples
            .iter()
            .map(|s| (s.commanded_position - s.actual_position).abs())
            .filter(|e| e.is_finite())
            .fold(0.0, f64::max);
        println!(
            "done: {cycles} cycles of 1 ms, final position {} counts; in CSP the actual position \
             trails the command by at most {worst:.0} counts (one exchange of latency)",
            self.samples.last().map_or(0.0, |s| s.actual_position)
        );
        Ok(core::mem::take(&mut self.samples))
    }

    /// One process-data cycle: the profile's command out, the feedback in, checked working
    /// counter, then one cycle of virtual time for the axis.
    async fn exchange(
        &self,
        group: &Group,
        pdo: &Pdo,
        profile: &Profile,
    ) -> Result<(bool, Option<State>, Feedback), String> {
        let sub = group.subdevice(self.main, 0).map_err(|e| e.to_string())?;
        {
            let mut outputs = sub.outputs_raw_mut();
            pdo.write(&mut outputs, profile.command());
        }
        let response = group.tx_rx(self.main).await.map_err(|e| e.to_string())?;
        if response.working_counter != 3 {
            return Err(format!("working counter {}", response.working_counter));
        }
        for master in &self.masters {
            master.settle().await;
        }
        MockDriver::get().advance(CYCLE);
        let inputs = sub.inputs_raw();
        let feedback = pdo.read_feedback(&inputs);
        Ok((
            response.all_op(),
            State::from_statusword(feedback.statusword),
            feedback,
        ))
    }
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
