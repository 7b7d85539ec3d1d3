//! ecat on an RP2040 (Raspberry Pi Pico): the 4-in/4-out digital I/O SubDevice of the STM32
//! firmware (`ecat_dio`: the same application and dictionary) behind a LAN9252 on SPI0, on
//! embassy-rp — a second Embassy HAL, and the Cortex-M0+ (thumbv6m: no compare-and-swap, so the
//! atomics of static_cell come from critical sections through portable-atomic).
//!
//! Two executors (priorities: README.md):
//! - an `InterruptExecutor` on SWI_IRQ_1 (a software interrupt no peripheral raises) at priority 1
//!   runs the process-data runner, which owns the PDI IRQ line, and the SYNC0 task: an exchange
//!   preempts the mailbox and the state machine at once;
//! - the thread executor runs the start-up and the state-machine/mailbox runner.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

mod board;

use board::{Board, DigitalIo, EscSpi, Leds, Pin};
use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_dio::IoOd;
use ecat_embassy::spi::lan9252::{self, Lan9252};
use ecat_embassy::{Config, Control, ProcessDataRunner, Resources, Status};
use embassy_executor::{Executor, InterruptExecutor, SendSpawner};
use embassy_rp::interrupt::{self, InterruptExt, Priority};
use panic_probe as _;
use static_cell::StaticCell;

/// The PDI driver: the LAN9252 over SPI0.
type Pdi = Lan9252<EscSpi>;

/// 1 byte of outputs, 1 byte of inputs; mailboxes of 128 bytes at 0x1000/0x1080.
const DEVICE: Config<Pdi, 1, 1> = Config::standard();

type Ecat = Resources<Pdi, DigitalIo, IoOd, 1, 1>;
static ECAT: StaticCell<Ecat> = StaticCell::new();

static EXECUTOR_HIGH: InterruptExecutor = InterruptExecutor::new();
static EXECUTOR_LOW: StaticCell<Executor> = StaticCell::new();

/// The process-data executor's interrupt.
#[embassy_rp::interrupt]
unsafe fn SWI_IRQ_1() {
    // SAFETY: the executor was started on this interrupt; only the interrupt handler calls it.
    unsafe { EXECUTOR_HIGH.on_interrupt() }
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let board = Board::init();
    info!("ecat digital I/O (RP2040) starting");
    // Below the HAL's handlers (priority 0: GPIO, DMA, the time driver), above thread mode.
    interrupt::SWI_IRQ_1.set_priority(Priority::P1);
    let high = EXECUTOR_HIGH.start(interrupt::SWI_IRQ_1);
    EXECUTOR_LOW
        .init(Executor::new())
        .run(|spawner| spawner.spawn(unwrap!(state_machine(high, board))))
}

/// The thread executor's task: resets the LAN9252 and waits until it is ready, starts the
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
    } = board;
    let pdi = match Lan9252::start(spi, lan9252::Config::default()).await {
        Ok(pdi) => pdi,
        Err(e) => {
            error!("ESC start-up failed: {}", e);
            park().await
        }
    };
    let ecat = ECAT.init_with(|| Ecat::new(&DEVICE, pdi, io, IoOd::default()));
    let (state_machine, process_data, control) = ecat.split();
    SendSpawner::for_current_executor()
        .await
        .spawn(unwrap!(indicators(control.status(), leds)));
    high.spawn(unwrap!(exchange(process_data, irq)));
    high.spawn(unwrap!(sync(control, sync0)));
    state_machine
        .run_then(|e| error!("PDI failed: {}", e))
        .await;
    park().await
}

/// The process-data exchange, in the interrupt executor; owns the PDI IRQ line. The device runs
/// SM-synchronous (no DC SYNC0 in `DEVICE`): SYNC0 only latches the inputs, in `sync` below.
#[embassy_executor::task]
async fn exchange(runner: ProcessDataRunner<'static, Pdi, DigitalIo, IoOd>, irq: Pin) -> ! {
    runner
        .run_then(irq, |e| error!("process data stopped: {}", e))
        .await;
    park().await
}

/// SYNC0 from the ESC's distributed clock: latches the inputs (in the interrupt executor, so the
/// instant does not depend on the mailbox's work).
#[embassy_executor::task]
async fn sync(control: Control<'static, Pdi, DigitalIo, IoOd>, mut sync0: Pin) {
    loop {
        sync0.wait_for_falling_edge().await;
        control.lock(|io, _| io.on_sync0());
    }
}

/// The ETG.1300 RUN/ERR LEDs, in the thread executor.
#[embassy_executor::task]
fn indicators(status: Status<'static, Pdi>, leds: Leds) -> impl core::future::Future<Output = ()> {
    ecat_embassy::run_indicators(status, leds)
}

/// Parks the calling task for good once its runner stopped (after logging why): a task that
/// never completes carries no drop code for its future.
async fn park() -> ! {
    loop {
        core::future::pending::<()>().await;
    }
}
