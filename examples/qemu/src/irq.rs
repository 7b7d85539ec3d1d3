//! The MPS2-AN386's external interrupts this firmware uses, and its interrupt table (no PAC
//! supplies one for this machine: cortex-m-rt's `device` feature takes `__INTERRUPTS` from here).

use cortex_m::peripheral::NVIC;

use crate::figures;

/// External interrupts (QEMU hw/arm/mps2.c: 32 lines; the timers on 8 and 9, 29 and 31 free).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum Irq {
    /// CMSDK TIMER0: the time driver's counter wrapped.
    Timer0 = 8,
    /// CMSDK TIMER1: the time driver's alarm.
    Timer1 = 9,
    /// The ESC model's IRQ line (what EXTI is on the STM32 board): the MainDevice pends it when
    /// its writes assert the line.
    Esc = 29,
    /// The interrupt executor's vector (the process-data runner).
    Executor = 31,
}

// SAFETY: every number is an external interrupt line of the machine (below 32).
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

impl Irq {
    /// Unmasks the line in the NVIC.
    pub fn enable(self) {
        // SAFETY: every handler this firmware unmasks is defined below and takes its own
        // critical sections; unmasking cannot break one.
        unsafe { NVIC::unmask(self) }
    }

    /// Whether the line is pending.
    pub fn is_pending(self) -> bool {
        NVIC::is_pending(self)
    }

    /// Clears a pending request.
    pub fn unpend(self) {
        NVIC::unpend(self)
    }

    /// Requests the interrupt.
    pub fn pend(self) {
        NVIC::pend(self)
    }
}

/// One entry of the interrupt table: a handler.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct Vector {
    handler: unsafe extern "C" fn(),
}

/// An interrupt no peripheral of this firmware raises.
unsafe extern "C" fn unused() {
    panic!("unexpected interrupt");
}

unsafe extern "C" fn timer0() {
    figures::TIMERS.measure(crate::time_driver::on_counter_wrap);
}

unsafe extern "C" fn timer1() {
    figures::TIMERS.measure(crate::time_driver::on_alarm);
}

unsafe extern "C" fn esc() {
    figures::ESC_IRQ.measure(crate::esc::on_irq);
}

unsafe extern "C" fn executor() {
    // SAFETY: the interrupt executor was started on this vector; only this handler calls it.
    figures::EXECUTOR.measure(|| unsafe { crate::EXECUTOR_HIGH.on_interrupt() })
}

/// The 32 external interrupt vectors, after cortex-m-rt's exception table.
#[unsafe(link_section = ".vector_table.interrupts")]
#[unsafe(no_mangle)]
pub static __INTERRUPTS: [Vector; 32] = {
    let mut table = [Vector { handler: unused }; 32];
    table[Irq::Timer0 as usize] = Vector { handler: timer0 };
    table[Irq::Timer1 as usize] = Vector { handler: timer1 };
    table[Irq::Esc as usize] = Vector { handler: esc };
    table[Irq::Executor as usize] = Vector { handler: executor };
    table
};
