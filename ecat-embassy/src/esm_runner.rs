//! The state-machine and mailbox runner: AL control, SyncManager checks, application hooks, the
//! mailbox with CoE and the application's other protocols ([`Application::mailbox`]). Runs in
//! the low-priority (thread) executor.

use core::cell::Cell;
use core::future::poll_fn;
use core::num::NonZeroU16;
use core::pin::{Pin, pin};
use core::task::Poll;

use ecat_core::dictionary::{Length, ObjectDictionary};
use ecat_core::{AlEvent, AlStatusCode, Event, RegisterAccess, SubDevice, Transition};
use embassy_futures::select::{Either, select};
use embassy_time::Timer;
use embedded_hal_async::digital::Wait;

use crate::device::{AppCell, Common};
use crate::handed_over::handed_over;
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
pub struct StateMachineRunner<'a, P, A, D, const MBX: usize = 128, S = ()>
where
    D: ObjectDictionary,
{
    common: &'a Common<P, A, D>,
    /// In the `Resources`, not in the runner: a SubDevice moved into the runner's future is a
    /// copy of several hundred bytes the firmware pays in code (a `memmove`) and stack.
    sub: &'a mut SubDevice<'static, MBX, D::Download>,
    storage: S,
}

impl<'a, P, A, D, const MBX: usize> StateMachineRunner<'a, P, A, D, MBX>
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
{
    pub(crate) fn new(
        common: &'a Common<P, A, D>,
        sub: &'a mut SubDevice<'static, MBX, D::Download>,
    ) -> Self {
        Self {
            common,
            sub,
            storage: (),
        }
    }

    /// The same runner performing 0x1010/0x1011 with `storage` ([`crate::storage`]).
    pub fn with_storage<S: Storage<D>>(
        self,
        storage: S,
    ) -> StateMachineRunner<'a, P, A, D, MBX, S> {
        let Self { common, sub, .. } = self;
        StateMachineRunner {
            common,
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
        let Self {
            common,
            sub,
            storage,
        } = self;
        async move {
            // The runner's own future never completes: the error it hands over ends this one.
            let error = Cell::new(None);
            handed_over(&error, run(common, sub, storage, |e| error.set(Some(e)))).await
        }
    }

    /// [`run`](Self::run), then `stopped` with the error, then nothing more: the future never
    /// completes. For a task that only runs the runner: the task's future is this one, without
    /// an `async fn` around it that keeps the runner a second time beside it, and, never
    /// completing, without a "resumed after completion" panic path (docs/performance.md,
    /// "Codegen rules").
    pub fn run_then(self, stopped: impl FnOnce(P::Error) + 'a) -> impl Future<Output = ()> + 'a {
        run(self.common, self.sub, self.storage, stopped)
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
///
/// Two awaits (docs/performance.md, "Codegen rules"): the PDI access, for every access the core
/// asks for after each step, and one wait, for the application's answer to a transition or for
/// news; the steps in between are synchronous.
#[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
fn run<'a, P, A, D, const MBX: usize, S>(
    common: &'a Common<P, A, D>,
    sub: &'a mut SubDevice<'static, MBX, D::Download>,
    mut storage: S,
    stopped: impl FnOnce(P::Error) + 'a,
) -> impl Future<Output = ()> + 'a
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
    S: Storage<D> + 'a,
{
    async move {
        take_outside_news(&common.esc, sub, &common.app);
        let mut step = Step::Serve;
        // The application's decision on the transition of `Step::Answer`, asked when the core
        // requested it and dropped when the transition is no longer pending.
        let mut decision = pin!(None);
        let error = 'run: loop {
            // Every step is followed by the accesses it asks for: the only place they are made,
            // in this loop rather than in a future of their own (docs/performance.md, "Codegen
            // rules"); then the process-data layout is published.
            while let Some((mut address, mut data, mut last, mut clears)) = next_access(sub) {
                // The access, then, when the message is shorter than SM1, its last byte, which
                // hands SM1 to the MainDevice: awaited at one place. The last byte's write
                // clears what a write of SM1's buffer clears, SM1's event: so the future keeps
                // neither the access's `clears` nor more than the last byte's address (2 bytes,
                // in its padding) beside the access (docs/size-history.md, session 12, ram3).
                let event = loop {
                    match common.esc.access(Runner::Esm, address, data, clears).await {
                        Ok(event) => match last.take() {
                            Some(byte) => {
                                (address, data) = (byte.get(), Data::Write(&[0]));
                                clears = AlEvent::sync_manager(1);
                            }
                            None => break event,
                        },
                        Err(e) => break 'run e,
                    }
                };
                sub.access_done(now(), event);
                common.esc.publish(
                    sub.process_data_news(),
                    sub.event_mask(),
                    Indication::of(sub),
                );
            }
            // The transition whose answer the wait is for, `None`: the wait is for news.
            let answering = loop {
                match step {
                    // Each message served, or request dropped (which re-arms SM0), makes its
                    // accesses due; the serve that finds nothing to do changed nothing.
                    Step::Serve => {
                        if !serve_mailbox(sub, &common.app) {
                            step = Step::Events { any: false };
                        } else if S::STORES
                            && common.app.lock(|_, od| storage.take(od))
                            && let Some(emergency) = storage.commit().await
                        {
                            // A store the message asked for, before its answer goes out.
                            sub.emergency(emergency);
                        }
                        continue 'run;
                    }
                    // AL events are still served while the transition waits: a new request from
                    // the MainDevice or the deadline ends it (and drops the decision). Once the
                    // application accepted, a SAFEOP→OP transition may still wait for the
                    // first outputs.
                    Step::Answer(t) if sub.pending_transition() == Some(t) => break Some(t),
                    Step::Answer(_) => {
                        decision.set(None);
                        step = Step::Events { any: true };
                        continue 'run;
                    }
                    Step::Events { any } => match sub.poll_event() {
                        // Every event told in one place (an aborted transition in an empty
                        // critical section); a request is asked at once, and waited for without
                        // accesses in between.
                        Some(event) => {
                            let asked = common.app.lock(|app, _| match event {
                                Event::TransitionRequested(t) => Some((t, app.on_transition(t))),
                                Event::StateChanged(t) => {
                                    app.on_state_change(t);
                                    None
                                }
                                Event::TransitionAborted(_) => None,
                            });
                            let Some((t, answer)) = asked else {
                                step = Step::Events { any: true };
                                continue 'run;
                            };
                            decision.set(Some(answer));
                            step = Step::Answer(t);
                        }
                        // What events led to (a new state, emergencies taken while answering)
                        // may have given the mailbox work: one more pass before waiting.
                        None if any => {
                            take_outside_news(&common.esc, sub, &common.app);
                            step = Step::Serve;
                            continue 'run;
                        }
                        None => break None,
                    },
                }
            };
            // The application's decision only while the core waits for it.
            let answer = match answering {
                Some(_) if sub.awaits_application() => decision.as_mut().as_pin_mut(),
                _ => None,
            };
            let woken = wait(
                &common.esc,
                answer,
                until(sub.poll_timeout()),
                answering.is_some(),
            )
            .await;
            let event = match woken {
                Woken::Answer(result) => {
                    if let Some(t) = answering {
                        sub.complete_transition(t, result);
                    }
                    None
                }
                Woken::Deadline => {
                    sub.handle_timeout(now());
                    None
                }
                Woken::News(event) => Some(event),
            };
            // An answer's wait hands the core what the rest of the firmware told the runner
            // before the AL event; news are followed by a serve of the mailbox.
            if answering.is_some() {
                take_reports::<P, D, MBX, _>(&common.esc, sub);
            }
            if let Some(event) = event {
                sub.handle_al_event(event);
            }
            if answering.is_none() {
                take_outside_news(&common.esc, sub, &common.app);
                step = Step::Serve;
            }
        };
        stopped(error);
        // Never completing, the future has no "resumed after completion" panic path.
        loop {
            core::future::pending::<()>().await;
        }
    }
}

/// What ended a wait of the state-machine runner.
enum Woken {
    /// The application answered the transition.
    Answer(Result<(), AlStatusCode>),
    /// The core's deadline ([`SubDevice::poll_timeout`]) passed.
    Deadline,
    /// State-machine events the other runner saw (or none: reports or emergencies arrived).
    News(AlEvent),
}

/// Waits for the application's `answer` (when there is one to wait for), the core's `deadline`
/// and news for the state machine ([`SharedEsc::poll_esm_events`]). Of those ready at once, the
/// answer first, then the news, but the deadline before the news while a transition waits
/// (`answering`): the order of the two waits this one replaces.
fn wait<'f, P: Pdi, F: Future<Output = Result<(), AlStatusCode>>>(
    esc: &'f SharedEsc<P>,
    mut answer: Option<Pin<&'f mut F>>,
    mut deadline: OrNever<Timer>,
    answering: bool,
) -> impl Future<Output = Woken> + 'f {
    poll_fn(move |cx| {
        if let Some(Poll::Ready(result)) = answer.as_mut().map(|a| a.as_mut().poll(cx)) {
            return Poll::Ready(Woken::Answer(result));
        }
        // One poll of each, in the order of the wait: each once in the code.
        for news in [!answering, answering] {
            let woken = if news {
                esc.poll_esm_events(cx).map(Woken::News)
            } else {
                Pin::new(&mut deadline).poll(cx).map(|()| Woken::Deadline)
            };
            if woken.is_ready() {
                return woken;
            }
        }
        Poll::Pending
    })
}

/// Serves one mailbox message, if any, with the application locked; then queues the emergencies
/// its hooks raised. Whether a message was served (or a request dropped). The one call of the
/// core's mailbox. Not inlined into the runner's future, whose poll it would make larger by
/// more than its own size (docs/performance.md, "Codegen rules").
#[inline(never)]
fn serve_mailbox<A: Application<D>, D: ObjectDictionary, const MBX: usize, L: Length>(
    sub: &mut SubDevice<'_, MBX, L>,
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
    /// Wait for the application's answer to this transition while it is pending.
    Answer(Transition),
    /// Hand the application the core's events, one at a time; `any`: some were handed since
    /// the mailbox was served. With none left, the runner waits for news (unless there were
    /// any) and serves again.
    Events { any: bool },
}

/// Takes what changed outside the core before it is served: the process-data configuration the
/// dictionary holds, and what the rest of the firmware reported ([`take_reports`]).
fn take_outside_news<P: Pdi, A, D: ObjectDictionary, const MBX: usize, L: Length>(
    esc: &SharedEsc<P>,
    sub: &mut SubDevice<'_, MBX, L>,
    app: &AppCell<A, D>,
) {
    app.lock(|_, od| sub.refresh_process_data(od));
    take_reports::<P, D, MBX, _>(esc, sub);
}

/// Hands the core what the rest of the firmware reported to the runner: emergencies the
/// application raised and what the process-data runner saw (outputs, SYNC0). Taking them is
/// what lets the runner's wait ([`SharedEsc::poll_esm_events`]) wait again.
///
/// SYNC0 received and lost and sync errors come only in DC SYNC0 mode: a dictionary without it
/// (`D::SYNC_MODES`, known at compile time) carries none of their handling.
fn take_reports<P: Pdi, D: ObjectDictionary, const MBX: usize, L: Length>(
    esc: &SharedEsc<P>,
    sub: &mut SubDevice<'_, MBX, L>,
) {
    // Each pass takes the reports so far with the oldest emergency, in one critical section:
    // one in the code, not one for each.
    loop {
        let (reports, emergency) = esc.take_reports();
        let dc = D::SYNC_MODES.dc();
        if dc && reports.contains(Reports::SYNC_RECEIVED) {
            sub.sync0_received();
        }
        if dc && reports.contains(Reports::SYNC_LOST) {
            sub.sync0_lost();
        }
        if dc && reports.contains(Reports::SYNC_ERROR) {
            sub.sync_error();
        }
        if reports.contains(Reports::OUTPUTS_RECEIVED) {
            sub.outputs_received();
        }
        match emergency {
            Some(emergency) => {
                sub.emergency(emergency);
            }
            None => break,
        }
    }
}

/// The next access the core asks for, as the PDI performs it: address, data, the address of a
/// last byte to write after the data ([`RegisterAccess::Send`]: SM1's last byte, never at
/// address 0, the ESC's type register), the AL event bits it clears.
/// Taken apart here so that the runner's future keeps the parts, not the access; not inlined
/// into that future (docs/performance.md, "Codegen rules").
#[inline(never)]
fn next_access<'s, const MBX: usize, L: Length>(
    sub: &'s mut SubDevice<'_, MBX, L>,
) -> Option<(u16, Data<'s>, Option<NonZeroU16>, AlEvent)> {
    let access = sub.poll_access()?;
    let clears = access.clears();
    match access {
        RegisterAccess::Read { address, buf, .. } => (address, Data::Read(buf), None, clears),
        RegisterAccess::Write { address, data, .. } => (address, Data::Write(data), None, clears),
        RegisterAccess::Send {
            address,
            data,
            last,
            ..
        } => (
            address,
            Data::Write(data),
            last.and_then(NonZeroU16::new),
            clears,
        ),
    }
    .into()
}
