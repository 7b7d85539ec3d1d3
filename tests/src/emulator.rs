//! The emulated ESC as the async world sees it: a shared handle, a [`Pdi`] on its PDI port, an
//! IRQ pin that wakes whoever waits on it, and the ESC's RUN and ERR LED outputs in virtual time
//! ([`Emulator::led_timeline`]).
//!
//! Everything runs on one thread (the host executor), so the handle is an `Rc<RefCell<_>>`.

use core::cell::{Cell, RefCell};
use core::convert::Infallible;
use core::future::poll_fn;
use core::task::{Poll, Waker};
use std::rc::Rc;

use ecat_core::AlEvent;
use ecat_core::indicator::{LedCode, LedOutput};
use ecat_core::register::{self, DcActivation, Watchdog};
use ecat_embassy::Pdi;
use ecat_embassy::pdi::Data;

use crate::esc::{Esc, EscConfig};

/// A shared handle to one emulated ESC.
#[derive(Clone)]
pub struct Emulator(Rc<Inner>);

struct Inner {
    esc: RefCell<Esc>,
    irq_waiters: RefCell<Vec<Waker>>,
    /// PDI accesses since the test script last had a turn (see [`Emulator::script_ran`]).
    pdi_streak: Cell<u64>,
    /// When the process-data watchdog expires, if it runs (virtual time).
    watchdog_deadline: Cell<Option<embassy_time::Instant>>,
    /// SYNC0 pulses generated so far.
    sync0_pulses: Cell<u64>,
    /// The system time (ns) of the last SYNC0 pulse generated.
    sync0_last: Cell<Option<u64>>,
    sync0_waiters: RefCell<Vec<Waker>>,
    /// The codes of the ESC's RUN and ERR LED outputs ([`Esc::run_led`], [`Esc::err_led`]) at
    /// each change, with the virtual time: the first entry is the power-on's.
    led_codes: RefCell<Vec<(embassy_time::Instant, LedCode, LedCode)>>,
}

/// One of the ESC's LED outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Led {
    /// The RUN LED (green).
    Run,
    /// The ERR LED (red).
    Err,
}

/// PDI accesses in a row, without the test script running, that count as a livelock: a runner
/// spinning on the ESC inside one executor poll.
const LIVELOCK: u64 = 100_000;

impl Emulator {
    /// A new ESC with `config`.
    pub fn new(config: EscConfig) -> Self {
        let esc = Esc::new(config);
        let leds = (embassy_time::Instant::now(), esc.run_led(), esc.err_led());
        Self(Rc::new(Inner {
            esc: RefCell::new(esc),
            irq_waiters: RefCell::new(Vec::new()),
            pdi_streak: Cell::new(0),
            watchdog_deadline: Cell::new(None),
            sync0_pulses: Cell::new(0),
            sync0_last: Cell::new(None),
            sync0_waiters: RefCell::new(Vec::new()),
            led_codes: RefCell::new(vec![leds]),
        }))
    }

    /// Switches the ESC off and on again, as a device's restart does ([`crate::restart`]): it
    /// becomes `fresh`'s ESC (registers at their reset values, its EEPROM loaded), linked as
    /// before (the DL status 0x0110 kept: the cables did not change). The PDI port and the IRQ
    /// and SYNC0 pins are still this handle's.
    pub fn power_cycle(&self, fresh: &Emulator) {
        let links: [u8; 2] = registers(&self.0.esc.borrow(), register::DL_STATUS);
        self.0.esc.swap(&fresh.0.esc);
        self.0.watchdog_deadline.set(None);
        self.0.sync0_last.set(None);
        self.with(|esc| esc.set_register(register::DL_STATUS, &links));
    }

    /// Runs `f` on the ESC, then wakes the IRQ waiters: any access may have changed the line.
    pub fn with<R>(&self, f: impl FnOnce(&mut Esc) -> R) -> R {
        let result = {
            let mut esc = self.0.esc.borrow_mut();
            let result = f(&mut esc);
            self.restart_watchdog(&mut esc);
            self.note_leds(&esc);
            result
        };
        self.wake_irq_waiters();
        result
    }

    /// Lets virtual time act on the ESC: the process-data watchdog expires at its deadline, the
    /// DC SYNC unit pulses SYNC0. The test master calls it whenever it advances time.
    pub fn tick(&self) {
        self.tick_sync0();
        let due = self
            .0
            .watchdog_deadline
            .get()
            .is_some_and(|d| embassy_time::Instant::now() >= d);
        if due {
            self.0.watchdog_deadline.set(None);
            let mut esc = self.0.esc.borrow_mut();
            esc.expire_watchdog();
            self.note_leds(&esc);
            drop(esc);
            self.wake_irq_waiters();
        }
    }

    /// Notes the codes the LED outputs show now, if they changed.
    fn note_leds(&self, esc: &Esc) {
        let (run, err) = (esc.run_led(), esc.err_led());
        let mut codes = self.0.led_codes.borrow_mut();
        if codes.last().map(|&(_, r, e)| (r, e)) != Some((run, err)) {
            codes.push((embassy_time::Instant::now(), run, err));
        }
    }

    /// What the ESC's `led` output showed from power-on until `until`: (virtual ms, level) at
    /// power-on and at each edge. Each code runs its ETG.1300 timeline from the instant the
    /// output started showing it (`ecat_esc`'s `leds` module).
    pub fn led_timeline(&self, led: Led, until: embassy_time::Instant) -> Vec<(u64, bool)> {
        let instant = |t: embassy_time::Instant| ecat_core::Instant::from_micros(t.as_micros());
        let end = instant(until);
        let codes = self.0.led_codes.borrow();
        let mut output = LedOutput::new();
        let mut edges: Vec<(u64, bool)> = Vec::new();
        for (i, &(at, run, err)) in codes.iter().enumerate() {
            let mut now = instant(at);
            output.show(now, if led == Led::Run { run } else { err });
            let next = codes.get(i + 1).map_or(end, |&(t, ..)| instant(t).min(end));
            while now < next {
                let level = output.level(now);
                if edges.last().map(|&(_, l)| l) != Some(level) {
                    edges.push((now.as_micros() / 1_000, level));
                }
                match output.next_edge(now) {
                    Some(edge) => now = edge,
                    None => break,
                }
            }
        }
        edges
    }

    /// A MainDevice write restarted the process-data watchdog: its deadline is one period
    /// ((divider + 2) × 40 ns × time, registers 0x0400/0x0420) from now; time 0 disables it.
    fn restart_watchdog(&self, esc: &mut Esc) {
        if !esc.take_watchdog_trigger() {
            return;
        }
        let divider = u16::from_le_bytes(registers(esc, register::WATCHDOG_DIVIDER));
        let time = u16::from_le_bytes(registers(esc, register::WATCHDOG_TIME_PROCESS_DATA));
        let period = Watchdog { divider, time }.period_ns();
        let deadline =
            period.map(|ns| embassy_time::Instant::now() + embassy_time::Duration::from_nanos(ns));
        esc.restart_watchdog();
        self.0.watchdog_deadline.set(deadline);
    }

    /// The DC SYNC unit's registers at the current virtual time: the system time (ns), the
    /// activation, the SYNC0 start time and cycle time.
    fn sync_unit(&self) -> (u64, DcActivation, u64, u64) {
        let local = embassy_time::Instant::now()
            .as_micros()
            .saturating_mul(1_000);
        let mut esc = self.0.esc.borrow_mut();
        esc.set_local_time(local);
        let activation = DcActivation(esc.register(register::DC_ACTIVATION));
        let (mut start, mut cycle) = ([0u8; 8], [0u8; 4]);
        // Start and cycle time only matter with SYNC0 active: every frame ticks every ESC of
        // a served line.
        if activation.sync0() {
            start = registers(&esc, register::DC_START_TIME);
            cycle = registers(&esc, register::DC_SYNC0_CYCLE_TIME);
        }
        (
            esc.system_time(),
            activation,
            u64::from_le_bytes(start),
            u64::from(u32::from_le_bytes(cycle)),
        )
    }

    /// The system time (ns) of the next SYNC0 pulse, if SYNC0 is active and one is still to
    /// come: the start time first, then every cycle after the last pulse.
    fn next_sync0(&self, activation: DcActivation, start: u64, cycle: u64) -> Option<u64> {
        if !activation.sync0() {
            return None;
        }
        match (self.0.sync0_last.get(), cycle) {
            (None, _) => Some(start),
            (Some(last), 1..) => Some(last.saturating_add(cycle)),
            (Some(_), 0) => None,
        }
    }

    /// The DC SYNC unit (ESC datasheet section I, "SyncSignal generation"): with cyclic
    /// operation and SYNC0 activated (0x0981 bits 0 and 1), SYNC0 pulses at the start time
    /// (0x0990) and every SYNC0 cycle (0x09A0) after it, on the system time (virtual time in ns
    /// plus the offset the MainDevice set, `Esc::system_time`). Pulses due since the last tick
    /// merge into one edge, as a level-sampling input would see them; a cycle of 0 gives a
    /// single pulse.
    fn tick_sync0(&self) {
        let (now, activation, start, cycle) = self.sync_unit();
        if !activation.sync0() {
            self.0.sync0_last.set(None);
            return;
        }
        let due = match self.next_sync0(activation, start, cycle) {
            Some(next) if now >= next => match self.0.sync0_last.get() {
                None => Some(start),
                Some(last) => Some(last + (now - last) / cycle * cycle),
            },
            _ => None,
        };
        if let Some(pulse) = due {
            self.0.sync0_last.set(Some(pulse));
            // The pin shows an edge only as the EEPROM's configuration area lets it: the SYNC out
            // unit on, SYNC0 an output, and in acknowledge mode only after the PDI read 0x098E
            // (`Esc::sync0_pulse`).
            if !self.0.esc.borrow_mut().sync0_pulse() {
                return;
            }
            self.0.sync0_pulses.set(self.0.sync0_pulses.get() + 1);
            for waker in self.0.sync0_waiters.borrow_mut().drain(..) {
                waker.wake();
            }
        }
    }

    /// When virtual time next acts on the ESC by itself (see [`Emulator::tick`]): the
    /// process-data watchdog's expiry or the next SYNC0 pulse, whichever comes first; `None`
    /// when neither runs. A line served on a real clock sleeps until then, or until a frame
    /// arrives.
    pub fn next_deadline(&self) -> Option<embassy_time::Instant> {
        let watchdog = self.0.watchdog_deadline.get();
        // Without SYNC0 (most SubDevices) the DC unit has no deadline: a line asks every ESC
        // several times per frame, so this costs no look at the clock.
        let activation = DcActivation(self.0.esc.borrow().register(register::DC_ACTIVATION));
        if !activation.sync0() {
            return watchdog;
        }
        let now = embassy_time::Instant::now();
        let (system, activation, start, cycle) = self.sync_unit();
        let sync0 = self.next_sync0(activation, start, cycle).map(|pulse| {
            let ns = pulse.saturating_sub(system);
            now + embassy_time::Duration::from_micros(ns.div_ceil(1_000))
        });
        match (watchdog, sync0) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Wakers waiting on the IRQ and SYNC0 lines: one per waiting task at most, however often
    /// a task polls before the line changes.
    pub fn waiters(&self) -> usize {
        self.0.irq_waiters.borrow().len() + self.0.sync0_waiters.borrow().len()
    }

    /// The SYNC0 output, for the process-data runner of a DC device.
    pub fn sync0_pin(&self) -> Sync0Pin {
        Sync0Pin(self.clone())
    }

    /// SYNC0 pulses so far.
    pub fn sync0_pulses(&self) -> u64 {
        self.0.sync0_pulses.get()
    }

    fn wake_irq_waiters(&self) {
        for waker in self.0.irq_waiters.borrow_mut().drain(..) {
            waker.wake();
        }
    }

    /// The PDI traffic so far, without waking anyone (unlike [`Emulator::with`]).
    pub fn stats(&self) -> crate::esc::PdiStats {
        self.0.esc.borrow().stats()
    }

    /// The test script got a turn: the runners did not starve it.
    pub fn script_ran(&self) {
        self.0.pdi_streak.set(0);
    }

    /// Counts one PDI access; fails the test when the runners never let anything else run.
    fn pdi_access(&self) {
        let streak = self.0.pdi_streak.get() + 1;
        self.0.pdi_streak.set(streak);
        assert!(
            streak < LIVELOCK,
            "livelock: {streak} PDI accesses without the executor running anything else"
        );
    }

    /// The PDI port, for the runners.
    pub fn pdi(&self) -> EmulatedPdi {
        EmulatedPdi(self.clone(), AlEvent::NONE)
    }

    /// The IRQ pin (active low), for the process-data runner.
    pub fn irq_pin(&self) -> IrqPin {
        IrqPin(self.clone())
    }

    /// Completes once `level(irq asserted)` holds.
    async fn wait_irq(&self, level: impl Fn(bool) -> bool) {
        poll_fn(|cx| {
            if level(self.0.esc.borrow().irq()) {
                Poll::Ready(())
            } else {
                register(&self.0.irq_waiters, cx.waker());
                Poll::Pending
            }
        })
        .await
    }
}

/// The `N` register bytes from `address` as the ESC holds them, without a port's side effects
/// (the ESC's own logic reading its registers).
fn registers<const N: usize>(esc: &Esc, address: u16) -> [u8; N] {
    core::array::from_fn(|n| esc.register(address.wrapping_add(n as u16)))
}

/// Adds `waker` to `waiters` unless a waker of the same task is already there: a task polled
/// again before the line changed (woken by a timer or another future it selects on) must not
/// add a copy per poll.
pub(crate) fn register(waiters: &RefCell<Vec<Waker>>, waker: &Waker) {
    let mut waiters = waiters.borrow_mut();
    if !waiters.iter().any(|w| w.will_wake(waker)) {
        waiters.push(waker.clone());
    }
}

/// The PDI port of an [`Emulator`]: every access completes at once and samples the AL event
/// register before it, as an SPI ESC does.
pub struct EmulatedPdi(Emulator, AlEvent);

impl Pdi for EmulatedPdi {
    type Error = Infallible;

    async fn access(&mut self, address: u16, data: Data<'_>) -> Result<(), Infallible> {
        self.0.pdi_access();
        self.1 = self.0.with(|esc| match data {
            Data::Read(buf) => esc.pdi_read(address, buf),
            Data::Write(data) => esc.pdi_write(address, data),
        });
        Ok(())
    }

    fn al_event(&self) -> AlEvent {
        self.1
    }
}

/// The ESC's IRQ output, active low: "low" while `AL event & AL event mask` is not empty.
pub struct IrqPin(Emulator);

impl embedded_hal::digital::ErrorType for IrqPin {
    type Error = Infallible;
}

impl embedded_hal_async::digital::Wait for IrqPin {
    async fn wait_for_low(&mut self) -> Result<(), Infallible> {
        self.0.wait_irq(|asserted| asserted).await;
        Ok(())
    }

    async fn wait_for_high(&mut self) -> Result<(), Infallible> {
        self.0.wait_irq(|asserted| !asserted).await;
        Ok(())
    }

    async fn wait_for_falling_edge(&mut self) -> Result<(), Infallible> {
        self.wait_for_high().await?;
        self.wait_for_low().await
    }

    async fn wait_for_rising_edge(&mut self) -> Result<(), Infallible> {
        self.wait_for_low().await?;
        self.wait_for_high().await
    }

    async fn wait_for_any_edge(&mut self) -> Result<(), Infallible> {
        let before = self.0.with(|esc| esc.irq());
        self.0.wait_irq(|asserted| asserted != before).await;
        Ok(())
    }
}

/// The ESC's SYNC0 output: a pulse (rising edge) per DC cycle, see [`Emulator::tick`].
pub struct Sync0Pin(Emulator);

impl Sync0Pin {
    /// Completes at the next pulse.
    async fn pulse(&self) {
        let seen = self.0.sync0_pulses();
        poll_fn(|cx| {
            if self.0.sync0_pulses() != seen {
                Poll::Ready(())
            } else {
                register(&self.0.0.sync0_waiters, cx.waker());
                Poll::Pending
            }
        })
        .await
    }
}

impl embedded_hal::digital::ErrorType for Sync0Pin {
    type Error = Infallible;
}

/// SYNC0 is a short pulse: every wait completes at the next pulse, but "low", the line's rest
/// level, which holds at once.
impl embedded_hal_async::digital::Wait for Sync0Pin {
    async fn wait_for_high(&mut self) -> Result<(), Infallible> {
        self.pulse().await;
        Ok(())
    }

    async fn wait_for_low(&mut self) -> Result<(), Infallible> {
        Ok(())
    }

    async fn wait_for_rising_edge(&mut self) -> Result<(), Infallible> {
        self.pulse().await;
        Ok(())
    }

    async fn wait_for_falling_edge(&mut self) -> Result<(), Infallible> {
        self.pulse().await;
        Ok(())
    }

    async fn wait_for_any_edge(&mut self) -> Result<(), Infallible> {
        self.pulse().await;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use core::future::Future;
    use core::pin::pin;
    use core::task::{Context, Poll, Waker};

    use embedded_hal_async::digital::Wait;

    use super::*;

    /// A runner that selects on the IRQ and a timer is polled again at every timer wake-up
    /// while the line stays high: the ESC must keep one waker for it, not one per poll (the
    /// virtual slave grew by 16 MB/s idle).
    #[test]
    fn a_waiter_polled_again_is_remembered_once() {
        let emu = Emulator::new(EscConfig::default());
        let (mut irq, sync0) = (emu.irq_pin(), emu.sync0_pin());
        struct Task;
        impl std::task::Wake for Task {
            fn wake(self: std::sync::Arc<Self>) {}
        }
        let waker = Waker::from(std::sync::Arc::new(Task));
        let mut cx = Context::from_waker(&waker);
        {
            let mut low = pin!(irq.wait_for_low());
            let mut pulse = pin!(sync0.pulse());
            for _ in 0..1000 {
                assert_eq!(low.as_mut().poll(&mut cx), Poll::Pending);
                assert_eq!(pulse.as_mut().poll(&mut cx), Poll::Pending);
            }
        }
        assert_eq!(emu.waiters(), 2, "one IRQ waiter and one SYNC0 waiter");
        emu.with(|_| ());
        assert_eq!(emu.waiters(), 1, "an ESC access wakes the IRQ waiters");
    }

    /// Without a watchdog trigger or SYNC0, nothing is due; a running process-data watchdog is
    /// due one period (reset values: 100 µs × 1000 = 100 ms) after the MainDevice's write.
    #[test]
    fn the_next_deadline_is_the_watchdog_expiry() {
        let _serial = crate::harness::exclusive();
        let start = embassy_time::Instant::now();
        let emu = Emulator::new(EscConfig::default());
        assert_eq!(emu.next_deadline(), None);
        let sm2 = register::sync_manager(2);
        emu.with(|esc| {
            esc.ecat_write(sm2, &[0x00, 0x10, 1, 0, 0x64]);
            esc.ecat_write(sm2 + 6, &[1]);
            esc.ecat_write(0x1000, &[0xAA]);
        });
        let due = start + embassy_time::Duration::from_millis(100);
        assert_eq!(emu.next_deadline(), Some(due));
        embassy_time::MockDriver::get().advance(embassy_time::Duration::from_millis(100));
        emu.tick();
        assert_eq!(emu.next_deadline(), None, "expired");
    }

    /// With cyclic SYNC0 active, the next pulse is due at the start time, then one cycle after
    /// the last pulse.
    #[test]
    fn the_next_deadline_is_the_next_sync0_pulse() {
        let _serial = crate::harness::exclusive();
        let start = embassy_time::Instant::now();
        let emu = Emulator::new(EscConfig {
            dc_supported: true,
            ..EscConfig::default()
        });
        emu.tick();
        let system = emu.with(|esc| esc.system_time());
        emu.with(|esc| {
            esc.ecat_write(register::DC_START_TIME, &(system + 500_000).to_le_bytes());
            esc.ecat_write(register::DC_SYNC0_CYCLE_TIME, &1_000_000u32.to_le_bytes());
            esc.ecat_write(register::DC_ACTIVATION, &[0x03]);
        });
        let us = embassy_time::Duration::from_micros;
        assert_eq!(emu.next_deadline(), Some(start + us(500)), "the start time");
        embassy_time::MockDriver::get().advance(us(500));
        emu.tick();
        assert_eq!(emu.sync0_pulses(), 1);
        assert_eq!(emu.next_deadline(), Some(start + us(1500)), "one cycle on");
    }
}
