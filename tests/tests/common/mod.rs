//! The devices and MainDevice walks the integration tests share.
#![allow(dead_code)]

pub mod od;

use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_core::{AlState, DeviceConfig};
use ecat_emu::master::TestMaster;

pub const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
pub const OUTPUTS: Area = Area::new(0x1100, 12);
pub const INPUTS: Area = Area::new(0x1180, 11);

/// An SDO client for the devices above (mailbox at [`MAILBOX`]).
pub fn client(master: &TestMaster) -> ecat_emu::coe_client::SdoClient<'_> {
    ecat_emu::coe_client::SdoClient::for_mailbox(master, &MAILBOX)
}

/// A drive-like device: 128-byte mailboxes, 12 bytes of outputs, 11 bytes of inputs, BOOT
/// supported with the same mailbox layout.
pub fn drive() -> DeviceConfig {
    let mut config = DeviceConfig::new(
        MAILBOX,
        ProcessDataSizes {
            outputs: 12,
            inputs: 11,
        },
    );
    config.bootstrap_mailbox = Some(MAILBOX);
    config
}

/// The same device without BOOT support.
pub fn drive_without_boot() -> DeviceConfig {
    DeviceConfig::new(
        MAILBOX,
        ProcessDataSizes {
            outputs: 12,
            inputs: 11,
        },
    )
}

/// Configures every SyncManager as a MainDevice does for [`drive`].
pub fn configure(master: &TestMaster) {
    master.configure_mailbox(&MAILBOX);
    master.configure_process_data(Some(OUTPUTS), Some(INPUTS));
}

/// Resets the SubDevice and walks it up to `state`, asserting each step.
pub async fn walk_to(master: &TestMaster, state: AlState) {
    walk_to_with(master, state, &MAILBOX).await;
}

/// [`walk_to`] with the mailboxes at `mailbox`.
pub async fn walk_to_with(master: &TestMaster, state: AlState, mailbox: &MailboxConfig) {
    master.reset().await;
    assert_eq!(master.request(0x0001).await, (0x0001, 0), "reset to INIT");
    configure(master);
    master.configure_mailbox(mailbox);
    master.settle().await;
    let path: &[u16] = match state {
        AlState::Init => &[],
        AlState::PreOp => &[0x02],
        AlState::Boot => &[0x03],
        AlState::SafeOp => &[0x02, 0x04],
        AlState::Op => &[0x02, 0x04, 0x08],
    };
    for &step in path {
        assert_eq!(master.request(step).await, (step, 0), "walking to {state}");
        if step == 0x04 {
            // As MainDevices do: cyclic frames with valid outputs from SAFEOP on.
            send_outputs(master).await;
        }
    }
}

/// Writes one output image into SM2 (zeros), as a MainDevice's cyclic frame does.
pub async fn send_outputs(master: &TestMaster) {
    master.write(OUTPUTS.start, &vec![0; usize::from(OUTPUTS.length)]);
    master.settle().await;
}
