//! Fuzz target for the mailbox + CoE input path (stable toolchain, proptest): raw and
//! structured frames into SM0, in any order, against a dictionary with every entry kind. The
//! SubDevice never panics, does bounded work, and every answer is a well-formed mailbox message.

mod common;

use common::{DEVICE, Op, Regs, configure_all};
use ecat_core::dictionary::{Bits, Domain, VisibleString};
use ecat_core::mailbox::{MailboxHeader, MailboxType};
use ecat_core::{AlEvent, AlState, Instant, SubDevice, Transition};
use proptest::prelude::*;

struct Rec {
    a: u8,
    b: Bits<3>,
    c: bool,
    d: i64,
}

struct Od {
    u: u32,
    s: VisibleString<200>,
    blob: Domain,
    rec: Rec,
    arr: [u16; 5],
    wo: i16,
}

ecat_core::dictionary! {
    minimal Od {
        0x1000 => var(u, RO, "U", default = 7);
        0x2000 => var(s, RW, "S");
        0x2001 => var(blob, RW, "Blob");
        0x2002 => record(rec: Rec, "Rec") {
            1 => a, RW, "A", max = 200;
            2 => b, RW_PREOP, "B";
            5 => c, RW | TXPDO, "C";
            6 => d, RW, "D", min = -5, max = 5;
        };
        0x2003 => array(arr, RW | RXPDO, "Arr", "Element", default = 3, min = 1, max = 9);
        0x2004 => var(wo, WO, "Wo");
    }
}

const SM0: usize = 0x1000;
const SM1: u16 = 0x1080;

fn frame() -> impl Strategy<Value = Vec<u8>> {
    let index = prop_oneof![
        Just(0x1000u16),
        Just(0x2000),
        Just(0x2001),
        Just(0x2002),
        Just(0x2003),
        Just(0x2004),
        any::<u16>()
    ];
    let structured = (
        any::<u8>(),
        index,
        0u8..8,
        any::<[u8; 4]>(),
        proptest::collection::vec(any::<u8>(), 0..120),
        0u8..16,
        0u8..8,
        any::<u8>(),
        // Header byte 4: channel 0 and priority 0 mostly, else any (channel ≠ 0 is 0x0003).
        prop_oneof![7 => Just(0u8), 1 => any::<u8>()],
    )
        .prop_map(
            |(command, index, sub, data, tail, service, counter, kind, channel)| {
                let [i0, i1] = index.to_le_bytes();
                let mut payload = vec![0x00, service << 4, command, i0, i1, sub];
                payload.extend_from_slice(&data);
                payload.extend_from_slice(&tail);
                let kind = if kind < 200 { 3 } else { kind & 0x0F };
                let mut f =
                    MailboxHeader::new(MailboxType::from_code(kind), payload.len() as u16, counter)
                        .to_bytes()
                        .to_vec();
                f[4] = channel;
                f.extend_from_slice(&payload);
                f
            },
        );
    prop_oneof![3 => structured, 1 => proptest::collection::vec(any::<u8>(), 0..128)]
}

/// Checks one answer in SM1.
fn check_answer(bytes: &[u8]) -> Result<(), TestCaseError> {
    let header = MailboxHeader::parse(bytes).unwrap();
    prop_assert!(
        usize::from(header.length) <= 128 - 6,
        "length {} beyond SM1",
        header.length
    );
    prop_assert!(
        (1..=7).contains(&header.counter),
        "counter {}",
        header.counter
    );
    let body = &bytes[6..6 + usize::from(header.length)];
    match header.kind {
        MailboxType::Error => {
            prop_assert_eq!(header.length, 4);
            prop_assert_eq!(&body[..2], &[0x01, 0x00]);
            prop_assert!(
                (1..=8).contains(&body[2]) && body[3] == 0,
                "detail {:02x?}",
                &body[2..]
            );
        }
        MailboxType::Coe => {
            prop_assert!(body.len() >= 2);
            let service = body[1] >> 4;
            prop_assert!([1, 2, 3, 8].contains(&service), "service {service}");
            if service == 2 {
                prop_assert_eq!(body.len(), 10, "an abort is 8 bytes of SDO");
                prop_assert_eq!(body[2], 0x80);
            }
        }
        other => prop_assert!(false, "answer of type {other:?}"),
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1_000, ..ProptestConfig::default() })]

    #[test]
    fn any_frame_sequence_gets_well_formed_answers(frames in proptest::collection::vec((frame(), 0u64..3_000_000), 1..24)) {
        let mut regs = Regs::new();
        let mut sub: SubDevice<'_, 128> = SubDevice::new::<Od>(&DEVICE);
        let mut od = Od::default();
        let mut now = Instant::from_micros(0);
        regs.drive(&mut sub, now);
        configure_all(&mut regs);
        regs.al_control(2);
        sub.handle_al_event(AlEvent(regs.event));
        regs.drive(&mut sub, now);
        sub.complete_transition(Transition { from: AlState::Init, to: AlState::PreOp }, Ok(()));
        regs.drive(&mut sub, now);
        prop_assert_eq!(sub.state(), AlState::PreOp);

        for (bytes, wait) in frames {
            now = Instant::from_micros(now.as_micros() + wait);
            sub.handle_timeout(now);
            let mut sm0 = vec![0u8; 128];
            let n = bytes.len().min(128);
            sm0[..n].copy_from_slice(&bytes[..n]);
            regs.mem[SM0..SM0 + 128].copy_from_slice(&sm0);
            regs.mem[usize::from(SM1)..usize::from(SM1) + 128].fill(0);
            sub.handle_al_event(AlEvent::sync_manager(0));
            let mut log = regs.drive(&mut sub, now);
            for _ in 0..4 {
                if !sub.service_mailbox(now, &mut od, &mut ()) {
                    break;
                }
                log.extend(regs.drive(&mut sub, now));
            }
            log.extend(regs.drive(&mut sub, now));
            let wrote_sm1 = log.iter().any(|op| matches!(op, Op::Write(a, _) if *a == SM1));
            if wrote_sm1 {
                check_answer(&regs.mem[usize::from(SM1)..usize::from(SM1) + 128])?;
                // The MainDevice reads the answer: SM1 free again.
                sub.handle_al_event(AlEvent::sync_manager(1));
                regs.drive(&mut sub, now);
            }
            prop_assert_eq!(sub.state(), AlState::PreOp, "mailbox traffic never changes the state");
        }
    }
}
