//! The CiA402 demo's scenario, shared by the `cia402-demo` binary and its test: ethercrab
//! (in-process, over a line with the dummy axis) scans, reads identity and dictionary, assigns
//! the axis's profile PDO set (0x1601/0x1A01) and writes the homing parameters over SDO, brings
//! the
//! axis to OP, enables it and runs the motion script of [`crate::cia402::Profile`]: homing, a PP
//! move with a set of two set-points, CSP, CSV, halt, quick stop.

use ecat_emu::master::TestMaster;
use ecat_emu::real_master::{self, next_cycle};
use ethercrab::{MainDevice, SubDeviceGroup};

use crate::cia402::{Feedback, Pdo, Phase, Profile, State, mode_names, state_name};

/// One cycle of the run.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Virtual time, ms.
    pub ms: f64,
    /// The script's phase.
    pub phase: Phase,
    /// The drive's state.
    pub state: Option<State>,
    /// Commanded position, counts.
    pub commanded_position: f64,
    /// 0x6064, counts.
    pub actual_position: f64,
    /// Commanded velocity, counts/s.
    pub commanded_velocity: f64,
    /// 0x606C, counts/s.
    pub actual_velocity: f64,
    /// 0x6041.
    pub statusword: u16,
    /// 0x60F4, counts: the drive's following error.
    pub following_error: f64,
}

type Group = SubDeviceGroup<2, 64, ethercrab::DefaultLock, ethercrab::subdevice_group::Op>;

/// The longest run, in cycles: the script needs about 3 000.
/// The homing the demo configures: method 7 (home cam, positive limit reverses, the index below
/// the cam), 50 000 counts/s searching the cam, 10 000 counts/s to the index, 5 000 000
/// counts/s², home offset 0.
/// Quick stop: 0x6085 1 500 000 counts/s² (80 ms from 120 000 counts/s). (0x6081, 0x6083,
/// 0x6084 travel in the profile RxPDO 0x1601.)
const HOMING: [(u16, u8, &[u8]); 6] = [
    (0x6085, 0, &1_500_000u32.to_le_bytes()),
    (0x6098, 0, &[7]),
    (0x6099, 1, &50_000u32.to_le_bytes()),
    (0x6099, 2, &10_000u32.to_le_bytes()),
    (0x609A, 0, &5_000_000u32.to_le_bytes()),
    (0x607C, 0, &0i32.to_le_bytes()),
];
const MAX_CYCLES: u32 = 20_000;

/// Runs the demo in-process; `report` sees every progress line. Returns the cycles' records.
pub fn run(report: impl FnMut(&str) + 'static) -> Result<Vec<Sample>, String> {
    let axis = crate::catalog::device("cia402").ok_or("no cia402 device")?;
    real_master::run_on_line(
        vec![axis],
        real_master::timeouts(),
        async move |main, masters| {
            Demo {
                main,
                masters,
                report: Box::new(report),
            }
            .run()
            .await
        },
    )
}

struct Demo {
    main: &'static MainDevice<'static>,
    masters: Vec<TestMaster>,
    report: Box<dyn FnMut(&str)>,
}

impl Demo {
    async fn run(&mut self) -> Result<Vec<Sample>, String> {
        let mut samples = Vec::new();
        let now = || embassy_time::Instant::now().as_micros() * 1_000;
        let group = self
            .main
            .init_single_group::<2, 64>(now)
            .await
            .map_err(|e| format!("scan: {e}"))?;
        let sub = group.subdevice(self.main, 0).map_err(|e| e.to_string())?;
        let id = sub.identity();
        (self.report)(&format!(
            "found {:?} at {:#06x}: vendor {:#010x}, product {:#010x}, revision {}, serial {:#010x}",
            sub.name(),
            sub.configured_address(),
            id.vendor_id,
            id.product_id,
            id.revision,
            id.serial
        ));
        let sdo = |e: ethercrab::error::Error| format!("SDO: {e}");
        let vendor: u32 = sub.sdo_read(0x1018, 1).await.map_err(sdo)?;
        let name: heapless::String<64> = sub.sdo_read(0x1008, 0).await.map_err(sdo)?;
        let modes: u32 = sub.sdo_read(0x6502, 0).await.map_err(sdo)?;
        (self.report)(&format!(
            "PREOP: 0x1018:01 = {vendor:#010x}, 0x1008 = {name:?}, 0x6502 = {modes:#010x} ({})",
            mode_names(modes)
        ));
        // The profile PDO set, as a configuration tool picks it from the ESI's alternatives:
        // 0x6081/0x6083/0x6084, 0x60B8 out; 0x60F4, 0x60FD, the touch probe in.
        for (assignment, pdo) in [(0x1C12u16, 0x1601u16), (0x1C13, 0x1A01)] {
            sub.sdo_write(assignment, 0, 0u8).await.map_err(sdo)?;
            sub.sdo_write(assignment, 1, pdo).await.map_err(sdo)?;
            sub.sdo_write(assignment, 0, 1u8).await.map_err(sdo)?;
        }
        for (index, sub_index, value) in HOMING {
            match value.len() {
                1 => sub.sdo_write(index, sub_index, value[0]).await,
                _ => {
                    let mut bytes = [0u8; 4];
                    bytes.copy_from_slice(value);
                    sub.sdo_write(index, sub_index, u32::from_le_bytes(bytes))
                        .await
                }
            }
            .map_err(sdo)?;
        }
        (self.report)(
            "PREOP: assigned RxPDO 0x1601 / TxPDO 0x1A01 (the profile set); homing method 7 at \
             50 000 / 10 000 counts/s; quick stop 1 500 000 counts/s²",
        );
        let pdo = Pdo::read(&sub).await.map_err(sdo)?;
        // OP follows the first valid outputs, so the cyclic frames start before it (ethercrab's
        // `into_op` would wait without sending any).
        let group = group
            .into_safe_op(self.main)
            .await
            .map_err(|e| format!("to SAFEOP: {e}"))?;
        (self.report)(&format!(
            "SAFEOP: {} output bytes, {} input bytes",
            pdo.outputs, pdo.inputs
        ));
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
                (self.report)(&format!("OP after {cycles} cycles"));
                op = true;
            }
            profile.step(state, feedback, 0.001);
            samples.push(Sample {
                ms: f64::from(cycles),
                phase: profile.phase(),
                state,
                commanded_position: profile.commanded().position,
                actual_position: f64::from(feedback.position),
                commanded_velocity: profile.commanded().velocity,
                actual_velocity: f64::from(feedback.velocity),
                statusword: feedback.statusword,
                following_error: f64::from(feedback.following_error),
            });
            let phase = profile.phase();
            if cycles.is_multiple_of(250) || phase != last_phase {
                (self.report)(&format!(
                    "t={:>5} ms  {:<10} {:<20} statusword {:#06x}  position {:>7}  velocity {:>7}",
                    cycles,
                    phase.name(),
                    state_name(state),
                    feedback.statusword,
                    feedback.position,
                    feedback.velocity
                ));
                last_phase = phase;
            }
            cycles += 1;
            if cycles > MAX_CYCLES {
                return Err(format!("stuck in {}", profile.phase().name()));
            }
        }
        let worst = samples
            .iter()
            .filter(|s| s.phase == Phase::Csp)
            .map(|s| (s.commanded_position - s.actual_position).abs())
            .filter(|e| e.is_finite())
            .fold(0.0, f64::max);
        (self.report)(&format!(
            "done: {cycles} cycles of 1 ms, final position {} counts; in CSP the actual position \
             trails the command by at most {worst:.0} counts (one exchange of latency)",
            samples.last().map_or(0.0, |s| s.actual_position)
        ));
        Ok(samples)
    }

    /// One process-data cycle of 1 ms: the profile's command out, the feedback in, the working
    /// counter checked.
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
        next_cycle(&self.masters).await;
        let inputs = sub.inputs_raw();
        let feedback = pdo.read_feedback(&inputs);
        Ok((
            response.all_op(),
            State::from_statusword(feedback.statusword),
            feedback,
        ))
    }
}
