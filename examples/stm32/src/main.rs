//! ecat on an STM32G474: a 4-in/4-out digital I/O SubDevice behind an AX58100 (default feature
//! `ax58100`, Beckhoff SPI protocol) or a LAN9252 (feature `lan9252`); its application and
//! dictionary are `io::DigitalIo` and `io::IoOd` (SOES's sample digital I/O objects). Size
//! variants: feature `no-dictionary` (the dictionary `()`, raw process images) and `no-leds` (no
//! ETG.1300 LED task); feature `storage`: 0x1010/0x1011 store the input polarity 0x6002 in flash
//! (`ecat_stm32::parameters`).
//!
//! Two executors (priorities: README.md):
//! - an `InterruptExecutor` on UART4's vector at priority 6 runs the process-data runner, which
//!   owns the PDI IRQ line, and the SYNC0 task: an exchange preempts the mailbox and the state
//!   machine at once;
//! - the thread executor runs the start-up and the state-machine/mailbox runner.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_embassy::{Config, Control, ProcessDataRunner, Resources};
use ecat_stm32::board::{Board, Pin};
use ecat_stm32::io::DigitalIo;
use ecat_stm32::{esc, park};
use embassy_executor::SendSpawner;
use panic_probe as _;
use static_cell::StaticCell;

/// 1 byte of outputs, 1 byte of inputs; mailboxes of 128 bytes at 0x1000/0x1080.
const DEVICE: Config<esc::Pdi, 1, 1> = Config::standard();

/// SOES's sample digital I/O dictionary, or none (feature `no-dictionary`).
#[cfg(not(feature = "no-dictionary"))]
type Od = ecat_stm32::io::IoOd;
#[cfg(feature = "no-dictionary")]
type Od = ();

type Ecat = Resources<esc::Pdi, DigitalIo, Od, 1, 1>;
static ECAT: StaticCell<Ecat> = StaticCell::new();
ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let board = Board::init();
    info!("ecat digital I/O starting");
    run_executors(|high, spawner| spawner.spawn(unwrap!(state_machine(high, board))))
}

/// The thread executor's task: brings the ESC up (the LAN9252 needs a reset sequence), starts the
/// process-data runner and the SYNC0 task in the interrupt executor, then runs the state machine
/// and the mailbox. One task, so the start-up's state shares the task's storage with the runner.
#[embassy_executor::task]
async fn state_machine(high: SendSpawner, board: Board) -> ! {
    let Board {
        spi,
        irq,
        sync0,
        io,
        leds,
        flash,
    } = board;
    let Some(pdi) = esc::start_logged(spi).await else {
        park().await
    };
    #[cfg(not(feature = "storage"))]
    let (od, _) = (Od::default(), flash);
    // The stored parameters, loaded before the runners start (feature `storage`).
    #[cfg(feature = "storage")]
    let (mut storage, mut od) = (ecat_stm32::parameters::storage(flash), Od::default());
    #[cfg(feature = "storage")]
    if let Some(storage) = storage.as_mut() {
        match storage.load(&mut od).await {
            Ok(loaded) => info!("parameters: {} loaded, {} skipped", loaded.applied, loaded.skipped),
            Err(e) => error!("parameters: {}", e),
        }
    }
    let ecat = ECAT.init(Ecat::new(&DEVICE, pdi, io, od));
    let (state_machine, process_data, control) = ecat.split();
    #[cfg(feature = "storage")]
    let state_machine = state_machine.with_storage(storage);
    #[cfg(not(feature = "no-leds"))]
    SendSpawner::for_current_executor()
        .await
        .spawn(unwrap!(ecat_stm32::indicators(control.status(), leds)));
    #[cfg(feature = "no-leds")]
    let _ = leds;
    high.spawn(unwrap!(exchange(process_data, irq)));
    high.spawn(unwrap!(sync(control, sync0)));
    error!("PDI failed: {}", state_machine.run().await);
    park().await
}

/// The process-data exchange, in the interrupt executor; owns the PDI IRQ line. The device runs
/// SM-synchronous (no DC SYNC0 in `DEVICE`): SYNC0 only latches the inputs, in `sync` below.
#[embassy_executor::task]
async fn exchange(runner: ProcessDataRunner<'static, esc::Pdi, DigitalIo, Od>, irq: Pin) -> ! {
    error!("process data stopped: {}", runner.run(irq).await);
    park().await
}

/// SYNC0 from the ESC's distributed clock: latches the inputs (in the interrupt executor, so the
/// instant does not depend on the mailbox's work).
#[embassy_executor::task]
async fn sync(control: Control<'static, esc::Pdi, DigitalIo, Od>, mut sync0: Pin) {
    loop {
        sync0.wait_for_falling_edge().await;
        control.lock(|io, _| io.on_sync0());
    }
}
