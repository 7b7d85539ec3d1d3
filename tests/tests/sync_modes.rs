//! Sync modes (conformance.md "Sync parameters"): the MainDevice picks the sync type in 0x1C32:01
//! during PREOP; PREOP→SAFEOP checks it against the device; free-run cycles on the local timer.

mod common;

use common::{client, walk_to};
use ecat_core::AlState;
use ecat_core::device::Area;
use ecat_core::dictionary::ObjectHooks;
use ecat_core::sync::SupportedSync;
use ecat_embassy::{Application, CycleHandler};
use ecat_emu::devices::Drive;
use ecat_emu::harness::{self, Device};
use ecat_emu::master::{SM2_CONTROL, SM3_CONTROL, TestMaster};
use embassy_time::Duration;

struct App;
impl Application for App {}
impl ObjectHooks<Drive> for App {}

/// Counts its cycles in the statusword (0x6041, the first two bytes of the TxPDO image).
struct Counter;

impl CycleHandler<Drive> for Counter {
    fn cycle(&mut self, od: &mut Drive, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        od.statusword = od.statusword.wrapping_add(1);
    }
}

const OUT: Area = Area::new(0x1100, 11);
const IN: Area = Area::new(0x1180, 11);

fn run(sync: u16, script: impl AsyncFnOnce(TestMaster) + 'static) {
    let mut device = Device::new(common::drive(), App, Counter).with_dictionary(Drive::default());
    device.config.sync = SupportedSync(sync);
    harness::run(device, |master| async move { script(master).await })
}

async fn safeop(master: &TestMaster, sm2_control: u8) -> (u16, u16) {
    master.configure_sm(2, OUT.start, OUT.length, sm2_control, true);
    master.configure_sm(3, IN.start, IN.length, SM3_CONTROL, true);
    master.request(0x14).await
}

fn cycles(master: &TestMaster) -> u16 {
    let image = master.read(IN.start, 2).expect("inputs readable");
    u16::from_le_bytes([image[0], image[1]])
}

const BOTH: u16 = SupportedSync::FREE_RUN | SupportedSync::SM;

#[test]
fn sm_synchronous_by_default_and_the_supported_types_are_readable() {
    run(BOTH, async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(
            c.upload(0x1C32, 1, false).await,
            Ok(vec![1, 0]),
            "SM-synchronous"
        );
        assert_eq!(
            c.upload(0x1C32, 4, false).await,
            Ok(vec![0x03, 0x00]),
            "free-run and SM"
        );
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        let before = cycles(&master);
        master.advance(Duration::from_millis(10)).await;
        assert_eq!(
            cycles(&master),
            before,
            "SM-synchronous: no cycle without the MainDevice"
        );
    });
}

#[test]
fn free_run_cycles_on_the_local_timer() {
    run(BOTH, async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x1C32, 1, false, &[0, 0]).await.unwrap();
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        assert_eq!(
            c.upload(0x1C32, 2, false).await,
            Ok(1_000_000u32.to_le_bytes().to_vec()),
            "1 ms in ns"
        );
        let before = cycles(&master);
        master.advance(Duration::from_millis(10)).await;
        assert_eq!(
            cycles(&master).wrapping_sub(before),
            10,
            "one cycle per millisecond"
        );
        common::send_outputs(&master).await;
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(
            master.request(0x08).await,
            (0x08, 0),
            "outputs seen by a free-run cycle"
        );
    });
}

#[test]
fn dc_sync0_is_not_supported_yet() {
    run(BOTH, async |master| {
        walk_to(&master, AlState::PreOp).await;
        client(&master)
            .download(0x1C32, 1, false, &[2, 0])
            .await
            .unwrap();
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x12, 0x0028));
    });
}

#[test]
fn free_run_on_a_device_without_it_is_0x0027() {
    run(SupportedSync::SM, async |master| {
        walk_to(&master, AlState::PreOp).await;
        client(&master)
            .download(0x1C32, 1, false, &[0, 0])
            .await
            .unwrap();
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x12, 0x0027));
    });
}

#[test]
fn free_run_needs_3_buffer_outputs() {
    run(BOTH, async |master| {
        walk_to(&master, AlState::PreOp).await;
        client(&master)
            .download(0x1C32, 1, false, &[0, 0])
            .await
            .unwrap();
        assert_eq!(
            safeop(&master, 0x66).await,
            (0x12, 0x0029),
            "SM2 in 1-buffer mode"
        );
    });
}
