//! PDO configuration through the real runners: the mapping reconfigured over SDO decides the
//! SyncManager lengths PREOP→SAFEOP accepts; complete access on the assignment; PREOP-only writes.

mod common;

use common::{client, walk_to};
use ecat_core::AlState;
use ecat_core::coe::AbortCode;
use ecat_core::device::Area;
use ecat_core::mailbox::MailboxType;
use ecat_core::pdo::MappingEntry;
use ecat_embassy::Application;
use ecat_emu::coe_client::{SdoClient, SdoError};
use ecat_emu::devices::{DRIVE_TX, Drive};
use ecat_emu::harness::{self, Device, Loopback};
use ecat_emu::master::{SM2_CONTROL, SM3_CONTROL, TestMaster};

struct App;
impl<D> Application<D> for App {}

/// A drive whose cycle echoes through the dictionary: statusword = controlword, actual position
/// = target position, actual velocity = target velocity, mode display = mode.
struct Echo;

impl Application<Drive> for Echo {
    fn cycle(&mut self, od: &mut Drive, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        od.statusword = od.controlword;
        od.position = od.target_position;
        od.velocity = od.target_velocity;
        od.mode_display = od.mode;
    }
}

const OUT: Area = Area::new(0x1100, 11);
const IN: Area = Area::new(0x1180, 11);

fn run(script: impl AsyncFnOnce(TestMaster) + 'static) {
    let device = Device::new(common::drive(), App, Loopback).with_dictionary(<Drive>::default());
    harness::run(device, |master| async move { script(master).await })
}

async fn request_safeop(master: &TestMaster, outputs: u16, inputs: u16) -> (u16, u16) {
    master.configure_sm(2, OUT.start, outputs, SM2_CONTROL, outputs > 0);
    master.configure_sm(3, IN.start, inputs, SM3_CONTROL, inputs > 0);
    // SAFEOP with acknowledge: a previous refusal latched the error.
    master.request(0x14).await
}

#[test]
fn the_default_mapping_needs_11_bytes_each_way() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        assert_eq!(
            request_safeop(&master, 12, 11).await,
            (0x12, 0x001D),
            "SM2 12 bytes for an 11-byte RxPDO"
        );
        assert_eq!(
            request_safeop(&master, 11, 10).await,
            (0x12, 0x001E),
            "SM3 10 bytes for an 11-byte TxPDO"
        );
        assert_eq!(request_safeop(&master, 11, 11).await, (0x04, 0));
    });
}

/// Maps `entries` into 0x1600 and assigns it alone, as MainDevices do: SI0 = 0, the entries,
/// SI0 = n, the assignment the same way.
async fn map_rx(c: &mut SdoClient<'_>, entries: &[MappingEntry]) {
    c.download(0x1C12, 0, false, &[0]).await.unwrap();
    c.download(0x1600, 0, false, &[0]).await.unwrap();
    for (sub, entry) in (1u8..).zip(entries) {
        c.download(0x1600, sub, false, &entry.0.to_le_bytes())
            .await
            .unwrap();
    }
    c.download(0x1600, 0, false, &[entries.len() as u8])
        .await
        .unwrap();
    c.download(0x1C12, 1, false, &0x1600u16.to_le_bytes())
        .await
        .unwrap();
    c.download(0x1C12, 0, false, &[1]).await.unwrap();
}

#[test]
fn a_mapping_reconfigured_over_sdo_changes_the_lengths_safeop_needs() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        map_rx(
            &mut c,
            &[
                MappingEntry::new(0x6040, 0, 16),
                MappingEntry::new(0, 0, 8),
                MappingEntry::new(0x6060, 0, 8),
            ],
        )
        .await;
        assert_eq!(
            request_safeop(&master, 11, 11).await,
            (0x12, 0x001D),
            "the old length"
        );
        assert_eq!(
            request_safeop(&master, 4, 11).await,
            (0x04, 0),
            "16 + 8 gap + 8 bits"
        );
        assert_eq!(
            c.download(0x1600, 0, false, &[0]).await,
            Err(SdoError::Abort(AbortCode::DEVICE_STATE)),
            "PDO configuration is writable in PREOP only"
        );
    });
}

#[test]
fn an_output_only_configuration_accepts_sm2_alone() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x1C13, 0, false, &[0]).await.unwrap();
        assert_eq!(
            request_safeop(&master, 11, 0).await,
            (0x04, 0),
            "no TxPDO assigned: SM3 disabled"
        );
    });
}

#[test]
fn complete_access_on_the_assignment_follows_the_configuration_sequence() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        // SI0 and the PDOs it counts, not every slot (SSC sizes an ARRAY by SI0's value).
        assert_eq!(c.upload(0x1C12, 0, true).await, Ok(vec![1, 0, 0x00, 0x16]));
        assert_eq!(
            c.download(0x1C12, 0, true, &[0, 0, 0, 0, 0, 0]).await,
            Ok(()),
            "nothing assigned"
        );
        assert_eq!(c.upload(0x1C12, 0, false).await, Ok(vec![0]));
        assert_eq!(
            c.download(0x1C12, 0, true, &[2, 0, 0x00, 0x16, 0x00, 0x1A])
                .await,
            Err(SdoError::Abort(AbortCode::VALUE_RANGE)),
            "a TxPDO in SM2's assignment"
        );
        assert_eq!(
            c.download(0x1C12, 0, true, &[1, 0, 0x00, 0x16, 0x00, 0x00])
                .await,
            Ok(())
        );
        assert_eq!(c.upload(0x1C12, 1, false).await, Ok(vec![0x00, 0x16]));
        assert_eq!(c.upload(0x1C12, 0, false).await, Ok(vec![1]));
    });
}

/// TwinCAT and SOEM write an assignment with complete access as SI0 and only the entries it
/// counts (`01 00 00 16`: one PDO, 4 bytes of a 6-byte object); the whole object is accepted as
/// well. Anything else is a length error: shorter than SI0 counts 0x06070013, longer than the
/// object 0x06070012, in between 0x06070010. A refused download leaves the assignment as it was.
#[test]
fn complete_access_on_the_assignment_takes_the_entries_si0_counts() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(c.download(0x1C12, 0, true, &[0, 0]).await, Ok(()), "none");
        assert_eq!(c.upload(0x1C12, 0, false).await, Ok(vec![0]));
        assert_eq!(
            c.download(0x1C12, 0, true, &[1, 0, 0x00, 0x16]).await,
            Ok(()),
            "SI0 and one entry"
        );
        assert_eq!(c.upload(0x1C12, 0, true).await, Ok(vec![1, 0, 0x00, 0x16]));
        let refused = [
            (&[2, 0, 0x00, 0x16][..], AbortCode::LENGTH_TOO_LOW),
            (&[1, 0, 0x00, 0x16, 0x00][..], AbortCode::LENGTH_MISMATCH),
            (
                &[1, 0, 0x00, 0x16, 0x00, 0x00, 0x00][..],
                AbortCode::LENGTH_TOO_HIGH,
            ),
            // Refused by the configuration rules before anything is stored: more than the
            // capacity of 2, a TxPDO in SM2's assignment.
            (
                &[3, 0, 0x00, 0x16, 0x00, 0x16][..],
                AbortCode::VALUE_TOO_HIGH,
            ),
            (&[1, 0, 0x00, 0x1A][..], AbortCode::VALUE_RANGE),
        ];
        for (image, code) in refused {
            assert_eq!(
                c.download(0x1C12, 0, true, image).await,
                Err(SdoError::Abort(code)),
                "{image:02x?}"
            );
        }
        assert_eq!(
            c.upload(0x1C12, 0, true).await,
            Ok(vec![1, 0, 0x00, 0x16]),
            "unchanged"
        );
    });
}

#[test]
fn main_devices_read_the_mapping_one_expedited_upload_at_a_time() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(c.upload(0x1C13, 0, false).await, Ok(vec![1]));
        assert_eq!(c.upload(0x1C13, 1, false).await, Ok(vec![0x00, 0x1A]));
        assert_eq!(c.upload(0x1A00, 0, false).await, Ok(vec![4]));
        for (sub, entry) in (1u8..).zip(DRIVE_TX) {
            assert_eq!(
                c.upload(0x1A00, sub, false).await,
                Ok(entry.0.to_le_bytes().to_vec())
            );
        }
    });
}

#[test]
fn op_moves_the_image_through_the_dictionary() {
    let device = Device::new(common::drive(), App, Echo).with_dictionary(<Drive>::default());
    harness::run(device, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        assert_eq!(request_safeop(&master, 11, 11).await, (0x04, 0));
        let rx = [
            0x0F, 0x00, 0x10, 0x27, 0x00, 0x00, 0x18, 0xFC, 0xFF, 0xFF, 0x08,
        ];
        assert!(master.write(OUT.start, &rx));
        master.settle().await;
        assert_eq!(
            master.read(IN.start, 11),
            Some(vec![0; 11]),
            "SAFEOP: outputs never reach the dictionary"
        );
        assert_eq!(master.request(0x08).await, (0x08, 0));
        assert!(master.write(OUT.start, &rx));
        master.settle().await;
        // statusword 0x000F, position 10 000, velocity -1000, mode display 8.
        assert_eq!(master.read(IN.start, 11), Some(rx.to_vec()));
        let rx2 = [
            0x06, 0x00, 0xFF, 0xFF, 0xFF, 0x7F, 0x00, 0x00, 0x00, 0x80, 0xFF,
        ];
        assert!(master.write(OUT.start, &rx2));
        master.settle().await;
        assert_eq!(master.read(IN.start, 11), Some(rx2.to_vec()));
    });
}

/// The whole answer to an expedited 4-byte download of `value` into `index:0`.
async fn download_u32(c: &mut SdoClient<'_>, index: u16, value: u32) -> Vec<u8> {
    let [i0, i1] = index.to_le_bytes();
    let mut request = vec![0x00, 0x20, 0x23, i0, i1, 0x00];
    request.extend_from_slice(&value.to_le_bytes());
    c.exchange(MailboxType::Coe, &request).await.unwrap()
}

/// In SAFEOP and OP the process data owns what the RxPDO configuration maps: an SDO download
/// into it is refused with 0x06010006 (conformance.md "CoE SDO"). Unmapped entries stay
/// writable, uploads stay allowed, and in PREOP nothing is blocked.
#[test]
fn downloads_into_mapped_rxpdo_entries_are_refused_in_safeop_and_op() {
    let device = Device::new(common::drive(), App, Echo).with_dictionary(<Drive>::default());
    harness::run(device, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        // 0x60FF out of the mapping, a 32-bit gap in its place: still 11 bytes.
        map_rx(
            &mut c,
            &[
                MappingEntry::new(0x6040, 0, 16),
                MappingEntry::new(0x607A, 0, 32),
                MappingEntry::new(0, 0, 32),
                MappingEntry::new(0x6060, 0, 8),
            ],
        )
        .await;
        let accepted = [0x00, 0x30, 0x60, 0x7A, 0x60, 0x00, 0, 0, 0, 0];
        assert_eq!(
            download_u32(&mut c, 0x607A, 7).await[6..16],
            accepted,
            "PREOP: mapped, but no process data yet"
        );
        assert_eq!(request_safeop(&master, 11, 11).await, (0x04, 0));
        let blocked = [0x00, 0x20, 0x80, 0x7A, 0x60, 0x00, 0x06, 0x00, 0x01, 0x06];
        for (state, control) in [("SAFEOP", None), ("OP", Some(0x08))] {
            if let Some(control) = control {
                assert!(master.write(OUT.start, &[0; 11]));
                master.settle().await;
                assert_eq!(master.request(control).await, (control, 0));
            }
            let answer = download_u32(&mut c, 0x607A, 8).await;
            assert_eq!(answer[..6], [0x0A, 0, 0, 0, 0, answer[5] & 0xF0 | 0x03]);
            assert_eq!(answer[6..16], blocked, "{state}: 0x607A is mapped");
            assert_eq!(
                c.download(0x60FF, 0, false, &[2, 0, 0, 0]).await,
                Ok(()),
                "{state}: 0x60FF is not mapped"
            );
            assert_eq!(
                c.upload(0x607A, 0, false).await,
                Ok(vec![7, 0, 0, 0]),
                "{state}: uploads are not blocked"
            );
        }
    });
}

/// The same for a complete-access download: any mapped entry among those it writes blocks it.
#[test]
fn complete_access_into_mapped_rxpdo_entries_is_refused_in_safeop() {
    let sample = ecat_emu::devices::dio();
    harness::run(sample.device, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(c.download(0x7000, 1, true, &[0x11, 0x22]).await, Ok(()));
        assert_eq!(request_safeop(&master, 2, 2).await, (0x04, 0));
        assert_eq!(
            c.sdo(&[0x31, 0x00, 0x70, 0x01, 2, 0, 0, 0, 0x33, 0x44])
                .await,
            Err(SdoError::Abort(AbortCode::MAPPED_TO_RXPDO)),
            "0x7000:01..02 are mapped"
        );
        assert_eq!(c.upload(0x7000, 1, true).await, Ok(vec![0x11, 0x22]));
    });
}
