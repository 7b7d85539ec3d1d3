//! The ESC as both runners share it: the PDI behind an async mutex, and the routing of the AL
//! events every access reports.

use core::cell::Cell;
use core::future::{Future, poll_fn};
use core::task::{Context, Poll, Waker};

use ecat_core::coe::Emergency;
use ecat_core::process_data::Setup;
use ecat_core::ring::Ring;
use ecat_core::{AlEvent, AlStatus, AlStatusCode};
use embassy_sync::blocking_mutex::Mutex as BlockingMutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex as Cs;
use embassy_sync::mutex::{Mutex, MutexGuard};
use embassy_sync::waitqueue::WakerRegistration;

use crate::Pdi;
use crate::pdi::{Data, Sample};

/// Which runner performs an access.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Runner {
    /// The state-machine runner: it hands the AL event to its core itself.
    Esm,
    /// The process-data runner.
    ProcessData,
}

/// Whose chunk an access moves next: the runner, and for the state-machine runner whether it
/// is its access's first chunk ([`SharedEsc::take_pdi`]). One byte that [`SharedEsc::access`]'s
/// future keeps for both (docs/size-history.md, session 12, ram3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Turn {
    /// The process-data runner's access, one piece.
    ProcessData,
    /// The state-machine runner's first chunk.
    EsmFirst,
    /// A later chunk of the state-machine runner's access.
    EsmLater,
}

impl Turn {
    /// The first chunk of `runner`'s access.
    const fn first(runner: Runner) -> Self {
        match runner {
            Runner::ProcessData => Self::ProcessData,
            Runner::Esm => Self::EsmFirst,
        }
    }

    /// Who moves the chunk.
    const fn runner(self) -> Runner {
        match self {
            Self::ProcessData => Runner::ProcessData,
            Self::EsmFirst | Self::EsmLater => Runner::Esm,
        }
    }
}

/// What the runners know about each other, behind a short critical section. Every field but
/// the chunk (fixed before the runners start) is a `Cell`: the routing is only ever borrowed
/// shared, so no critical section checks a borrow flag or carries its panic path.
// `repr(C)`: small fields first (docs/performance.md, "Codegen rules"), the six flags and the
// chunk in the first 8 bytes: no padding before the words, so every byte of the routing's start
// is written and `SharedEsc::with_chunk` builds it in place, not on the stack and copied
// (docs/size-history.md, "Session 13: … (branch init10)").
#[repr(C)]
struct Routing {
    /// State-machine events were set in the last AL event seen, or are waiting to be taken: they
    /// may hold the IRQ line asserted.
    esm_holds_irq: Cell<bool>,
    /// What the process-data runner reported and the state-machine runner has not taken yet.
    reports: Cell<Reports>,
    /// Something changed for the process-data runner since it last looked
    /// ([`SharedEsc::pd_view`]): its trigger was seen, the IRQ line is free again, the layout
    /// changed (then also `layout_news`); or it waits for the PDI. One fact for the
    /// state-machine runner: the process-data runner comes first, so it does not take the PDI
    /// while this is set ([`SharedEsc::take_pdi`]).
    pd_news: Cell<bool>,
    /// The process-data runner has stopped (its PDI or IRQ failed): nothing to give way to.
    pd_stopped: Cell<bool>,
    /// The state-machine runner waits for its turn or for the PDI ([`SharedEsc::take_pdi`]),
    /// not for news: the process-data runner's next view wakes it.
    esm_waits_pdi: Cell<bool>,
    /// The layout changed since the process-data runner last looked: [`SharedEsc::pd_view`]
    /// hands it over (the runners compare no layouts).
    layout_news: Cell<bool>,
    /// The largest chunk of a state-machine access, in bytes; 0: whole accesses.
    chunk: u16,
    /// State-machine events seen by the process-data runner and not yet taken.
    esm_events: Cell<AlEvent>,
    /// Process-data trigger events seen and not yet taken.
    pd_events: Cell<AlEvent>,
    /// The state-machine runner's share of the AL event mask in the ESC: the masked events, which
    /// can hold the IRQ line, less the process-data trigger, which belongs to the process-data
    /// runner. Both are published by the state-machine runner ([`SharedEsc::publish`]).
    esm_mask: Cell<AlEvent>,
    /// The AL event seen by the last access of either runner.
    last_event: Cell<AlEvent>,
    /// The AL status and status code the state-machine runner last published, for the
    /// indicators ([`Indication`]); [`Indication::UNPUBLISHED`] until its first publication, which
    /// puts its AL event mask in the ESC (before that the ESC's reset mask may assert the IRQ for
    /// events no runner clears).
    indication: Cell<Indication>,
    /// The state-machine runner waits for news ([`SharedEsc::poll_esm_events`]) or for its turn
    /// and the PDI ([`SharedEsc::take_pdi`], then also `esm_waits_pdi`): it waits at one place
    /// at a time.
    esm_waker: WakerCell,
    /// The process-data runner waits for news ([`SharedEsc::pd_changed`]) or for the PDI
    /// ([`SharedEsc::take_pdi`]): it waits at one place at a time.
    pd_waker: WakerCell,
    /// The indicator task, woken when the indication changes.
    led_waker: WakerCell,
    /// Emergencies raised by the application, waiting for the state-machine runner.
    emergencies: Cell<Ring<Emergency, EMERGENCIES>>,
    /// The process-data layout published by the state-machine runner.
    layout: Cell<Option<Setup>>,
}

impl Routing {
    /// The process-data runner's trigger.
    fn trigger(&self) -> AlEvent {
        self.layout.get().map_or(AlEvent::NONE, |l| l.trigger())
    }

    /// The masked events of `event` that belong to the state-machine runner.
    fn esm_share(&self, event: AlEvent) -> AlEvent {
        event.intersection(self.esm_mask.get())
    }

    /// Updates whether state-machine events hold the IRQ line, from the last AL event seen
    /// and the current mask; tells the process-data runner when the line is free again.
    fn update_irq_holder(&self) {
        let holds =
            !self.esm_share(self.last_event.get()).is_empty() || !self.esm_events.get().is_empty();
        let was_holding = self.esm_holds_irq.replace(holds);
        if was_holding && !holds {
            self.notify_pd();
        }
    }

    /// Publishes `layout` as news for the process-data runner, which [`SharedEsc::pd_view`]
    /// hands over (the runners compare no layouts).
    fn new_layout(&self, layout: Option<Setup>) {
        self.layout.set(layout);
        self.layout_news.set(true);
        self.notify_pd();
    }

    /// Tells the process-data runner that something changed for it, and wakes it.
    fn notify_pd(&self) {
        self.pd_news.set(true);
        self.pd_waker.wake();
    }

    /// Routes one AL event value: state-machine events to the state-machine runner (unless it made
    /// the access itself: then its core already has them, and they are the freshest news), the
    /// process-data trigger to the process-data runner.
    fn observe(&self, runner: Runner, event: AlEvent) {
        self.last_event.set(event);
        match runner {
            Runner::Esm => {
                self.esm_events.set(AlEvent::NONE);
                let pd = event.intersection(self.trigger());
                if !pd.is_empty() {
                    self.pd_events.set(self.pd_events.get() | pd);
                    self.notify_pd();
                }
            }
            Runner::ProcessData => {
                let esm = self.esm_share(event);
                if !esm.is_empty() {
                    self.esm_events.set(self.esm_events.get() | esm);
                    self.esm_waker.wake();
                }
            }
        }
        self.update_irq_holder();
    }
}

/// A [`WakerRegistration`] in a `Cell`: taken out for each call and put back.
struct WakerCell(Cell<WakerRegistration>);

impl WakerCell {
    /// No waker registered.
    const fn new() -> Self {
        Self(Cell::new(WakerRegistration::new()))
    }

    /// [`WakerRegistration::register`].
    fn register(&self, waker: &Waker) {
        let mut registration = self.0.take();
        registration.register(waker);
        self.0.set(registration);
    }

    /// [`WakerRegistration::wake`], which leaves it empty: as taking it out does.
    fn wake(&self) {
        self.0.take().wake();
    }
}

/// What the process-data runner looks at before it waits ([`SharedEsc::pd_view`]).
pub(crate) struct PdView {
    /// The process-data layout of the current state, when it is new since the last view.
    pub(crate) new_layout: Option<Option<Setup>>,
    /// Process-data trigger events the state-machine runner saw.
    pub(crate) pd_events: AlEvent,
    /// No state-machine event may hold the IRQ line asserted: the process-data runner may wait
    /// on it.
    pub(crate) irq_free: bool,
}

/// What the process-data runner reports to the state-machine runner besides AL events: a set of
/// flags.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Reports(u8);

impl Reports {
    pub(crate) const NONE: Self = Self(0);
    /// Outputs arrived from the MainDevice.
    pub(crate) const OUTPUTS_RECEIVED: Self = Self(1);
    /// A SYNC0-triggered cycle ran.
    pub(crate) const SYNC_RECEIVED: Self = Self(2);
    /// No SYNC0 for too long in OP.
    pub(crate) const SYNC_LOST: Self = Self(4);
    /// The sync error supervision tripped (0x10F1, too many missed SM/SYNC events).
    pub(crate) const SYNC_ERROR: Self = Self(8);

    pub(crate) const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// Whether all of `other` is in `self`.
    pub(crate) const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
}

/// The AL status (0x0130) and AL status code (0x0134) as the state-machine runner publishes
/// them for the indicators: one word, so a publication costs one compare and one store.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Indication(u32);

impl Indication {
    /// Before the state-machine runner's first publication: no AL status (a published one has
    /// a state, never 0).
    pub(crate) const UNPUBLISHED: Self = Self(0);

    /// What the SubDevice presents now.
    pub(crate) fn of<const MBX: usize, L: ecat_core::dictionary::Length>(
        sub: &ecat_core::SubDevice<'_, MBX, L>,
    ) -> Self {
        Self(u32::from(sub.al_status().bits()) | u32::from(sub.al_status_code().0) << 16)
    }

    /// The AL status, `None` before the state-machine runner published (the ESC's INIT).
    pub(crate) fn status(self) -> Option<AlStatus> {
        AlStatus::from_bits(self.0 as u16)
    }

    /// The AL status code.
    pub(crate) fn code(self) -> AlStatusCode {
        AlStatusCode((self.0 >> 16) as u16)
    }
}

/// Emergencies the application may raise between two turns of the state-machine runner: as
/// many as wait in the mailbox, so both queues are one type.
const EMERGENCIES: usize = ecat_core::coe::EMERGENCY_QUEUE;

/// The ESC shared by the two runners, behind critical-section mutexes: the runners may live in
/// different executors.
///
/// The state-machine runner's accesses move in chunks of at most
/// [`Resources::with_chunk`](crate::Resources::with_chunk) bytes, each under its own lock of the PDI, and a process-data access that waits for the PDI
/// takes it at the next chunk boundary: the process-data exchange never waits for more than
/// one chunk of mailbox traffic (plus the transaction in flight), whatever the mailbox size and
/// whether or not the runners share an executor.
pub(crate) struct SharedEsc<P> {
    pdi: Mutex<Cs, P>,
    routing: BlockingMutex<Cs, Routing>,
}

impl<P: Pdi> SharedEsc<P> {
    /// Wraps the PDI driver, with state-machine accesses (mailbox messages, registers) in chunks
    /// of at most `chunk` bytes (0: each access whole, as one transaction), which the driver may
    /// cut smaller at its own boundaries ([`Pdi::chunk`]). Smaller chunks bound the process-data
    /// exchange's wait more tightly and cost more bus overhead per mailbox byte (an address
    /// phase per chunk on the Beckhoff SPI, a PRAM command on the LAN9252;
    /// docs/performance.md). A SyncManager's mailbox buffer is released when its last byte is
    /// read and marked full when its last byte is written, so a mailbox message moved in order,
    /// chunk by chunk, is handed over exactly as a whole one.
    pub(crate) const fn with_chunk(pdi: P, chunk: u16) -> Self {
        Self {
            pdi: Mutex::new(pdi),
            routing: BlockingMutex::new(Routing {
                chunk,
                esm_events: Cell::new(AlEvent::NONE),
                esm_holds_irq: Cell::new(false),
                pd_events: Cell::new(AlEvent::NONE),
                layout: Cell::new(None),
                esm_mask: Cell::new(AlEvent::NONE),
                last_event: Cell::new(AlEvent::NONE),
                indication: Cell::new(Indication::UNPUBLISHED),
                // Evaluated at compile time: no call of `Ring::new` where the firmware builds
                // its resources.
                emergencies: Cell::new(const { Ring::new(Emergency::NONE) }),
                reports: Cell::new(Reports::NONE),
                pd_news: Cell::new(false),
                layout_news: Cell::new(false),
                pd_stopped: Cell::new(false),
                esm_waits_pdi: Cell::new(false),
                esm_waker: WakerCell::new(),
                pd_waker: WakerCell::new(),
                led_waker: WakerCell::new(),
            }),
        }
    }

    /// Performs one access for `runner`; returns the AL event seen, less the bits the access
    /// clears (reading a register clears its event, writing SM1's buffer clears its read event).
    ///
    /// The process-data runner's access is one piece, and the PDI is its at the next chunk
    /// boundary of the state-machine runner: it says that it waits, and the state-machine runner
    /// takes the PDI for its next chunk only once the process-data runner had it (nor while the
    /// process-data runner has news from a chunk it has not looked at). In firmware,
    /// where the process-data runner preempts (an interrupt executor), it takes the PDI as soon as
    /// the chunk in flight releases it; in one cooperative executor the same rule lets it in at
    /// the next chunk boundary as well.
    ///
    /// The state-machine runner's access moves in chunks, in address order, each under its own
    /// lock and routed as an access of its own; it returns what its chunks saw (the union: the
    /// state-machine events are cleared only by that runner's own accesses, so none of them is
    /// stale but the bits the access itself clears).
    #[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
    pub(crate) fn access(
        &self,
        runner: Runner,
        mut address: u16,
        mut rest: Data<'_>,
        clears: AlEvent,
    ) -> impl Future<Output = Result<AlEvent, P::Error>> {
        // The runner with whether the chunk is the first, in one byte beside the data.
        let mut turn = Turn::first(runner);
        async move {
            let mut event = AlEvent::NONE;
            // One wait for the turn and the lock, one driver access, each awaited at one place
            // for both runners: the driver's access future is inlined once.
            loop {
                // The guard dropped at the block's end, not moved: the future keeps no drop flag.
                let seen = {
                    let (mut pdi, chunk) = self.take_pdi(turn).await;
                    let len = match (turn, chunk) {
                        (Turn::ProcessData, _) | (_, 0) => rest.len(),
                        (Turn::EsmFirst | Turn::EsmLater, chunk) => {
                            pdi.chunk(address, rest.len(), usize::from(chunk)).max(1)
                        }
                    };
                    if turn == Turn::EsmFirst {
                        turn = Turn::EsmLater;
                    }
                    let (piece, tail) = rest.split_at(len);
                    rest = tail;
                    // The next chunk's address, taken before the await: the future keeps no
                    // length.
                    let at = address;
                    address = address.wrapping_add(len as u16);
                    // The AL event taken after any outcome (meaningless after an error, and
                    // dropped then): 60 bytes less than a `map` on success
                    // (docs/size-history.md, session 14, chain15).
                    let done = pdi.access(at, piece).await;
                    (done, pdi.al_event())
                };
                event = event.union(self.observe_access(turn.runner(), seen, clears)?);
                if rest.is_empty() {
                    return Ok(event);
                }
            }
        }
    }

    /// The `turn`'s runner's turn and the PDI's lock, in one wait; with the lock taken, the
    /// driver is told what the chunk's AL event must be ([`Pdi::sample`]). The process-data
    /// runner's wait for the PDI is news for the state-machine runner (`pd_news`, until its next
    /// view). The state-machine runner waits while the process-data runner has news it has not
    /// looked at (its trigger seen by a chunk, the IRQ line free again, its wait for the PDI):
    /// that one comes first. In firmware it has always run by then (its interrupt preempts as
    /// soon as it is woken), so this waits only where the runners share an executor. Both
    /// runners must run (the process-data runner says when it stops; a firmware that drops its
    /// future while it waits for the PDI stalls the state machine). The process-data runner,
    /// finding the PDI locked, is woken when the state-machine runner releases it
    /// ([`SharedEsc::observe_access`]); the state-machine runner by the process-data runner's
    /// next view ([`SharedEsc::pd_view`]): the lock's own waiting is not used
    /// (docs/performance.md, "Codegen rules").
    fn take_pdi(&self, turn: Turn) -> impl Future<Output = (MutexGuard<'_, Cs, P>, u16)> + '_ {
        poll_fn(move |cx| {
            self.with(|r| {
                let pd = turn == Turn::ProcessData;
                if pd {
                    // Its wait for the PDI is news the state-machine runner gives way to; its
                    // next view clears it.
                    r.pd_news.set(true);
                }
                // The state-machine runner gives way while the process-data runner has news,
                // which it has while it holds the PDI.
                let pd_first = !pd && r.pd_news.get() && !r.pd_stopped.get();
                let locked = if pd_first {
                    None
                } else {
                    self.pdi.try_lock().ok()
                };
                let Some(mut pdi) = locked else {
                    if pd {
                        r.pd_waker.register(cx.waker());
                    } else {
                        r.esm_waits_pdi.set(true);
                        r.esm_waker.register(cx.waker());
                    }
                    return Poll::Pending;
                };
                // What the chunk's AL event must be, told the driver with the lock taken.
                let sample = if turn != Turn::EsmLater {
                    Sample::Usual
                } else if r.esm_holds_irq.get() {
                    // The trigger makes no edge: a later chunk's AL event is its only news
                    // before the access ends (the first chunk's is what the driver reports
                    // for any access: a short access adds no read of its own).
                    Sample::Fresh
                } else {
                    Sample::Continued
                };
                if sample != Sample::Usual {
                    pdi.sample(sample);
                }
                Poll::Ready((pdi, r.chunk))
            })
        })
    }

    /// Sets the largest chunk of a state-machine access ([`SharedEsc::with_chunk`]).
    pub(crate) fn set_chunk(&mut self, chunk: u16) {
        self.routing.get_mut().chunk = chunk;
    }

    /// After `runner` released the PDI: wakes the process-data runner, which may wait for it
    /// ([`SharedEsc::take_pdi`]; the state-machine runner, which waits for the process-data
    /// runner's news while it holds the PDI, is woken by its next view); when the access
    /// succeeded, the AL event it saw (`seen`, taken from the driver whatever the outcome: no
    /// branch before the routing's), less the bits it cleared, routed.
    fn observe_access<E>(
        &self,
        runner: Runner,
        (done, seen): (Result<(), E>, AlEvent),
        clears: AlEvent,
    ) -> Result<AlEvent, E> {
        let event = done.map(|()| seen.difference(clears));
        self.with(|r| {
            // The process-data runner's waker is the one of its wait for news: it waits at one
            // place at a time (a wake while it waits for news that are set is no loss: they are
            // ready). Its own access wakes nobody.
            if runner == Runner::Esm && r.pd_news.get() {
                r.pd_waker.wake();
            }
            if let Ok(event) = event {
                r.observe(runner, event);
            }
        });
        event
    }

    /// Takes the state-machine events seen by the other runner, ready also when only an
    /// emergency raised by the application or a report of the process-data runner waits; the
    /// state-machine runner's wait polls it.
    pub(crate) fn poll_esm_events(&self, cx: &mut Context<'_>) -> Poll<AlEvent> {
        self.with(|r| {
            let emergencies = r.emergencies.get();
            if r.esm_events.get().is_empty()
                && emergencies.is_empty()
                && r.reports.get() == Reports::NONE
            {
                r.esm_waker.register(cx.waker());
                Poll::Pending
            } else {
                Poll::Ready(r.esm_events.take())
            }
        })
    }

    /// Queues an emergency for the state-machine runner ([`Status::raise_emergency`]).
    pub(crate) fn raise_emergency(&self, emergency: Emergency) {
        self.with(|r| {
            r.emergencies.update(|mut queue| {
                queue.push(emergency);
                queue
            });
            r.esm_waker.wake();
        });
    }

    /// The process-data runner reports `reports` to the state-machine runner.
    pub(crate) fn report(&self, reports: Reports) {
        self.with(|r| {
            r.reports.set(r.reports.get().union(reports));
            r.esm_waker.wake();
        });
    }

    /// Takes what the process-data runner reported and the oldest emergency the application
    /// raised, in one critical section. One emergency at a time, so the queue is never copied
    /// out of the critical section.
    pub(crate) fn take_reports(&self) -> (Reports, Option<Emergency>) {
        self.with(|r| {
            let mut queue = r.emergencies.get();
            let emergency = queue.pop();
            r.emergencies.set(queue);
            (r.reports.replace(Reports::NONE), emergency)
        })
    }

    /// Publishes the AL event mask in the ESC and, when it may be new, the process-data layout
    /// of the current state ([`ecat_core::SubDevice::process_data_news`]: no layouts are
    /// compared). The core writes its mask before anything else, so from the first publication
    /// on, every masked event is one a runner clears.
    /// With them the AL status and code the SubDevice presents, for the indicators.
    pub(crate) fn publish(
        &self,
        news: Option<Option<Setup>>,
        mask: AlEvent,
        indication: Indication,
    ) {
        self.with(|r| {
            let published = r.indication.replace(indication);
            if published != indication {
                r.led_waker.wake();
            }
            // The first publication has news (the core's first answer): the process-data runner
            // looks again, and finds the IRQ line free.
            if let Some(layout) = news {
                r.new_layout(layout);
            }
            r.esm_mask.set(mask.difference(r.trigger()));
            r.update_irq_holder();
        });
    }

    /// What the process-data runner looks at before it waits, in one critical section: the
    /// layout of the current state when it is new, else the trigger events seen by the
    /// state-machine runner and whether the IRQ line is free for it; from then on
    /// [`SharedEsc::pd_changed`] waits for what changes next. Not inlined into the process-data
    /// runner's future (docs/performance.md, "Codegen rules").
    #[inline(never)]
    pub(crate) fn pd_view(&self) -> PdView {
        self.with(|r| {
            let news = r.layout_news.take();
            r.pd_news.set(false);
            if r.esm_waits_pdi.take() {
                r.esm_waker.wake();
            }
            PdView {
                new_layout: news.then(|| r.layout.get()),
                pd_events: if news {
                    AlEvent::NONE
                } else {
                    r.pd_events.take()
                },
                // Before the state-machine runner set up the ESC, its reset mask may hold the line.
                irq_free: r.indication.get() != Indication::UNPUBLISHED && !r.esm_holds_irq.get(),
            }
        })
    }

    /// The process-data runner stopped: the state-machine runner no longer gives way to it.
    pub(crate) fn pd_stopped(&self) {
        self.with(|r| {
            r.pd_stopped.set(true);
            r.esm_waker.wake();
        });
    }

    /// Takes the process-data trigger events seen by the state-machine runner.
    pub(crate) fn take_pd_events(&self) -> AlEvent {
        self.with(|r| r.pd_events.take())
    }

    /// Waits until something changed for the process-data runner since its last
    /// [`SharedEsc::pd_view`]: its trigger was seen, the state-machine events released the IRQ
    /// line, or the layout changed.
    pub(crate) fn pd_changed(&self) -> impl Future<Output = ()> + '_ {
        poll_fn(move |cx| {
            self.with(|r| {
                if r.pd_news.get() {
                    Poll::Ready(())
                } else {
                    r.pd_waker.register(cx.waker());
                    Poll::Pending
                }
            })
        })
    }

    /// The AL status and code last published.
    pub(crate) fn indication(&self) -> Indication {
        self.with(|r| r.indication.get())
    }

    fn with<R>(&self, f: impl FnOnce(&Routing) -> R) -> R {
        self.routing.lock(f)
    }
}

/// The SubDevice as the rest of the firmware sees it: its AL status for the indicators
/// ([`run_indicators`](crate::run_indicators)) and emergencies to send. A reference, `Copy`:
/// hand it to any task of either executor.
pub struct Status<'a, P>(pub(crate) &'a SharedEsc<P>);

impl<P> Clone for Status<'_, P> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<P> Copy for Status<'_, P> {}

impl<'a, P: Pdi> Status<'a, P> {
    /// Raises an emergency (ETG.1000.6 §5.6.4) from anywhere in the firmware: the state-machine
    /// runner queues it in the mailbox, which sends it when SM1 is free and the SubDevice is in
    /// PREOP, SAFEOP or OP. At most 4 wait between two turns of that runner; beyond that the
    /// oldest is dropped and counted ([`Status::emergencies_dropped`]).
    pub fn raise_emergency(self, emergency: Emergency) {
        self.0.raise_emergency(emergency);
    }

    /// How many emergencies [`raise_emergency`](Self::raise_emergency) dropped because 4 were
    /// already waiting for the state-machine runner (saturating at 65 535). The mailbox's own
    /// queue, which waits for SM1, counts its drops apart
    /// ([`SubDevice::emergencies_dropped`](ecat_core::SubDevice::emergencies_dropped)).
    pub fn emergencies_dropped(self) -> u16 {
        self.0.with(|r| r.emergencies.get().dropped())
    }

    /// The AL status and code last published.
    pub(crate) fn indication(self) -> Indication {
        self.0.indication()
    }

    /// The AL status and code last published, once it differs from `seen`: for the indicator
    /// task, which waits for it and for its next edge between two edges.
    pub(crate) fn poll_indication(
        self,
        seen: Indication,
        cx: &mut Context<'_>,
    ) -> Poll<Indication> {
        self.0.with(|r| {
            let now = r.indication.get();
            if now != seen {
                Poll::Ready(now)
            } else {
                r.led_waker.register(cx.waker());
                Poll::Pending
            }
        })
    }
}
