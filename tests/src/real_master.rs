//! ethercrab, an independent pure-Rust MainDevice, in-process: its frames pass through emulated
//! ESCs instead of a network interface, so tests bring SubDevices to OP with a real master and no
//! NIC, no root and virtual time on the SubDevice side.
//!
//! ethercrab's own timeouts run on the wall clock (its `std` feature uses async-io timers; see
//! the project's masters reference): harmless here, because the emulated line answers every
//! frame at once.

use core::cell::RefCell;
use core::future::{Future, poll_fn};
use core::task::Poll;
use std::rc::Rc;

use embassy_futures::select::{Either, select};
use ethercrab::{MainDevice, MainDeviceConfig, PduRx, PduStorage, PduTx, Timeouts};

use crate::emulator::Emulator;
use crate::harness::{self, Spawn};
use crate::line::Line;
use crate::master::TestMaster;

/// Frames ethercrab may have in flight (a power of two).
const MAX_FRAMES: usize = 16;
/// Largest PDU payload ethercrab may put in one frame (1100 bytes: enough for these tests'
/// process images and mailboxes).
const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
/// Largest Ethernet frame the transport carries.
const MAX_FRAME: usize = 1518;

/// The storage of one in-process MainDevice's PDUs.
type Storage = PduStorage<MAX_FRAMES, MAX_PDU_DATA>;

/// A medium for Ethernet frames: processes one frame in place, as the cable and the SubDevices
/// on it do, and returns the length of the frame that comes back, `None` if it is lost.
pub trait Medium {
    /// Passes `frame` through the medium.
    fn process(&mut self, frame: &mut [u8]) -> Option<usize>;
}

impl<F: FnMut(&mut [u8]) -> Option<usize>> Medium for F {
    fn process(&mut self, frame: &mut [u8]) -> Option<usize> {
        self(frame)
    }
}

/// ethercrab's timeouts for an in-process line: its defaults (30 ms per PDU, 10 ms per EEPROM
/// operation, 5 s per state transition) are wall-clock times meant for a real network; here
/// every frame is answered at once, so they can only expire when the host is starved (a loaded
/// CI machine), and a test would fail for nothing. A hundred times longer, they still end a
/// test that hangs.
pub fn timeouts() -> Timeouts {
    let d = Timeouts::default();
    Timeouts {
        state_transition: d.state_transition * 100,
        pdu: d.pdu * 100,
        eeprom: d.eeprom * 100,
        wait_loop_delay: d.wait_loop_delay,
        mailbox_echo: d.mailbox_echo * 100,
        mailbox_response: d.mailbox_response * 100,
    }
}

/// The configuration for tests: no DC static-drift compensation (ethercrab's default sends
/// 10 000 DC frames before OP), ethercrab's defaults otherwise (the timeouts are [`timeouts`]).
pub fn config() -> MainDeviceConfig {
    MainDeviceConfig {
        dc_static_sync_iterations: 0,
        ..MainDeviceConfig::default()
    }
}

/// An ethercrab [`MainDevice`] whose frames go through `medium`, and the transport task that
/// carries them; the task must run beside every use of the MainDevice (e.g. with
/// `embassy_futures::select`). Each call leaks one PDU storage (a few tens of KiB): ethercrab
/// needs it `'static`.
pub fn main_device(
    medium: impl Medium + 'static,
    timeouts: Timeouts,
    config: MainDeviceConfig,
) -> (&'static MainDevice<'static>, impl Future<Output = ()>) {
    let storage: &'static Storage = Box::leak(Box::new(Storage::new()));
    let Ok((tx, rx, pdu_loop)) = storage.try_split() else {
        unreachable!("a new PDU storage splits")
    };
    let main: &'static MainDevice<'static> =
        Box::leak(Box::new(MainDevice::new(pdu_loop, timeouts, config)));
    (main, transport(tx, rx, medium))
}

/// Sends every frame ethercrab queues through `medium` and hands the answer back to ethercrab,
/// until ethercrab releases the PDU loop.
async fn transport(mut tx: PduTx<'static>, mut rx: PduRx<'static>, mut medium: impl Medium) {
    let mut buf = vec![0u8; MAX_FRAME];
    poll_fn(|cx| {
        tx.replace_waker(cx.waker());
        while let Some(frame) = tx.next_sendable_frame() {
            let mut answer = None;
            let sent = frame.send_blocking(|bytes| {
                let frame = buf
                    .get_mut(..bytes.len())
                    .ok_or(ethercrab::error::Error::Internal)?;
                frame.copy_from_slice(bytes);
                answer = medium.process(frame);
                Ok(bytes.len())
            });
            if let (Ok(_), Some(len)) = (sent, answer) {
                let reply = buf.get(..len).unwrap_or_default();
                if let Err(e) = rx.receive_frame(reply) {
                    panic!("ethercrab refused a frame from the emulated line: {e:?}");
                }
            }
        }
        if tx.should_exit() {
            Poll::Ready(())
        } else {
            Poll::Pending
        }
    })
    .await
}

/// Runs `scenario` with an ethercrab MainDevice in front of a [`Line`] of `devices` (the real
/// runners on the harness executor, virtual time), and returns what it returned. The scenario
/// also gets a [`TestMaster`] per SubDevice, to let the runners settle after each frame.
pub fn run_on_line<T: 'static>(
    devices: Vec<Box<dyn Spawn>>,
    timeouts: Timeouts,
    scenario: impl AsyncFnOnce(&'static MainDevice<'static>, Vec<TestMaster>) -> T + 'static,
) -> T {
    let result = Rc::new(RefCell::new(None));
    let out = result.clone();
    harness::run_many(devices, move |escs: Vec<Emulator>| async move {
        let masters: Vec<TestMaster> = escs.iter().cloned().map(TestMaster::new).collect();
        let line = Line::new(escs);
        let (main, transport) = main_device(
            move |frame: &mut [u8]| line.process(frame),
            timeouts,
            config(),
        );
        match select(transport, scenario(main, masters)).await {
            Either::First(()) => panic!("ethercrab's transport stopped"),
            Either::Second(value) => *out.borrow_mut() = Some(value),
        }
    });
    let value = result.borrow_mut().take();
    match value {
        Some(value) => value,
        None => panic!("the scenario did not run"),
    }
}

/// After a frame: lets the SubDevices' runners react, then one millisecond of virtual time passes
/// (the emulated ESCs' watchdogs and SYNC units see it) and they settle again.
pub async fn next_cycle(masters: &[TestMaster]) {
    for master in masters {
        master.settle().await;
    }
    embassy_time::MockDriver::get().advance(embassy_time::Duration::from_millis(1));
    for master in masters {
        master.emulator().tick();
        master.settle().await;
    }
}
