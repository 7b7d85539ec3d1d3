//! A long served line (`harness::serve`, what the virtual slave runs): 256 SubDevices whose
//! runners all wait on timers at once. embassy-time's timer queue holds 128 entries; with one
//! task per runner, 512 waiting timers overflowed it, and every overflow woke a timer early,
//! which took an entry again and woke the next: the executor spun for as long as the timers
//! waited (and the harness's task pool, 256 tasks, did not even start such a line).

use core::cell::Cell;
use core::future::Future;
use core::pin::Pin;
use core::task::{Context, Poll};
use std::rc::Rc;

use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness::{self, SERVED_TASKS, Spawn, Stop};
use ecat_emu::scheduler::Task;
use embassy_time::{Duration, MockDriver, Timer};

/// SubDevices on the line.
const DEVICES: usize = 256;
/// How long each runner sleeps.
const SLEEP: Duration = Duration::from_secs(1);

/// A SubDevice whose two runners sleep [`SLEEP`] on a timer and count their polls.
struct Sleeper {
    polls: Rc<Cell<u64>>,
}

/// A future that counts its polls in `polls`.
struct Counted<F> {
    future: Pin<Box<F>>,
    polls: Rc<Cell<u64>>,
}

impl<F: Future> Future for Counted<F> {
    type Output = F::Output;
    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<F::Output> {
        self.polls.set(self.polls.get() + 1);
        self.future.as_mut().poll(cx)
    }
}

impl Spawn for Sleeper {
    fn emulator(&self) -> Emulator {
        Emulator::new(EscConfig::default())
    }

    /// Like a device's runners: one at interrupt level, one in thread mode.
    fn spawn(self: Box<Self>, _emu: &Emulator, _stop: &'static Stop) -> Vec<Task> {
        let sleeper = || Counted {
            future: Box::pin(Timer::after(SLEEP)),
            polls: self.polls.clone(),
        };
        vec![Task::interrupt(sleeper()), Task::thread(sleeper())]
    }
}

/// Advances the virtual clock by `by` in steps of 5 ms, letting every woken task run after each.
async fn pass(by: Duration) {
    let step = Duration::from_millis(5);
    for _ in 0..by.as_ticks() / step.as_ticks() {
        MockDriver::get().advance(step);
        for _ in 0..4 {
            embassy_futures::yield_now().await;
        }
    }
}

/// Every runner of 256 SubDevices waits on a timer at once: none is polled before its timer is
/// due (the first poll arms it, the second finds it expired), so the line sleeps instead of
/// spinning.
#[test]
fn the_runners_of_256_subdevices_all_waiting_on_timers_are_polled_only_when_due() {
    let polls = Rc::new(Cell::new(0));
    let devices: Vec<Box<dyn Spawn>> = (0..DEVICES)
        .map(|_| {
            Box::new(Sleeper {
                polls: polls.clone(),
            }) as Box<dyn Spawn>
        })
        .collect();
    let runners = 2 * DEVICES as u64;
    let seen = polls.clone();
    let finished = Rc::new(Cell::new(false));
    let done = finished.clone();
    harness::serve(devices, move |emulators| async move {
        assert_eq!(emulators.len(), DEVICES);
        pass(SLEEP - Duration::from_millis(5)).await;
        assert_eq!(
            seen.get(),
            runners,
            "one poll per runner (arming its timer) before the timers are due"
        );
        pass(Duration::from_millis(10)).await;
        assert_eq!(
            seen.get(),
            2 * runners,
            "one more poll per runner once its timer expired"
        );
        done.set(true);
    });
    assert!(finished.get(), "the script ran to its end");
    const { assert!(SERVED_TASKS < 128, "a timer queue entry per task, and room") };
}
