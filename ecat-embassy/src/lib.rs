//! # ecat-embassy: run an ecat SubDevice under Embassy
//!
//! The async glue between [`ecat_core`] (which makes every protocol decision) and the hardware.
//! A firmware implements [`Application`] (every method has a default), describes its device
//! with a [`Config`], puts the PDI driver, the application and its dictionary in [`Resources`]
//! (one `StaticCell`) and [`split`](Resources::split)s them into two runners and a [`Control`]:
//!
//! ```no_run
//! use ecat_embassy::{Application, Config, Control, ProcessDataRunner, Resources};
//! use embassy_executor::{SendSpawner, Spawner};
//! use static_cell::StaticCell;
//! # mod board {
//! #     //! Stand-ins for a board's PDI driver and pins, so that the example builds on a host.
//! #     use ecat_embassy::pdi::Data;
//! #     pub struct Pdi;
//! #     impl ecat_embassy::Pdi for Pdi {
//! #         type Error = ();
//! #         async fn access(&mut self, _: u16, _: Data<'_>) -> Result<(), ()> {
//! #             Ok(())
//! #         }
//! #         fn al_event(&self) -> ecat_core::AlEvent {
//! #             ecat_core::AlEvent::NONE
//! #         }
//! #     }
//! #     pub struct Pin;
//! #     impl embedded_hal::digital::ErrorType for Pin {
//! #         type Error = core::convert::Infallible;
//! #     }
//! #     impl embedded_hal_async::digital::Wait for Pin {
//! #         async fn wait_for_high(&mut self) -> Result<(), Self::Error> { Ok(()) }
//! #         async fn wait_for_low(&mut self) -> Result<(), Self::Error> { Ok(()) }
//! #         async fn wait_for_rising_edge(&mut self) -> Result<(), Self::Error> { Ok(()) }
//! #         async fn wait_for_falling_edge(&mut self) -> Result<(), Self::Error> { Ok(()) }
//! #         async fn wait_for_any_edge(&mut self) -> Result<(), Self::Error> { Ok(()) }
//! #     }
//! # }
//! # use board::{Pdi, Pin};
//! # use embedded_hal_async::digital::Wait;
//!
//! /// 1 byte of outputs, 1 byte of inputs, 128-byte mailboxes at 0x1000 and 0x1080.
//! const DEVICE: Config<Pdi, 1, 1> = Config::standard();
//!
//! /// A loopback: the inputs are the outputs, latched at SYNC0.
//! #[derive(Default)]
//! struct Loopback {
//!     outputs: u8,
//!     latched: u8,
//! }
//!
//! impl Application for Loopback {
//!     fn cycle(&mut self, _: &mut (), outputs: Option<&[u8]>, inputs: &mut [u8]) {
//!         self.outputs = outputs.and_then(|o| o.first().copied()).unwrap_or(0);
//!         inputs.fill(self.latched);
//!     }
//! }
//!
//! type Ecat = Resources<Pdi, Loopback, (), 1, 1>;
//! static ECAT: StaticCell<Ecat> = StaticCell::new();
//!
//! #[embassy_executor::main]
//! async fn main(spawner: Spawner) {
//!     // In firmware: an `InterruptExecutor`'s spawner, above the thread executor.
//!     let high: SendSpawner = spawner.make_send();
//!     let ecat = ECAT.init_with(|| Ecat::new(&DEVICE, Pdi, Loopback::default(), ()));
//!     let (state_machine, process_data, control) = ecat.split();
//!     high.spawn(exchange(process_data, Pin).unwrap());
//!     high.spawn(sync0(control, Pin).unwrap());
//!     let _error = state_machine.run().await;
//! }
//!
//! /// The process-data exchange, in the interrupt executor; owns the ESC's IRQ pin.
//! #[embassy_executor::task]
//! async fn exchange(runner: ProcessDataRunner<'static, Pdi, Loopback, ()>, irq: Pin) {
//!     let _error = runner.run(irq).await;
//! }
//!
//! /// Latches the outputs at each SYNC0 pulse: the application, reached from another task.
//! #[embassy_executor::task]
//! async fn sync0(control: Control<'static, Pdi, Loopback>, mut sync0: Pin) {
//!     while sync0.wait_for_rising_edge().await.is_ok() {
//!         control.lock(|app, _od| app.latched = app.outputs);
//!     }
//! }
//! ```
//!
//! A first device may run both runners in one task of one executor instead:
//! `ecat.run(irq).await` ([`Resources::run`]); the process-data exchange then waits for at most
//! one chunk of mailbox traffic.
//!
//! | module | role |
//! |---|---|
//! | [`app`] | [`Application`]: the process-data cycle, the state hooks, the SDO hooks |
//! | [`device`] | [`Config`], [`Resources`], [`Control`]: the entry point |
//! | [`pdi`] | the [`Pdi`] trait: register access to the ESC, returning the AL event register |
//! | [`esm_runner`] | [`StateMachineRunner`]: the state machine and the mailbox, in the low-priority thread executor |
//! | [`pd_runner`] | [`ProcessDataRunner`]: the process-data exchange, in an `InterruptExecutor`; owns the IRQ line |
//! | [`spi`] | PDI drivers over `embedded-hal-async` SPI: Beckhoff ESC SPI protocol, Microchip LAN9252 |
//! | [`mcu`] | the PDI driver over the ET1100/AX58100 16-bit asynchronous microcontroller interface (a memory controller such as the STM32's FMC), on a [`mcu::Bus16`] the firmware provides |
//! | [`indicator`] | [`run_indicators`]: the ETG.1300 RUN/ERR LEDs on GPIO pins, from the AL status the state-machine runner publishes |
//!
//! ## Who wakes whom
//! The ESC has one IRQ line: asserted while `AL event & AL event mask` is not empty. The
//! process-data runner owns it. When it fires, that runner reads the AL event register (in
//! SyncManager-synchronous mode it reads the output buffer instead and gets the AL event for free
//! from an SPI ESC). Every PDI access of either runner reports the AL event value it saw to the
//! routing they share, which wakes the state-machine runner for state-machine events and the
//! process-data runner for its trigger. While state-machine events hold the IRQ line asserted, the
//! process-data runner does not wait on the line (it would spin) but on the shared state, and the
//! state-machine runner's own accesses tell it when the line is free again. Nothing polls.
//!
//! ## Who waits for whom
//! The state-machine runner's accesses (a mailbox message can be 1 KiB) move in chunks of
//! [`Resources::with_chunk`] bytes, and the process-data runner takes the PDI at the next chunk
//! boundary: its exchange never waits for more than the transaction in flight and one chunk.
#![no_std]
// No panic path in the runners and the PDI drivers.
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::unreachable,
    clippy::todo,
    clippy::unimplemented
)]

pub mod app;
pub mod device;
pub mod esm_runner;
mod handed_over;
pub mod indicator;
pub mod mcu;
mod or_never;
pub mod pd_runner;
pub mod pdi;
mod shared;
pub mod spi;
pub mod storage;
mod time;

pub use app::Application;
pub use device::{Config, Control, Resources};
pub use esm_runner::StateMachineRunner;
pub use indicator::run_indicators;
pub use pd_runner::{Error, ProcessDataRunner};
pub use pdi::Pdi;
pub use shared::Status;
