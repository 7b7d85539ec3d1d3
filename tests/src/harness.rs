//! Runs a SubDevice on the host exactly as firmware runs it: the real `ecat-embassy` runners as
//! tasks, the process-data runner at interrupt level (it runs before any thread-mode task is
//! polled again whenever it is woken, as a pended interrupt preempts the thread executor:
//! [`scheduler`]), the emulated ESC behind the PDI, embassy-time's mock driver
//! as the clock, and a scripted MainDevice.
//!
//! The mock driver is global to the process, so scenarios in one test binary run one at a time.

use core::cell::{Cell, RefCell};
use core::future::Future;
use core::pin::Pin;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};

use ecat_core::coe::Emergency;
use ecat_core::dictionary::{ObjectDictionary, ObjectHooks};
use ecat_core::mailbox::Handlers;
use ecat_core::{AlStatusCode, DeviceConfig, Transition};
use ecat_embassy::{Application, Config, Pdi, Resources, Status};
use embassy_futures::select::select;
use embassy_time::MockDriver;

use crate::emulator::{EmulatedPdi, Emulator};
use crate::esc::EscConfig;
use crate::flash::{self, Flash};
use crate::master::TestMaster;
use crate::scheduler::{self, Scheduler, Task};

/// Serialises scenarios: the mock time driver is one per process.
static SERIAL: Mutex<()> = Mutex::new(());

/// Holds the mock time driver for the caller alone until dropped: for tests that move the
/// clock outside a scenario.
pub fn exclusive() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A scenario still running after this much wall-clock time is hung (a task spinning without
/// yielding): the test process aborts with a message instead of hanging CI. Scenarios take
/// milliseconds; all their waiting is in virtual time.
const HANG_LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

/// Aborts the process if the scenario it guards outlives [`HANG_LIMIT`].
struct HangGuard(std::sync::mpsc::Sender<()>);

impl HangGuard {
    fn arm(limit: std::time::Duration) -> Self {
        let (done, finished) = std::sync::mpsc::channel::<()>();
        std::thread::spawn(move || {
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(limit) {
                eprintln!(
                    "harness: scenario still running after {limit:?}: a task spins without yielding"
                );
                std::process::abort();
            }
        });
        Self(done)
    }
}

impl Drop for HangGuard {
    fn drop(&mut self) {
        let _ = self.0.send(());
    }
}

/// Largest process image the harness's runner buffers hold.
const MAX_IMAGE: usize = 1024;
/// Largest mailbox the harness's SubDevice holds.
const MAX_MAILBOX: usize = 1024;

/// Tells every runner of a scenario to stop: once signalled, every wait on it completes, for
/// however many tasks wait. (An embassy-sync `Signal` holds one waker: two runners waiting on
/// one woke each other in turn, for ever: the virtual slave spun a core at idle.)
#[derive(Default)]
pub struct Stop {
    stopped: Cell<bool>,
    waiters: RefCell<Vec<core::task::Waker>>,
}

impl Stop {
    /// Stops every waiter, now and later.
    pub fn signal(&self) {
        self.stopped.set(true);
        for waker in self.waiters.borrow_mut().drain(..) {
            waker.wake();
        }
    }

    /// Completes once [`Stop::signal`] was called.
    pub async fn wait(&self) {
        core::future::poll_fn(|cx| {
            if self.stopped.get() {
                core::task::Poll::Ready(())
            } else {
                crate::emulator::register(&self.waiters, cx.waker());
                core::task::Poll::Pending
            }
        })
        .await
    }
}

/// Polls of the runners so far, in this process: a runner polled while nothing changed for it
/// is a busy loop.
static RUNNER_POLLS: AtomicU64 = AtomicU64::new(0);

/// How often the runners were polled so far, in this process.
pub fn runner_polls() -> u64 {
    RUNNER_POLLS.load(Ordering::Relaxed)
}

/// The device under test.
pub struct Device<A, C, D = ()> {
    /// The description the SubDevice checks against.
    pub config: DeviceConfig,
    /// The state, SDO and emergency side of the application ([`Pair`]).
    pub app: A,
    /// The process-data side of the application: its cycle and safe state ([`Pair`]).
    pub cycle: C,
    /// The emulated ESC's hardware.
    pub esc: EscConfig,
    /// The explicit device ID.
    pub device_id: u16,
    /// What the MainDevice did to the ESC before the firmware started.
    pub before_start: fn(&TestMaster),
    /// The object dictionary.
    pub od: D,
    /// The SII EEPROM image the ESC loads at power-on (empty: no EEPROM).
    pub eeprom: Vec<u8>,
    /// The largest chunk of a state-machine access (`Resources::with_chunk`; 0: whole accesses).
    pub chunk: u16,
    /// How the harness orders the runners ([`run`] and [`run_with_pdi`]).
    pub scheduler: Scheduler,
    /// Both runners in one task (`Resources::run`, no SYNC0), as a first device in one executor
    /// runs them.
    pub one_task: bool,
    /// The flash whose PARAMETERS partition keeps the stored parameters (0x1010), loaded into
    /// the dictionary at start-up ([`Device::with_parameters`]); `None`: no storage.
    pub parameters: Option<Flash>,
}

impl<A, C> Device<A, C, ()> {
    /// `config` with the given hooks, no dictionary, an ET1100-like ESC and device ID 0.
    pub fn new(config: DeviceConfig, app: A, cycle: C) -> Self {
        Self {
            config,
            app,
            cycle,
            esc: EscConfig::default(),
            device_id: 0,
            before_start: |_| {},
            od: (),
            eeprom: Vec::new(),
            chunk: ecat_embassy::device::DEFAULT_CHUNK,
            scheduler: Scheduler::Preemptive,
            one_task: false,
            parameters: None,
        }
    }
}

impl<A, C, D> Device<A, C, D> {
    /// The same device with the object dictionary `od`.
    pub fn with_dictionary<E>(self, od: E) -> Device<A, C, E> {
        let Device {
            config,
            app,
            cycle,
            esc,
            device_id,
            before_start,
            eeprom,
            chunk,
            scheduler,
            one_task,
            parameters,
            ..
        } = self;
        Device {
            config,
            app,
            cycle,
            esc,
            device_id,
            before_start,
            od,
            eeprom,
            chunk,
            scheduler,
            one_task,
            parameters,
        }
    }

    /// The same device with both runners in one task ([`Device::one_task`]).
    pub fn in_one_task(mut self) -> Self {
        self.one_task = true;
        self
    }

    /// The same device storing its parameters in `flash`'s PARAMETERS partition.
    pub fn with_parameters(mut self, flash: Flash) -> Self {
        self.parameters = Some(flash);
        self
    }

    /// The same device with the SII EEPROM image `eeprom`.
    pub fn with_eeprom(mut self, eeprom: Vec<u8>) -> Self {
        self.eeprom = eeprom;
        self
    }
}

/// An [`Application`] that accepts every transition at once and has no object hooks.
pub struct AcceptAll;

impl<D> Application<D> for AcceptAll {}

/// An [`Application`] whose cycle copies the raw outputs to the raw inputs (as far as both
/// reach).
pub struct Loopback;

impl<D> Application<D> for Loopback {
    fn cycle(&mut self, _od: &mut D, outputs: Option<&[u8]>, inputs: &mut [u8]) {
        if let Some(outputs) = outputs {
            for (i, o) in inputs.iter_mut().zip(outputs) {
                *i = *o;
            }
        }
    }
}

/// One [`Application`] made of two, as the tests write them: `hooks`'s transition, state-change,
/// SDO, mailbox and emergency hooks, `cycle`'s cycle and safe state.
pub struct Pair<A, C> {
    /// The state-machine side.
    pub hooks: A,
    /// The process-data side.
    pub cycle: C,
}

impl<A: Application<D>, C: Application<D>, D> Application<D> for Pair<A, C> {
    fn cycle(&mut self, od: &mut D, outputs: Option<&[u8]>, inputs: &mut [u8]) {
        self.cycle.cycle(od, outputs, inputs);
    }

    fn safe_state(&mut self, od: &mut D) {
        self.cycle.safe_state(od);
    }

    fn on_transition(
        &mut self,
        transition: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> + use<A, C, D> {
        self.hooks.on_transition(transition)
    }

    fn on_state_change(&mut self, transition: Transition) {
        self.hooks.on_state_change(transition);
    }

    fn object_hooks(&mut self) -> impl ObjectHooks<D> + '_ {
        self.hooks.object_hooks()
    }

    fn mailbox(&mut self) -> (impl ObjectHooks<D> + '_, impl Handlers + '_) {
        self.hooks.mailbox()
    }

    fn take_emergency(&mut self) -> Option<Emergency> {
        self.hooks.take_emergency()
    }
}

/// Runs `script` against `device` until the script ends, then stops the runners. The runners
/// reach the emulated ESC through [`EmulatedPdi`].
pub fn run<A, C, D, F>(device: Device<A, C, D>, script: impl FnOnce(TestMaster) -> F)
where
    A: Application<D> + 'static,
    C: Application<D> + 'static,
    D: ObjectDictionary,
    F: Future<Output = ()> + 'static,
{
    run_with_pdi(device, |emu: &Emulator| emu.pdi(), script);
}

/// Like [`run`], with the runners reaching the emulated ESC through the PDI `make_pdi` builds
/// on it (e.g. an SPI driver talking to a fake SPI chip in front of the emulator).
pub fn run_with_pdi<A, C, D, P, F>(
    device: Device<A, C, D>,
    make_pdi: impl FnOnce(&Emulator) -> P,
    script: impl FnOnce(TestMaster) -> F,
) where
    A: Application<D> + 'static,
    C: Application<D> + 'static,
    D: ObjectDictionary,
    P: Pdi + 'static,
    F: Future<Output = ()> + 'static,
{
    let scheduler = device.scheduler;
    execute(Some(HANG_LIMIT), scheduler, |stop| {
        let emu = device.emulator();
        let pdi = make_pdi(&emu);
        let (mut futures, status) = device.runners(&emu, pdi, stop);
        let master = TestMaster::new(emu.clone()).with_firmware(move |e| status.raise_emergency(e));
        futures.push(Task::thread(scenario(
            stop,
            TestMaster::new(emu),
            script(master),
        )));
        futures
    });
}

/// Like [`run`], with more tasks beside the runners (e.g. the indicator task), which `extra`
/// builds on the SubDevice's [`Status`]; they stop when the script ends. Each waits for
/// that on a signal of its own: tasks waiting on one [`Signal`](embassy_sync::signal::Signal) wake each other (it keeps one
/// waker and wakes the one it replaces), which would hide whether a task wakes only when it
/// should.
pub fn run_with_tasks<A, C, D, F>(
    device: Device<A, C, D>,
    extra: impl FnOnce(Status<'static, EmulatedPdi>) -> Vec<BoxedTask>,
    script: impl FnOnce(TestMaster) -> F,
) where
    A: Application<D> + 'static,
    C: Application<D> + 'static,
    D: ObjectDictionary,
    F: Future<Output = ()> + 'static,
{
    let scheduler = device.scheduler;
    execute(Some(HANG_LIMIT), scheduler, |stop| {
        let emu = device.emulator();
        let (mut futures, status) = device.runners(&emu, emu.pdi(), stop);
        let mut ends: Vec<&'static Stop> = Vec::new();
        for task in extra(status) {
            let end: &'static Stop = Box::leak(Box::new(Stop::default()));
            ends.push(end);
            futures.push(Task::thread(async move {
                select(task, end.wait()).await;
            }));
        }
        let master = TestMaster::new(emu.clone()).with_firmware(move |e| status.raise_emergency(e));
        let script = scenario(stop, TestMaster::new(emu), script(master));
        futures.push(Task::thread(async move {
            script.await;
            for end in ends {
                end.signal();
            }
        }));
        futures
    });
}

/// Runs several SubDevices, each on its own emulated ESC, and `script` with their emulators (in
/// the order given) until the script ends; then stops the runners. For MainDevices that talk to
/// the ESCs at the frame level.
pub fn run_many<F>(devices: Vec<Box<dyn Spawn>>, script: impl FnOnce(Vec<Emulator>) -> F)
where
    F: Future<Output = ()> + 'static,
{
    execute_many(devices, script, Some(HANG_LIMIT), None);
}

/// Like [`run_many`] but for as long as the script runs, without the test harness's limit on
/// wall-clock time: for programs that serve emulated SubDevices (a virtual slave, a demo). The
/// runners share at most [`SERVED_TASKS`] tasks, however long the line.
pub fn serve<F>(devices: Vec<Box<dyn Spawn>>, script: impl FnOnce(Vec<Emulator>) -> F)
where
    F: Future<Output = ()> + 'static,
{
    execute_many(devices, script, None, Some(SERVED_TASKS));
}

/// The most tasks [`serve`] runs the runners of a line in. A task waiting on a timer takes one
/// entry of embassy-time's timer queue (the generic queue: 128 entries at most, entries told
/// apart by waker); a full queue wakes its last timer early, which then takes an entry again and
/// wakes the next: with one task per runner, a line of more than 64 SubDevices whose runners
/// all wait on timers at once (free-run cycles, transitions left pending) spun a core. Runners
/// sharing a task share its waker, so the queue holds one entry per task whatever the line's
/// length; the price is that a wake polls every runner of the task.
pub const SERVED_TASKS: usize = 64;

fn execute_many<F>(
    devices: Vec<Box<dyn Spawn>>,
    script: impl FnOnce(Vec<Emulator>) -> F,
    limit: Option<std::time::Duration>,
    tasks: Option<usize>,
) where
    F: Future<Output = ()> + 'static,
{
    execute(limit, Scheduler::Preemptive, |stop| {
        let mut runners = Vec::new();
        let mut emulators = Vec::new();
        for device in devices {
            let emu = device.emulator();
            runners.extend(device.spawn(&emu, stop));
            emulators.push(emu);
        }
        let mut futures = match tasks {
            Some(tasks) => share(runners, tasks),
            None => runners,
        };
        let masters: Vec<TestMaster> = emulators.iter().cloned().map(TestMaster::new).collect();
        let script = script(emulators);
        futures.push(Task::thread(async move {
            for master in &masters {
                master.settle().await;
            }
            script.await;
            stop.signal();
        }));
        futures
    });
}

/// `runners` in at most `tasks` futures, consecutive runners together: each future polls all
/// of its runners whenever its task is woken, until every one of them ended.
fn share(runners: Vec<Task>, tasks: usize) -> Vec<Task> {
    // Runners of one level share tasks of that level: the process-data runners stay at
    // interrupt level, each level gets half of `tasks`.
    let (interrupt, thread): (Vec<Task>, Vec<Task>) =
        runners.into_iter().partition(|task| task.interrupt);
    let per_level = (tasks / 2).max(1);
    let mut shared = Vec::new();
    for (at_interrupt, runners) in [(true, interrupt), (false, thread)] {
        let per_task = runners.len().div_ceil(per_level).max(1);
        let mut runners = runners.into_iter().map(|task| task.future).peekable();
        while runners.peek().is_some() {
            let mut group: Vec<_> = runners.by_ref().take(per_task).collect();
            let future = core::future::poll_fn(move |cx| {
                group.retain_mut(|runner| runner.as_mut().poll(cx).is_pending());
                if group.is_empty() {
                    core::task::Poll::Ready(())
                } else {
                    core::task::Poll::Pending
                }
            });
            shared.push(if at_interrupt {
                Task::interrupt(future)
            } else {
                Task::thread(future)
            });
        }
    }
    shared
}

/// A device that [`run_many`] can start next to devices of other types.
pub trait Spawn {
    /// A new emulated ESC for the device, loaded with its SII image.
    fn emulator(&self) -> Emulator;
    /// The device's two runners on `emu`, stopping when `stop` is signalled.
    fn spawn(self: Box<Self>, emu: &Emulator, stop: &'static Stop) -> Vec<Task>;
}

impl<A, C, D> Spawn for Device<A, C, D>
where
    A: Application<D> + 'static,
    C: Application<D> + 'static,
    D: ObjectDictionary,
{
    fn emulator(&self) -> Emulator {
        Device::emulator(self)
    }

    fn spawn(self: Box<Self>, emu: &Emulator, stop: &'static Stop) -> Vec<Task> {
        self.runners(emu, emu.pdi(), stop).0
    }
}

impl<A, C, D> Device<A, C, D>
where
    A: Application<D> + 'static,
    C: Application<D> + 'static,
    D: ObjectDictionary,
{
    /// A new emulated ESC for the device: its EEPROM loaded, then what the MainDevice did
    /// before the firmware started.
    fn emulator(&self) -> Emulator {
        let emu = Emulator::new(self.esc);
        if !self.eeprom.is_empty() {
            emu.with(|esc| esc.load_eeprom(self.eeprom.clone()));
        }
        (self.before_start)(&TestMaster::new(emu.clone()));
        emu
    }

    /// The state-machine and process-data runners of this device on `pdi`, made as firmware
    /// makes them, and the SubDevice's [`Status`].
    fn runners<P: Pdi + 'static>(
        self,
        emu: &Emulator,
        pdi: P,
        stop: &'static Stop,
    ) -> (Vec<Task>, Status<'static, P>) {
        let app = Pair {
            hooks: self.app,
            cycle: self.cycle,
        };
        let config = Box::leak(Box::new(
            Config::<P, MAX_IMAGE, MAX_IMAGE, MAX_MAILBOX>::at_most(self.config),
        ));
        let mut od = self.od;
        let storage = self.parameters.map(|flash| {
            let partition = flash.partition(flash::layout::PARAMETERS);
            let mut storage = ParameterStorage::new(partition).expect("two whole pages");
            // A flash without a valid map keeps the defaults, as firmware does.
            let _ = embassy_futures::block_on(storage.load(&mut od));
            storage
        });
        let resources = Box::leak(Box::new(
            Resources::new(config, pdi, app, od).with_chunk(self.chunk),
        ));
        let (irq, sync0) = (emu.irq_pin(), emu.sync0_pin());
        let (state_machine, process_data, control) = resources.split();
        let mut state_machine = state_machine.with_storage(storage);
        state_machine.set_device_id(self.device_id);
        if self.one_task {
            let task = Task::thread(stoppable(stop, async move {
                let error = state_machine.run_with(process_data, irq).await;
                panic!("runners stopped: {error:?}");
            }));
            return (vec![task], control.status());
        }
        let futures = vec![
            Task::thread(stoppable(stop, async move {
                // In firmware the process-data runner's interrupt executor runs first; make that
                // so here whatever order the scheduler polls its tasks in (the cooperative one:
                // wake order).
                embassy_futures::yield_now().await;
                state_machine
                    .run_then(|error| panic!("state-machine runner stopped: {error:?}"))
                    .await;
            })),
            // The runners' own futures, as the firmwares run them (`run_then`).
            Task::interrupt(stoppable(
                stop,
                process_data.run_with_sync0_then(irq, sync0, |error| {
                    panic!("process-data runner stopped: {error:?}")
                }),
            )),
        ];
        (futures, control.status())
    }
}

/// The stored parameters' storage of a [`Device`]: room for a record of 1 KiB less the map's.
pub type ParameterStorage = ecat_embassy::storage::FlashStorage<flash::Partition, 1024>;

/// A runner or script, as the harness spawns it.
pub type BoxedTask = Pin<Box<dyn Future<Output = ()>>>;

/// Runs the tasks `build` makes (on a fresh virtual clock, one scenario at a time) until all of
/// them ended, ordered as `scheduler` says; aborts the process if that takes longer than `limit`
/// of wall-clock time.
fn execute(
    limit: Option<std::time::Duration>,
    scheduler: Scheduler,
    build: impl FnOnce(&'static Stop) -> Vec<Task>,
) {
    let _serial = SERIAL.lock().unwrap_or_else(PoisonError::into_inner);
    let _guard = limit.map(HangGuard::arm);
    MockDriver::get().reset();
    let stop: &'static Stop = Box::leak(Box::default());
    scheduler::run(build(stop), scheduler);
}

async fn stoppable(stop: &'static Stop, runner: impl Future<Output = ()>) {
    let mut runner = core::pin::pin!(runner);
    let counted = core::future::poll_fn(|cx| {
        RUNNER_POLLS.fetch_add(1, Ordering::Relaxed);
        runner.as_mut().poll(cx)
    });
    select(counted, stop.wait()).await;
    stop.signal();
}

/// Lets the runners start up, then runs the script, then stops the runners.
async fn scenario(stop: &'static Stop, master: TestMaster, script: impl Future<Output = ()>) {
    master.settle().await;
    script.await;
    stop.signal();
}
