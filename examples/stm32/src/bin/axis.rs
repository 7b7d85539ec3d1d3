//! ecat on an STM32G474: the CiA402 dummy axis of `ecat-axis` (the same application the host
//! demo and the virtual slave run) behind an AX58100 (default) or a LAN9252 (feature `lan9252`).
//! DC SYNC0 capable: SYNC0 (EXTI8) starts the cycle when the MainDevice selects DC mode.
//!
//! Executors as in `src/main.rs`: the process-data runner in an `InterruptExecutor` on UART4 at
//! priority 6, the state-machine/mailbox runner in the thread executor.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_axis::{Axis, AxisOd};
use ecat_embassy::{Config, ProcessDataRunner, Resources, StateMachineRunner};
use ecat_stm32::board::{Board, Pin};
use ecat_stm32::{SentBeforePoll, esc};
use embassy_futures::block_on;
use panic_probe as _;
use static_cell::StaticCell;

/// The axis's description (DC SYNC0 capable: the board wires SYNC0): 13 bytes of outputs, 19
/// of inputs, 128-byte mailboxes.
const DEVICE: Config<esc::Pdi, 13, 19> = Config::new(ecat_axis::DEVICE);

type Ecat = Resources<esc::Pdi, Axis, AxisOd, 13, 19>;
static ECAT: StaticCell<Ecat> = StaticCell::new();
ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let Board {
        bus,
        irq,
        sync0,
        leds,
        ..
    } = Board::init();
    info!("ecat CiA402 axis starting");
    // The start-up runs to completion before the executors (as in `src/main.rs`): no task keeps
    // its state.
    let Some(pdi) = block_on(esc::start_logged(bus)) else {
        run_executors(|_, _| ())
    };
    let ecat = ECAT.init_with(|| Ecat::new(&DEVICE, pdi, Axis::new(), AxisOd::default()));
    let (state_machine_runner, process_data, control) = ecat.split();
    run_executors(|high, low| {
        low.spawn(unwrap!(ecat_stm32::indicators(control.status(), leds)));
        high.spawn(unwrap!(exchange(process_data, irq, sync0)));
        low.spawn(unwrap!(state_machine(state_machine_runner)));
    })
}

/// The state machine and the mailbox, in the thread executor (the runner's own future, as in
/// `src/main.rs`). The board's digital I/O stays unused.
#[embassy_executor::task]
fn state_machine(
    runner: StateMachineRunner<'static, esc::Pdi, Axis, AxisOd>,
) -> impl Future<Output = ()> {
    runner.run_then(|e| error!("PDI failed: {}", e))
}

/// The axis's cycle, in the interrupt executor; owns the PDI IRQ and SYNC0 lines. The task's
/// future is the runner's own, sent before its first poll (as in `src/main.rs`).
#[embassy_executor::task]
fn exchange(
    runner: ProcessDataRunner<'static, esc::Pdi, Axis, AxisOd>,
    irq: Pin,
    sync0: Pin,
) -> impl Future<Output = ()> + Send {
    // SAFETY: the interrupt executor's spawner sends it before its first poll.
    unsafe {
        SentBeforePoll::new((runner, irq, sync0), |(runner, irq, sync0)| {
            runner.run_with_sync0_then(irq, sync0, |e| error!("process data stopped: {}", e))
        })
    }
}
