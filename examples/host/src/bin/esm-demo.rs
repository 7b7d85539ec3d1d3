//! The ESM walk-through: one emulated SubDevice, running the real `ecat-embassy` runners on the
//! host executor, walked INIT → PREOP → SAFEOP → OP and back by a scripted MainDevice, with a
//! refused transition and its acknowledgement on the way. Time is virtual.
//!
//! `cargo run -p ecat-examples --bin esm-demo`

use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_core::{AlStatus, AlStatusCode, DeviceConfig, Transition};
use ecat_embassy::Application;
use ecat_emu::harness::{self, Device};
use ecat_emu::master::TestMaster;
use embassy_time::{Duration, Instant};

const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
const OUTPUTS: Area = Area::new(0x1100, 4);
const INPUTS: Area = Area::new(0x1180, 4);

fn stamp() -> String {
    format!("t={:>8.3} ms", Instant::now().as_micros() as f64 / 1000.0)
}

/// Accepts every transition and says so.
struct Hooks;

impl Application for Hooks {
    fn on_transition(
        &mut self,
        t: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> + use<> {
        println!("{}  device  asked {} → {}: accepted", stamp(), t.from, t.to);
        async { Ok(()) }
    }

    fn on_state_change(&mut self, t: Transition) {
        println!("{}  device  state {} → {}", stamp(), t.from, t.to);
    }
}

/// Inputs = outputs + 1 (as a little-endian u32), so the exchange is visible.
struct Increment;

impl Application for Increment {
    fn cycle(&mut self, _od: &mut (), outputs: Option<&[u8]>, inputs: &mut [u8]) {
        let value = outputs
            .and_then(|o| o.try_into().ok())
            .map_or(0, u32::from_le_bytes);
        inputs.copy_from_slice(&value.wrapping_add(1).to_le_bytes());
    }
}

async fn request(master: &TestMaster, control: u16) {
    let name = ecat_core::AlState::from_bits(control as u8).map_or("unknown state", |s| s.name());
    println!("{}  master  AL control ← {control:#06x} ({name})", stamp());
    let (status, code) = master.request(control).await;
    report(status, code);
}

fn report(status: u16, code: u16) {
    let state = AlStatus::from_bits(status).map_or("?", |s| s.state.name());
    let error = if status & AlStatus::ERROR != 0 {
        " + ERROR"
    } else {
        ""
    };
    println!(
        "{}  master  AL status {status:#06x} ({state}{error}), code {}",
        stamp(),
        AlStatusCode(code)
    );
}

async fn exchange(master: &TestMaster, cycles: u32) {
    for n in 0..cycles {
        let value = 1000 * n;
        master.write(OUTPUTS.start, &value.to_le_bytes());
        master.settle().await;
        let inputs = master.read(INPUTS.start, 4).unwrap_or_default();
        let echoed = inputs.try_into().map_or(0, u32::from_le_bytes);
        println!(
            "{}  master  cycle {n}: outputs {value:>5} → inputs {echoed:>5}",
            stamp()
        );
        master.advance(Duration::from_millis(1)).await;
    }
}

fn main() {
    let config = DeviceConfig::new(
        MAILBOX,
        ProcessDataSizes {
            outputs: 4,
            inputs: 4,
        },
    );
    println!(
        "ecat ESM demo: an emulated SubDevice on the host executor, driven by a scripted MainDevice"
    );
    println!("(virtual time; the device answers through the real ecat-embassy runners)\n");
    harness::run(Device::new(config, Hooks, Increment), |master| async move {
        println!(
            "{}  master  reset: AL control ← 0x0011, all SyncManagers zeroed",
            stamp()
        );
        master.reset().await;
        report(master.al_status(), master.al_status_code());
        println!(
            "{}  master  SM0/SM1 ← mailboxes 0x1000/0x1080 (128 bytes)",
            stamp()
        );
        master.configure_mailbox(&MAILBOX);
        request(&master, 0x0002).await;
        println!(
            "{}  master  SM2 ← outputs 0x1100 (4 bytes), SM3 ← inputs 0x1180 (4 bytes)",
            stamp()
        );
        master.configure_process_data(Some(OUTPUTS), Some(INPUTS));
        request(&master, 0x0004).await;
        exchange(&master, 2).await;
        request(&master, 0x0008).await;
        exchange(&master, 3).await;
        println!("\n-- a refused transition: OP → BOOT is not allowed --");
        request(&master, 0x0003).await;
        request(&master, 0x0008).await;
        println!(
            "{}  master  (ignored: the error must be acknowledged)",
            stamp()
        );
        request(&master, 0x0018).await;
        println!("\n-- back down --");
        request(&master, 0x0004).await;
        request(&master, 0x0002).await;
        request(&master, 0x0001).await;
    });
}
