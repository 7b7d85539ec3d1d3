//! Sync error supervision (ETG.1020 §6.3, `ecat_core::sync_error`): in DC SYNC0 mode in OP each
//! SYNC0 cycle without new outputs adds 3 to a counter, each cycle with outputs takes 1 off; at
//! the limit (0x10F1:02, SSC's 4 for a dictionary without 0x10F1) the SubDevice falls back to
//! SAFEOP with 0x001A. A MainDevice that loses one output frame in N, in virtual time.

mod common;

use common::{client, walk_to};
use ecat_core::AlState;
use ecat_core::register;
use ecat_embassy::Application;
use ecat_emu::coe_client::SdoError;
use ecat_emu::devices::DriveSmDc;
use ecat_emu::harness::{self, Device};
use ecat_emu::master::{SM2_CONTROL, SM3_CONTROL, TestMaster};
use embassy_time::{Duration, Instant};

struct App;
impl<D> Application<D> for App {}

struct Idle;
impl Application<DriveSmDc> for Idle {
    fn cycle(&mut self, _od: &mut DriveSmDc, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {}
}

fn u16_of(bytes: Result<Vec<u8>, SdoError>) -> u16 {
    let bytes = bytes.expect("upload");
    u16::from_le_bytes([bytes[0], bytes[1]])
}

/// The Drive device with DC SYNC0 support (and SM-synchronous), in DC mode at a 1 ms SYNC0,
/// in OP; then `cycles` SYNC0 cycles in which the MainDevice's output frame is lost every
/// `n`th time. Returns the cycle (1-based) after which the SubDevice was no longer in OP, and
/// AL status, AL status code, 0x1C32:0B and 0x1C32:20 at the end.
fn drop_one_in(n: u32, cycles: u32) -> Outcome {
    let (result, _) = drop_one_in_diagnosed(n, cycles);
    result
}

/// The cycle after which the SubDevice left OP, AL status, AL status code, 0x1C32:0B and
/// 0x1C32:20.
type Outcome = (Option<u32>, u16, u16, u16, Vec<u8>);

/// What the MainDevice saw of the diagnosis after [`drop_one_in`]'s scenario: the emergencies
/// and 0x10F3:02, 0x10F3:04 and the newest message.
struct Diagnosis {
    emergencies: Vec<[u8; 8]>,
    newest: Vec<u8>,
    available: Vec<u8>,
    message: Vec<u8>,
}

/// [`drop_one_in`] and what the MainDevice then reads of the diagnosis.
fn drop_one_in_diagnosed(n: u32, cycles: u32) -> (Outcome, Diagnosis) {
    let result = std::rc::Rc::new(std::cell::RefCell::new(None));
    let out = result.clone();
    let device = Device::new(common::drive(), App, Idle).with_dictionary(DriveSmDc::default());
    harness::run(device, move |master: TestMaster| async move {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x1C32, 1, false, &2u16.to_le_bytes())
            .await
            .unwrap();
        let start = (Instant::now() + Duration::from_millis(1)).as_micros() * 1_000;
        assert!(master.write(register::DC_SYNC0_CYCLE_TIME, &1_000_000u32.to_le_bytes()));
        assert!(master.write(register::DC_START_TIME, &start.to_le_bytes()));
        assert!(master.write(register::DC_ACTIVATION, &[0x03]));
        master.configure_sm(2, 0x1100, 11, SM2_CONTROL, true);
        master.configure_sm(3, 0x1180, 11, SM3_CONTROL, true);
        assert_eq!(master.request(0x04).await, (0x04, 0));
        common::send_outputs(&master).await;
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(master.request(0x08).await, (0x08, 0));
        let mut left_op = None;
        for k in 1..=cycles {
            if k % n != 0 {
                common::send_outputs(&master).await;
            }
            master.advance(Duration::from_millis(1)).await;
            if left_op.is_none() && master.al_status() != 0x08 {
                left_op = Some(k);
            }
        }
        let result = (
            left_op,
            master.al_status(),
            master.al_status_code(),
            u16_of(c.upload(0x1C32, 0x0B, false).await),
            c.upload(0x1C32, 0x20, false).await.unwrap(),
        );
        let newest = c.upload(0x10F3, 2, false).await.unwrap();
        let available = c.upload(0x10F3, 4, false).await.unwrap();
        let message = match newest.first() {
            Some(&si) if si >= 6 => c.upload(0x10F3, si, false).await.unwrap(),
            _ => Vec::new(),
        };
        let diagnosis = Diagnosis {
            emergencies: c.emergencies.clone(),
            newest,
            available,
            message,
        };
        *out.borrow_mut() = Some((result, diagnosis));
    });
    result.borrow_mut().take().expect("the scenario ran")
}

#[test]
fn one_lost_frame_in_four_keeps_op() {
    // Counter: 0, 0, 0, 3, 2, 1, 0, 3, …: never at 4.
    assert_eq!(drop_one_in(4, 200), (None, 0x08, 0, 50, vec![1]));
    // The last cycle (200) was one of the lost ones: 0x20 shows it; one later it would not.
    assert_eq!(drop_one_in(4, 201), (None, 0x08, 0, 50, vec![0]));
}

#[test]
fn one_lost_frame_in_three_is_safeop_with_0x001a_at_the_second_loss() {
    // Counter: 0, 0, 3, 2, 1, 4 → the limit at cycle 6; no cycle counts after OP.
    assert_eq!(drop_one_in(3, 30), (Some(6), 0x14, 0x001A, 2, vec![1]));
}

#[test]
fn two_lost_frames_in_a_row_trip_at_the_second() {
    assert_eq!(drop_one_in(1, 10), (Some(2), 0x14, 0x001A, 2, vec![1]));
    // One in two: 0, 3, 2, 5 → cycle 4.
    assert_eq!(drop_one_in(2, 10), (Some(4), 0x14, 0x001A, 2, vec![1]));
}

#[test]
fn a_sync_error_raises_0x8700_and_is_the_newest_diagnosis_message() {
    let (result, diagnosis) = drop_one_in_diagnosed(1, 10);
    assert_eq!(result, (Some(2), 0x14, 0x001A, 2, vec![1]));
    // The emergency came in place of the first SDO answer after the trip: sync controller
    // error, error register generic + communication, the AL status code in the data.
    assert_eq!(
        diagnosis.emergencies,
        [[0x00, 0x87, 0x11, 0x1A, 0x00, 0, 0, 0]]
    );
    assert_eq!((diagnosis.newest, diagnosis.available), (vec![6], vec![1]));
    assert_eq!(
        diagnosis.message[..8],
        [0x00, 0xE0, 0x00, 0x00, 0x12, 0x00, 0x1A, 0x00],
        "diag code 0xE000, error with a local timestamp, text ID 0x001A"
    );
    let ns = u64::from_le_bytes(diagnosis.message[8..16].try_into().unwrap());
    // Stamped by the mailbox service after the trip, on the virtual clock.
    assert_eq!((diagnosis.message.len(), ns), (16, 3_000_000));
}
