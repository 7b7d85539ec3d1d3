//! FoE (ETG.1000.6 §5.9) end to end: the test MainDevice's FoE client through the emulated ESC
//! to the real runners, the application's FoE handler given by `Application::mailbox`. In BOOT
//! with the bootstrap mailbox (256 bytes at 0x1800: segments of 244 bytes), the bytes the
//! device's files received checked exactly.

mod common;

use std::cell::RefCell;
use std::rc::Rc;

use common::walk_to_with;
use ecat_core::device::MailboxConfig;
use ecat_core::dictionary::ObjectHooks;
use ecat_core::foe::{Files, Foe, FoeError, Progress};
use ecat_core::mailbox::Handlers;
use ecat_core::{AlState, DeviceConfig};
use ecat_embassy::Application;
use ecat_emu::foe_client::{FoeClient, FoeFailure, opcode};
use ecat_emu::harness::{self, Device, Loopback};
use ecat_emu::master::TestMaster;

const BOOT_MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1800, 256);
const SEGMENT: usize = 256 - 12;
const PASSWORD: u32 = 0xC0DE_0016;

/// What the device's files hold and were told, shared with the test.
#[derive(Debug, Default)]
struct Store {
    /// The file as written, segment by segment.
    written: Vec<u8>,
    /// Finished writes: their lengths.
    finished: Vec<u32>,
    /// Transfers aborted.
    aborts: usize,
    /// Answer the next segment with busy.
    busy_once: bool,
}

/// One file, `app.bin`, writable with [`PASSWORD`] and readable back; FoE in BOOT only.
#[derive(Clone, Default)]
struct TestFiles(Rc<RefCell<Store>>);

impl Files for TestFiles {
    fn open_write(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        match (name, password) {
            (b"app.bin", PASSWORD) => {
                self.0.borrow_mut().written.clear();
                Ok(())
            }
            (b"app.bin", _) => Err(FoeError::NO_RIGHTS),
            _ => Err(FoeError::NOT_FOUND),
        }
    }

    fn write(&mut self, offset: u32, data: &[u8]) -> Result<Progress, FoeError> {
        let mut store = self.0.borrow_mut();
        if std::mem::take(&mut store.busy_once) {
            return Ok(Progress::Busy { done: 1, entire: 4 });
        }
        assert_eq!(offset as usize, store.written.len(), "in order, once");
        store.written.extend_from_slice(data);
        Ok(Progress::Written)
    }

    fn finish_write(&mut self, length: u32) -> Result<(), FoeError> {
        self.0.borrow_mut().finished.push(length);
        Ok(())
    }

    fn open_read(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        match (name, password) {
            (b"app.bin", PASSWORD) => Ok(()),
            (b"app.bin", _) => Err(FoeError::NO_RIGHTS),
            _ => Err(FoeError::NOT_FOUND),
        }
    }

    fn read(&mut self, offset: u32, out: &mut [u8]) -> Result<usize, FoeError> {
        let store = self.0.borrow();
        let rest = store.written.get(offset as usize..).unwrap_or_default();
        let n = rest.len().min(out.len());
        out[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }

    fn abort(&mut self) {
        self.0.borrow_mut().aborts += 1;
    }
}

/// An application whose only addition is FoE.
struct FoeApp {
    foe: (Foe<TestFiles>,),
}

impl Application for FoeApp {
    fn mailbox(&mut self) -> (impl ObjectHooks<()> + '_, impl Handlers + '_) {
        ((), &mut self.foe)
    }
}

fn config() -> DeviceConfig {
    let mut config = common::drive();
    config.bootstrap_mailbox = Some(BOOT_MAILBOX);
    config
}

/// Runs `script` with the device in BOOT, its files' store and an FoE client on the bootstrap
/// mailbox.
fn in_boot(script: impl AsyncFnOnce(&TestMaster, FoeClient<'_>, Rc<RefCell<Store>>) + 'static) {
    let files = TestFiles::default();
    let store = files.0.clone();
    let app = FoeApp {
        foe: (Foe::new(files),),
    };
    harness::run(Device::new(config(), app, Loopback), |master| async move {
        walk_to_with(&master, AlState::Boot, &BOOT_MAILBOX).await;
        let client = FoeClient::for_mailbox(&master, &BOOT_MAILBOX);
        script(&master, client, store).await;
    });
}

/// `len` bytes that differ from segment to segment.
fn file(len: usize) -> Vec<u8> {
    (0..len).map(|i| (i * 7 + i / 251) as u8).collect()
}

#[test]
fn a_multi_segment_write_in_boot_then_read_back_then_init() {
    in_boot(async |master, mut foe, store| {
        assert_eq!(foe.segment, SEGMENT);
        let image = file(3 * SEGMENT + 100);
        foe.write("app.bin", PASSWORD, &image).await.unwrap();
        assert_eq!(store.borrow().written, image, "exactly the bytes sent");
        assert_eq!(store.borrow().finished, [image.len() as u32]);
        assert_eq!(foe.round_trips(), 1 + 4, "the request and 4 segments");
        assert_eq!(foe.read("app.bin", PASSWORD).await.unwrap(), image);
        // Leaving BOOT for INIT.
        assert_eq!(master.request(0x0001).await, (0x0001, 0));
        assert_eq!(store.borrow().aborts, 0, "nothing was in progress");
    });
}

#[test]
fn an_exact_multiple_ends_with_an_empty_segment_and_busy_is_sent_again() {
    in_boot(async |_, mut foe, store| {
        store.borrow_mut().busy_once = true;
        let image = file(2 * SEGMENT);
        foe.write("app.bin", PASSWORD, &image).await.unwrap();
        assert_eq!(foe.busy, 1);
        assert_eq!(store.borrow().written, image);
        assert_eq!(store.borrow().finished, [2 * SEGMENT as u32]);
        assert_eq!(
            foe.round_trips(),
            1 + 1 + 3,
            "request, busy, 2 segments, the empty one"
        );
    });
}

#[test]
fn a_wrong_password_or_name_is_refused_and_nothing_written() {
    in_boot(async |_, mut foe, store| {
        assert_eq!(
            foe.write("app.bin", PASSWORD ^ 1, &file(300)).await,
            Err(FoeFailure::Error(0x800A)),
            "no rights"
        );
        assert_eq!(
            foe.write("boot.bin", PASSWORD, &file(300)).await,
            Err(FoeFailure::Error(0x8001)),
            "not found"
        );
        assert_eq!(foe.read("app.bin", 0).await, Err(FoeFailure::Error(0x800A)));
        // Data without an accepted request: illegal.
        assert_eq!(
            foe.frame(opcode::DATA, 1, &file(10))
                .await
                .unwrap()
                .map(|f| (f.opcode, f.value)),
            Some((opcode::ERROR, 0x8004))
        );
        assert!(store.borrow().written.is_empty());
        assert!(store.borrow().finished.is_empty());
    });
}

#[test]
fn a_lost_ack_is_recovered_by_the_mailbox_repeat() {
    in_boot(async |_, mut foe, store| {
        let image = file(2 * SEGMENT + 5);
        let ack = |n| Some((opcode::ACK, n));
        let sent = |f: Option<ecat_emu::foe_client::Frame>| f.map(|f| (f.opcode, f.value));
        assert_eq!(
            sent(
                foe.frame(opcode::WRITE, PASSWORD, b"app.bin")
                    .await
                    .unwrap()
            ),
            ack(0)
        );
        assert_eq!(
            sent(foe.frame(opcode::DATA, 1, &image[..SEGMENT]).await.unwrap()),
            ack(1)
        );
        // The acknowledge of packet 1 was lost: the repeat writes it again.
        let again = foe.repeat().await.unwrap();
        assert_eq!((again.opcode, again.value), (opcode::ACK, 1));
        // A MainDevice that sends packet 1 again instead gets it acknowledged, not written twice.
        assert_eq!(
            sent(foe.frame(opcode::DATA, 1, &image[..SEGMENT]).await.unwrap()),
            ack(1)
        );
        assert_eq!(
            sent(
                foe.frame(opcode::DATA, 2, &image[SEGMENT..2 * SEGMENT])
                    .await
                    .unwrap()
            ),
            ack(2)
        );
        assert_eq!(
            sent(
                foe.frame(opcode::DATA, 3, &image[2 * SEGMENT..])
                    .await
                    .unwrap()
            ),
            ack(3)
        );
        assert_eq!(store.borrow().written, image);
        assert_eq!(store.borrow().finished, [image.len() as u32]);
    });
}

#[test]
fn leaving_boot_drops_the_transfer_in_progress() {
    in_boot(async |master, mut foe, store| {
        let image = file(3 * SEGMENT);
        assert_eq!(
            foe.frame(opcode::WRITE, PASSWORD, b"app.bin")
                .await
                .unwrap()
                .map(|f| f.opcode),
            Some(opcode::ACK)
        );
        assert_eq!(
            foe.frame(opcode::DATA, 1, &image[..SEGMENT])
                .await
                .unwrap()
                .map(|f| f.value),
            Some(1)
        );
        assert_eq!(master.request(0x0001).await, (0x0001, 0), "BOOT to INIT");
        walk_to_with(master, AlState::Boot, &BOOT_MAILBOX).await;
        let mut foe = FoeClient::for_mailbox(master, &BOOT_MAILBOX);
        assert_eq!(
            foe.frame(opcode::DATA, 2, &image[SEGMENT..2 * SEGMENT])
                .await
                .unwrap()
                .map(|f| (f.opcode, f.value)),
            Some((opcode::ERROR, 0x8004)),
            "the transfer ended with BOOT"
        );
        assert_eq!(store.borrow().aborts, 1, "the files heard of it");
        assert_eq!(
            store.borrow().written,
            image[..SEGMENT],
            "nothing more written"
        );
        assert!(store.borrow().finished.is_empty());
    });
}

#[test]
fn foe_outside_boot_is_bootstrap_only() {
    let app = FoeApp {
        foe: (Foe::new(TestFiles::default()),),
    };
    harness::run(Device::new(config(), app, Loopback), |master| async move {
        walk_to_with(&master, AlState::PreOp, &common::MAILBOX).await;
        let mut foe = FoeClient::for_mailbox(&master, &common::MAILBOX);
        assert_eq!(
            foe.write("app.bin", PASSWORD, &file(10)).await,
            Err(FoeFailure::Error(0x8008))
        );
    });
}
