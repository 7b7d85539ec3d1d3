//! The state-machine and mailbox runner: AL control, SyncManager checks, application hooks, the
//! mailbox with CoE and the application's other protocols ([`Application::mailbox`]). Runs in
//! the low-priority (thread) executor.

use core::pin::pin;

use ecat_core::dictionary::ObjectDictionary;
use ecat_core::{AlEvent, AlStatusCode, Event, RegisterAccess, SubDevice, Transition};
use embassy_futures::select::{Either, Either3, select, select3};
use embedded_hal_async::digital::Wait;

use crate::device::AppCell;
use crate::or_never::OrNever;
use crate::pd_runner::{Error, ProcessDataRunner};
use crate::pdi::Data;
use crate::shared::{Indication, Reports, Runner, SharedEsc};
use crate::storage::Storage;
use crate::time::{now, until};
use crate::{Application, Pdi};

/// Runs the state machine and the mailbox of the SubDevice: made by
/// [`Resources::split`](crate::Resources::split), for the thread executor; `S`: the stored
/// parameters' [`Storage`] ([`StateMachineRunner::with_storage`]), none by default.
pub struct StateMachineRunner<'a, P, A, D, const MBX: usize = 128, S = ()> {
    esc: &'a SharedEsc<P>,
    app: &'a AppCell<A, D>,
    /// In the `Resources`, not in the runner: a SubDevice moved into the runner's future is a
    /// copy of several hundred bytes the firmware pays in code (a `memmove`) and stack.
    sub: &'a mut SubDevice<'static, MBX>,
    storage: S,
}

impl<'a, P, A, D, const MBX: usize> StateMachineRunner<'a, P, A, D, MBX>
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
{
    pub(crate) fn new(
        esc: &'a SharedEsc<P>,
        app: &'a AppCell<A, D>,
        sub: &'a mut SubDevice<'static, MBX>,
    ) -> Self {
        Self {
            esc,
            app,
            sub,
            storage: (),
        }
    }

    /// The same runner performing 0x1010/0x1011 with `storage` ([`crate::storage`]).
    pub fn with_storage<S: Storage<D>>(
        self,
        storage: S,
    ) -> StateMachineRunner<'a, P, A, D, MBX, S> {
        let Self { esc, app, sub, .. } = self;
        StateMachineRunner {
            esc,
            app,
            sub,
            storage,
        }
    }
}

impl<'a, P, A, D, const MBX: usize, S> StateMachineRunner<'a, P, A, D, MBX, S>
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
    S: Storage<D> + 'a,
{
    /// Shows `id` as the explicit device ID (`DeviceConfig::explicit_device_id`), e.g. read from
    /// switches at start-up.
    pub fn set_device_id(&mut self, id: u16) {
        self.sub.set_device_id(id);
    }

    /// Runs until the PDI fails; returns the PDI error. SDO requests are served from the
    /// dictionary, with the application's [`object_hooks`](Application::object_hooks).
    ///
    /// Woken only by AL events the process-data runner routes to it, by emergencies the
    /// application raises and by the core's deadlines; never polls the ESC. Each mailbox message
    /// costs one PDI read of SM0 and one or two writes of SM1, each moved in chunks
    /// ([`Resources::with_chunk`](crate::Resources::with_chunk)): the process-data runner takes
    /// the PDI at the next chunk boundary.
    pub fn run(self) -> impl Future<Output = P::Error> + 'a {
        run(self.esc, self.sub, self.app, self.storage)
    }

    /// Runs this runner and `process_data` in one task, for a first device in one executor
    /// ([`Resources::run`](crate::Resources::run)); returns the error of the one that stopped.
    pub async fn run_with<I: Wait>(
        self,
        process_data: ProcessDataRunner<'a, P, A, D>,
        irq: I,
    ) -> Error<P::Error, I::Error> {
        match select(self.run(), process_data.run(irq)).await {
            Either::First(e) => Error::Pdi(e),
            Either::Second(e) => e,
        }
    }
}

/// The loop of [`StateMachineRunner::run`].
#[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
fn run<'a, P, A, D, const MBX: usize, S>(
    esc: &'a SharedEsc<P>,
    sub: &'a mut SubDevice<'static, MBX>,
    app: &'a AppCell<A, D>,
    mut storage: S,
) -> impl Future<Output = P::Error> + 'a
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
    S: Storage<D> + 'a,
{
    async move {
        take_outside_news(esc, sub, app);
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
                    if serve_mailbox(sub, app) {
                        // A store the message asked for, before its answer goes out.
                        if S::STORES
                            && app.lock(|_, od| storage.take(od))
                            && let Some(emergency) = storage.commit().await
                        {
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
                        let mut decision = pin!(app.lock(|app, _| app.on_transition(t)));
                        while sub.pending_transition() == Some(t) {
                            // The application's decision only while the core waits for it.
                            let pending =
                                OrNever(sub.awaits_application().then_some(decision.as_mut()));
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
                        app.lock(|app, _| app.on_state_change(t));
                        Step::Events { any: true }
                    }
                    Some(Event::TransitionAborted(_)) => Step::Events { any: true },
                    None => {
                        // What events led to (a new state, emergencies taken while answering)
                        // may have given the mailbox work: one more pass before waiting.
                        if !any {
                            match select(esc.esm_events(), until(sub.poll_timeout())).await {
                                Either::First(event) => sub.handle_al_event(event),
                                Either::Second(()) => sub.handle_timeout(now()),
                            }
                        }
                        take_outside_news(esc, sub, app);
                        Step::Serve
                    }
                },
            };
        }
    }
}

/// Serves one mailbox message, if any, with the application locked; then queues the emergencies
/// its hooks raised. Whether a message was served (or a request dropped). The one call of the
/// core's mailbox.
fn serve_mailbox<A: Application<D>, D: ObjectDictionary, const MBX: usize>(
    sub: &mut SubDevice<'_, MBX>,
    app: &AppCell<A, D>,
) -> bool {
    app.lock(|app, od| {
        let served = {
            let (mut hooks, mut handlers) = app.mailbox();
            sub.service_mailbox_with(now(), od, &mut hooks, &mut handlers)
        };
        if served {
            while let Some(emergency) = app.take_emergency() {
                sub.emergency(emergency);
            }
        }
        served
    })
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
/// dictionary holds, and what the rest of the firmware reported ([`take_reports`]).
fn take_outside_news<P: Pdi, A, D: ObjectDictionary, const MBX: usize>(
    esc: &SharedEsc<P>,
    sub: &mut SubDevice<'_, MBX>,
    app: &AppCell<A, D>,
) {
    app.lock(|_, od| sub.refresh_process_data(od));
    take_reports(esc, sub);
}

/// Hands the core what the rest of the firmware reported to the runner: emergencies the
/// application raised and what the process-data runner saw (outputs, SYNC0). Taking them is
/// what lets [`SharedEsc::esm_events`] wait again.
fn take_reports<P: Pdi, const MBX: usize>(esc: &SharedEsc<P>, sub: &mut SubDevice<'_, MBX>) {
    let reports = esc.take_reports();
    if reports.contains(Reports::SYNC_RECEIVED) {
        sub.sync0_received();
    }
    if reports.contains(Reports::SYNC_LOST) {
        sub.sync0_lost();
    }
    if reports.contains(Reports::SYNC_ERROR) {
        sub.sync_error();
    }
    if reports.contains(Reports::OUTPUTS_RECEIVED) {
        sub.outputs_received();
    }
    while let Some(emergency) = esc.take_emergency() {
        sub.emergency(emergency);
    }
}

/// Performs every register access the core asks for, then publishes the process-data layout.
#[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
fn sync<'a, P: Pdi, const MBX: usize>(
    esc: &'a SharedEsc<P>,
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
fn answer<P: Pdi, const MBX: usize>(
    esc: &SharedEsc<P>,
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
    take_reports(esc, sub);
    if let Some(event) = event {
        sub.handle_al_event(event);
    }
}
