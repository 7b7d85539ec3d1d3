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
//! The start-up (the ESC brought up, the stored parameters loaded, the resources put in their
//! static) runs to completion before the executors, then two executors (priorities: README.md):
//! - an `InterruptExecutor` on UART4's vector at priority 6 runs the process-data runner, which
//!   owns the PDI IRQ line, and the SYNC0 task: an exchange preempts the mailbox and the state
//!   machine at once;
//! - the thread executor runs the state-machine/mailbox runner and the LED task (and the
//!   update's flash task).
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use core::mem::MaybeUninit;
use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_embassy::{Config, Control, ProcessDataRunner, Resources, StateMachineRunner};
use ecat_stm32::board::{Board, DigitalIo, Leds, Pin};
use ecat_stm32::{SentBeforePoll, esc};
use embassy_futures::block_on;
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
/// The state-machine runner, with the stored parameters (feature `storage`).
#[cfg(not(feature = "storage"))]
type Runner = StateMachineRunner<'static, esc::Pdi, App, Od>;
#[cfg(feature = "storage")]
type Runner =
    StateMachineRunner<'static, esc::Pdi, App, Od, 128, Option<ecat_stm32::parameters::Storage>>;
static ECAT: StaticCell<Ecat> = StaticCell::new();
ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let board = Board::init();
    info!("ecat digital I/O starting");
    let Some(started) = start(board) else {
        run_executors(|_, _| ())
    };
    let (state_machine_runner, process_data, control) = started.ecat.split();
    #[cfg(feature = "storage")]
    let state_machine_runner = state_machine_runner.with_storage(started.storage);
    run_executors(|high, low| {
        #[cfg(feature = "bootloader")]
        low.spawn(unwrap!(ecat_stm32::update::run(started.flash)));
        #[cfg(not(feature = "no-leds"))]
        low.spawn(unwrap!(ecat_stm32::indicators(
            control.status(),
            started.leds
        )));
        high.spawn(unwrap!(exchange(process_data, started.irq)));
        high.spawn(unwrap!(sync(control, started.sync0)));
        low.spawn(unwrap!(state_machine(state_machine_runner)));
    })
}

/// What the start-up hands the tasks: the stack's resources and the board's parts they run on.
struct Started {
    ecat: &'static mut Ecat,
    irq: Pin,
    sync0: Pin,
    #[cfg_attr(feature = "no-leds", allow(dead_code))]
    leds: Leds,
    #[cfg(feature = "bootloader")]
    flash: &'static ecat_stm32::flash::SharedFlash,
    #[cfg(feature = "storage")]
    storage: Option<ecat_stm32::parameters::Storage>,
}

/// The start-up, to completion before the executors run (`block_on`, on the stack: its state
/// is gone once it returned, no task keeps it): brings the ESC up (the LAN9252 needs a reset
/// sequence), loads the stored parameters (feature `storage`) and puts the resources in their
/// static. `None` (logged) when the ESC does not come up.
#[inline(never)]
fn start(board: Board) -> Option<Started> {
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
    let pdi = block_on(esc::start_logged(bus))?;
    #[cfg(any(feature = "bootloader", feature = "storage"))]
    let flash = ecat_stm32::flash::share(flash);
    #[cfg(feature = "bootloader")]
    let io = ecat_stm32::update::Updatable::new(io);
    #[cfg(not(feature = "storage"))]
    #[allow(clippy::let_unit_value)] // `()` with `no-dictionary`
    let od = Od::default();
    // The stored parameters, loaded before the runners start.
    #[cfg(feature = "storage")]
    let (mut storage, mut od) = (ecat_stm32::parameters::storage(flash), Od::default());
    #[cfg(feature = "storage")]
    if let Some(storage) = storage.as_mut() {
        match block_on(storage.load(&mut od)) {
            Ok(loaded) => info!(
                "parameters: {} loaded, {} skipped",
                loaded.applied, loaded.skipped
            ),
            Err(e) => error!("parameters: {}", e),
        }
    }
    // Zeroed first: the compiler drops the constructor's stores of zeros where this `memclr`
    // survives (it trims the part the constructor overwrites whole): 12..72 B less here, 40 B
    // more in the axis firmware, which keeps `init_with` (docs/size-history.md, session 11, init6).
    let slot = ECAT.uninit();
    *slot = MaybeUninit::zeroed();
    let ecat = slot.write(Ecat::new(&DEVICE, pdi, io, od));
    Some(Started {
        ecat,
        irq,
        sync0,
        leds,
        #[cfg(feature = "bootloader")]
        flash,
        #[cfg(feature = "storage")]
        storage,
    })
}

/// The state machine and the mailbox, in the thread executor. The task's future is the
/// runner's own, which logs the error and parks (`run_then`): neither the start-up's state nor a
/// second copy of the runner is kept beside it.
#[embassy_executor::task]
fn state_machine(runner: Runner) -> impl Future<Output = ()> {
    runner.run_then(|e| error!("PDI failed: {}", e))
}

/// The process-data exchange, in the interrupt executor; owns the PDI IRQ line. The device runs
/// SM-synchronous (no DC SYNC0 in `DEVICE`): SYNC0 only latches the inputs, in `sync` below.
/// The task's future is the runner's own, which logs the error and parks (`run_then`), sent to
/// the interrupt executor before its first poll (`SentBeforePoll`: the SPI transfer's future is
/// not `Send`).
#[embassy_executor::task]
fn exchange(
    runner: ProcessDataRunner<'static, esc::Pdi, App, Od>,
    irq: Pin,
) -> impl Future<Output = ()> + Send {
    // SAFETY: the interrupt executor's spawner sends it before its first poll.
    unsafe {
        SentBeforePoll::new((runner, irq), |(runner, irq)| {
            runner.run_then(irq, |e| error!("process data stopped: {}", e))
        })
    }
}

/// SYNC0 from the ESC's distributed clock: latches the inputs (in the interrupt executor, so the
/// instant does not depend on the mailbox's work). A `fn` returning its loop: an `async fn`
/// task keeps its arguments beside the ones its body works on.
#[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
#[embassy_executor::task]
fn sync(
    control: Control<'static, esc::Pdi, App, Od>,
    mut sync0: Pin,
) -> impl Future<Output = ()> + Send {
    async move {
        loop {
            sync0.wait_for_falling_edge().await;
            control.lock(|io, _| io.on_sync0());
        }
    }
}
