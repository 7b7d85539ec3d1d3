//! ecat's runners on a Cortex-M4 under QEMU (machine `mps2-an386`): the ESC model the host
//! tests run (`ecat-esc`) on the target, a scripted MainDevice in the SysTick handler, and the
//! two executors of the STM32 firmware:
//! - an `InterruptExecutor` on a spare NVIC vector (31) runs the process-data runner, woken by
//!   the ESC model's IRQ vector (29), which the MainDevice pends when its writes assert the line;
//! - the thread executor runs the state-machine/mailbox runner.
//!
//! embassy-time runs on the machine's CMSDK timers (`time_driver`). The verdict leaves through
//! semihosting: the report, then exit code 0 (passed) or 1.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

mod app;
mod esc;
mod irq;
mod main_device;
mod runners;
mod time_driver;

use core::cell::RefCell;
use core::mem::MaybeUninit;

use cortex_m::peripheral::scb::SystemHandler;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::{debug, hprintln};
use critical_section::Mutex;
use embassy_executor::{Executor, InterruptExecutor};
use embedded_alloc::LlffHeap as Heap;
use static_cell::StaticCell;

use irq::Irq;
use main_device::{CYCLE_US, MainDevice};

/// The process-data executor, on [`Irq::Executor`].
static EXECUTOR_HIGH: InterruptExecutor = InterruptExecutor::new();
static EXECUTOR_LOW: StaticCell<Executor> = StaticCell::new();
static MAIN_DEVICE: Mutex<RefCell<MainDevice>> = Mutex::new(RefCell::new(MainDevice::new()));

#[global_allocator]
static HEAP: Heap = Heap::empty();
/// The ESC model's 64 KiB address space, its EEPROM image and area map.
const HEAP_SIZE: usize = 96 * 1024;

/// The system clock of the MPS2 (QEMU hw/arm/mps2.c): SysTick's and the timers' clock.
pub const SYSCLK_HZ: u32 = 25_000_000;

/// Interrupt priorities (upper 3 bits; lower is more urgent): the MainDevice's SysTick and the
/// time driver above the process-data executor and the ESC's IRQ, which preempt the thread.
const PRIORITY_MAIN_DEVICE: u8 = 0x20;
const PRIORITY_TIMERS: u8 = 0x20;
const PRIORITY_EXECUTOR: u8 = 0x60;
const PRIORITY_ESC: u8 = 0x60;

#[entry]
fn main() -> ! {
    {
        static mut MEMORY: [MaybeUninit<u8>; HEAP_SIZE] = [MaybeUninit::uninit(); HEAP_SIZE];
        // SAFETY: called once, before any allocation; `MEMORY` is used by nothing else.
        unsafe { HEAP.init(&raw mut MEMORY as usize, HEAP_SIZE) }
    }
    let Some(mut core) = cortex_m::Peripherals::take() else {
        fail("core peripherals taken twice")
    };
    // SAFETY: priorities are set before any of these interrupts is enabled.
    unsafe {
        core.NVIC.set_priority(Irq::Timer0, PRIORITY_TIMERS);
        core.NVIC.set_priority(Irq::Timer1, PRIORITY_TIMERS);
        core.NVIC.set_priority(Irq::Executor, PRIORITY_EXECUTOR);
        core.NVIC.set_priority(Irq::Esc, PRIORITY_ESC);
        core.SCB.set_priority(SystemHandler::SysTick, PRIORITY_MAIN_DEVICE);
    }
    time_driver::init();
    esc::init();
    let high = EXECUTOR_HIGH.start(Irq::Executor);
    // The MainDevice's clock: two interrupts a cycle, their distance set at each.
    let syst = &mut core.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(main_device::first_reload());
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
    log(format_args!(
        "ecat on QEMU mps2-an386: {CYCLE_US} us cycle, {} OP cycles",
        main_device::OP_CYCLES
    ));
    EXECUTOR_LOW.init(Executor::new()).run(|spawner| {
        match runners::state_machine(high) {
            Ok(token) => spawner.spawn(token),
            Err(_) => fail("cannot spawn the state-machine runner"),
        }
    })
}

#[exception]
fn SysTick() {
    let (report, reload) = critical_section::with(|cs| MAIN_DEVICE.borrow_ref_mut(cs).on_tick());
    // SAFETY: only this handler writes the reload register after start-up; a write takes effect
    // at the next wrap.
    unsafe { (*cortex_m::peripheral::SYST::PTR).rvr.write(reload) }
    if let Some(report) = report {
        log(format_args!("{report:?}"));
        if report.passed() {
            log(format_args!("PASS"));
            debug::exit(debug::EXIT_SUCCESS);
        } else {
            fail("the report shows a failure");
        }
    }
}

/// One line to the host.
pub fn log(args: core::fmt::Arguments<'_>) {
    hprintln!("{}", args);
}

/// Reports `why` and ends the run with exit code 1.
pub fn fail(why: &str) -> ! {
    hprintln!("FAIL: {}", why);
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    hprintln!("panic: {}", info);
    fail("panic")
}

#[exception]
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    hprintln!("hard fault: {:?}", frame);
    fail("hard fault")
}
