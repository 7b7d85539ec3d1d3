//! The SM watchdog (conformance.md "Watchdogs"): in OP, outputs must keep coming within the
//! process-data watchdog time, or the SubDevice falls back to SAFEOP with 0x001B and its outputs
//! go to their safe state at once.

mod common;

use std::cell::RefCell;
use std::rc::Rc;

use common::{send_outputs, walk_to};
use ecat_core::AlState;
use ecat_embassy::Application;
use ecat_emu::harness::{self, AcceptAll, Device};
use embassy_time::Duration;

/// Counts safe-state calls and the cycles that applied outputs.
#[derive(Clone, Default)]
struct Outputs {
    safe: Rc<RefCell<u32>>,
    applied: Rc<RefCell<u32>>,
}

impl<D> Application<D> for Outputs {
    fn cycle(&mut self, _od: &mut D, outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        if outputs.is_some() {
            *self.applied.borrow_mut() += 1;
        }
    }

    fn safe_state(&mut self, _od: &mut D) {
        *self.safe.borrow_mut() += 1;
    }
}

#[test]
fn outputs_every_10_ms_keep_the_subdevice_in_op() {
    let cycle = Outputs::default();
    let safe = cycle.safe.clone();
    harness::run(
        Device::new(common::drive(), AcceptAll, cycle),
        move |master| async move {
            walk_to(&master, AlState::Op).await;
            for _ in 0..100 {
                send_outputs(&master).await;
                master.advance(Duration::from_millis(10)).await;
            }
            assert_eq!(
                (master.al_status(), master.al_status_code()),
                (0x08, 0),
                "1 s of outputs every 10 ms"
            );
            assert_eq!(*safe.borrow(), 0);
        },
    );
}

#[test]
fn silence_beyond_the_watchdog_time_is_safeop_with_0x001b() {
    let cycle = Outputs::default();
    let (safe, applied) = (cycle.safe.clone(), cycle.applied.clone());
    harness::run(
        Device::new(common::drive(), AcceptAll, cycle),
        move |master| async move {
            walk_to(&master, AlState::Op).await;
            send_outputs(&master).await;
            let before = *applied.borrow();
            // The ESC's reset values: (0x09C2 + 2) × 40 ns × 1000 = 100 ms.
            master.advance(Duration::from_millis(99)).await;
            assert_eq!(
                (master.al_status(), master.al_status_code()),
                (0x08, 0),
                "99 ms: still OP"
            );
            master.advance(Duration::from_millis(1)).await;
            assert_eq!(
                (master.al_status(), master.al_status_code()),
                (0x14, 0x001B),
                "100 ms: SM watchdog"
            );
            assert_eq!(*safe.borrow(), 1, "the outputs went to their safe state");
            send_outputs(&master).await;
            assert_eq!(
                *applied.borrow(),
                before,
                "outputs are not applied in SAFEOP"
            );
            assert_eq!(
                master.read(0x0442, 1),
                Some(vec![1]),
                "the ESC counted one SM watchdog expiry"
            );
        },
    );
}

#[test]
fn leaving_op_on_request_also_calls_the_safe_state() {
    let cycle = Outputs::default();
    let safe = cycle.safe.clone();
    harness::run(
        Device::new(common::drive(), AcceptAll, cycle),
        move |master| async move {
            walk_to(&master, AlState::Op).await;
            assert_eq!(master.request(0x04).await, (0x04, 0));
            assert_eq!(*safe.borrow(), 1);
            assert_eq!(master.request(0x02).await, (0x02, 0));
            assert_eq!(*safe.borrow(), 1, "once per departure from OP");
        },
    );
}
