//! The EtherCAT state machine against the emulated ESC, through the real runners: every
//! (current state, AL control bits 4:0) pair, with and without a latched error, asserting the
//! exact AL status (0x0130) and AL status code (0x0134) the MainDevice reads afterwards.
//!
//! The expected values come from an oracle written from the ETG.1000.6 transition table
//! (conformance.md §3 "ESM"), independent of `ecat_core::esm`.

mod common;

use common::walk_to;
use ecat_core::AlState;
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};

/// The transitions ETG.1000.6 allows; every other change between known states is 0x0011.
fn allowed(from: AlState, to: AlState) -> bool {
    use AlState::*;
    matches!(
        (from, to),
        (Init, PreOp)
            | (Init, Boot)
            | (PreOp, SafeOp)
            | (SafeOp, Op)
            | (PreOp, Init)
            | (SafeOp, Init)
            | (SafeOp, PreOp)
            | (Op, Init)
            | (Op, PreOp)
            | (Op, SafeOp)
            | (Boot, Init)
    )
}

/// (AL status, AL status code) after writing `control` to a SubDevice in `from` whose error
/// indication carries `latched` (a code) or is clear.
fn expected(from: AlState, control: u16, latched: Option<u16>) -> (u16, u16) {
    let requested = control & 0x0F;
    let acknowledge = control & 0x10 != 0;
    let stay = u16::from(from.bits());
    if let Some(code) = latched
        && !acknowledge
        && requested != 0x01
    {
        return (stay | 0x10, code);
    }
    match AlState::from_bits(requested as u8) {
        None => (stay | 0x10, 0x0012),
        Some(to) if to == from => (stay, 0),
        Some(to) if allowed(from, to) => (u16::from(to.bits()), 0),
        Some(_) => (stay | 0x10, 0x0011),
    }
}

fn table(from: AlState, latched: bool) {
    let device = Device::new(common::drive(), AcceptAll, Loopback);
    harness::run(device, move |master| async move {
        for control in 0u16..0x20 {
            walk_to(&master, from).await;
            let latched_code = if latched {
                // 0x0F names no state: the SubDevice latches 0x0012 and stays.
                let stay = u16::from(from.bits());
                assert_eq!(master.request(0x0F).await, (stay | 0x10, 0x0012));
                Some(0x0012)
            } else {
                None
            };
            let got = master.request(control).await;
            let want = expected(from, control, latched_code);
            assert_eq!(
                got, want,
                "{from} (error latched: {latched}) + AL control {control:#04x}"
            );
        }
    });
}

macro_rules! tables {
    ($($name:ident: $state:ident, $latched:expr;)*) => {$(
        #[test]
        fn $name() {
            table(AlState::$state, $latched);
        }
    )*};
}

tables! {
    init_table: Init, false;
    preop_table: PreOp, false;
    boot_table: Boot, false;
    safeop_table: SafeOp, false;
    op_table: Op, false;
    init_table_error_latched: Init, true;
    preop_table_error_latched: PreOp, true;
    boot_table_error_latched: Boot, true;
    safeop_table_error_latched: SafeOp, true;
    op_table_error_latched: Op, true;
}

#[test]
fn boot_request_without_boot_support_is_0x0013() {
    let device = Device::new(common::drive_without_boot(), AcceptAll, Loopback);
    harness::run(device, |master| async move {
        walk_to(&master, AlState::Init).await;
        assert_eq!(master.request(0x03).await, (0x11, 0x0013));
        assert_eq!(
            master.request(0x13).await,
            (0x11, 0x0013),
            "acknowledged and refused again"
        );
        assert_eq!(master.request(0x11).await, (0x01, 0));
    });
}

#[test]
fn acknowledge_clears_the_error_and_its_code() {
    let device = Device::new(common::drive(), AcceptAll, Loopback);
    harness::run(device, |master| async move {
        walk_to(&master, AlState::SafeOp).await;
        assert_eq!(
            master.request(0x08 | 0x01).await,
            (0x14, 0x0012),
            "0x09 names no state"
        );
        assert_eq!(
            master.request(0x08).await,
            (0x14, 0x0012),
            "OP ignored while the error is latched"
        );
        assert_eq!(
            master.request(0x04).await,
            (0x14, 0x0012),
            "same state without acknowledge ignored"
        );
        assert_eq!(
            master.request(0x02).await,
            (0x14, 0x0012),
            "lower state without acknowledge ignored"
        );
        assert_eq!(master.request(0x14).await, (0x04, 0), "acknowledged");
        assert_eq!(master.request(0x08).await, (0x08, 0));
    });
}

#[test]
fn init_request_is_accepted_while_the_error_is_latched() {
    let device = Device::new(common::drive(), AcceptAll, Loopback);
    harness::run(device, |master| async move {
        walk_to(&master, AlState::Op).await;
        assert_eq!(master.request(0x05).await, (0x18, 0x0012));
        assert_eq!(
            master.request(0x01).await,
            (0x01, 0),
            "INIT without acknowledge"
        );
    });
}

#[test]
fn device_id_request_presents_the_id_instead_of_a_code() {
    let mut device = Device::new(common::drive(), AcceptAll, Loopback);
    device.device_id = 0x1234;
    harness::run(device, |master| async move {
        walk_to(&master, AlState::Init).await;
        assert_eq!(
            master.request(0x21).await,
            (0x21, 0x1234),
            "INIT with ID request"
        );
        assert_eq!(
            master.request(0x22).await,
            (0x22, 0x1234),
            "PREOP with ID request"
        );
        assert_eq!(master.request(0x02).await, (0x02, 0), "request withdrawn");
        assert_eq!(
            master.request(0x2F).await,
            (0x12, 0x0012),
            "an error wins over the ID"
        );
        assert_eq!(
            master.request(0x32).await,
            (0x22, 0x1234),
            "acknowledged with ID request"
        );
    });
}
