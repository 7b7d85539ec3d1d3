//! ecat on an STM32G474: the CiA402 dummy axis of `ecat-axis` (the same application the host
//! demo and the virtual slave run) behind an AX58100 (default) or a LAN9252 (feature `lan9252`).
//! DC SYNC0 capable: SYNC0 (EXTI8) starts the cycle when the MainDevice selects DC mode.
//!
//! Executors as in `src/main.rs`: the process-data runner in an `InterruptExecutor` on UART4 at
//! priority 6, the state-machine/mailbox runner in the thread executor.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use core::cell::RefCell;

use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_axis::{Axis, AxisApp, AxisOd};
use ecat_core::{DeviceConfig, SubDevice};
use ecat_embassy::pd_runner::Buffers;
use ecat_embassy::{SharedDictionary, SharedEsc, run_esm, run_process_data};
use ecat_stm32::board::Board;
use ecat_stm32::{esc, park};
use embassy_executor::SendSpawner;
use embassy_stm32::exti::ExtiInput;

use embassy_stm32::mode::Async;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use panic_probe as _;
use static_cell::StaticCell;

/// The axis's description (DC SYNC0 capable: the board wires SYNC0) on this ESC.
const DEVICE: DeviceConfig = esc::fit(ecat_axis::DEVICE);
const _: () = assert!(DEVICE.validate().is_ok());

type Esc = SharedEsc<CriticalSectionRawMutex, esc::Pdi>;
type Dictionary = SharedDictionary<CriticalSectionRawMutex, AxisOd>;

static ESC: StaticCell<Esc> = StaticCell::new();
static DICTIONARY: StaticCell<Dictionary> = StaticCell::new();
ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let board = Board::init();
    info!("ecat CiA402 axis starting");
    run_executors(|high, spawner| spawner.spawn(unwrap!(state_machine(high, board))))
}

/// The thread executor's task: brings the ESC up, starts the process-data runner in the interrupt
/// executor, then runs the state machine and the mailbox. One task, so the start-up's state
/// shares the task's storage with the runner. The board's digital I/O stays unused.
#[embassy_executor::task]
async fn state_machine(high: SendSpawner, board: Board) -> ! {
    let Board {
        spi,
        irq,
        sync0,
        leds,
        ..
    } = board;
    let Some(pdi) = esc::start_logged(spi).await else {
        park().await
    };
    let esc: &'static Esc = ESC.init(SharedEsc::new(pdi));
    let od: &'static Dictionary = DICTIONARY.init(Mutex::new(RefCell::new(AxisOd::default())));
    let low = SendSpawner::for_current_executor().await;
    low.spawn(unwrap!(ecat_stm32::indicators(esc, leds)));
    high.spawn(unwrap!(process_data(esc, od, irq, sync0)));
    let mut sub: SubDevice<'static> = SubDevice::new(&DEVICE);
    let error = run_esm(esc, &mut sub, &mut AxisApp, od).await;
    error!("PDI failed: {}", error);
    park().await
}

/// The axis's cycle, in the interrupt executor; owns the PDI IRQ and SYNC0 lines.
#[embassy_executor::task]
async fn process_data(
    esc: &'static Esc,
    od: &'static Dictionary,
    mut irq: ExtiInput<'static, Async>,
    mut sync0: ExtiInput<'static, Async>,
) -> ! {
    let (mut outputs, mut inputs) = ([0; 32], [0; 32]);
    let buffers = Buffers {
        outputs: &mut outputs,
        inputs: &mut inputs,
    };
    let mut axis = Axis::new();
    let error = run_process_data(esc, &mut irq, &mut sync0, &mut axis, od, buffers).await;
    error!("process data stopped: {}", error);
    park().await
}
