//! A device that restarts while its line runs, as a real one does after a firmware update: its
//! firmware asks for a reset ([`Reset::request`], where an MCU calls `SCB::sys_reset`), its
//! runners stop, it boots anew from what survives the reset (its flash: [`crate::update`]) and
//! its ESC starts afresh. The other devices of the line go on as before.
//!
//! A restart here is a power cycle of the whole device, ESC included (its reset tied to the
//! MCU's): the ESC's registers return to their reset values (the station address too: the
//! MainDevice scans again, as for any device that restarted) and it loads the SII the new
//! firmware describes (a new revision), its ports linked as before ([`Emulator::power_cycle`]).

use core::cell::{Cell, RefCell};
use core::future::poll_fn;
use core::task::{Poll, Waker};
use std::rc::Rc;

use embassy_futures::select::select;

use crate::emulator::Emulator;
use crate::harness::{BoxedTask, Spawn, Stop};
use crate::scheduler::Task;

/// A device's reset request, from its firmware to the [`Restarting`] device that runs it. A
/// device run without one (`harness::run`) asks and nothing happens: the test resets it.
#[derive(Clone, Default)]
pub struct Reset(Rc<Request>);

#[derive(Default)]
struct Request {
    asked: Cell<bool>,
    /// The task that restarts the device.
    waker: RefCell<Option<Waker>>,
}

impl Reset {
    /// Asks for a reset: the device restarts once the runner that asked reaches its next wait
    /// (firmware would stop at once; what it does before that wait, the host's runner does).
    pub fn request(&self) {
        self.0.asked.set(true);
        if let Some(waker) = self.0.waker.borrow_mut().take() {
            waker.wake();
        }
    }

    /// Whether a reset was asked for since the last call.
    fn take(&self) -> bool {
        self.0.asked.replace(false)
    }

    fn listen(&self, waker: &Waker) {
        *self.0.waker.borrow_mut() = Some(waker.clone());
    }
}

/// What makes a [`Restarting`] device, given the reset its firmware asks through.
type Boot = dyn FnMut(&Reset) -> Box<dyn Spawn>;

/// A device that restarts when its firmware asks ([`Reset`]): `boot` makes it at power-on and
/// again at every reset, from what survives one (module docs). Each life's runners keep their
/// resources for the process, as firmware's statics are (a few KiB a restart).
pub struct Restarting {
    boot: Box<Boot>,
    reset: Reset,
    /// The device as it booted at power-on.
    device: Box<dyn Spawn>,
}

impl Restarting {
    /// The device `boot` makes, booted once now; `boot` gets the [`Reset`] its firmware asks
    /// through.
    pub fn new(mut boot: impl FnMut(&Reset) -> Box<dyn Spawn> + 'static) -> Self {
        let reset = Reset::default();
        let device = boot(&reset);
        Self {
            boot: Box::new(boot),
            reset,
            device,
        }
    }
}

/// The interrupt-level runners of a [`Restarting`] device's current life: one task polls them,
/// a restart replaces them.
#[derive(Clone, Default)]
struct Runners(Rc<RefCell<(Vec<BoxedTask>, Option<Waker>)>>);

impl Runners {
    /// Drops the runners there were (they stop) and starts `runners`.
    fn replace(&self, runners: Vec<BoxedTask>) {
        let mut slot = self.0.borrow_mut();
        slot.0 = runners;
        if let Some(waker) = slot.1.take() {
            waker.wake();
        }
    }

    /// Polls the current runners until `stop`.
    async fn run(self, stop: &'static Stop) {
        let runners = poll_fn(|cx| {
            let mut slot = self.0.borrow_mut();
            slot.1 = Some(cx.waker().clone());
            slot.0
                .retain_mut(|runner| runner.as_mut().poll(cx).is_pending());
            Poll::<()>::Pending
        });
        select(runners, stop.wait()).await;
    }
}

impl Spawn for Restarting {
    fn emulator(&self) -> Emulator {
        self.device.emulator()
    }

    /// Two tasks, as a device's runners: at thread level the state-machine runner of the
    /// current life and the restarts, at interrupt level the process-data runner.
    fn spawn(self: Box<Self>, emu: &Emulator, stop: &'static Stop) -> Vec<Task> {
        let Self {
            mut boot,
            reset,
            device,
        } = *self;
        let interrupt = Runners::default();
        let emu = emu.clone();
        let level = interrupt.clone();
        // A life's runners: those at thread level for the caller, the others to `level`.
        let start = move |device: Box<dyn Spawn>, emu: &Emulator| -> Vec<BoxedTask> {
            let (at_interrupt, at_thread): (Vec<Task>, Vec<Task>) = device
                .spawn(emu, stop)
                .into_iter()
                .partition(|task| task.interrupt);
            level.replace(at_interrupt.into_iter().map(|task| task.future).collect());
            at_thread.into_iter().map(|task| task.future).collect()
        };
        let mut thread = start(device, &emu);
        let life = poll_fn(move |cx| {
            reset.listen(cx.waker());
            loop {
                thread.retain_mut(|runner| runner.as_mut().poll(cx).is_pending());
                if !reset.take() {
                    return Poll::<()>::Pending;
                }
                // The runners stop where they are (dropped: those at interrupt level when the
                // next life's replace them); the device boots again, on a fresh ESC.
                thread.clear();
                let device = boot(&reset);
                emu.power_cycle(&device.emulator());
                thread = start(device, &emu);
            }
        });
        vec![
            Task::thread(async move {
                select(life, stop.wait()).await;
            }),
            Task::interrupt(interrupt.run(stop)),
        ]
    }
}
