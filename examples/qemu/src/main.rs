//! ecat's runners on a Cortex-M4 under QEMU (machine `mps2-an386`): the ESC model the host
//! tests run (`ecat-esc`) on the target, a scripted MainDevice in the SysTick handler, and the
//! two executors of the STM32 firmware:
//! - an `InterruptExecutor` on a spare NVIC vector (31) runs the process-data runner, woken by
//!   the ESC model's IRQ vector (29), which the MainDevice pends when its writes assert the line;
//! - the thread executor runs the state-machine/mailbox runner.
//!
//! embassy-time runs on the machine's CMSDK timers (`time_driver`). The verdict leaves through
//! semihosting: the report and the figures (`figures`), then exit code 0 (passed) or 1.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

mod app;
mod esc;
mod figures;
mod irq;
mod main_device;
mod runners;
mod time_driver;

use core::cell::RefCell;
use core::mem::MaybeUninit;
use core::sync::atomic::Ordering;

use cortex_m::peripheral::scb::SystemHandler;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::{debug, hprintln};
use critical_section::Mutex;
use embassy_executor::{Executor, InterruptExecutor, SendSpawner};
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

/// The one priority of every handler (upper 3 bits): the process-data executor, the ESC's IRQ,
/// the time driver and the MainDevice's SysTick all preempt the thread, none another, so each
/// handler's stack is measured alone (`figures`).
const PRIORITY: u8 = 0x20;
/// SysTick counts to the MainDevice's first tick.
const FIRST_TICK: u32 = 1_000;
/// The shortest SysTick period: a tick already late comes this soon.
const SOONEST: u32 = 25;

/// The interrupt executor's spawner, for the thread (which starts on its own stack).
static HIGH: Mutex<core::cell::Cell<Option<SendSpawner>>> = Mutex::new(core::cell::Cell::new(None));

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
        for irq in [Irq::Timer0, Irq::Timer1, Irq::Executor, Irq::Esc] {
            core.NVIC.set_priority(irq, PRIORITY);
        }
        core.SCB.set_priority(SystemHandler::SysTick, PRIORITY);
    }
    time_driver::init();
    esc::init();
    let high = EXECUTOR_HIGH.start(Irq::Executor);
    critical_section::with(|cs| HIGH.borrow(cs).set(Some(high)));
    // The MainDevice's clock: two interrupts a cycle, their distance set at each.
    let syst = &mut core.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(FIRST_TICK);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
    log(format_args!(
        "ecat on QEMU mps2-an386: {CYCLE_US} us cycle, {} OP cycles",
        main_device::OP_CYCLES
    ));
    // The thread moves to its own painted stack (the process stack), so the handlers' main
    // stack and the thread executor's are measured apart.
    let base = &raw mut figures::THREAD_STACK as usize;
    for word in 0..figures::THREAD_STACK_BYTES / 4 {
        // SAFETY: the thread stack is not in use yet; an aligned word of the static.
        unsafe { core::ptr::write_volatile((base + 4 * word) as *mut u32, figures::PAINT) }
    }
    figures::HANDLER_BASE.store(cortex_m::register::msp::read(), Ordering::Relaxed);
    let top = base + figures::THREAD_STACK_BYTES;
    // SAFETY: PSP is the top of the thread stack (8-byte aligned: a static of u32 words whose
    // size is a multiple of 8); with CONTROL.SPSEL set, thread mode runs on it from here on.
    // `thread` never returns, so nothing of `main`'s frame (left on the main stack) is used
    // again.
    unsafe {
        core::arch::asm!(
            "msr psp, {top}",
            "mrs {top}, control",
            "orr {top}, {top}, #2",
            "msr control, {top}",
            "isb",
            "bx {thread}",
            top = in(reg) top & !7,
            thread = in(reg) thread as *const () as usize,
            options(noreturn),
        )
    }
}

/// The thread executor, on the process stack.
extern "C" fn thread() -> ! {
    let Some(high) = critical_section::with(|cs| HIGH.borrow(cs).get()) else {
        fail("no interrupt executor")
    };
    EXECUTOR_LOW
        .init(Executor::new())
        .run(|spawner| match runners::state_machine(high) {
            Ok(token) => spawner.spawn(token),
            Err(_) => fail("cannot spawn the state-machine runner"),
        })
}

#[exception]
fn SysTick() {
    let mut tick = (None, 0);
    figures::MAIN_DEVICE.measure(|| {
        let now = time_driver::count();
        tick = critical_section::with(|cs| MAIN_DEVICE.borrow_ref_mut(cs).on_tick(now));
    });
    let (report, deadline) = tick;
    // The next tick at `deadline`: SysTick restarted with the distance.
    let distance = deadline.wrapping_sub(time_driver::count());
    let distance = if (distance as i32) < SOONEST as i32 {
        SOONEST
    } else {
        distance
    };
    // SAFETY: only this handler writes SysTick's reload and current value after start-up;
    // clearing the current value restarts the count from the reload value.
    unsafe {
        let syst = &*cortex_m::peripheral::SYST::PTR;
        syst.rvr.write(distance - 1);
        syst.cvr.write(0);
    }
    if let Some(report) = report {
        log(format_args!("{report:?}"));
        let latency = figures::latency();
        log(format_args!(
            "IRQ -> inputs written, the state-machine runner between transfers: {}",
            latency.total_idle
        ));
        log(format_args!(
            "  of which outside the ESC model: {}",
            latency.firmware_idle
        ));
        log(format_args!(
            "IRQ -> inputs written, the state-machine runner inside a chunked transfer: {}",
            latency.total_inside
        ));
        log(format_args!(
            "  of which outside the ESC model: {}",
            latency.firmware_inside
        ));
        log(format_args!(
            "peak stack: thread executor {} B; handlers from the main stack's base: interrupt executor {}, ESC IRQ {}, time driver {}, MainDevice (test) {}",
            figures::thread_stack_peak(),
            figures::EXECUTOR,
            figures::ESC_IRQ,
            figures::TIMERS,
            figures::MAIN_DEVICE
        ));
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
