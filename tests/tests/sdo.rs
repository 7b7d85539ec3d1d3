//! The SDO server through the real runners: request bytes in, response bytes out, exactly
//! (ETG.1000.6 §5.6.2; conformance.md "CoE SDO").

mod common;

use common::od::{BlobApp, TestOd};
use common::{MAILBOX, client, walk_to, walk_to_with};
use ecat_core::AlState;
use ecat_core::coe::AbortCode;
use ecat_core::device::MailboxConfig;
use ecat_emu::coe_client::{SdoClient, SdoError};
use ecat_emu::harness::{self, Device, Loopback};
use ecat_emu::master::TestMaster;
use embassy_time::Duration;

fn device(app: BlobApp) -> Device<BlobApp, Loopback, TestOd> {
    Device::new(common::drive(), app, Loopback).with_dictionary(TestOd::default())
}

fn run(script: impl AsyncFnOnce(TestMaster) + 'static) {
    harness::run(device(BlobApp::default()), |master| async move {
        script(master).await
    })
}

#[test]
fn expedited_upload_frames_are_exact() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let answer = c
            .exchange_raw(
                &[0x0A, 0, 0, 0, 0, 0x13],
                &[0x00, 0x20, 0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0],
            )
            .await;
        let mut expected = vec![
            0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x30, 0x43, 0x00, 0x10, 0x00, 0x92, 0x01,
            0x02, 0x00,
        ];
        expected.resize(128, 0);
        assert_eq!(
            answer,
            Some(expected),
            "4-byte expedited upload of 0x1000, SubDevice counter 1"
        );
    });
}

#[test]
fn expedited_uploads_of_1_2_3_and_4_bytes() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        for (index, expected) in [
            (0x1001u16, [0x4F, 0x01, 0x10, 0x00, 0x00, 0, 0, 0]),
            (0x2004, [0x4B, 0x04, 0x20, 0x00, 0x00, 0x00, 0, 0]),
            (0x1009, [0x47, 0x09, 0x10, 0x00, b'1', b'.', b'0', 0]),
            (0x1000, [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]),
        ] {
            let [i0, i1] = index.to_le_bytes();
            assert_eq!(
                c.sdo(&[0x40, i0, i1, 0, 0, 0, 0, 0]).await,
                Ok(expected.to_vec()),
                "{index:#06x}"
            );
        }
    });
}

#[test]
fn expedited_downloads_of_1_2_and_4_bytes() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(
            c.sdo(&[0x2B, 0x40, 0x60, 0x00, 0x34, 0x12, 0, 0]).await,
            Ok(vec![0x60, 0x40, 0x60, 0x00, 0, 0, 0, 0])
        );
        assert_eq!(c.upload(0x6040, 0, false).await, Ok(vec![0x34, 0x12]));
        assert_eq!(
            c.sdo(&[0x23, 0x7A, 0x60, 0x00, 0x18, 0xFC, 0xFF, 0xFF])
                .await,
            Ok(vec![0x60, 0x7A, 0x60, 0x00, 0, 0, 0, 0])
        );
        assert_eq!(
            c.upload(0x607A, 0, false).await,
            Ok((-1000i32).to_le_bytes().to_vec())
        );
        assert_eq!(
            c.sdo(&[0x2F, 0x02, 0x20, 0x01, 0x01, 0, 0, 0]).await,
            Ok(vec![0x60, 0x02, 0x20, 0x01, 0, 0, 0, 0])
        );
        assert_eq!(c.upload(0x2002, 1, false).await, Ok(vec![1]));
    });
}

#[test]
fn normal_upload_carries_size_and_data() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let mut expected = vec![0x41, 0x08, 0x10, 0x00, 16, 0, 0, 0];
        expected.extend_from_slice(b"ecat test device");
        let answer = c.sdo(&[0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(answer[..24], expected[..]);
    });
}

#[test]
fn segmented_upload_and_download_of_a_300_byte_string_with_128_byte_mailboxes() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let text: Vec<u8> = (0..300u32).map(|i| b'a' + (i % 26) as u8).collect();
        c.download(0x2000, 0, false, &text).await.unwrap();
        // 112 bytes in the initiate request, then 119 + 69 in two segments.
        assert_eq!(c.round_trips, 3);

        let first = c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(
            first[..8],
            [0x41, 0x00, 0x20, 0x00, 0x2C, 0x01, 0, 0],
            "normal response: size 300"
        );
        assert_eq!(first[8..120], text[..112]);
        let segment = c.sdo(&[0x60, 0, 0, 0, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(segment[0], 0x00, "toggle 0, more to come");
        assert_eq!(segment[1..120], text[112..231]);
        let last = c.sdo(&[0x70, 0, 0, 0, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(last[0], 0x11, "toggle 1, last segment");
        assert_eq!(last[1..70], text[231..300]);
        assert_eq!(c.upload(0x2000, 0, false).await, Ok(text));
    });
}

#[test]
fn short_last_segment_reports_its_unused_bytes() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let text = vec![b'x'; 114];
        c.download(0x2000, 0, false, &text).await.unwrap();
        c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        let last = c.sdo(&[0x60, 0, 0, 0, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(
            last[..8],
            [0x0B, b'x', b'x', 0, 0, 0, 0, 0],
            "2 data bytes, 5 unused (0x0A), last (0x01)"
        );
    });
}

fn blob_round_trip(mailbox: MailboxConfig, round_trips: usize) {
    let app = BlobApp::default();
    let blob = app.blob.clone();
    let mut device = device(app);
    device.config.mailbox = mailbox;
    device.config.bootstrap_mailbox = None;
    harness::run(device, move |master| async move {
        walk_to_with(&master, AlState::PreOp, &mailbox).await;
        let mut c = SdoClient::for_mailbox(&master, &mailbox);
        let data: Vec<u8> = (0..10_240u32).map(|i| (i * 7 + i / 256) as u8).collect();
        c.download(0x2001, 0, false, &data).await.unwrap();
        assert_eq!(
            *blob.borrow(),
            data,
            "DOMAIN download streamed to the application"
        );
        assert_eq!(c.round_trips, round_trips, "download round trips");
        c.round_trips = 0;
        assert_eq!(c.upload(0x2001, 0, false).await, Ok(data));
        assert_eq!(c.round_trips, round_trips, "upload round trips");
    });
}

/// 10 KiB with 128-byte mailboxes: 112 bytes in the initiate message, then ⌈10128 / 119⌉ = 86
/// segments: 87 round trips, the minimum for that mailbox size.
#[test]
fn ten_kib_domain_with_128_byte_mailboxes_takes_87_round_trips() {
    blob_round_trip(MAILBOX, 87);
}

/// 10 KiB with 1024-byte mailboxes: 1008 bytes first, then ⌈9232 / 1015⌉ = 10 segments.
#[test]
fn ten_kib_domain_with_1024_byte_mailboxes_takes_11_round_trips() {
    blob_round_trip(MailboxConfig::contiguous(0x1000, 1024), 11);
}

#[test]
fn toggle_error_aborts_the_transfer() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2000, 0, false, &[b'z'; 200]).await.unwrap();
        c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(
            c.sdo(&[0x70, 0, 0, 0, 0, 0, 0, 0]).await,
            Err(SdoError::Abort(AbortCode::TOGGLE_BIT))
        );
        let answer = c.read().await;
        assert_eq!(answer, None, "the abort was already read");
        assert_eq!(
            c.sdo(&[0x60, 0, 0, 0, 0, 0, 0, 0]).await,
            Err(SdoError::Abort(AbortCode::COMMAND_SPECIFIER)),
            "transfer gone"
        );
    });
}

/// The same on the download side: a segment whose toggle does not alternate (the first
/// carries 0) is 0x05030000, and the value stays as it was.
#[test]
fn download_toggle_error_aborts_the_transfer() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2000, 0, false, &[b'a'; 4]).await.unwrap();
        // A normal download of 200 bytes announced, 8 carried: segments must follow.
        let mut initiate = vec![0x21, 0x00, 0x20, 0x00, 200, 0, 0, 0];
        initiate.extend_from_slice(&[b'z'; 8]);
        assert_eq!(c.sdo(&initiate).await.map(|a| a[0]), Ok(0x60));
        assert_eq!(
            c.sdo(&[0x10, b'z', b'z', b'z', b'z', b'z', b'z', b'z'])
                .await,
            Err(SdoError::Abort(AbortCode::TOGGLE_BIT)),
            "first segment with toggle 1"
        );
        assert_eq!(
            c.sdo(&[0x00, b'z', b'z', b'z', b'z', b'z', b'z', b'z'])
                .await,
            Err(SdoError::Abort(AbortCode::COMMAND_SPECIFIER)),
            "transfer gone"
        );
        assert_eq!(c.upload(0x2000, 0, false).await, Ok(b"aaaa".to_vec()));
    });
}

#[test]
fn toggle_abort_names_the_transfer_object() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2000, 0, false, &[b'z'; 200]).await.unwrap();
        c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        let answer = c
            .exchange(
                ecat_core::mailbox::MailboxType::Coe,
                &[0x00, 0x20, 0x70, 0, 0, 0, 0, 0, 0, 0],
            )
            .await
            .unwrap();
        assert_eq!(
            answer[..16],
            [
                0x0A, 0, 0, 0, 0, answer[5], 0x00, 0x20, 0x80, 0x00, 0x20, 0x00, 0x00, 0x00, 0x03,
                0x05
            ]
        );
        assert_eq!(answer[5] & 0x0F, 0x03, "CoE");
    });
}

#[test]
fn client_abort_ends_the_transfer_without_an_answer() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2000, 0, false, &[b'q'; 250]).await.unwrap();
        c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        let mut abort = vec![0x00, 0x20, 0x80, 0x00, 0x20, 0x00];
        abort.extend_from_slice(&0x0800_0000u32.to_le_bytes());
        assert_eq!(
            c.exchange(ecat_core::mailbox::MailboxType::Coe, &abort)
                .await,
            None,
            "no answer to an abort"
        );
        assert_eq!(
            c.sdo(&[0x60, 0, 0, 0, 0, 0, 0, 0]).await,
            Err(SdoError::Abort(AbortCode::COMMAND_SPECIFIER))
        );
    });
}

#[test]
fn transfer_times_out_after_a_second_without_segments() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2000, 0, false, &[b'q'; 250]).await.unwrap();
        c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        master.advance(Duration::from_millis(999)).await;
        assert!(
            c.sdo(&[0x60, 0, 0, 0, 0, 0, 0, 0]).await.is_ok(),
            "999 ms: still alive"
        );
        master.advance(Duration::from_millis(1000)).await;
        assert_eq!(
            c.sdo(&[0x70, 0, 0, 0, 0, 0, 0, 0]).await,
            Err(SdoError::Abort(AbortCode::TIMEOUT))
        );
    });
}

#[test]
fn every_abort_code_the_server_produces() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let cases: &[(&str, [u8; 8], AbortCode)] = &[
            (
                "write read-only",
                [0x23, 0x00, 0x10, 0x00, 1, 2, 3, 4],
                AbortCode::READ_ONLY,
            ),
            (
                "read write-only",
                [0x40, 0x03, 0x20, 0x00, 0, 0, 0, 0],
                AbortCode::WRITE_ONLY,
            ),
            (
                "missing object",
                [0x40, 0x00, 0x30, 0x00, 0, 0, 0, 0],
                AbortCode::NO_OBJECT,
            ),
            (
                "missing subindex",
                [0x40, 0x18, 0x10, 0x05, 0, 0, 0, 0],
                AbortCode::NO_SUBINDEX,
            ),
            (
                "too high",
                [0x23, 0x7A, 0x60, 0x00, 0xE9, 0x03, 0, 0],
                AbortCode::VALUE_TOO_HIGH,
            ),
            (
                "too low",
                [0x23, 0x7A, 0x60, 0x00, 0x17, 0xFC, 0xFF, 0xFF],
                AbortCode::VALUE_TOO_LOW,
            ),
            (
                "length too high",
                [0x23, 0x40, 0x60, 0x00, 1, 2, 3, 4],
                AbortCode::LENGTH_TOO_HIGH,
            ),
            (
                "length too low",
                [0x2F, 0x40, 0x60, 0x00, 1, 0, 0, 0],
                AbortCode::LENGTH_TOO_LOW,
            ),
            (
                "UNICODE_STRING of 3 bytes",
                [0x27, 0x05, 0x20, 0x00, b'A', 0x00, b'B', 0],
                AbortCode::LENGTH_MISMATCH,
            ),
            (
                "unknown command",
                [0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0],
                AbortCode::COMMAND_SPECIFIER,
            ),
            (
                "complete access from 2",
                [0x50, 0x18, 0x10, 0x02, 0, 0, 0, 0],
                AbortCode::UNSUPPORTED_ACCESS,
            ),
            (
                "complete access to a VAR",
                [0x50, 0x00, 0x10, 0x00, 0, 0, 0, 0],
                AbortCode::UNSUPPORTED_ACCESS,
            ),
            (
                "segment without transfer",
                [0x00, 0, 0, 0, 0, 0, 0, 0],
                AbortCode::COMMAND_SPECIFIER,
            ),
            (
                "vetoed by the application",
                [0x2B, 0x40, 0x60, 0x00, 0xAD, 0xDE, 0, 0],
                AbortCode::LOCAL_CONTROL,
            ),
            (
                "record SI0",
                [0x2F, 0x18, 0x10, 0x00, 4, 0, 0, 0],
                AbortCode::READ_ONLY,
            ),
            (
                "array element read-only",
                [0x2F, 0x00, 0x1C, 0x01, 4, 0, 0, 0],
                AbortCode::READ_ONLY,
            ),
            (
                "BOOL out of range",
                [0x2F, 0x02, 0x20, 0x01, 2, 0, 0, 0],
                AbortCode::VALUE_RANGE,
            ),
            (
                "BIT3 out of range",
                [0x2F, 0x02, 0x20, 0x02, 8, 0, 0, 0],
                AbortCode::VALUE_RANGE,
            ),
            (
                "record entry too high",
                [0x2B, 0x02, 0x20, 0x03, 0xE9, 0x03, 0, 0],
                AbortCode::VALUE_TOO_HIGH,
            ),
            (
                "download larger than the buffer",
                [0x21, 0x00, 0x20, 0x00, 0xD0, 0x07, 0, 0],
                AbortCode::OUT_OF_MEMORY,
            ),
        ];
        for (what, request, code) in cases {
            assert_eq!(c.sdo(request).await, Err(SdoError::Abort(*code)), "{what}");
        }
        let text = vec![b'y'; 301];
        assert_eq!(
            c.download(0x2000, 0, false, &text).await,
            Err(SdoError::Abort(AbortCode::LENGTH_TOO_HIGH)),
            "301 bytes into 300"
        );
        assert_eq!(
            c.download(0x2005, 0, false, &[b'A', 0, b'B', 0, b'C'])
                .await,
            Err(SdoError::Abort(AbortCode::LENGTH_MISMATCH)),
            "normal download of 5 bytes into a UNICODE_STRING"
        );
    });
}

/// Complete access to an ARRAY of numbers (0x1C00, the SM types 1..4): from SI0 the count, one
/// pad byte and the elements; from SI1 the elements only. (Objects with strings refuse it with
/// 0x06010004: `coe::sdo::complete_access` unit test.)
#[test]
fn complete_access_reads_an_array_of_numbers() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        assert_eq!(c.upload(0x1C00, 0, true).await, Ok(vec![4, 0, 1, 2, 3, 4]));
        assert_eq!(
            c.upload(0x1C00, 1, true).await,
            Ok(vec![1, 2, 3, 4]),
            "from subindex 1: no SI0"
        );
    });
}

#[test]
fn writable_only_in_preop_is_refused_in_safeop_with_0x08000022() {
    run(async |master| {
        walk_to(&master, AlState::SafeOp).await;
        let mut c = client(&master);
        assert_eq!(
            c.sdo(&[0x2B, 0x04, 0x20, 0x00, 1, 0, 0, 0]).await,
            Err(SdoError::Abort(AbortCode::DEVICE_STATE))
        );
        assert_eq!(
            c.upload(0x2004, 0, false).await,
            Ok(vec![0, 0]),
            "still readable"
        );
        assert_eq!(
            c.download(0x6040, 0, false, &[0x0F, 0x00]).await,
            Ok(()),
            "RW in every state"
        );
    });
}

#[test]
fn complete_access_upload_of_the_identity_record() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let answer = c.sdo(&[0x50, 0x18, 0x10, 0x00, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(
            answer[..26],
            [
                0x51, 0x18, 0x10, 0x00, 18, 0, 0, 0, // normal, complete access, 18 bytes
                4, 0, // SI0 and its padding byte
                0x01, 0x00, 0x00, 0xE0, 0x02, 0x04, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x78, 0x56,
                0x34, 0x12
            ]
        );
    });
}

#[test]
fn complete_access_download_packs_bits_and_aligns_bytes() {
    let app = BlobApp::default();
    let written = app.written.clone();
    harness::run(device(app), move |master| async move {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        // SI0 4 + pad; enable (1 bit) = 1, level (3 bits) = 5 → 0b1011; gain 500; offset -2.
        let image = [4, 0, 0x0B, 0xF4, 0x01, 0xFE, 0xFF, 0xFF, 0xFF];
        let mut request = vec![0x31, 0x02, 0x20, 0x00, 9, 0, 0, 0];
        request.extend_from_slice(&image);
        assert_eq!(
            c.sdo(&request).await,
            Ok(vec![0x70, 0x02, 0x20, 0x00, 0, 0, 0, 0])
        );
        assert_eq!(c.upload(0x2002, 1, false).await, Ok(vec![1]));
        assert_eq!(c.upload(0x2002, 2, false).await, Ok(vec![5]));
        assert_eq!(c.upload(0x2002, 3, false).await, Ok(vec![0xF4, 0x01]));
        assert_eq!(
            c.upload(0x2002, 4, false).await,
            Ok((-2i32).to_le_bytes().to_vec())
        );
        assert_eq!(c.upload(0x2002, 0, true).await, Ok(image.to_vec()));
        assert_eq!(
            *written.borrow(),
            [(0x2002, 1), (0x2002, 2), (0x2002, 3), (0x2002, 4)]
        );
        let mut wrong_si0 = vec![0x31, 0x02, 0x20, 0x00, 9, 0, 0, 0, 3];
        wrong_si0.extend_from_slice(&image[1..]);
        assert_eq!(
            c.sdo(&wrong_si0).await,
            Err(SdoError::Abort(AbortCode::READ_ONLY))
        );
        let mut short = vec![0x31, 0x02, 0x20, 0x00, 8, 0, 0, 0];
        short.extend_from_slice(&image[..8]);
        assert_eq!(
            c.sdo(&short).await,
            Err(SdoError::Abort(AbortCode::LENGTH_TOO_LOW))
        );
    });
}

#[test]
fn strings_shorten_on_a_shorter_download() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2000, 0, false, b"a long text of twenty")
            .await
            .unwrap();
        c.download(0x2000, 0, false, b"abc").await.unwrap();
        assert_eq!(
            c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await,
            Ok(vec![0x47, 0x00, 0x20, 0x00, b'a', b'b', b'c', 0])
        );
    });
}

/// The drive's application: accepts everything.
struct DriveApp;
impl<D> ecat_embassy::Application<D> for DriveApp {}

/// What SOEM's `ecx_readOE` (`slaveinfo -sdo`, pysoem's `slave.od`) does with 0x1C32 through the
/// runners: an entry description of every subindex 0..=0x20 (value info 7, as SOEM sends it).
/// Each is an entry description, none an SDO Info error (there were 22 per axis, one per gap);
/// 0x1C32:1F, a gap whatever entries the record declares, is described as SSC describes it.
#[test]
fn every_subindex_of_0x1c32_is_described_through_the_runners() {
    let device = Device::new(common::drive(), DriveApp, Loopback)
        .with_dictionary(<ecat_emu::devices::Drive>::default());
    harness::run(device, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let mut described = Vec::new();
        for sub in 0..=0x20u8 {
            let counter = sub % 7 + 1;
            let header = [0x0A, 0x00, 0, 0, 0, (counter << 4) | 0x03];
            let request = [0x00, 0x80, 0x05, 0x00, 0x00, 0x00, 0x32, 0x1C, sub, 0x07];
            let answer = c.exchange_raw(&header, &request).await.expect("an answer");
            let length = usize::from(u16::from_le_bytes([answer[0], answer[1]]));
            let message = &answer[6..6 + length];
            assert_eq!(message[..3], [0x00, 0x80, 0x06], "0x1C32:{sub:02X}");
            assert_eq!(message[6..9], [0x32, 0x1C, sub]);
            described.push(message.to_vec());
        }
        assert_eq!(
            described[0x1F],
            [
                0x00, 0x80, 0x06, 0x00, 0x00, 0x00, // CoE, entry description response
                0x32, 0x1C, 0x1F, 0x00, // 0x1C32:1F, value info 0
                0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // data type 0, bit length 0, access 0
                b'S', b'u', b'b', b'I', b'n', b'd', b'e', b'x', b' ', b'0', b'3', b'1',
            ]
        );
    });
}
