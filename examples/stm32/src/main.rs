//! ecat on an STM32G474: a 4-in/4-out digital I/O SubDevice behind an AX58100 (default feature
//! `ax58100`, Beckhoff SPI protocol), a LAN9252 (feature `lan9252`) or an AX58100 on the FMC
//! (feature `fmc`, its 16-bit asynchronous microcontroller interface); its application and
//! dictionary are `ecat_dio::DigitalIo` and `ecat_dio::IoOd` (SOES's sample digital I/O objects,
//! shared with the RP2040 firmware). Size
//! variants: feature `no-dictionary` (the dictionary `()`, raw process images) and `no-leds` (no
//! ETG.1300 LED task). Feature `bootloader`: the firmware under examples/stm32-bootloader, with
//! the firmware update by FoE in BOOT (`ecat_stm32::update`; the bootstrap mailbox is the
//! standard one). Feature `storage`: 0x1010/0x1011 keep the input polarity 0x6002 in flash
//! (`ecat_stm32::parameters`), loaded before the runners start.
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
use ecat_stm32::board::{Board, DigitalIo, Pin};
use ecat_stm32::{esc, park};
use embassy_executor::{SendSpawner, Spawner};
use panic_probe as _;
use static_cell::StaticCell;

/// 1 byte of outputs, 1 byte of inputs; mailboxes of 128 bytes at 0x1000/0x1080.
#[cfg(not(feature = "bootloader"))]
const DEVICE: Config<esc::Pdi, 1, 1> = Config::standard();
/// The same with BOOT, through the same mailbox layout (FoE segments of 116 bytes).
#[cfg(feature = "bootloader")]
const DEVICE: Config<esc::Pdi, 1, 1> = Config::new({
    let mut device = *Config::<esc::Pdi, 1, 1>::standard().device();
    device.bootstrap_mailbox = Some(device.mailbox);
    device
});

/// The application: the digital I/O, with the firmware update under the bootloader.
#[cfg(not(feature = "bootloader"))]
type App = DigitalIo;
#[cfg(feature = "bootloader")]
type App = ecat_stm32::update::Updatable<DigitalIo>;

/// SOES's sample digital I/O dictionary, or none (feature `no-dictionary`).
#[cfg(not(feature = "no-dictionary"))]
type Od = ecat_dio::IoOd;
#[cfg(feature = "no-dictionary")]
type Od = ();

type Ecat = Resources<esc::Pdi, App, Od, 1, 1>;
static ECAT: StaticCell<Ecat> = StaticCell::new();
ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let board = Board::init();
    info!("ecat digital I/O starting");
    run_executors(|high, low| low.spawn(unwrap!(state_machine(high, low, board))))
}

/// The thread executor's task: brings the ESC up (the LAN9252 needs a reset sequence), starts the
/// process-data runner and the SYNC0 task in the interrupt executor (`high`) and the LED task
/// (and the update's flash task) in the thread executor (`low`), then runs the state machine
/// and the mailbox. One task, so the start-up's state shares the task's storage with the runner.
#[embassy_executor::task]
async fn state_machine(high: SendSpawner, low: Spawner, board: Board) -> ! {
    let Board {
        bus,
        irq,
        sync0,
        io,
        leds,
        #[cfg(any(feature = "bootloader", feature = "storage"))]
        flash,
        ..
    } = board;
    let Some(pdi) = esc::start_logged(bus).await else {
        park().await
    };
    #[cfg(any(feature = "bootloader", feature = "storage"))]
    let flash = ecat_stm32::flash::share(flash);
    #[cfg(feature = "bootloader")]
    let io = {
        low.spawn(unwrap!(ecat_stm32::update::run(flash)));
        ecat_stm32::update::Updatable::new(io)
    };
    #[cfg(not(feature = "storage"))]
    let od = Od::default();
    // The stored parameters, loaded before the runners start.
    #[cfg(feature = "storage")]
    let (mut storage, mut od) = (ecat_stm32::parameters::storage(flash), Od::default());
    #[cfg(feature = "storage")]
    if let Some(storage) = storage.as_mut() {
        match storage.load(&mut od).await {
            Ok(loaded) => info!(
                "parameters: {} loaded, {} skipped",
                loaded.applied, loaded.skipped
            ),
            Err(e) => error!("parameters: {}", e),
        }
    }
    let ecat = ECAT.init(Ecat::new(&DEVICE, pdi, io, od));
    let (state_machine, process_data, control) = ecat.split();
    #[cfg(feature = "storage")]
    let state_machine = state_machine.with_storage(storage);
    #[cfg(not(feature = "no-leds"))]
    low.spawn(unwrap!(ecat_stm32::indicators(control.status(), leds)));
    #[cfg(feature = "no-leds")]
    let _ = (leds, low);
    high.spawn(unwrap!(exchange(process_data, irq)));
    high.spawn(unwrap!(sync(control, sync0)));
    error!("PDI failed: {}", state_machine.run().await);
    park().await
}

/// The process-data exchange, in the interrupt executor; owns the PDI IRQ line. The device runs
/// SM-synchronous (no DC SYNC0 in `DEVICE`): SYNC0 only latches the inputs, in `sync` below.
#[embassy_executor::task]
async fn exchange(runner: ProcessDataRunner<'static, esc::Pdi, App, Od>, irq: Pin) -> ! {
    error!("process data stopped: {}", runner.run(irq).await);
    park().await
}

/// SYNC0 from the ESC's distributed clock: latches the inputs (in the interrupt executor, so the
/// instant does not depend on the mailbox's work).
#[embassy_executor::task]
async fn sync(control: Control<'static, esc::Pdi, App, Od>, mut sync0: Pin) {
    loop {
        sync0.wait_for_falling_edge().await;
        control.lock(|io, _| io.on_sync0());
    }
}
