//! ecat on an STM32G474: a 4-in/4-out digital I/O SubDevice behind an AX58100 (default feature
//! `ax58100`, Beckhoff SPI protocol) or a LAN9252 (feature `lan9252`); its dictionary is
//! `io::IoOd` (SOES's sample digital I/O objects). Size variants: feature `no-dictionary` (the
//! dictionary `()`, raw process images) and `no-leds` (no ETG.1300 LED task).
//!
//! Two executors (priorities: README.md):
//! - an `InterruptExecutor` on UART4's vector at priority 6 runs the process-data runner, which
//!   owns the PDI IRQ line, and the SYNC0 task: an exchange preempts the mailbox and the state
//!   machine at once;
//! - the thread executor runs the start-up and the state-machine/mailbox runner.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use core::cell::RefCell;

use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_core::device::{MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::ObjectHooks;
use ecat_core::{DeviceConfig, SubDevice, Transition};
use ecat_embassy::pd_runner::{Buffers, NoSync0};
use ecat_embassy::{Application, SharedDictionary, SharedEsc, run_esm, run_process_data};
use ecat_stm32::board::Board;
use ecat_stm32::io::{self, DigitalIo};
use ecat_stm32::{esc, park};
use embassy_executor::SendSpawner;
use embassy_stm32::exti::ExtiInput;

use embassy_stm32::mode::Async;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use panic_probe as _;
use static_cell::StaticCell;

/// Mailboxes of 128 bytes at 0x1000/0x1080; 1 byte of outputs, 1 byte of inputs.
const DEVICE: DeviceConfig = esc::fit(DeviceConfig::new(
    MailboxConfig::contiguous(0x1000, 128),
    ProcessDataSizes {
        outputs: 1,
        inputs: 1,
    },
));
const _: () = assert!(DEVICE.validate().is_ok());

/// SOES's sample digital I/O dictionary, or none (feature `no-dictionary`).
#[cfg(not(feature = "no-dictionary"))]
type Od = io::IoOd;
#[cfg(feature = "no-dictionary")]
type Od = ();

type Esc = SharedEsc<CriticalSectionRawMutex, esc::Pdi>;
type Dictionary = SharedDictionary<CriticalSectionRawMutex, Od>;

static ESC: StaticCell<Esc> = StaticCell::new();
static DICTIONARY: StaticCell<Dictionary> = StaticCell::new();
ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let board = Board::init();
    info!("ecat digital I/O starting");
    run_executors(|high, spawner| spawner.spawn(unwrap!(state_machine(high, board))))
}

/// State hooks: accept every transition, log state changes.
struct Hooks;

impl Application for Hooks {
    fn on_state_change(&mut self, transition: Transition) {
        info!(
            "AL state {=u8:#x} -> {=u8:#x}",
            transition.from as u8, transition.to as u8
        );
        if !transition.to.has_process_data() {
            io::on_process_data_stopped();
        }
    }
}

impl ObjectHooks<Od> for Hooks {}

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
    } = board;
    let Some(pdi) = esc::start_logged(spi).await else {
        park().await
    };
    let esc: &'static Esc = ESC.init(SharedEsc::new(pdi));
    let od: &'static Dictionary = DICTIONARY.init(Mutex::new(RefCell::new(Od::default())));
    #[cfg(not(feature = "no-leds"))]
    SendSpawner::for_current_executor()
        .await
        .spawn(unwrap!(ecat_stm32::indicators(esc, leds)));
    #[cfg(feature = "no-leds")]
    let _ = leds;
    high.spawn(unwrap!(process_data(esc, od, irq, io)));
    high.spawn(unwrap!(sync(sync0)));
    let mut sub: SubDevice<'static> = SubDevice::new(&DEVICE);
    let error = run_esm(esc, &mut sub, &mut Hooks, od).await;
    error!("PDI failed: {}", error);
    park().await
}

/// The process-data exchange, in the interrupt executor; owns the PDI IRQ line.
#[embassy_executor::task]
async fn process_data(
    esc: &'static Esc,
    od: &'static Dictionary,
    mut irq: ExtiInput<'static, Async>,
    mut io: DigitalIo,
) -> ! {
    let (mut outputs, mut inputs) = ([0; 1], [0; 1]);
    let buffers = Buffers {
        outputs: &mut outputs,
        inputs: &mut inputs,
    };
    // The device runs SM-synchronous (DEVICE.sync_modes has no DC SYNC0): SYNC0 only latches the
    // inputs, in its own task below.
    let mut no_sync0 = NoSync0::new();
    let error = run_process_data(esc, &mut irq, &mut no_sync0, &mut io, od, buffers).await;
    io.apply(0);
    error!("process data stopped: {}", error);
    park().await
}

/// SYNC0 from the ESC's distributed clock: samples the inputs (in the interrupt executor, so the
/// instant does not depend on the mailbox's work).
#[embassy_executor::task]
async fn sync(mut sync0: ExtiInput<'static, Async>) {
    loop {
        sync0.wait_for_falling_edge().await;
        io::on_sync0();
    }
}
