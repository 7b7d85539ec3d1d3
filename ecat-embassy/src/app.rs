//! What the firmware author implements.
//!
//! Two traits, because the two runners live in two executors: the state hooks run in the
//! low-priority thread executor next to the mailbox, the cycle in the process-data interrupt
//! executor. Data both need is shared by the application through its own
//! `CriticalSectionRawMutex` cell.

use ecat_core::coe::Emergency;
use ecat_core::{AlStatusCode, Transition};

/// State-machine hooks, called by [`run_esm`](crate::run_esm).
pub trait Application {
    /// An upward transition (INIT→PREOP, PREOP→SAFEOP, SAFEOP→OP, INIT→BOOT) passed the
    /// SyncManager checks. Return `Ok` to accept, `Err(code)` to refuse with that AL status code.
    ///
    /// The future may take time (the transition is "pending" meanwhile): if it is not done within
    /// the device's `transition_timeout`, the MainDevice gets 0x0001 and the future is dropped. It is
    /// also dropped when the MainDevice replaces the request. Implement it as an `async fn`.
    ///
    /// The default accepts at once, with a future that has no state machine of its own and no
    /// panic path (`core::future::ready` panics with a message when polled again).
    fn on_transition(
        &mut self,
        transition: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> {
        let _ = transition;
        core::future::poll_fn(|_| core::task::Poll::Ready(Ok(())))
    }

    /// The state changed (accepted upward, downward, or a fall back after an error).
    fn on_state_change(&mut self, transition: Transition) {
        let _ = transition;
    }

    /// An emergency (ETG.1000.6 §5.6.4) the application wants sent, asked after every mailbox
    /// message the runner served, until it returns `None`: what an SDO write hook of the
    /// application ([`ObjectHooks`](ecat_core::dictionary::ObjectHooks)) raised. Elsewhere
    /// (the process-data cycle, a task) raise one with
    /// [`SharedEsc::raise_emergency`](crate::SharedEsc::raise_emergency). The default has none.
    fn take_emergency(&mut self) -> Option<Emergency> {
        None
    }
}

/// The process-data cycle, called by [`run_process_data`](crate::run_process_data).
pub trait CycleHandler<D> {
    /// One cycle, with the dictionary `od` locked. In OP the outputs the MainDevice wrote are
    /// already unpacked into their mapped entries; after the call the mapped input entries are
    /// packed into the input image. `outputs` (`Some` only in OP) and `inputs` are the raw images,
    /// for devices whose process data is not mapped through the dictionary (a fixed layout).
    /// Keep it short: it runs in the interrupt executor with the dictionary locked.
    fn cycle(&mut self, od: &mut D, outputs: Option<&[u8]>, inputs: &mut [u8]);

    /// Outputs stopped being applied (OP left: by request, SM watchdog, or error): put the
    /// outputs of the device into their safe state now. Called once per departure from OP.
    fn safe_state(&mut self, od: &mut D) {
        let _ = od;
    }
}
