//! Sync modes (conformance.md "Sync parameters", "Distributed clocks"): the MainDevice picks the
//! sync type in 0x1C32:01 during PREOP; PREOP→SAFEOP checks it against the device (and the DC
//! SYNC unit in DC mode); free-run cycles on the local timer, DC mode on SYNC0.

mod common;

use common::{client, walk_to};
use ecat_core::AlState;
use ecat_core::coe::AbortCode;
use ecat_core::device::Area;
use ecat_core::dictionary::ObjectDictionary;
use ecat_core::register;
use ecat_embassy::Application;
use ecat_emu::coe_client::{SdoClient, SdoError};
use ecat_emu::devices::{Drive, DriveDc, DriveSm, DriveSync1};
use ecat_emu::harness::{self, Device};
use ecat_emu::master::{SM2_CONTROL, SM3_CONTROL, TestMaster};
use embassy_time::{Duration, Instant};

struct App;
impl<D> Application<D> for App {}

/// Counts its cycles in the statusword (0x6041, the first two bytes of the TxPDO image).
struct Counter;

impl<const SYNC: u16> Application<Drive<SYNC>> for Counter {
    fn cycle(&mut self, od: &mut Drive<SYNC>, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        od.statusword = od.statusword.wrapping_add(1);
    }
}

const OUT: Area = Area::new(0x1100, 11);
const IN: Area = Area::new(0x1180, 11);

/// Runs `script` against the drive with the sync modes of its dictionary `D` ([`Drive`],
/// [`DriveDc`]…).
fn run<D>(script: impl AsyncFnOnce(TestMaster) + 'static)
where
    D: ObjectDictionary + Default + 'static,
    Counter: Application<D>,
{
    let device = Device::new(common::drive(), App, Counter).with_dictionary(D::default());
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

#[test]
fn sm_synchronous_by_default_and_the_supported_types_are_readable() {
    run::<Drive>(async |master| {
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
        assert_eq!(
            c.upload(0x1C33, 1, false).await,
            Ok(vec![0x22, 0x00]),
            "inputs latched with the SM2 event"
        );
        assert_eq!(c.upload(0x1C33, 4, false).await, Ok(vec![0x03, 0x00]));
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

/// TwinCAT and SOEM setups write 0x1C33:01 beside 0x1C32:01 in PREOP: the write is accepted
/// (conformance.md "Sync parameters": SI1 writable in PREOP), and 0x1C33:01 shows the inputs'
/// type that follows from the outputs' — SM-synchronous with outputs: 0x22, latched with SM2. A
/// value that is no sync type is 0x06090030; in SAFEOP it is read-only like 0x1C32:01
/// (0x08000022).
#[test]
fn the_inputs_sync_type_is_writable_in_preop_and_follows_the_outputs() {
    run::<Drive>(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(c.download(0x1C32, 1, false, &[1, 0]).await, Ok(()));
        assert_eq!(c.download(0x1C33, 1, false, &[1, 0]).await, Ok(()));
        assert_eq!(c.upload(0x1C33, 1, false).await, Ok(vec![0x22, 0]));
        assert_eq!(
            c.download(0x1C33, 1, false, &[0x05, 0]).await,
            Err(SdoError::Abort(AbortCode::VALUE_RANGE)),
            "not a sync type"
        );
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        assert_eq!(
            c.download(0x1C33, 1, false, &[0x22, 0]).await,
            Err(SdoError::Abort(AbortCode::DEVICE_STATE))
        );
    });
}

#[test]
fn free_run_cycles_on_the_local_timer() {
    run::<Drive>(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x1C32, 1, false, &[0, 0]).await.unwrap();
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        assert_eq!(
            c.upload(0x1C32, 2, false).await,
            Ok(1_000_000u32.to_le_bytes().to_vec()),
            "1 ms in ns"
        );
        assert_eq!(c.upload(0x1C33, 1, false).await, Ok(vec![0, 0]), "free-run");
        assert_eq!(
            c.upload(0x1C33, 2, false).await,
            Ok(1_000_000u32.to_le_bytes().to_vec())
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

/// A cycle time the MainDevice writes into 0x1C32:02 sets the free-run period.
#[test]
fn free_run_takes_the_cycle_time_the_maindevice_wrote() {
    run::<Drive>(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x1C32, 1, false, &[0, 0]).await.unwrap();
        let two_ms = 2_000_000u32.to_le_bytes();
        c.download(0x1C32, 2, false, &two_ms).await.unwrap();
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        assert_eq!(c.upload(0x1C32, 2, false).await, Ok(two_ms.to_vec()));
        let before = cycles(&master);
        master.advance(Duration::from_millis(10)).await;
        assert_eq!(
            cycles(&master).wrapping_sub(before),
            5,
            "one cycle per 2 ms"
        );
    });
}

/// A cycle time below the minimum (0x1C32:05, 250 µs) in free-run or SM-synchronous mode is
/// 0x002E at PREOP→SAFEOP; the minimum itself is accepted.
#[test]
fn a_cycle_time_below_the_minimum_is_0x002e() {
    for (sync_type, cycle_ns, expected) in [
        (0u16, 200_000u32, (0x12, 0x002E)),
        (1, 249_000, (0x12, 0x002E)),
        (1, 250_000, (0x04, 0)),
    ] {
        run::<Drive>(async move |master| {
            let mut c = preop_with_sync_type(&master, sync_type).await;
            c.download(0x1C32, 2, false, &cycle_ns.to_le_bytes())
                .await
                .unwrap();
            assert_eq!(
                safeop(&master, SM2_CONTROL).await,
                expected,
                "sync type {sync_type}, {cycle_ns} ns"
            );
        });
    }
}

/// The cycle time the MainDevice wrote is what PREOP→SAFEOP checks, not the interval the
/// SubDevice measured since (0x1C32:02 in SM-synchronous mode).
#[test]
fn a_measured_cycle_does_not_replace_the_written_one() {
    run::<Drive>(async |master| {
        let mut c = preop_with_sync_type(&master, 1).await;
        c.download(0x1C32, 2, false, &1_000_000u32.to_le_bytes())
            .await
            .unwrap();
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        for _ in 0..3 {
            common::send_outputs(&master).await;
            master.advance(Duration::from_micros(50)).await;
        }
        assert_eq!(
            u16_of(c.upload(0x1C32, 2, false).await.map(|b| b[..2].to_vec())),
            50_000,
            "SI2 shows the measured 50 µs"
        );
        assert_eq!(master.request(0x02).await, (0x02, 0));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
    });
}

/// In DC SYNC0 mode a cycle time the MainDevice wrote must be the SYNC0 cycle: 0x0035.
#[test]
fn a_cycle_time_other_than_sync0_is_0x0035() {
    for (cycle_ns, expected) in [(2_000_000u32, (0x12, 0x0035)), (1_000_000, (0x04, 0))] {
        run::<DriveDc>(async move |master| {
            let mut c = preop_with_sync_type(&master, 2).await;
            c.download(0x1C32, 2, false, &cycle_ns.to_le_bytes())
                .await
                .unwrap();
            program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
            assert_eq!(
                safeop(&master, SM2_CONTROL).await,
                expected,
                "{cycle_ns} ns"
            );
        });
    }
}

/// What a MainDevice chose is forgotten when the SubDevice goes back to INIT: the next one,
/// writing nothing, gets the ESC's DC SYNC0 followed (as ethercrab needs) even though the value
/// left in 0x1C32:01 is the default.
#[test]
fn a_choice_lasts_until_init() {
    run::<DriveDc>(async |master| {
        preop_with_sync_type(&master, 1).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x12, 0x0030));
        walk_to(&master, AlState::Init).await;
        walk_to(&master, AlState::PreOp).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
    });
}

/// Programs the ESC's DC SYNC unit as a MainDevice does: SYNC0 cycle, start time `start_in`
/// from now (system time = virtual time in ns), then the activation byte.
fn program_dc(master: &TestMaster, activation: u8, cycle_ns: u32, start_in: Duration) {
    let start = (Instant::now() + start_in).as_micros() * 1_000;
    assert!(master.write(register::DC_SYNC0_CYCLE_TIME, &cycle_ns.to_le_bytes()));
    assert!(master.write(register::DC_START_TIME, &start.to_le_bytes()));
    assert!(master.write(register::DC_ACTIVATION, &[activation]));
}

/// PREOP with sync type `sync_type` in 0x1C32:01; the SDO client for more (a new client would
/// start its mailbox counter at 1 again, and the SubDevice drop its first request as a repeat).
async fn preop_with_sync_type(master: &TestMaster, sync_type: u16) -> SdoClient<'_> {
    walk_to(master, AlState::PreOp).await;
    let mut c = client(master);
    c.download(0x1C32, 1, false, &sync_type.to_le_bytes())
        .await
        .unwrap();
    c
}

#[test]
fn dc_sync0_cycles_on_every_sync0_pulse_and_reports_its_cycle() {
    run::<DriveDc>(async |master| {
        let mut c = preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        assert_eq!(
            c.upload(0x1C32, 2, false).await,
            Ok(1_000_000u32.to_le_bytes().to_vec()),
            "the SYNC0 cycle in ns"
        );
        assert_eq!(
            c.upload(0x1C32, 5, false).await,
            Ok(250_000u32.to_le_bytes().to_vec()),
            "the minimum cycle in ns"
        );
        assert_eq!(c.upload(0x1C33, 1, false).await, Ok(vec![2, 0]), "DC SYNC0");
        assert_eq!(
            c.upload(0x1C33, 2, false).await,
            Ok(1_000_000u32.to_le_bytes().to_vec())
        );
        let before = cycles(&master);
        common::send_outputs(&master).await;
        common::send_outputs(&master).await;
        assert_eq!(cycles(&master), before, "SM2 writes do not start DC cycles");
        let pulses = master.emulator().sync0_pulses();
        master.advance(Duration::from_millis(10)).await;
        assert_eq!(master.emulator().sync0_pulses() - pulses, 10);
        assert_eq!(
            cycles(&master).wrapping_sub(before),
            10,
            "one cycle per SYNC0 pulse"
        );
        assert_eq!(
            master.request(0x08).await,
            (0x08, 0),
            "outputs seen at SYNC0"
        );
    });
}

#[test]
fn dc_configuration_errors_are_0x0030() {
    // (sync type, activation): SYNC0 mode without SYNC0; the SYNC unit on without SYNC0;
    // SYNC1 without SYNC0; SYNC1 with SYNC0 on this SYNC0-only device (0x1C32:04 without
    // 0x0008: SSC's CheckDcSettings refuses it with 0x0030 too); SYNC0 running while the
    // MainDevice chose free-run, or chose SM-synchronous by writing 0x1C32:01's default value.
    let cases = [
        (2, 0x00),
        (2, 0x01),
        (2, 0x05),
        (2, 0x07),
        (0, 0x03),
        (1, 0x03),
    ];
    for (sync_type, activation) in cases {
        run::<DriveDc>(async move |master| {
            preop_with_sync_type(&master, sync_type).await;
            program_dc(&master, activation, 1_000_000, Duration::from_millis(1));
            assert_eq!(
                safeop(&master, SM2_CONTROL).await,
                (0x12, 0x0030),
                "sync type {sync_type}, activation {activation:#04x}"
            );
        });
    }
}

#[test]
fn a_sync0_cycle_below_the_minimum_or_single_shot_is_0x0036() {
    for cycle in [0, 100_000, 249_999] {
        run::<DriveDc>(async move |master| {
            preop_with_sync_type(&master, 2).await;
            program_dc(&master, 0x03, cycle, Duration::from_millis(1));
            assert_eq!(
                safeop(&master, SM2_CONTROL).await,
                (0x12, 0x0036),
                "cycle {cycle} ns"
            );
        });
    }
    run::<DriveDc>(async move |master| {
        preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x03, 250_000, Duration::from_millis(1));
        assert_eq!(
            safeop(&master, SM2_CONTROL).await,
            (0x04, 0),
            "the minimum itself"
        );
    });
}

#[test]
fn safeop_to_op_without_sync0_is_0x002d_and_with_sync0_but_no_outputs_0x001b() {
    run::<DriveDc>(async |master| {
        preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_secs(60));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        common::send_outputs(&master).await;
        master.write_al_control(0x08);
        master.advance(Duration::from_millis(1_100)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x14, 0x002D),
            "no SYNC0 before the transition timeout"
        );
    });
    run::<DriveDc>(async |master| {
        preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        master.write_al_control(0x08);
        master.advance(Duration::from_millis(1_100)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x14, 0x001B),
            "SYNC0 runs but the MainDevice sends no outputs"
        );
    });
}

/// SYNC1 activated beside SYNC0 (0x0981 = 0x07) is refused only where the device does not
/// announce SYNC1 (0x1C32:04 bit 3, `dc_configuration_errors_are_0x0030`): one that does runs
/// DC SYNC0 and leaves SYNC1 to the application.
#[test]
fn sync1_beside_sync0_is_accepted_where_supported() {
    run::<DriveSync1>(async |master| {
        preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x07, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
    });
}

#[test]
fn sync1_is_not_supported() {
    run::<DriveSync1>(async |master| {
        preop_with_sync_type(&master, 3).await;
        program_dc(&master, 0x07, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x12, 0x0028));
    });
}

/// 0x22 (inputs latched with the SM2 event) and unknown values are not sync types of the
/// outputs: 0x0028 at PREOP→SAFEOP.
#[test]
fn sm2_synchronous_or_unknown_in_0x1c32_is_0x0028() {
    for sync_type in [0x22, 0x07] {
        run::<DriveDc>(async move |master| {
            preop_with_sync_type(&master, sync_type).await;
            assert_eq!(
                safeop(&master, SM2_CONTROL).await,
                (0x12, 0x0028),
                "sync type {sync_type:#x}"
            );
        });
    }
}

/// 0x1C32:03, :06 and :09 (shift, calc and copy, delay time) exist, read-only, 0 by default.
#[test]
fn the_timing_entries_are_readable() {
    run::<DriveDc>(async |master| {
        let mut c = preop_with_sync_type(&master, 1).await;
        for index in [0x1C32, 0x1C33] {
            for sub in [3, 6, 9] {
                assert_eq!(c.upload(index, sub, false).await, Ok(vec![0; 4]));
                assert_eq!(
                    c.download(index, sub, false, &[1, 0, 0, 0]).await,
                    Err(SdoError::Abort(AbortCode::READ_ONLY)),
                    "{index:#06x}:{sub}"
                );
            }
        }
    });
}

#[test]
fn free_run_on_a_device_without_it_is_0x0027() {
    run::<DriveSm>(async |master| {
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
    run::<Drive>(async |master| {
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

fn u16_of(bytes: Result<Vec<u8>, ecat_emu::coe_client::SdoError>) -> u16 {
    let bytes = bytes.expect("upload");
    u16::from_le_bytes([bytes[0], bytes[1]])
}

#[test]
fn sm_synchronous_measures_the_cycle_time() {
    run::<Drive>(async |master| {
        let mut c = preop_with_sync_type(&master, 1).await;
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        for _ in 0..3 {
            master.advance(Duration::from_millis(2)).await;
            common::send_outputs(&master).await;
        }
        let two_ms = 2_000_000u32.to_le_bytes().to_vec();
        assert_eq!(c.upload(0x1C32, 2, false).await, Ok(two_ms.clone()));
        assert_eq!(c.upload(0x1C33, 2, false).await, Ok(two_ms));
    });
}

#[test]
fn dc_cycles_without_new_outputs_count_as_sm_events_missed() {
    run::<DriveDc>(async |master| {
        let mut c = preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        common::send_outputs(&master).await;
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(master.request(0x08).await, (0x08, 0));
        for _ in 0..4 {
            common::send_outputs(&master).await;
            master.advance(Duration::from_millis(1)).await;
        }
        assert_eq!(
            u16_of(c.upload(0x1C32, 0x0B, false).await),
            0,
            "outputs every cycle"
        );
        assert_eq!(
            c.upload(0x1C32, 0x20, false).await,
            Ok(vec![0]),
            "no sync error"
        );
        master.advance(Duration::from_millis(5)).await;
        // The sync error supervision (0x10F1, SSC's limit 4 without the object: tests/tests/
        // sync_error.rs) takes the SubDevice out of OP at the second cycle in a row without
        // outputs; from then on no cycle expects outputs.
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x14, 0x001A)
        );
        assert_eq!(
            u16_of(c.upload(0x1C32, 0x0B, false).await),
            2,
            "two SYNC0 without outputs in OP"
        );
        assert_eq!(
            c.upload(0x1C32, 0x20, false).await,
            Ok(vec![1]),
            "sync error"
        );
        assert_eq!(
            u16_of(c.upload(0x1C32, 0x0C, false).await),
            0,
            "no cycle lost"
        );
        // Conformance: the SM-event-missed counter is reset at PREOP→SAFEOP.
        assert_eq!(master.request(0x12).await, (0x02, 0));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        common::send_outputs(&master).await;
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(master.request(0x08).await, (0x08, 0));
        for _ in 0..2 {
            common::send_outputs(&master).await;
            master.advance(Duration::from_millis(1)).await;
        }
        assert_eq!(
            u16_of(c.upload(0x1C32, 0x0B, false).await),
            0,
            "reset at PREOP→SAFEOP"
        );
        assert_eq!(c.upload(0x1C32, 0x20, false).await, Ok(vec![0]));
    });
}

#[test]
fn lost_clocked_cycles_count_as_cycle_time_too_small() {
    run::<DriveDc>(async |master| {
        let mut c = preop_with_sync_type(&master, 2).await;
        // 500 µs SYNC0, but the runner gets a turn once per millisecond: every other cycle is lost.
        program_dc(&master, 0x03, 500_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        master.advance(Duration::from_millis(5)).await;
        assert_eq!(
            u16_of(c.upload(0x1C32, 0x0C, false).await),
            4,
            "every cycle after the first"
        );
    });
}

#[test]
fn a_maindevice_that_activates_sync0_without_choosing_a_sync_type_gets_dc_mode() {
    // As ethercrab does: DC configured in the ESC, 0x1C32:01 left at its default (SM-synchronous).
    run::<DriveDc>(async |master| {
        walk_to(&master, AlState::PreOp).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        let before = cycles(&master);
        common::send_outputs(&master).await;
        assert_eq!(cycles(&master), before, "no cycle on the SM2 event");
        master.advance(Duration::from_millis(5)).await;
        assert_eq!(
            cycles(&master).wrapping_sub(before),
            5,
            "one cycle per SYNC0"
        );
        let mut c = client(&master);
        assert_eq!(
            c.upload(0x1C33, 1, false).await,
            Ok(vec![2, 0]),
            "inputs follow SYNC0"
        );
    });
}

/// An input-only DC device: SAFEOP→OP waits for SYNC0 (there are no outputs to wait for). Its
/// SII image is written for DC SYNC0: the ESC's SYNC out unit is on.
fn input_only_dc(start_in: Duration, expected: (u16, u16)) {
    let mut sample = ecat_emu::devices::sensor_dc();
    sample.device.eeprom = sample.eeprom();
    harness::run(sample.device, move |master| async move {
        master.configure_mailbox(&ecat_core::device::MailboxConfig::contiguous(0x1000, 128));
        assert_eq!(master.request(0x02).await, (0x02, 0));
        program_dc(&master, 0x03, 1_000_000, start_in);
        master.configure_sm(2, 0x1100, 0, SM2_CONTROL, false);
        master.configure_sm(3, 0x1180, 6, SM3_CONTROL, true);
        assert_eq!(master.request(0x04).await, (0x04, 0));
        master.write_al_control(0x08);
        master.advance(Duration::from_millis(1_100)).await;
        assert_eq!((master.al_status(), master.al_status_code()), expected);
    });
}

#[test]
fn an_input_only_dc_device_enters_op_with_sync0_and_refuses_it_without() {
    input_only_dc(Duration::from_millis(2), (0x08, 0));
    input_only_dc(Duration::from_secs(60), (0x14, 0x002D));
}

#[test]
fn sync0_lost_in_op_is_0x002c_and_back_to_safeop() {
    run::<DriveDc>(async |master| {
        let _c = preop_with_sync_type(&master, 2).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x04, 0));
        common::send_outputs(&master).await;
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(master.request(0x08).await, (0x08, 0));
        for _ in 0..20 {
            common::send_outputs(&master).await;
            master.advance(Duration::from_millis(1)).await;
        }
        assert_eq!(master.al_status(), 0x08, "still in OP while SYNC0 runs");
        assert!(master.write(register::DC_ACTIVATION, &[0]), "SYNC0 stops");
        master.advance(Duration::from_millis(9)).await;
        assert_eq!(
            master.al_status(),
            0x08,
            "nine cycles without SYNC0 are tolerated"
        );
        master.advance(Duration::from_millis(3)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x14, 0x002C),
            "fatal sync error after ten cycles without SYNC0"
        );
    });
}

#[test]
fn dc_activated_on_a_device_without_dc_is_0x0030() {
    run::<Drive>(async |master| {
        walk_to(&master, AlState::PreOp).await;
        program_dc(&master, 0x03, 1_000_000, Duration::from_millis(1));
        assert_eq!(safeop(&master, SM2_CONTROL).await, (0x12, 0x0030));
        assert!(master.write(register::DC_ACTIVATION, &[0]));
        assert_eq!(
            safeop(&master, SM2_CONTROL).await,
            (0x04, 0),
            "without it: SAFEOP"
        );
    });
}
