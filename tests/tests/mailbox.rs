//! The mailbox layer through the real runners (conformance.md "Mailbox", "Emergency"): counters,
//! repeat, error replies with their exact bytes, nothing in INIT, both mailbox sizes, emergencies.

mod common;

use common::od::{BlobApp, TestOd};
use common::{MAILBOX, client, walk_to, walk_to_with};
use ecat_core::AlState;
use ecat_core::coe::{AbortCode, Emergency};
use ecat_core::device::MailboxConfig;
use ecat_core::mailbox::MailboxType;
use ecat_emu::coe_client::{SdoClient, SdoError};
use ecat_emu::harness::{self, Device, Loopback};
use ecat_emu::master::TestMaster;

/// Upload 0x1001 (error register, u8), counter `c`.
fn upload_1001(c: u8) -> ([u8; 6], [u8; 10]) {
    (
        [0x0A, 0, 0, 0, 0, (c << 4) | 0x03],
        [0x00, 0x20, 0x40, 0x01, 0x10, 0x00, 0, 0, 0, 0],
    )
}

fn run(script: impl AsyncFnOnce(TestMaster) + 'static) {
    let device = Device::new(common::drive(), BlobApp::default(), Loopback)
        .with_dictionary(TestOd::default());
    harness::run(device, |master| async move { script(master).await })
}

/// The mailbox error reply with `detail` and SubDevice counter `counter`, padded to SM1.
fn error_reply(counter: u8, detail: u8) -> Vec<u8> {
    let mut reply = vec![
        0x04,
        0x00,
        0x00,
        0x00,
        0x00,
        counter << 4,
        0x01,
        0x00,
        detail,
        0x00,
    ];
    reply.resize(128, 0);
    reply
}

#[test]
fn a_repeated_counter_is_dropped_and_counter_0_is_always_served() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let (header, payload) = upload_1001(3);
        assert!(c.exchange_raw(&header, &payload).await.is_some());
        assert_eq!(
            c.exchange_raw(&header, &payload).await,
            None,
            "same counter again: dropped"
        );
        let (header, payload) = upload_1001(4);
        assert!(
            c.exchange_raw(&header, &payload).await.is_some(),
            "next counter served"
        );
        let (header, payload) = upload_1001(0);
        assert!(c.exchange_raw(&header, &payload).await.is_some());
        assert!(
            c.exchange_raw(&header, &payload).await.is_some(),
            "counter 0 is never a repeat"
        );
    });
}

#[test]
fn the_subdevice_counts_its_own_messages_1_to_7_and_wraps() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let mut counters = Vec::new();
        for _ in 0..9 {
            let answer = c
                .exchange(MailboxType::Coe, &upload_1001(0).1)
                .await
                .unwrap();
            counters.push(answer[5] >> 4);
        }
        assert_eq!(counters, [1, 2, 3, 4, 5, 6, 7, 1, 2]);
    });
}

#[test]
fn repeat_request_writes_the_last_message_again_then_acknowledges() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let first = c
            .exchange(MailboxType::Coe, &upload_1001(0).1)
            .await
            .unwrap();
        assert_eq!(master.read(0x080F, 1), Some(vec![0x00]), "repeat ack 0");
        // The answer was lost on its way back: toggle SM1's repeat request (activate bit 1).
        master.write(0x080E, &[0x03]);
        master.settle().await;
        assert_eq!(
            master.read(MAILBOX.send.start, 128),
            Some(first),
            "the same bytes, same counter"
        );
        assert_eq!(
            master.read(0x080F, 1),
            Some(vec![0x02]),
            "repeat ack follows the request"
        );
        // And the mailbox goes on.
        assert!(
            c.exchange(MailboxType::Coe, &upload_1001(0).1)
                .await
                .is_some()
        );
    });
}

#[test]
fn malformed_messages_get_the_exact_error_reply() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let cases: [(&str, [u8; 6], &[u8], u8); 8] = [
            ("length 0", [0x00, 0x00, 0, 0, 0, 0x13], &[], 0x05),
            (
                "length beyond SM0 - 6",
                [0x7B, 0x00, 0, 0, 0, 0x23],
                &[0; 8],
                0x08,
            ),
            (
                "unknown type 7",
                [0x0A, 0x00, 0, 0, 0, 0x37],
                &[0; 10],
                0x02,
            ),
            (
                "EoE is not supported",
                [0x0A, 0x00, 0, 0, 0, 0x42],
                &[0; 10],
                0x02,
            ),
            (
                "CoE shorter than its header",
                [0x01, 0x00, 0, 0, 0, 0x53],
                &[0x00],
                0x08,
            ),
            (
                "SDO shorter than 8 bytes",
                [0x07, 0x00, 0, 0, 0, 0x63],
                &[0x00, 0x20, 0x40, 0x00, 0x10, 0x00, 0x00],
                0x08,
            ),
            // The channel (byte 4, bits 0..5) is reserved, 0 (ETG.1000.4 Table 29): 0x0003
            // "invalid channel" (Table 30) for an otherwise valid SDO upload.
            (
                "channel 1",
                [0x0A, 0x00, 0, 0, 0x01, 0x73],
                &upload_1001(0).1,
                0x03,
            ),
            (
                "channel 0x3F, priority 3",
                [0x0A, 0x00, 0, 0, 0xFF, 0x13],
                &upload_1001(0).1,
                0x03,
            ),
        ];
        for (n, (what, header, payload, detail)) in cases.into_iter().enumerate() {
            let answer = c.exchange_raw(&header, payload).await;
            assert_eq!(answer, Some(error_reply(n as u8 % 7 + 1, detail)), "{what}");
        }
        // The priority bits (6..7) are not judged: channel 0, priority 3 is served.
        let (mut header, request) = upload_1001(2);
        header[4] = 0xC0;
        let answer = c.exchange_raw(&header, &request).await.expect("an answer");
        assert_eq!(answer[5] & 0x0F, 0x03, "CoE, not a mailbox error");
        assert_eq!(
            answer[6..16],
            [0x00, 0x30, 0x4F, 0x01, 0x10, 0x00, 0, 0, 0, 0]
        );
    });
}

/// In BOOT only FoE would be served (conformance.md "ESM"); FoE is not implemented, so every
/// protocol, CoE and FoE alike, gets the mailbox error reply 0x0002 "protocol not supported".
#[test]
fn in_boot_every_protocol_gets_error_0x0002() {
    run(async |master| {
        walk_to(&master, AlState::Boot).await;
        let mut c = client(&master);
        let (header, payload) = upload_1001(1);
        assert_eq!(
            c.exchange_raw(&header, &payload).await,
            Some(error_reply(1, 0x02)),
            "CoE in BOOT"
        );
        // FoE read request (opcode 1, password 0, file "fw").
        let foe = [0x01, 0x00, 0, 0, 0, 0, b'f', b'w'];
        assert_eq!(
            c.exchange_raw(&[0x08, 0x00, 0, 0, 0, 0x24], &foe).await,
            Some(error_reply(2, 0x02)),
            "FoE in BOOT"
        );
    });
}

/// An SDO Information request shorter than its header and the fixed part of its opcode is a CoE
/// payload shorter than required: mailbox error 0x0008 (conformance.md "Mailbox"). A well-formed
/// request that cannot be served still gets an SDO Info error.
#[test]
fn short_sdo_information_requests_get_error_0x0008() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let cases: [(&str, [u8; 6], &[u8]); 3] = [
            (
                "SDO Information header cut",
                [0x04, 0x00, 0, 0, 0, 0x13],
                &[0x00, 0x80, 0x01, 0x00],
            ),
            (
                "Get OD List without its list type",
                [0x06, 0x00, 0, 0, 0, 0x23],
                &[0x00, 0x80, 0x01, 0x00, 0x00, 0x00],
            ),
            (
                "Get Entry Description without its value info",
                [0x09, 0x00, 0, 0, 0, 0x33],
                &[0x00, 0x80, 0x05, 0x00, 0x00, 0x00, 0x00, 0x10, 0x00],
            ),
        ];
        for (n, (what, header, payload)) in cases.into_iter().enumerate() {
            let answer = c.exchange_raw(&header, payload).await;
            assert_eq!(answer, Some(error_reply(n as u8 + 1, 0x08)), "{what}");
        }
        let list_type_9 = [0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x09, 0x00];
        let mut info_error = vec![
            0x0A, 0x00, 0x00, 0x00, 0x00, 0x43, 0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00,
            0x01, 0x06,
        ];
        info_error.resize(128, 0);
        assert_eq!(
            c.exchange_raw(&[0x08, 0x00, 0, 0, 0, 0x43], &list_type_9)
                .await,
            Some(info_error),
            "list type 9: SDO Info error 0x06010000"
        );
    });
}

/// Runs `script` on the test device with both mailboxes of `size` bytes (contiguous at 0x1000, no
/// BOOT), walked to PREOP.
fn in_preop_with_mailbox(size: u16, script: impl AsyncFnOnce(TestMaster) + 'static) {
    let mailbox = MailboxConfig::contiguous(0x1000, size);
    let mut device = Device::new(common::drive(), BlobApp::default(), Loopback)
        .with_dictionary(TestOd::default());
    device.config.mailbox = mailbox;
    device.config.bootstrap_mailbox = None;
    harness::run(device, move |master| async move {
        walk_to_with(&master, AlState::PreOp, &mailbox).await;
        script(master).await
    })
}

/// A short SDO Information request is still a new request: it ends a fragmented OD list in
/// progress, as any other would.
#[test]
fn a_short_sdo_information_request_ends_a_fragmented_list() {
    in_preop_with_mailbox(16, async |master| {
        let mut c = SdoClient::new(&master, (0x1000, 16), (0x1010, 16));
        let all = [0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00];
        let first = c.exchange(MailboxType::Coe, &all).await.unwrap();
        assert_eq!(first[8], 0x82, "an OD list response, more fragments follow");
        // The request is served before the next fragment: the mailbox error, and the list ends.
        let short = c.exchange(MailboxType::Coe, &[0x00, 0x80, 0x01]).await;
        assert_eq!(
            short.unwrap()[..10],
            [0x04, 0x00, 0x00, 0x00, 0x00, 0x20, 0x01, 0x00, 0x08, 0x00]
        );
        assert_eq!(c.read().await, None, "no fragment after the error");
    });
}

#[test]
fn unknown_coe_service_is_answered_with_an_sdo_abort() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        let answer = c
            .exchange(MailboxType::Coe, &[0x00, 0x90, 0, 0, 0, 0, 0, 0, 0, 0])
            .await
            .unwrap();
        assert_eq!(
            answer[..16],
            [
                0x0A, 0, 0, 0, 0, 0x13, 0x00, 0x20, 0x80, 0, 0, 0, 0x00, 0x00, 0x01, 0x06
            ]
        );
    });
}

/// In INIT the SubDevice keeps SM0 and SM1 deactivated over its PDI (0x0807 + 8n bit 0), which
/// closes their areas to the MainDevice (ESC datasheet section I, "SyncManager deactivation by
/// the PDI"): the request is not taken, the read of SM1 not served, neither counted.
#[test]
fn nothing_is_served_in_init() {
    run(async |master| {
        walk_to(&master, AlState::Init).await;
        master.configure_mailbox(&MAILBOX);
        master.settle().await;
        let before = master.pdi_accesses();
        let (header, payload) = upload_1001(1);
        let mut request: Vec<u8> = header.iter().chain(&payload).copied().collect();
        request.resize(usize::from(MAILBOX.receive.length), 0);
        assert!(
            !master.write(MAILBOX.receive.start, &request),
            "SM0 closed in INIT: the request is not counted"
        );
        master.settle().await;
        assert_eq!(
            master.read(MAILBOX.send.start, usize::from(MAILBOX.send.length)),
            None,
            "SM1 closed in INIT: no answer, not counted"
        );
        assert_eq!(
            master.pdi_accesses(),
            before,
            "the SubDevice did not even look"
        );
    });
}

#[test]
fn a_1024_byte_mailbox_carries_long_answers_in_one_message() {
    in_preop_with_mailbox(1024, async |master| {
        let mut c = SdoClient::new(&master, (0x1000, 1024), (0x1400, 1024));
        let text = vec![b'k'; 300];
        c.download(0x2000, 0, false, &text).await.unwrap();
        assert_eq!(c.round_trips, 1, "300 bytes fit one 1024-byte message");
        let answer = c.sdo(&[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]).await.unwrap();
        assert_eq!(answer[..8], [0x41, 0x00, 0x20, 0x00, 0x2C, 0x01, 0, 0]);
        assert_eq!(answer[8..308], text[..]);
        let length = c.read().await;
        assert_eq!(length, None);
        assert_eq!(
            c.sdo(&[0x40, 0x00, 0x30, 0x00, 0, 0, 0, 0]).await,
            Err(SdoError::Abort(AbortCode::NO_OBJECT))
        );
    });
}

fn emergency(code: u16) -> Emergency {
    Emergency {
        code,
        register: 0x81,
        data: [1, 2, 3, 4, 5],
    }
}

fn emergency_frame(counter: u8, code: u16) -> Vec<u8> {
    let [c0, c1] = code.to_le_bytes();
    let mut frame = vec![
        0x0A,
        0x00,
        0x00,
        0x00,
        0x00,
        (counter << 4) | 0x03,
        0x00,
        0x10,
        c0,
        c1,
        0x81,
        1,
        2,
        3,
        4,
        5,
    ];
    frame.resize(128, 0);
    frame
}

#[test]
fn emergencies_are_sent_in_order_when_sm1_is_free() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        for code in [0xA000, 0x8110, 0xFF01] {
            master.raise_emergency(emergency(code));
        }
        assert_eq!(c.read().await, Some(emergency_frame(1, 0xA000)));
        assert_eq!(c.read().await, Some(emergency_frame(2, 0x8110)));
        assert_eq!(c.read().await, Some(emergency_frame(3, 0xFF01)));
        assert_eq!(c.read().await, None);
    });
}

#[test]
fn emergencies_wait_behind_an_unread_answer() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.write_raw(&upload_1001(1).0, &upload_1001(1).1).await;
        master.raise_emergency(emergency(0x5000));
        master.settle().await;
        let answer = c.read().await.unwrap();
        assert_eq!(answer[6..8], [0x00, 0x30], "the SDO answer first");
        assert_eq!(
            c.read().await,
            Some(emergency_frame(2, 0x5000)),
            "then the emergency"
        );
    });
}

/// While the MainDevice leaves SM1 unread, 4 emergencies wait in the mailbox
/// (`EMERGENCY_QUEUE`); beyond that the oldest is dropped.
#[test]
fn four_emergencies_wait_behind_an_unread_one_and_the_oldest_are_dropped() {
    run(async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        master.raise_emergency(emergency(0x1000));
        master.settle().await;
        for code in 0x2001..=0x2006 {
            master.raise_emergency(emergency(code));
            master.settle().await;
        }
        assert_eq!(c.read().await, Some(emergency_frame(1, 0x1000)));
        for (counter, code) in (2..).zip(0x2003..=0x2006) {
            assert_eq!(c.read().await, Some(emergency_frame(counter, code)));
        }
        assert_eq!(c.read().await, None, "0x2001 and 0x2002 dropped");
    });
}

/// The firmware may raise emergencies faster than the state-machine runner takes them: 4 wait
/// for it (`Status::raise_emergency`); beyond that the oldest is dropped and counted, and
/// `Status::emergencies_dropped` says how many, so no emergency is lost silently.
#[test]
fn emergencies_raised_between_two_turns_beyond_four_are_dropped_and_counted() {
    let status = std::rc::Rc::new(std::cell::Cell::new(None));
    let keep = status.clone();
    let device = Device::new(common::drive(), BlobApp::default(), Loopback)
        .with_dictionary(TestOd::default());
    harness::run_with_tasks(
        device,
        move |s| {
            keep.set(Some(s));
            Vec::new()
        },
        async move |master| {
            walk_to(&master, AlState::PreOp).await;
            let status = status.get().expect("the harness hands over the status");
            assert_eq!(status.emergencies_dropped(), 0);
            let mut c = client(&master);
            // No turn of the runner in between: the application's queue holds the last 4.
            for code in 0x2001..=0x2006 {
                master.raise_emergency(emergency(code));
            }
            assert_eq!(status.emergencies_dropped(), 2);
            for (counter, code) in (1..).zip(0x2003..=0x2006) {
                assert_eq!(c.read().await, Some(emergency_frame(counter, code)));
            }
            assert_eq!(c.read().await, None, "0x2001 and 0x2002 dropped");
            assert_eq!(status.emergencies_dropped(), 2, "counted once");
        },
    );
}

#[test]
fn emergencies_need_a_mailbox_state() {
    run(async |master| {
        walk_to(&master, AlState::Init).await;
        master.raise_emergency(emergency(0x1000));
        master.settle().await;
        common::configure(&master);
        assert_eq!(master.request(0x02).await, (0x02, 0));
        assert_eq!(
            client(&master).read().await,
            None,
            "an emergency raised in INIT is not sent later"
        );
    });
}

/// An emergency raised while a transition waits for the application is queued, not spun on: the
/// runner keeps waiting (the emulator's livelock detector would fail the test otherwise) and the
/// emergency goes out once the transition is over.
#[test]
fn an_emergency_during_a_pending_transition_waits_its_turn() {
    use ecat_core::{AlStatusCode, Transition};
    use ecat_embassy::Application;
    use embassy_time::{Duration, Timer};

    #[derive(Clone, Default)]
    struct Slow;
    impl Application<TestOd> for Slow {
        fn on_transition(
            &mut self,
            t: Transition,
        ) -> impl Future<Output = Result<(), AlStatusCode>> + use<> {
            async move {
                if t.to == AlState::SafeOp {
                    Timer::after(Duration::from_millis(50)).await;
                }
                Ok(())
            }
        }
    }

    let device = Device::new(common::drive(), Slow, Loopback).with_dictionary(TestOd::default());
    harness::run(device, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        assert_eq!(master.request(0x04).await, (0x02, 0), "pending");
        master.raise_emergency(emergency(0x1234));
        master.settle().await;
        master.advance(Duration::from_millis(50)).await;
        assert_eq!((master.al_status(), master.al_status_code()), (0x04, 0));
        assert_eq!(
            client(&master).read().await,
            Some(emergency_frame(1, 0x1234))
        );
    });
}

/// An emergency raised by the application's SDO write hook (`Application::take_emergency`) is
/// sent right after the answer to the write: the sample drive reports the CiA 301 error code
/// written to 0x2001 with error register 0x01.
#[test]
fn an_emergency_raised_by_a_write_hook_follows_the_answer() {
    harness::run(ecat_emu::devices::drive().device, async |master| {
        walk_to(&master, AlState::PreOp).await;
        let mut c = client(&master);
        c.download(0x2001, 0, false, &0x5000u16.to_le_bytes())
            .await
            .unwrap();
        let mut expected = vec![
            0x0A, 0x00, 0x00, 0x00, 0x00, 0x23, 0x00, 0x10, 0x00, 0x50, 0x01, 0, 0, 0, 0, 0,
        ];
        expected.resize(128, 0);
        assert_eq!(c.read().await, Some(expected));
        assert_eq!(c.read().await, None, "one emergency per write");
        // Writing 0 raises none.
        c.download(0x2001, 0, false, &[0, 0]).await.unwrap();
        assert_eq!(c.read().await, None);
    });
}
