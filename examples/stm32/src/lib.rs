//! The board around the ecat firmware: an STM32G474 (NUCLEO-G474RE) wired to an EtherCAT
//! SubDevice Controller (AX58100/ET1100 or LAN9252) over SPI1 (or an AX58100 on the FMC: feature
//! `fmc`), and the pins of the 4-in/4-out digital I/O application (`ecat_dio`, shared with the
//! RP2040 firmware). Shared by the firmwares (`src/main.rs`: digital I/O, `src/bin/axis.rs`: the
//! CiA402 dummy axis) and the size baseline (`src/bin/baseline.rs`), which differ only in what
//! runs on top.
#![no_std]

pub mod board;
pub mod esc;
#[cfg(any(feature = "bootloader", feature = "storage"))]
pub mod flash;
#[cfg(feature = "fmc")]
pub mod fmc;
pub mod mem;
#[cfg(feature = "storage")]
pub mod parameters;
#[cfg(feature = "bootloader")]
pub mod update;

#[cfg(all(feature = "storage", feature = "no-dictionary"))]
compile_error!(
    "feature `storage` keeps dictionary entries: it needs the dictionary (no `no-dictionary`)"
);

/// The ETG.1300 RUN/ERR LEDs of the SubDevice whose `status` they show, in the thread executor:
/// woken only at a pattern's edges and when the AL status changes. The task is
/// `run_indicators`' future itself (no `async fn` around it keeping the arguments twice).
#[embassy_executor::task]
pub fn indicators(
    status: ecat_embassy::Status<'static, esc::Pdi>,
    leds: board::Leds,
) -> impl core::future::Future<Output = ()> {
    ecat_embassy::run_indicators(status, leds)
}

/// A task's future that is `Send` until its first poll: it is made from parts that are `Send`
/// and only hold them until then. The process-data task's future is the runner's own
/// (`ProcessDataRunner::run_then`), without an `async fn` around it that keeps the runner and
/// the IRQ pin a second time (24 bytes of RAM); the interrupt executor's `SendSpawner` takes
/// only `Send` futures, and embassy-stm32's SPI transfer future holds raw pointers across its
/// await (docs/performance.md, "Codegen rules").
pub struct SentBeforePoll<F>(F);

impl<F: core::future::Future> SentBeforePoll<F> {
    /// The future `make(parts)`, whose parts are `Send`.
    ///
    /// # Safety
    /// `make` only moves the parts into the future, which does its work from its first poll on
    /// (the runners' `run_then` do); the value is sent to another context (an executor of
    /// another priority) only before that poll: a task spawner does exactly that.
    /// embassy-executor reasons the same way for an `async fn` task whose arguments are `Send`
    /// (`TaskPool::_spawn_async_fn`).
    pub unsafe fn new<T: Send>(parts: T, make: impl FnOnce(T) -> F) -> Self {
        Self(make(parts))
    }
}

// SAFETY: until its first poll the future holds only the `Send` parts it was made of; `new`'s
// contract keeps it from being sent after.
unsafe impl<F> Send for SentBeforePoll<F> {}

impl<F: core::future::Future> core::future::Future for SentBeforePoll<F> {
    type Output = F::Output;

    fn poll(
        self: core::pin::Pin<&mut Self>,
        cx: &mut core::task::Context<'_>,
    ) -> core::task::Poll<F::Output> {
        // SAFETY: structural pinning: the future is never moved out of the wrapper, which has no
        // `Drop` of its own.
        unsafe { self.map_unchecked_mut(|sent| &mut sent.0) }.poll(cx)
    }
}

/// The two executors every firmware of this board runs (priorities: README.md): defines the
/// statics, the UART4 handler (UART4 is unused on this board, its vector runs the interrupt
/// executor) and `run_executors(init)`, which starts the interrupt executor at priority 6 and
/// runs the thread executor, handing `init` both spawners.
#[macro_export]
macro_rules! executors {
    () => {
        use embassy_stm32::interrupt;

        static EXECUTOR_HIGH: embassy_executor::InterruptExecutor =
            embassy_executor::InterruptExecutor::new();
        static EXECUTOR_LOW: static_cell::StaticCell<embassy_executor::Executor> =
            static_cell::StaticCell::new();

        /// The process-data executor's interrupt.
        #[embassy_stm32::interrupt]
        unsafe fn UART4() {
            // SAFETY: the executor was started on this interrupt; only the interrupt handler
            // calls it.
            unsafe { EXECUTOR_HIGH.on_interrupt() }
        }

        /// Starts the interrupt executor on UART4 at priority 6, then runs the thread executor.
        fn run_executors(
            init: impl FnOnce(embassy_executor::SendSpawner, embassy_executor::Spawner),
        ) -> ! {
            use embassy_stm32::interrupt::{InterruptExt, Priority};
            interrupt::UART4.set_priority(Priority::P6);
            let high = EXECUTOR_HIGH.start(interrupt::UART4);
            EXECUTOR_LOW
                .init(embassy_executor::Executor::new())
                .run(|spawner| init(high, spawner))
        }
    };
}
