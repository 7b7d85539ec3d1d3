//! The state-machine and mailbox runner: AL control, SyncManager checks, application hooks, the
//! mailbox with CoE. Runs in the low-priority (thread) executor.

use core::cell::RefCell;
use core::pin::pin;

use ecat_core::dictionary::{ObjectDictionary, ObjectHooks};
use ecat_core::{AlEvent, AlStatusCode, Event, RegisterAccess, SubDevice, Transition};
use embassy_futures::select::{Either, Either3, select, select3};
use embassy_sync::blocking_mutex::Mutex as BlockingMutex;
use embassy_sync::blocking_mutex::raw::RawMutex;

use crate::maybe::Maybe;
use crate::pdi::Data;
use crate::shared::{Indication, Notes, Runner};
use crate::time::{now, until};
use crate::{Application, Pdi, SharedEsc};

/// The object dictionary as both runners share it: behind a blocking mutex, locked only for
/// the CPU work of one mailbox message (no `.await` inside).
pub type SharedDictionary<M, D> = BlockingMutex<M, RefCell<D>>;

/// Runs `f` on the dictionary, locked: the one place the runners borrow it (one borrow check
/// and one panic location for all of them; the lock makes the borrow always free).
pub(crate) fn with_dictionary<M: RawMutex, D, R>(
    od: &SharedDictionary<M, D>,
    f: impl FnOnce(&mut D) -> R,
) -> R {
    od.lock(|cell| f(&mut cell.borrow_mut()))
}

/// Runs the state machine and the mailbox of `sub` on `esc` until the PDI fails; returns the PDI
/// error. SDO requests are served from `od`, with `app` as the [`ObjectHooks`].
///
/// Woken only by AL events the process-data runner routes to it, by emergencies the application
/// raises and by the core's deadlines; never polls the ESC. Each mailbox message costs one PDI
/// read of SM0 and one or two writes of SM1, each moved in chunks ([`SharedEsc::with_chunk`]):
/// the process-data runner takes the PDI at the next chunk boundary.
///
/// An `async` block rather than an `async fn`, which would keep a copy of its arguments beside
/// the ones the loop works on.
#[allow(clippy::manual_async_fn)] // the async block keeps no copy of the arguments
pub fn run_esm<M, P, A, D, const MBX: usize>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_, MBX>,
    app: &mut A,
    od: &SharedDictionary<M, D>,
) -> impl Future<Output = P::Error>
where
    M: RawMutex,
    P: Pdi,
    A: Application + ObjectHooks<D>,
    D: ObjectDictionary,
{
    async move {
        catch_up(esc, sub, od);
        let mut step = Step::Serve;
        loop {
            // Every step is followed by the accesses it asks for: the only place they are made,
            // but for those of a pending transition.
            if let Err(e) = sync(esc, sub).await {
                return e;
            }
            step = match step {
                // Each message served, or request dropped (which re-arms SM0), makes its
                // accesses due; the serve that finds nothing to do changed nothing.
                Step::Serve => {
                    if with_dictionary(od, |od| sub.service_mailbox(now(), od, app)) {
                        while let Some(emergency) = app.take_emergency() {
                            sub.emergency(emergency);
                        }
                        Step::Serve
                    } else {
                        Step::Events { any: false }
                    }
                }
                Step::Events { any } => match sub.poll_event() {
                    Some(Event::TransitionRequested(t)) => {
                        // The application is asked while AL events are still served: a new
                        // request from the MainDevice or the deadline ends the wait and drops
                        // its future. Once it accepted, a SAFEOP→OP transition may still wait
                        // for the first outputs.
                        let mut decision = pin!(app.on_transition(t));
                        while sub.pending_transition() == Some(t) {
                            // The application's decision only while the core waits for it.
                            let pending =
                                Maybe(sub.awaits_application().then_some(decision.as_mut()));
                            let timeout = until(sub.poll_timeout());
                            let outcome = select3(pending, timeout, esc.esm_events()).await;
                            answer(esc, sub, t, outcome);
                            if let Err(e) = sync(esc, sub).await {
                                return e;
                            }
                        }
                        Step::Events { any: true }
                    }
                    Some(Event::StateChanged(t)) => {
                        app.on_state_change(t);
                        Step::Events { any: true }
                    }
                    Some(Event::TransitionAborted(_)) => Step::Events { any: true },
                    None => {
                        // What events led to (a new state, emergencies absorbed while
                        // answering) may have given the mailbox work: one more pass before
                        // waiting.
                        if !any {
                            match select(esc.esm_events(), until(sub.poll_timeout())).await {
                                Either::First(event) => sub.handle_al_event(event),
                                Either::Second(()) => sub.handle_timeout(now()),
                            }
                        }
                        catch_up(esc, sub, od);
                        Step::Serve
                    }
                },
            };
        }
    }
}

/// What the state-machine runner does after its accesses.
#[derive(Clone, Copy)]
enum Step {
    /// Serve the mailbox, one message at a time.
    Serve,
    /// Hand the application the core's events, one at a time; `any`: some were handed since
    /// the mailbox was served. With none left, the runner waits for news (unless there were
    /// any) and serves again.
    Events { any: bool },
}

/// Takes what changed outside the core before it is served: the process-data configuration the
/// dictionary holds, and what the rest of the firmware told the runner ([`absorb`]).
fn catch_up<M: RawMutex, P: Pdi, D: ObjectDictionary, const MBX: usize>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_, MBX>,
    od: &SharedDictionary<M, D>,
) {
    with_dictionary(od, |od| sub.refresh_process_data(od));
    absorb(esc, sub);
}

/// Hands the core what the rest of the firmware told the runner: emergencies the application
/// raised and outputs the process-data runner received. Taking them is what lets
/// [`SharedEsc::esm_events`] wait again.
fn absorb<M: RawMutex, P: Pdi, const MBX: usize>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_, MBX>,
) {
    let notes = esc.take_notes();
    if notes.contains(Notes::SYNC_RECEIVED) {
        sub.sync0_received();
    }
    if notes.contains(Notes::SYNC_LOST) {
        sub.sync0_lost();
    }
    if notes.contains(Notes::SYNC_ERROR) {
        sub.sync_error();
    }
    if notes.contains(Notes::OUTPUTS_RECEIVED) {
        sub.outputs_received();
    }
    while let Some(emergency) = esc.take_emergency() {
        sub.emergency(emergency);
    }
}

/// Performs every register access the core asks for, then publishes the process-data layout.
/// An `async` block, which keeps no copy of its arguments beside them (as an `async fn` would).
#[allow(clippy::manual_async_fn)] // the async block keeps no copy of the arguments
fn sync<'a, M: RawMutex, P: Pdi, const MBX: usize>(
    esc: &'a SharedEsc<M, P>,
    sub: &'a mut SubDevice<'_, MBX>,
) -> impl Future<Output = Result<(), P::Error>> + 'a {
    async move {
        while let Some(access) = sub.poll_access() {
            let (mut address, mut data, mut last, clears) = pdi_access(access);
            // The access, then, when the message is shorter than SM1, its last byte, which
            // hands SM1 to the MainDevice: awaited at one place.
            let event = loop {
                let event = esc.access(Runner::Esm, address, data, clears).await?;
                match last.take() {
                    Some(byte) => (address, data) = (byte, Data::Write(&[0])),
                    None => break event,
                }
            };
            sub.access_done(now(), event);
            esc.publish(sub.process_data(), sub.event_mask(), Indication::of(sub));
        }
        Ok(())
    }
}

/// An access of the core as the PDI performs it: address, data, the address of a last byte to
/// write after the data ([`RegisterAccess::Send`]), the AL event bits it clears. Taken apart here so
/// that the runner's future keeps the parts, not the access.
fn pdi_access(access: RegisterAccess<'_>) -> (u16, Data<'_>, Option<u16>, AlEvent) {
    let clears = access.clears();
    match access {
        RegisterAccess::Read { address, buf, .. } => (address, Data::Read(buf), None, clears),
        RegisterAccess::Write { address, data, .. } => (address, Data::Write(data), None, clears),
        RegisterAccess::Send {
            address,
            data,
            last,
            ..
        } => (address, Data::Write(data), last, clears),
    }
}

/// Hands the core what ended a wait for the application's answer to `t`: the answer, the
/// deadline, or an AL event (with whatever the rest of the firmware told the runner meanwhile).
fn answer<M: RawMutex, P: Pdi, const MBX: usize>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_, MBX>,
    t: Transition,
    outcome: Either3<Result<(), AlStatusCode>, (), AlEvent>,
) {
    let event = match outcome {
        Either3::First(result) => {
            sub.complete_transition(t, result);
            None
        }
        Either3::Second(()) => {
            sub.handle_timeout(now());
            None
        }
        Either3::Third(event) => Some(event),
    };
    absorb(esc, sub);
    if let Some(event) = event {
        sub.handle_al_event(event);
    }
}
