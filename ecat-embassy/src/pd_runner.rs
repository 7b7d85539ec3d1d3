//! The process-data runner: owns the IRQ line, exchanges the process image. Runs in an
//! `InterruptExecutor` at a priority above the thread executor.

use core::cell::Cell;
use core::pin::pin;

use ecat_core::AlEvent;
use ecat_core::dictionary::ObjectDictionary;
use ecat_core::pdo::Direction;
use ecat_core::pdo::image::{pack, unpack};
use ecat_core::pdo::layout::{Layout as PdoLayout, RxLayout};
use ecat_core::process_data::{Clock, Setup};
use ecat_core::register::AL_EVENT_REQUEST;
use ecat_core::sync_parameters::{CycleMonitor, CycleReport};
use embassy_futures::select::{Either4, select4};
use embassy_time::Instant;
use embedded_hal_async::digital::Wait;

use crate::device::Common;
use crate::handed_over::handed_over;
use crate::or_never::OrNever;
use crate::pdi::Data;
use crate::shared::{Reports, Runner};
use crate::time::{now, to_embassy, until_instant as until};
use crate::{Application, Pdi};

/// Why a runner stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<P, I> {
    /// The PDI failed.
    Pdi(P),
    /// Waiting on the IRQ pin failed.
    Irq(I),
    /// The MainDevice configured a process image larger than the buffers of the
    /// [`Resources`](crate::Resources).
    BufferTooSmall,
}

/// The buffers the process image passes through, sized for the device's images.
struct Buffers<'b> {
    /// Receives the output image (SM2).
    outputs: &'b mut [u8],
    /// Holds the input image (SM3).
    inputs: &'b mut [u8],
}

/// Runs the process-data exchange: made by [`Resources::split`](crate::Resources::split), for an
/// `InterruptExecutor` above the state-machine runner's executor. It owns the ESC's IRQ line.
pub struct ProcessDataRunner<'a, P, A, D> {
    common: &'a Common<P, A, D>,
    buffers: Buffers<'a>,
}

impl<'a, P, A, D> ProcessDataRunner<'a, P, A, D>
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
{
    pub(crate) fn new(
        common: &'a Common<P, A, D>,
        outputs: &'a mut [u8],
        inputs: &'a mut [u8],
    ) -> Self {
        Self {
            common,
            buffers: Buffers { outputs, inputs },
        }
    }

    /// Runs until something fails, for a device without distributed clocks (or whose SYNC0
    /// does not start the cycle); returns why it stopped, after the application's
    /// [`safe_state`](Application::safe_state) if outputs were applied. `irq` is the ESC's IRQ
    /// pin (active low, e.g. an `ExtiInput`).
    pub fn run<I: Wait + 'a>(self, irq: I) -> impl Future<Output = Error<P::Error, I::Error>> + 'a {
        self.run_with_sync0(irq, NoSync0::new())
    }

    /// [`ProcessDataRunner::run`] with the ESC's SYNC0 output `sync0` (a pulse per DC cycle;
    /// its rising edge starts a cycle when the MainDevice chose DC SYNC0 mode).
    ///
    /// In SAFEOP and OP each trigger (SM2 written by the MainDevice, or SM3 read by it for an
    /// input-only device) costs a read of the AL event alone (an empty read), a read of the
    /// output area and a write of the input area. Between the last two, with the application
    /// locked: the outputs are unpacked into their mapped entries (in OP only), the
    /// application's [`cycle`](Application::cycle) runs, the mapped input entries are packed.
    ///
    /// The output area is read only after an AL event read showed the trigger (the runner's
    /// own on the IRQ, or an access of the other runner): reading it takes the newest SM2 buffer
    /// and clears the SM2 event, so a read made on the IRQ of another event (a mailbox's) would
    /// take a buffer that arrived after the AL event was sampled, with nothing left to report
    /// it: a lost cycle. Sampled first, a buffer that arrives later keeps its event, and the IRQ
    /// line, until the next wake-up.
    pub fn run_with_sync0<I, S>(
        self,
        irq: I,
        sync0: S,
    ) -> impl Future<Output = Error<P::Error, I::Error>> + 'a
    where
        I: Wait + 'a,
        S: Wait<Error = I::Error> + 'a,
    {
        let Self { common, buffers } = self;
        async move {
            // The runner's own future never completes: the error it hands over ends this one.
            let error = Cell::new(None);
            handed_over(
                &error,
                run(common, irq, sync0, buffers, |e| error.set(Some(e))),
            )
            .await
        }
    }

    /// [`run`](Self::run), then `stopped` with why it stopped, then nothing more: the future
    /// never completes. For a task around the runner: a future that never completes has no
    /// "resumed after completion" panic path (docs/performance.md, "Codegen rules").
    pub fn run_then<I: Wait + 'a>(
        self,
        irq: I,
        stopped: impl FnOnce(Error<P::Error, I::Error>) + 'a,
    ) -> impl Future<Output = ()> + 'a {
        run(self.common, irq, NoSync0::new(), self.buffers, stopped)
    }

    /// [`run_with_sync0`](Self::run_with_sync0), then `stopped` with why it stopped, then
    /// nothing more, as [`run_then`](Self::run_then).
    pub fn run_with_sync0_then<I, S>(
        self,
        irq: I,
        sync0: S,
        stopped: impl FnOnce(Error<P::Error, I::Error>) + 'a,
    ) -> impl Future<Output = ()> + 'a
    where
        I: Wait + 'a,
        S: Wait<Error = I::Error> + 'a,
    {
        run(self.common, irq, sync0, self.buffers, stopped)
    }
}

/// The loop of [`ProcessDataRunner::run_with_sync0`].
#[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
fn run<'a, P, I, S, A, D>(
    common: &'a Common<P, A, D>,
    mut irq: I,
    mut sync0: S,
    buffers: Buffers<'a>,
    stopped: impl FnOnce(Error<P::Error, I::Error>) + 'a,
) -> impl Future<Output = ()> + 'a
where
    P: Pdi,
    I: Wait + 'a,
    S: Wait<Error = I::Error> + 'a,
    A: Application<D>,
    D: ObjectDictionary,
{
    // Made before the future: the future holds the exchange, not also the references and
    // buffers it is made of (an async block keeps what it captures apart from its locals).
    let mut exchange = Exchange {
        common,
        buffers,
        images: None,
        monitor: CycleMonitor::default(),
        reported: Reported::default(),
        trigger_sampled: false,
    };
    async move {
        let mut current: Option<Setup> = None;
        // Free-run: the next cycle's deadline; each follows the previous by one cycle (no drift).
        // DC SYNC0 in OP: when SYNC0 counts as lost (see `SYNC0_LOSS_CYCLES`).
        // `NO_TICK`: none (an `Option<Instant>` is 16 bytes: the instant has no niche).
        let mut tick = NO_TICK;
        // Every way out of the loop ends here: the state-machine runner stops giving way.
        let error = 'run: loop {
            // What woke the runner and what follows; the view and its copy of the layout end here,
            // so only `current` lives on across the waits and the exchange.
            let then = {
                let view = common.esc.pd_view();
                let sampled = core::mem::take(&mut exchange.trigger_sampled);
                if let Some(layout) = view.new_layout {
                    let was_active = current.is_some_and(|l| l.outputs_active);
                    current = layout;
                    if was_active && !layout.is_some_and(|l| l.outputs_active) {
                        exchange.safe_state();
                    }
                    tick = layout.and_then(first_deadline::<D>).unwrap_or(NO_TICK);
                    exchange.on_new_layout(layout)
                } else if sampled || !view.pd_events.is_empty() {
                    Some(Then::triggered(current, true))
                } else {
                    // The layout is `current`: no second copy is kept across the wait.
                    let sync0_on = current.is_some_and(sync0_starts::<D>);
                    let mut irq_low = pin!(irq.wait_for_low());
                    let mut sync0_edge = pin!(sync0.wait_for_rising_edge());
                    match select4(
                        OrNever(view.irq_free.then_some(irq_low.as_mut())),
                        common.esc.pd_changed(),
                        until((tick != NO_TICK).then_some(tick)),
                        OrNever(sync0_on.then_some(sync0_edge.as_mut())),
                    )
                    .await
                    {
                        Either4::First(Ok(())) => Some(Then::triggered(current, false)),
                        Either4::First(Err(e)) | Either4::Fourth(Err(e)) => {
                            break 'run Error::Irq(e);
                        }
                        Either4::Second(()) => None,
                        Either4::Third(()) => exchange.on_tick(current, &mut tick),
                        Either4::Fourth(Ok(())) => {
                            tick = current.and_then(first_deadline::<D>).unwrap_or(NO_TICK);
                            exchange.on_sync0(current)
                        }
                    }
                }
            };
            let Some(then) = then else { continue };
            // The read `then` starts with, then the cycle when the read confirms it, then the
            // write of the inputs: the two accesses of an exchange, awaited at one place rather
            // than in a future of their own.
            let mut access = match exchange.read(then, current) {
                Ok(access) => access,
                Err(e) => break 'run e,
            };
            let mut then = Some(then);
            loop {
                let mut event = AlEvent::NONE;
                if let Some((address, data, clears)) = access {
                    match common
                        .esc
                        .access(Runner::ProcessData, address, data, clears)
                        .await
                    {
                        Ok(seen) => event = seen,
                        Err(e) => break 'run Error::Pdi(e),
                    }
                }
                let Some(then) = then.take() else { break };
                access = match exchange.after_read(then, event, &current) {
                    Ok(access) => access,
                    Err(e) => break 'run e,
                };
            }
        };
        common.esc.pd_stopped();
        if current.is_some_and(|l| l.outputs_active) {
            exchange.safe_state();
        }
        stopped(error);
        // Never completing, the future has no "resumed after completion" panic path.
        loop {
            core::future::pending::<()>().await;
        }
    }
}

/// What a wake-up of the runner leads to: at most one read (the output area, or the AL event
/// alone, which routes the IRQ's cause; [`Exchange::read`]), then maybe a cycle (whose input
/// write is the only other access), on the current layout. The decisions are synchronous, so
/// the runner's future holds one access at a time, whatever woke it. A read of the AL event
/// alone that shows the trigger leads to a turn that reads the outputs.
#[derive(Clone, Copy)]
enum Then {
    /// Nothing: the read only routed the AL event to the state-machine runner.
    Nothing,
    /// The cycle that starts a new layout: valid inputs at once, no outputs applied.
    FirstCycle,
    /// A cycle started by a clock (free-run timer or SYNC0); the SM2 event the read brings along
    /// tells whether the MainDevice sent outputs.
    Clocked,
    /// A cycle on the trigger event, unless the read shows it was not the trigger. `true`: the
    /// trigger was seen before the read (by the other runner, or by the AL event read before a
    /// read of the outputs). `false`: the read was of the AL event alone; if it shows the trigger,
    /// the outputs are read next turn.
    Triggered(bool),
}

impl Then {
    /// The IRQ fired (`known` = false) or the other runner saw the trigger (`known` = true).
    /// Not exchanging process data on events (none, or free-run): the IRQ is for the state
    /// machine, and reading the AL event routes it there.
    fn triggered(layout: Option<Setup>, known: bool) -> Self {
        if layout.is_some_and(|l| l.period().is_none()) {
            Self::Triggered(known)
        } else {
            Self::Nothing
        }
    }
}

/// The PDO layouts of both directions, from the dictionary's assignment and mapping objects.
struct Images<D: ObjectDictionary> {
    outputs: Option<RxLayout<D>>,
    inputs: Option<PdoLayout<D>>,
}

/// The write an exchange ends with: the input area's address and the input image, if the
/// device has inputs.
type InputWrite<'b> = Option<(u16, &'b [u8])>;

/// One of the two accesses of an exchange, if it makes it: the address, the data and the AL
/// event bits it clears.
type ExchangeAccess<'b> = Option<(u16, Data<'b>, AlEvent)>;

/// What one exchange needs.
// `repr(C)`, the PDO images first: the future is built at spawn with the images `None`, and
// the buffers beside its other parts rather than behind 80 bytes the builder copies undefined
// (docs/performance.md, "Codegen rules").
#[repr(C)]
struct Exchange<'a, P, A, D: ObjectDictionary> {
    images: Option<Images<D>>,
    buffers: Buffers<'a>,
    /// The diagnostics of 0x1C32/0x1C33.
    monitor: CycleMonitor,
    common: &'a Common<P, A, D>,
    /// What the state-machine runner was told since the layout changed: it needs the first
    /// outputs and the first SYNC0 cycle after entering SAFEOP (for SAFEOP→OP), not every one.
    reported: Reported,
    /// The AL event read on the IRQ showed the trigger: the next turn reads the outputs.
    trigger_sampled: bool,
}

/// News the process-data runner already passed on for the current layout.
#[derive(Debug, Clone, Copy, Default)]
struct Reported {
    outputs: bool,
    sync: bool,
}

impl<P: Pdi, A: Application<D>, D: ObjectDictionary> Exchange<'_, P, A, D> {
    /// Outputs are no longer applied: the application's safe state.
    fn safe_state(&mut self) {
        self.common.app.lock(|app, od| app.safe_state(od));
    }

    /// Entering SAFEOP (or a new layout): the PDO layouts of the configuration the SubDevice
    /// accepted, and valid inputs at once.
    fn on_new_layout(&mut self, layout: Option<Setup>) -> Option<Then> {
        self.reported = Reported::default();
        if layout.is_none() {
            self.images = None;
            return None;
        }
        if self.images.is_none() {
            self.monitor.reset();
        }
        self.images = self.common.app.lock(|_, od| {
            Some(Images {
                outputs: RxLayout::outputs(&*od).ok().flatten(),
                inputs: PdoLayout::of(&*od, Direction::Tx).ok().flatten(),
            })
        });
        Some(Then::FirstCycle)
    }

    /// Free-run: a cycle is due. It reads the outputs (their SM2 event, coming along, tells
    /// whether the MainDevice sent any) and runs; the next one is due one cycle later.
    /// DC SYNC0 in OP: no SYNC0 for [`SYNC0_LOSS_CYCLES`] cycles, reported once.
    fn on_tick(&mut self, layout: Option<Setup>, tick: &mut Instant) -> Option<Then> {
        let layout = layout?;
        if sync0_starts::<D>(layout) {
            *tick = NO_TICK;
            self.common.esc.report(Reports::SYNC_LOST);
            return None;
        }
        if let Some(period) = layout.period() {
            *tick = tick.checked_add(to_embassy(period)).unwrap_or(NO_TICK);
        }
        Some(Then::Clocked)
    }

    fn on_sync0(&mut self, layout: Option<Setup>) -> Option<Then> {
        layout.filter(Setup::sync0)?;
        if !core::mem::replace(&mut self.reported.sync, true) {
            self.common.esc.report(Reports::SYNC_RECEIVED);
        }
        Some(Then::Clocked)
    }

    /// The read `then` starts with on `layout`: the output area into the output buffer
    /// (`Clocked`, and `Triggered` when the trigger is known), or nothing at the AL event
    /// register (an empty read: the AL event alone, which is all an IRQ's `Triggered` reads
    /// first); `None` when it reads nothing.
    fn read<I>(
        &mut self,
        then: Then,
        layout: Option<Setup>,
    ) -> Result<ExchangeAccess<'_>, Error<P::Error, I>> {
        let outputs = layout.and_then(|l| l.outputs);
        let (address, buf) = match (then, outputs) {
            (Then::FirstCycle, _) | (Then::Clocked, None) => return Ok(None),
            (Then::Clocked | Then::Triggered(true), Some(area)) => (
                area.start,
                self.buffers
                    .outputs
                    .get_mut(..usize::from(area.length))
                    .ok_or(Error::BufferTooSmall)?,
            ),
            (Then::Nothing | Then::Triggered(_), _) => (AL_EVENT_REQUEST, &mut [][..]),
        };
        Ok(Some((address, Data::Read(buf), AlEvent::NONE)))
    }

    /// What follows the read of `then`, which saw `event`: the cycle when the read confirms it.
    /// Returns the write of the inputs, if any (it clears the SM3 event).
    fn after_read<I>(
        &mut self,
        then: Then,
        event: AlEvent,
        layout: &Option<Setup>,
    ) -> Result<ExchangeAccess<'_>, Error<P::Error, I>> {
        let (layout, new_outputs) = match (then, layout) {
            (Then::Nothing, _) | (_, None) => return Ok(None),
            (Then::FirstCycle, Some(layout)) => (layout, None),
            (Then::Clocked, Some(layout)) => {
                (layout, Some(event.intersects(AlEvent::sync_manager(2))))
            }
            (Then::Triggered(known), Some(layout)) => {
                // Taken whatever the read saw: a trigger the other runner saw before it is the
                // one this read (or the read of the outputs it leads to) consumes, and must not
                // start a second cycle.
                let seen = !self.common.esc.take_pd_events().is_empty();
                if !(known || seen || event.intersects(layout.trigger())) {
                    return Ok(None);
                }
                if !known && layout.outputs.is_some() {
                    // The AL event alone showed the trigger: the outputs are read next turn.
                    self.trigger_sampled = true;
                    return Ok(None);
                }
                (layout, Some(layout.outputs.is_some()))
            }
        };
        let apply = new_outputs.is_some() && layout.outputs_active && layout.outputs.is_some();
        let write = self.cycle(layout, apply, new_outputs)?;
        Ok(write.map(|(address, inputs)| (address, Data::Write(inputs), AlEvent::sync_manager(3))))
    }

    /// One exchange: outputs (already read) into the dictionary when `apply_outputs`, the
    /// application's cycle, the inputs packed. `new_outputs`, for a cycle of the sync mode (not
    /// the one that starts a new layout, which applies no outputs): whether the MainDevice wrote
    /// SM2 since the last cycle, for the state-machine runner (once per layout) and the cycle
    /// diagnostics. Returns the input area's address and image, to be written.
    fn cycle<I>(
        &mut self,
        layout: &Setup,
        apply_outputs: bool,
        new_outputs: Option<bool>,
    ) -> Result<InputWrite<'_>, Error<P::Error, I>> {
        let out_len = layout.outputs.map_or(0, |a| usize::from(a.length));
        let in_len = layout.inputs.map_or(0, |a| usize::from(a.length));
        let outputs = self
            .buffers
            .outputs
            .get(..out_len)
            .ok_or(Error::BufferTooSmall)?;
        let inputs = self
            .buffers
            .inputs
            .get_mut(..in_len)
            .ok_or(Error::BufferTooSmall)?;
        let (images, monitor) = (&self.images, &mut self.monitor);
        let report = new_outputs.map(|new_outputs| CycleReport {
            now: now(),
            nominal: layout.period(),
            expects_outputs: sync0_starts::<D>(*layout) && apply_outputs,
            new_outputs,
        });
        let sync_error = self.common.app.lock(|app, od| {
            let sync_error = report.is_some_and(|report| monitor.cycle(od, report));
            let pdo = images.as_ref();
            if let (true, Some(rx)) = (apply_outputs, pdo.and_then(|i| i.outputs.as_ref())) {
                unpack(rx, outputs, od);
            }
            app.cycle(od, apply_outputs.then_some(outputs), inputs);
            if let Some(tx) = pdo.and_then(|i| i.inputs.as_ref()) {
                pack(tx, od, inputs);
            }
            sync_error
        });
        // What the state-machine runner is told, in one report: the first outputs of the
        // layout, a tripped sync error supervision.
        let mut reports = Reports::NONE;
        if new_outputs == Some(true) && !core::mem::replace(&mut self.reported.outputs, true) {
            reports = Reports::OUTPUTS_RECEIVED;
        }
        if sync_error {
            reports = reports.union(Reports::SYNC_ERROR);
        }
        if reports != Reports::NONE {
            self.common.esc.report(reports);
        }
        Ok(layout.inputs.map(|area| (area.start, &*inputs)))
    }
}

/// SYNC0 counts as lost in OP after this many SYNC0 cycles without a pulse (conformance:
/// "In OP: SYNC0 lost → 0x002C").
pub const SYNC0_LOSS_CYCLES: u32 = 10;

/// Whether SYNC0 starts the cycles of `layout` ([`Setup::sync0`]): never for a dictionary
/// without DC SYNC0 (`D::SYNC_MODES`), known at compile time, so such a device carries none of
/// the SYNC0 paths.
fn sync0_starts<D: ObjectDictionary>(layout: Setup) -> bool {
    D::SYNC_MODES.dc() && layout.sync0()
}

/// The first deadline of a new layout or after a SYNC0 pulse: the next free-run cycle, or in DC
/// SYNC0 mode in OP the instant SYNC0 counts as lost. A deadline beyond Embassy's clock is none
/// (the checked arithmetic has no panic path).
fn first_deadline<D: ObjectDictionary>(layout: Setup) -> Option<Instant> {
    let now = Instant::now();
    match layout.clock {
        Clock::FreeRun(period) => now.checked_add(to_embassy(period.duration())),
        Clock::Sync0(period) if D::SYNC_MODES.dc() && layout.outputs_active => {
            to_embassy(period.duration())
                .checked_mul(SYNC0_LOSS_CYCLES)
                .and_then(|lost| now.checked_add(lost))
        }
        Clock::Sync0(_) | Clock::Event(_) => None,
    }
}

/// The process-data loop's tick when none is due: the end of time (a deadline past it would
/// overflow, and is none as well).
const NO_TICK: Instant = Instant::MAX;

/// The SYNC0 input of a device without distributed clocks: it never pulses.
struct NoSync0<E = core::convert::Infallible>(core::marker::PhantomData<E>);

impl<E> NoSync0<E> {
    /// No SYNC0 pin.
    const fn new() -> Self {
        Self(core::marker::PhantomData)
    }
}

impl<E: embedded_hal::digital::Error> embedded_hal::digital::ErrorType for NoSync0<E> {
    type Error = E;
}

/// Each wait is a future that never completes (docs/performance.md, "Codegen rules").
impl<E: embedded_hal::digital::Error> Wait for NoSync0<E> {
    fn wait_for_high(&mut self) -> impl Future<Output = Result<(), E>> {
        core::future::pending()
    }

    fn wait_for_low(&mut self) -> impl Future<Output = Result<(), E>> {
        core::future::pending()
    }

    fn wait_for_rising_edge(&mut self) -> impl Future<Output = Result<(), E>> {
        core::future::pending()
    }

    fn wait_for_falling_edge(&mut self) -> impl Future<Output = Result<(), E>> {
        core::future::pending()
    }

    fn wait_for_any_edge(&mut self) -> impl Future<Output = Result<(), E>> {
        core::future::pending()
    }
}
