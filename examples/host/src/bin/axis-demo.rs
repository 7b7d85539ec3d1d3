//! The dummy CiA 402 axis (`ecat-axis`) behind the real runners: a scripted MainDevice walks it
//! to OP, enables it in CSP through the RxPDO, moves it along a ramp of target positions, and
//! quick-stops it with the quick stop ramp set over SDO. Time is virtual.
//!
//! `cargo run -p ecat-examples --bin axis-demo`

use ecat_axis::{Axis, AxisApp, AxisOd};
use ecat_core::DeviceConfig;
use ecat_core::cia402::State;
use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_emu::coe_client::SdoClient;
use ecat_emu::harness::{self, Device};
use ecat_emu::master::TestMaster;

const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
/// RxPDO 0x1600 (13 bytes) and TxPDO 0x1A00 (19 bytes) of the axis.
const OUTPUTS: Area = Area::new(0x1100, 13);
const INPUTS: Area = Area::new(0x1180, 19);
const CSP: i8 = 8;

/// One cyclic frame: controlword and target position out, the TxPDO back, printed.
async fn frame(master: &TestMaster, controlword: u16, target: i32) {
    let mut outputs = controlword.to_le_bytes().to_vec();
    outputs.extend_from_slice(&target.to_le_bytes());
    outputs.extend_from_slice(&[0; 6]); // target velocity, target torque
    outputs.push(CSP as u8);
    master.write(OUTPUTS.start, &outputs);
    master.settle().await;
    let inputs = master.read(INPUTS.start, 19).unwrap_or_default();
    let word = |at: usize| {
        inputs
            .get(at..at + 2)
            .map_or(0, |b| u16::from_le_bytes([b[0], b[1]]))
    };
    let long = |at: usize| {
        inputs
            .get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .map_or(0, i32::from_le_bytes)
    };
    let statusword = word(0);
    let state = State::from_statusword(statusword).map_or("?".into(), |s| format!("{s:?}"));
    println!(
        "controlword {controlword:#06x} target {target:>6} | statusword {statusword:#06x} {state:<20} position {:>6} velocity {:>8} following error {:>5}",
        long(2),
        long(6),
        long(13),
    );
}

fn main() {
    let config = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes {
            outputs: 13,
            inputs: 19,
        },
    );
    let device = Device::new(config, AxisApp, Axis::new()).with_dictionary(AxisOd::new());
    harness::run(device, |master| async move {
        master.reset().await;
        master.request(0x01).await;
        master.configure_mailbox(&MAILBOX);
        master.configure_process_data(Some(OUTPUTS), Some(INPUTS));
        master.settle().await;
        master.request(0x02).await;
        let mut sdo = SdoClient::for_mailbox(&master, &MAILBOX);
        println!(
            "SDO 0x6060 ← 1 (profile position): {:?}",
            sdo.download(0x6060, 0, false, &[1]).await
        );
        println!("SDO 0x6502: {:02x?}", sdo.upload(0x6502, 0, false).await);
        // Quick stop ramp 100 000 000 counts/s²: 100 000 counts/s less per 1 ms cycle.
        let ramp = 100_000_000u32.to_le_bytes();
        println!(
            "SDO 0x6085 ← 100 000 000: {:?}",
            sdo.download(0x6085, 0, false, &ramp).await
        );
        master.request(0x04).await;
        frame(&master, 0x00, 0).await;
        let (status, code) = master.request(0x08).await;
        println!("AL status {status:#06x}, code {code:#06x}: OP");
        for controlword in [0x00, 0x06, 0x0F] {
            frame(&master, controlword, 0).await;
        }
        // 1 000 counts per cycle is the speed limit 0x607F (1 000 000 counts/s): no lag; the
        // last step of 2 500 is not, and shows a following error.
        for n in 1..=8 {
            frame(&master, 0x0F, n * 1_000).await;
        }
        frame(&master, 0x0F, 10_500).await;
        // Quick stop (0x605A = 2): 10 cycles of ramp, then Switch on disabled.
        for _ in 0..12 {
            frame(&master, 0x02, 10_500).await;
        }
    });
}
