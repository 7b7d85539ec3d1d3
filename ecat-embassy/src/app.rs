//! What the firmware author implements: one trait, [`Application`], every method with a default.
//!
//! The application lives with its object dictionary behind one critical-section mutex
//! ([`Resources`](crate::Resources)): the state-machine runner (thread executor) calls the state
//! and SDO hooks, the process-data runner (interrupt executor) the cycle, and any other task
//! reaches it through a [`Control`](crate::Control). Each call has the dictionary at hand and
//! holds the lock for its duration: keep them short.

use ecat_core::coe::Emergency;
use ecat_core::dictionary::ObjectHooks;
use ecat_core::mailbox::Handlers;
use ecat_core::{AlStatusCode, Transition};

/// A SubDevice's application over its object dictionary `D` (`()`: none, raw process images).
/// Every method has a default: an application implements only what it uses.
pub trait Application<D = ()> {
    /// One process-data cycle, in the interrupt executor. In OP the outputs the MainDevice wrote
    /// are already unpacked into their mapped entries of `od`; after the call the mapped input
    /// entries are packed into the input image. `outputs` (`Some` only in OP) and `inputs` are
    /// the raw images, for devices whose process data is not mapped through the dictionary. The
    /// default does nothing.
    fn cycle(&mut self, od: &mut D, outputs: Option<&[u8]>, inputs: &mut [u8]) {
        let _ = (od, outputs, inputs);
    }

    /// Outputs stopped being applied (OP left by request, SM watchdog or error, or the
    /// process-data runner stopped): put the outputs of the device into their safe state now.
    /// Called once per departure from OP.
    fn safe_state(&mut self, od: &mut D) {
        let _ = od;
    }

    /// An upward transition (INIT→PREOP, PREOP→SAFEOP, SAFEOP→OP, INIT→BOOT) passed the
    /// SyncManager checks. The future's `Ok` accepts, `Err(code)` refuses with that AL status
    /// code.
    ///
    /// The future may take time (the transition is "pending" meanwhile): if it is not done
    /// within the device's `transition_timeout`, the MainDevice gets 0x0001 and the future is
    /// dropped; it is also dropped when the MainDevice replaces the request. It does not borrow
    /// the application (the runner does not hold the lock while it waits): copy in what it
    /// needs, or a [`Control`](crate::Control) to lock the application with.
    ///
    /// The default accepts at once (a `poll_fn`: docs/performance.md, "Codegen rules").
    fn on_transition(
        &mut self,
        transition: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> + use<Self, D> {
        let _ = transition;
        core::future::poll_fn(|_| core::task::Poll::Ready(Ok(())))
    }

    /// The state changed (accepted upward, downward, or a fall back after an error).
    fn on_state_change(&mut self, transition: Transition) {
        let _ = transition;
    }

    /// The application's say in SDO access to `D` (veto a write, refresh a value before a read,
    /// DOMAIN contents). The default has none: `()`.
    fn object_hooks(&mut self) -> impl ObjectHooks<D> + '_ {}

    /// What serves the mailbox, asked for each message: the SDO hooks
    /// ([`object_hooks`](Application::object_hooks)) and the mailbox protocols beside CoE, a
    /// tuple of [`Handler`](ecat_core::mailbox::Handler)s such as `(Foe::new(files),)` kept in
    /// the application ([`ecat_core::foe`]: a firmware update in BOOT), returned as `&mut`.
    /// One method for both because both borrow the application for the message.
    ///
    /// The default: the SDO hooks and no other protocol (`()`), so a firmware without FoE
    /// carries none of its code.
    fn mailbox(&mut self) -> (impl ObjectHooks<D> + '_, impl Handlers + '_) {
        (self.object_hooks(), ())
    }

    /// An emergency (ETG.1000.6 §5.6.4) the application wants sent, asked after every mailbox
    /// message the runner served, until it returns `None`: what an SDO hook of the application
    /// raised. Elsewhere (the cycle, a task) raise one with
    /// [`Control::raise_emergency`](crate::Control::raise_emergency). The default has none.
    fn take_emergency(&mut self) -> Option<Emergency> {
        None
    }
}
