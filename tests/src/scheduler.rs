//! The harness's executor: the firmware's two priority levels on one host thread.
//!
//! In firmware the process-data runner lives in an `InterruptExecutor`: when its IRQ, SYNC0 or
//! the PDI it waits for wakes it, its interrupt is pended and preempts the thread executor, so
//! the state-machine runner (and anything else in thread mode) does not run again before the
//! process-data runner has reached its next wait. [`Scheduler::Preemptive`] gives the host the
//! same ordering at every point where a thread-mode task yields (each `await` that is not
//! ready, e.g. every SPI transaction of the fakes): before any thread-mode task is polled again,
//! every woken interrupt-level task is polled until none is woken. [`Scheduler::Cooperative`]
//! is one run queue for all, in wake order: what a single executor does (and what the harness
//! did before), kept to measure the difference.
//!
//! The state-machine runner also gives the process-data runner the PDI at its next chunk
//! boundary by itself (`SharedEsc::access`): a host thread cannot preempt between two
//! synchronous statements, the firmware's interrupt can, and the shared ESC's rule makes both
//! orders the same.

use std::collections::VecDeque;
use std::future::Future;
use std::pin::Pin;
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::task::{Context, Poll, Wake, Waker};

/// How the harness orders its tasks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scheduler {
    /// Interrupt-level tasks (the process-data runners) run before any thread-mode task is
    /// polled again, as a pended interrupt preempts the thread executor.
    #[default]
    Preemptive,
    /// Every task in one run queue, in wake order.
    Cooperative,
}

/// A task to run: a future and its level.
pub struct Task {
    /// What the task does.
    pub future: Pin<Box<dyn Future<Output = ()>>>,
    /// It runs as a pended interrupt would (the process-data runner).
    pub interrupt: bool,
}

impl Task {
    /// A thread-mode task.
    pub fn thread(future: impl Future<Output = ()> + 'static) -> Self {
        Self {
            future: Box::pin(future),
            interrupt: false,
        }
    }

    /// An interrupt-level task.
    pub fn interrupt(future: impl Future<Output = ()> + 'static) -> Self {
        Self {
            future: Box::pin(future),
            interrupt: true,
        }
    }
}

/// The run queues, shared with every waker (wakers may be used from other threads: a clock
/// thread, a receiving socket, ethercrab's transport).
#[derive(Default)]
struct Queues {
    state: Mutex<Ready>,
    woken: Condvar,
}

#[derive(Default)]
struct Ready {
    interrupt: VecDeque<usize>,
    thread: VecDeque<usize>,
    queued: Vec<bool>,
    /// The executor waits on [`Queues::woken`]: only then does a wake need to notify it. Most
    /// wakes come from the executor's own thread, inside a poll, and a notification is a
    /// system call (a futex wake) whether anyone waits or not: thousands a frame on a line of
    /// 256 SubDevices.
    sleeping: bool,
}

struct TaskWaker {
    queues: Arc<Queues>,
    index: usize,
    /// Which queue it goes to.
    interrupt: bool,
}

impl Wake for TaskWaker {
    fn wake(self: Arc<Self>) {
        self.wake_by_ref();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        let mut ready = self
            .queues
            .state
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if !std::mem::replace(&mut ready.queued[self.index], true) {
            if self.interrupt {
                ready.interrupt.push_back(self.index);
            } else {
                ready.thread.push_back(self.index);
            }
        }
        if ready.sleeping {
            self.queues.woken.notify_one();
        }
    }
}

/// Runs `tasks` until all of them have ended, ordered as `scheduler` says.
pub fn run(tasks: Vec<Task>, scheduler: Scheduler) {
    let queues = Arc::new(Queues::default());
    let mut futures: Vec<Option<Pin<Box<dyn Future<Output = ()>>>>> = Vec::new();
    let mut wakers = Vec::new();
    {
        let mut ready = queues.state.lock().unwrap_or_else(PoisonError::into_inner);
        for (index, task) in tasks.into_iter().enumerate() {
            let interrupt = task.interrupt && scheduler == Scheduler::Preemptive;
            wakers.push(Waker::from(Arc::new(TaskWaker {
                queues: queues.clone(),
                index,
                interrupt,
            })));
            futures.push(Some(task.future));
            ready.queued.push(true);
            if interrupt {
                ready.interrupt.push_back(index);
            } else {
                ready.thread.push_back(index);
            }
        }
    }
    let mut alive = futures.len();
    while alive > 0 {
        // Interrupt level first, until none is woken; then one thread-mode task.
        let next = {
            let mut ready = queues.state.lock().unwrap_or_else(PoisonError::into_inner);
            loop {
                if let Some(index) = ready
                    .interrupt
                    .pop_front()
                    .or_else(|| ready.thread.pop_front())
                {
                    ready.queued[index] = false;
                    break index;
                }
                ready.sleeping = true;
                ready = queues
                    .woken
                    .wait(ready)
                    .unwrap_or_else(PoisonError::into_inner);
                ready.sleeping = false;
            }
        };
        let Some(future) = futures[next].as_mut() else {
            continue;
        };
        let mut cx = Context::from_waker(&wakers[next]);
        if let Poll::Ready(()) = future.as_mut().poll(&mut cx) {
            futures[next] = None;
            alive -= 1;
        }
    }
}
