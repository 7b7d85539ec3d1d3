//! SyncManager checks (conformance.md §3 "Sync managers"): the exact code and resulting state for
//! every way a MainDevice can get SM0..SM3 wrong, at the transition and on an SM-change event.

mod common;

use common::{INPUTS, MAILBOX, OUTPUTS, configure, walk_to};
use ecat_core::AlState;
use ecat_core::device::{Area, ProcessDataSizes};
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::master::{SM0_CONTROL, SM1_CONTROL, SM2_CONTROL, SM3_CONTROL, TestMaster};

fn run(config: ecat_core::DeviceConfig, script: impl AsyncFnOnce(TestMaster) + 'static) {
    harness::run(
        Device::new(config, AcceptAll, Loopback),
        |master| async move { script(master).await },
    )
}

/// Each bad SM0/SM1 setting is refused at INIT→PREOP with 0x0016, staying in INIT.
#[test]
fn bad_mailbox_settings_are_refused_with_0x0016() {
    let (rx, tx) = (MAILBOX.receive, MAILBOX.send);
    let cases: [(&str, u8, u16, u16, u8, bool); 12] = [
        ("SM0 disabled", 0, rx.start, rx.length, SM0_CONTROL, false),
        (
            "SM0 without the PDI event",
            0,
            rx.start,
            rx.length,
            0x06,
            true,
        ),
        (
            "SM1 without the PDI event",
            1,
            tx.start,
            tx.length,
            0x02,
            true,
        ),
        ("SM0 start", 0, rx.start + 2, rx.length, SM0_CONTROL, true),
        ("SM0 length", 0, rx.start, rx.length - 1, SM0_CONTROL, true),
        ("SM0 length 0", 0, rx.start, 0, SM0_CONTROL, true),
        ("SM0 direction read", 0, rx.start, rx.length, 0x22, true),
        ("SM0 3-buffer mode", 0, rx.start, rx.length, 0x24, true),
        ("SM0 reserved mode", 0, rx.start, rx.length, 0x27, true),
        ("SM1 disabled", 1, tx.start, tx.length, SM1_CONTROL, false),
        ("SM1 direction write", 1, tx.start, tx.length, 0x26, true),
        (
            "SM1 odd length",
            1,
            tx.start,
            tx.length + 1,
            SM1_CONTROL,
            true,
        ),
    ];
    run(common::drive(), async move |master| {
        for (what, n, start, length, control, enable) in cases {
            walk_to(&master, AlState::Init).await;
            master.configure_mailbox(&MAILBOX);
            master.configure_sm(n, start, length, control, enable);
            assert_eq!(master.request(0x02).await, (0x11, 0x0016), "{what}");
        }
        walk_to(&master, AlState::Init).await;
        master.configure_mailbox(&MAILBOX);
        master.configure_sm(0, rx.start, rx.length, SM0_CONTROL | 0x10, true);
        assert_eq!(
            master.request(0x02).await,
            (0x02, 0),
            "the ECAT event bit is the MainDevice's choice"
        );
    });
}

/// A bad bootstrap mailbox is 0x0015.
#[test]
fn bad_bootstrap_mailbox_is_0x0015() {
    run(common::drive(), async move |master| {
        walk_to(&master, AlState::Init).await;
        master.configure_sm(
            1,
            MAILBOX.send.start,
            MAILBOX.send.length,
            SM1_CONTROL,
            false,
        );
        assert_eq!(master.request(0x03).await, (0x11, 0x0015));
    });
}

/// Each bad SM2/SM3 setting is refused at PREOP→SAFEOP, staying in PREOP.
#[test]
fn bad_process_data_settings_are_refused_with_0x001d_or_0x001e() {
    let cases: [(&str, u8, u16, u16, u8, bool, u16); 12] = [
        (
            "SM2 length 11 for 12 bytes",
            2,
            OUTPUTS.start,
            11,
            SM2_CONTROL,
            true,
            0x001D,
        ),
        (
            "SM2 length 13",
            2,
            OUTPUTS.start,
            13,
            SM2_CONTROL,
            true,
            0x001D,
        ),
        (
            "SM2 disabled with outputs",
            2,
            OUTPUTS.start,
            OUTPUTS.length,
            SM2_CONTROL,
            false,
            0x001D,
        ),
        (
            "SM2 enabled with length 0",
            2,
            OUTPUTS.start,
            0,
            SM2_CONTROL,
            true,
            0x001D,
        ),
        (
            "SM2 direction read",
            2,
            OUTPUTS.start,
            OUTPUTS.length,
            0x60,
            true,
            0x001D,
        ),
        (
            "SM2 reserved mode",
            2,
            OUTPUTS.start,
            OUTPUTS.length,
            0x65,
            true,
            0x001D,
        ),
        (
            "SM2 over the send mailbox",
            2,
            MAILBOX.send.start + 4,
            OUTPUTS.length,
            SM2_CONTROL,
            true,
            0x001D,
        ),
        (
            "SM2 below process RAM",
            2,
            0x0F00,
            OUTPUTS.length,
            SM2_CONTROL,
            true,
            0x001D,
        ),
        (
            "SM2 past the end of RAM",
            2,
            0x2FF8,
            OUTPUTS.length,
            SM2_CONTROL,
            true,
            0x001D,
        ),
        (
            "SM3 length 12 for 11 bytes",
            3,
            INPUTS.start,
            12,
            SM3_CONTROL,
            true,
            0x001E,
        ),
        (
            "SM3 direction write",
            3,
            INPUTS.start,
            INPUTS.length,
            0x24,
            true,
            0x001E,
        ),
        // SM2 occupies 3 × 12 bytes from 0x1100 in 3-buffer mode: 0x1100..0x1124.
        (
            "SM3 inside SM2's third buffer",
            3,
            OUTPUTS.start + 30,
            INPUTS.length,
            SM3_CONTROL,
            true,
            0x001E,
        ),
    ];
    run(common::drive(), async move |master| {
        for (what, n, start, length, control, enable, code) in cases {
            walk_to(&master, AlState::PreOp).await;
            master.configure_sm(n, start, length, control, enable);
            assert_eq!(master.request(0x04).await, (0x12, code), "{what}");
        }
        walk_to(&master, AlState::PreOp).await;
        master.configure_sm(2, OUTPUTS.start, OUTPUTS.length, 0x66, true);
        assert_eq!(
            master.request(0x04).await,
            (0x04, 0),
            "1-buffer mode for process data is allowed"
        );
    });
}

/// A direction without data accepts its SyncManager disabled with length 0, and nothing else.
#[test]
fn input_only_device_needs_sm2_disabled() {
    let mut config = common::drive();
    config.process_data = ProcessDataSizes {
        outputs: 0,
        inputs: 11,
    };
    run(config, async move |master| {
        walk_to(&master, AlState::PreOp).await;
        master.configure_process_data(None, Some(INPUTS));
        assert_eq!(
            master.request(0x04).await,
            (0x04, 0),
            "SM2 disabled, length 0"
        );
        assert_eq!(master.request(0x08).await, (0x08, 0));
        for (what, length) in [("enabled, length 0", 0), ("enabled, length 12", 12)] {
            walk_to(&master, AlState::PreOp).await;
            master.configure_process_data(None, Some(INPUTS));
            master.configure_sm(2, OUTPUTS.start, length, SM2_CONTROL, true);
            assert_eq!(master.request(0x04).await, (0x12, 0x001D), "SM2 {what}");
        }
    });
}

#[test]
fn output_only_device_needs_sm3_disabled() {
    let mut config = common::drive();
    config.process_data = ProcessDataSizes {
        outputs: 12,
        inputs: 0,
    };
    run(config, async move |master| {
        walk_to(&master, AlState::PreOp).await;
        master.configure_process_data(Some(OUTPUTS), None);
        assert_eq!(master.request(0x04).await, (0x04, 0));
        walk_to(&master, AlState::PreOp).await;
        master.configure_process_data(Some(OUTPUTS), Some(Area::new(INPUTS.start, 0)));
        master.configure_sm(3, INPUTS.start, 0, SM3_CONTROL, true);
        assert_eq!(
            master.request(0x04).await,
            (0x12, 0x001E),
            "SM3 enabled with length 0"
        );
    });
}

/// An SM-change event re-checks what the current state relies on.
#[test]
fn sm_change_in_preop_safeop_op_falls_back_with_the_right_code() {
    run(common::drive(), async move |master| {
        walk_to(&master, AlState::PreOp).await;
        master.configure_sm(
            0,
            MAILBOX.receive.start,
            MAILBOX.receive.length,
            SM0_CONTROL,
            false,
        );
        master.settle().await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x11, 0x0016),
            "SM0 disabled in PREOP"
        );

        walk_to(&master, AlState::SafeOp).await;
        master.configure_sm(2, OUTPUTS.start, OUTPUTS.length, SM2_CONTROL, false);
        master.settle().await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x12, 0x001D),
            "SM2 disabled in SAFEOP"
        );

        walk_to(&master, AlState::Op).await;
        master.configure_sm(3, INPUTS.start, INPUTS.length, SM3_CONTROL, false);
        master.settle().await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x12, 0x001E),
            "SM3 disabled in OP"
        );

        walk_to(&master, AlState::Op).await;
        master.configure_sm(
            1,
            MAILBOX.send.start,
            MAILBOX.send.length,
            SM1_CONTROL,
            false,
        );
        master.settle().await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x11, 0x0016),
            "SM1 disabled in OP"
        );

        walk_to(&master, AlState::Init).await;
        master.configure_sm(0, 0x1234, 3, 0x00, false);
        master.settle().await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x01, 0),
            "INIT ignores SyncManagers"
        );
        configure(&master);
        assert_eq!(master.request(0x02).await, (0x02, 0));
    });
}

/// An SM-change event of a channel the SubDevice does not use (SM4..SM7 of the 8 an ET1100 has)
/// is cleared too: the ESC clears AL event bit 4 only once every changed channel's activation
/// register was read, so the SubDevice reads them all, four channels at a time (SM4..SM7 in one
/// read, SM0..SM3 in another), and stays where it is.
#[test]
fn sm_change_of_a_channel_beyond_sm3_is_cleared() {
    run(common::drive(), async move |master| {
        walk_to(&master, AlState::PreOp).await;
        for n in 4..8 {
            let before = master.pdi_accesses();
            assert!(master.write(ecat_core::register::sync_manager(n) + 6, &[0]));
            master.settle().await;
            let event = master.emulator().with(|esc| esc.al_event());
            assert!(
                !event.contains(ecat_core::AlEvent::SM_CHANGE),
                "SM{n}'s change still pending: {event:?}"
            );
            assert_eq!(
                master.pdi_accesses() - before,
                3,
                "SM{n}: the AL event, SM4..SM7, SM0..SM3"
            );
            assert_eq!((master.al_status(), master.al_status_code()), (0x02, 0));
        }
    });
}

/// SM2's watchdog trigger bit and the process-data watchdog time must agree (0x001F).
#[test]
fn inconsistent_watchdog_configuration_is_0x001f() {
    run(common::drive(), async move |master| {
        let time = ecat_core::register::WATCHDOG_TIME_PROCESS_DATA;
        walk_to(&master, AlState::PreOp).await;
        master.write(time, &0u16.to_le_bytes());
        assert_eq!(
            master.request(0x04).await,
            (0x12, 0x001F),
            "trigger set, time 0"
        );
        walk_to(&master, AlState::PreOp).await;
        master.write(time, &1000u16.to_le_bytes());
        master.configure_sm(2, OUTPUTS.start, OUTPUTS.length, SM2_CONTROL & !0x40, true);
        assert_eq!(
            master.request(0x04).await,
            (0x12, 0x001F),
            "time set, no trigger"
        );
        walk_to(&master, AlState::PreOp).await;
        master.write(time, &0u16.to_le_bytes());
        master.configure_sm(2, OUTPUTS.start, OUTPUTS.length, SM2_CONTROL & !0x40, true);
        assert_eq!(master.request(0x04).await, (0x04, 0), "no watchdog at all");
        master.write(time, &1000u16.to_le_bytes());
    });
}
