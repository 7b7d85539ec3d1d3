//! The embassy-time driver on the MPS2's two CMSDK APB timers (25 MHz, QEMU's hw/timer/
//! cmsdk-apb-timer.c): TIMER0 counts down from 0xFFFF_FFFF and reloads, its wrap interrupt
//! (IRQ 8) extends it to 64 bits; TIMER1 is the one-shot alarm (IRQ 9). Ticks are 1 µs
//! (embassy-time's default tick rate): 25 timer counts each.

use core::cell::{Cell, RefCell};
use core::ptr::{read_volatile, write_volatile};
use core::task::Waker;

use critical_section::{CriticalSection, Mutex};
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;

use crate::irq::Irq;

/// TIMER0's registers (the counter).
const TIMER0: usize = 0x4000_0000;
/// TIMER1's registers (the alarm).
const TIMER1: usize = 0x4000_1000;
/// Register offsets: CTRL (bit 0 enable, bit 3 interrupt enable), VALUE, RELOAD, INTCLEAR.
const CTRL: usize = 0x0;
const VALUE: usize = 0x4;
const RELOAD: usize = 0x8;
const INTCLEAR: usize = 0xC;
const ENABLE: u32 = 1;
const IRQ_ENABLE: u32 = 1 << 3;
/// Timer counts per embassy-time tick: 25 MHz / 1 MHz.
const COUNTS_PER_TICK: u64 = 25;

fn write(timer: usize, offset: usize, value: u32) {
    // SAFETY: a CMSDK APB timer register of the MPS2 memory map; a 32-bit aligned device register.
    unsafe { write_volatile((timer + offset) as *mut u32, value) }
}

fn read(timer: usize, offset: usize) -> u32 {
    // SAFETY: as in `write`.
    unsafe { read_volatile((timer + offset) as *const u32) }
}

/// The driver's state: wraps of TIMER0 and the timer queue.
struct CmsdkTime {
    wraps: Mutex<Cell<u32>>,
    queue: Mutex<RefCell<Queue>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: CmsdkTime = CmsdkTime {
    wraps: Mutex::new(Cell::new(0)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

/// TIMER0's count since `init`, the low 32 bits (wraps every 171 s).
pub fn count() -> u32 {
    u32::MAX - read(TIMER0, VALUE)
}

/// Starts the counter; enables both timers' interrupts.
pub fn init() {
    write(TIMER0, RELOAD, u32::MAX);
    write(TIMER0, VALUE, u32::MAX);
    write(TIMER0, CTRL, ENABLE | IRQ_ENABLE);
    Irq::Timer0.enable();
    Irq::Timer1.enable();
}

impl CmsdkTime {
    /// Timer counts since `init`, 64 bits; a wrap not yet handled is counted here.
    fn counts(&self, cs: CriticalSection) -> u64 {
        let mut wraps = self.wraps.borrow(cs).get();
        let mut value = read(TIMER0, VALUE);
        if Irq::Timer0.is_pending() {
            wraps += 1;
            value = read(TIMER0, VALUE);
        }
        (u64::from(wraps) << 32) | u64::from(u32::MAX - value)
    }

    /// Arms the alarm for the queue's next deadline; wakes what is due already.
    fn arm(&self, cs: CriticalSection) {
        let mut queue = self.queue.borrow_ref_mut(cs);
        loop {
            let now = self.counts(cs) / COUNTS_PER_TICK;
            let next = queue.next_expiration(now);
            write(TIMER1, CTRL, 0);
            write(TIMER1, INTCLEAR, 1);
            Irq::Timer1.unpend();
            if next == u64::MAX {
                return;
            }
            let counts = next.saturating_sub(now).saturating_mul(COUNTS_PER_TICK);
            // At most one counter period ahead: the alarm re-arms when it fires early.
            let counts = u32::try_from(counts).unwrap_or(u32::MAX).max(1);
            write(TIMER1, RELOAD, counts);
            write(TIMER1, VALUE, counts);
            write(TIMER1, CTRL, ENABLE | IRQ_ENABLE);
            // Still in the future once armed: done; else go round and wake it now.
            if self.counts(cs) / COUNTS_PER_TICK < next {
                return;
            }
        }
    }
}

impl Driver for CmsdkTime {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.counts(cs)) / COUNTS_PER_TICK
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            if self.queue.borrow_ref_mut(cs).schedule_wake(at, waker) {
                self.arm(cs);
            }
        });
    }
}

/// TIMER0 wrapped: one more 2^32 counts.
pub fn on_counter_wrap() {
    critical_section::with(|cs| {
        write(TIMER0, INTCLEAR, 1);
        let wraps = DRIVER.wraps.borrow(cs);
        wraps.set(wraps.get() + 1);
    });
}

/// TIMER1 fired: wake what is due, arm the next deadline.
pub fn on_alarm() {
    critical_section::with(|cs| DRIVER.arm(cs));
}
