//! # ecat-embassy: run an ecat SubDevice under Embassy
//!
//! The async glue between [`ecat_core`] (which makes every protocol decision) and the hardware:
//!
//! | module | role |
//! |---|---|
//! | [`pdi`] | the [`Pdi`] trait: register access to the ESC, returning the AL event register |
//! | [`shared`] | [`SharedEsc`]: the PDI behind an async mutex plus the routing of AL events between the runners |
//! | [`app`] | what the firmware author implements: [`Application`] (state hooks) and [`CycleHandler`] (process data) |
//! | [`esm_runner`] | [`run_esm`]: the state machine, in the low-priority thread executor |
//! | [`spi`] | PDI drivers over `embedded-hal-async` SPI: Beckhoff ESC SPI protocol, Microchip LAN9252 |
//! | [`indicator`] | [`run_indicators`]: the ETG.1300 RUN/ERR LEDs on GPIO pins, from the AL status the state-machine runner publishes |
//! | [`pd_runner`] | [`run_process_data`]: the process-data exchange, in an `InterruptExecutor`; owns the IRQ line |
//!
//! ## Who wakes whom
//! The ESC has one IRQ line: asserted while `AL event & AL event mask` is not empty. The
//! process-data runner owns it. When it fires, that runner reads the AL event register (in
//! SyncManager-synchronous mode it reads the output buffer instead and gets the AL event for free
//! from an SPI ESC). Every PDI access of either runner reports the AL event value it saw to the
//! [`SharedEsc`], which wakes the state-machine runner for state-machine events and the
//! process-data runner for its trigger. While state-machine events hold the IRQ line asserted, the
//! process-data runner does not wait on the line (it would spin) but on the shared state, and the
//! state-machine runner's own accesses tell it when the line is free again. Nothing polls.
//!
//! ## Who waits for whom
//! The state-machine runner's accesses (a mailbox message can be 1 KiB) move in chunks of
//! [`SharedEsc::with_chunk`] bytes, and the process-data runner takes the PDI at the next chunk
//! boundary: its exchange never waits for more than the transaction in flight and one chunk.
//!
//! ## Firmware shape
//! ```ignore
//! static ESC: StaticCell<SharedEsc<CriticalSectionRawMutex, MyPdi>> = StaticCell::new();
//!
//! #[embassy_executor::task]
//! async fn esm(esc: &'static SharedEsc<CriticalSectionRawMutex, MyPdi>, app: MyApp) {
//!     let mut sub = SubDevice::new(&CONFIG);
//!     let mut app = app;
//!     let err = ecat_embassy::run_esm(esc, &mut sub, &mut app).await;
//!     defmt::error!("PDI failed: {}", err);
//! }
//! ```
#![no_std]

pub mod app;
pub mod esm_runner;
pub mod indicator;
mod maybe;
pub mod pd_runner;
pub mod pdi;
pub mod shared;
pub mod spi;
mod time;

pub use app::{Application, CycleHandler};
pub use esm_runner::{SharedDictionary, run_esm};
pub use indicator::run_indicators;
pub use pd_runner::run_process_data;
pub use pdi::Pdi;
pub use shared::SharedEsc;
