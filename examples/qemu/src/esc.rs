//! The ESC on the target: the host tests' model (`ecat-esc`), shared by the MainDevice's
//! SysTick handler (its EtherCAT port) and the runners (its PDI), each access in one critical
//! section as a real ESC arbitrates its two ports; its IRQ line on an NVIC vector.

use core::cell::RefCell;
use core::convert::Infallible;
use core::future::poll_fn;
use core::sync::atomic::{AtomicBool, Ordering};
use core::task::Poll;

use cortex_m::peripheral::SCB;
use cortex_m::peripheral::scb::VectActive;
use critical_section::Mutex;
use ecat_core::AlEvent;
use ecat_core::chip::Chip;
use ecat_embassy::Pdi;
use ecat_embassy::pdi::Data;
use ecat_esc::{Esc, EscConfig};
use embassy_sync::waitqueue::AtomicWaker;

use crate::app::DEVICE;
use crate::irq::Irq;
use crate::main_device::INPUTS;

/// The chip the model is: an ET1100 (8 SyncManagers, 8 KiB of process RAM).
pub const CHIP: Chip = Chip::ET1100;

static ESC: Mutex<RefCell<Option<Esc>>> = Mutex::new(RefCell::new(None));
/// Who waits for the IRQ line: the process-data runner.
static IRQ_WAKER: AtomicWaker = AtomicWaker::new();

/// Powers the ESC on (its EEPROM loaded) and unmasks its IRQ vector.
pub fn init() {
    let esc = Esc::new(EscConfig::of(CHIP));
    critical_section::with(|cs| ESC.borrow_ref_mut(cs).replace(esc));
    Irq::Esc.enable();
}

/// Runs `f` on the ESC in a critical section.
pub fn with<R>(f: impl FnOnce(&mut Esc) -> R) -> R {
    critical_section::with(|cs| {
        crate::figures::in_model(|| match ESC.borrow_ref_mut(cs).as_mut() {
            Some(esc) => f(esc),
            None => panic!("the ESC is not powered on"),
        })
    })
}

/// The IRQ vector: the line may have been asserted, the runner looks.
pub fn on_irq() {
    IRQ_WAKER.wake();
}

/// The state-machine runner's last access to a mailbox (SM0 or SM1) ended before the buffer's
/// end: it is inside a chunked transfer.
static INSIDE_TRANSFER: AtomicBool = AtomicBool::new(false);

/// Whether the state-machine runner is inside a chunked mailbox transfer (part of SM0 read or
/// part of SM1 written).
pub fn inside_transfer() -> bool {
    INSIDE_TRANSFER.load(Ordering::Relaxed)
}

/// The PDI: each access is one critical section on the model, as the SPI drivers' are one
/// transaction.
pub struct ModelPdi {
    /// The AL event the last access sampled.
    event: AlEvent,
}

impl ModelPdi {
    /// The PDI before its first access.
    pub const fn new() -> Self {
        Self {
            event: AlEvent::NONE,
        }
    }

    /// Notes where a thread-mode (state-machine runner) access to a mailbox ended.
    fn track(address: u16, len: usize) {
        if SCB::vect_active() != VectActive::ThreadMode {
            return;
        }
        let end = usize::from(address) + len;
        let mailbox = DEVICE.device().mailbox;
        for area in [mailbox.receive, mailbox.send] {
            let (start, area_end) = (
                usize::from(area.start),
                usize::from(area.start) + usize::from(area.length),
            );
            if usize::from(address) < area_end && end > start {
                INSIDE_TRANSFER.store(end < area_end, Ordering::Relaxed);
            }
        }
    }
}

impl Pdi for ModelPdi {
    type Error = Infallible;
    const CHIP: Option<Chip> = Some(CHIP);

    async fn access(&mut self, address: u16, data: Data<'_>) -> Result<(), Infallible> {
        Self::track(address, data.len());
        let inputs = matches!(data, Data::Write(_)) && address == INPUTS.start;
        self.event = with(|esc| match data {
            Data::Read(buf) => esc.pdi_read(address, buf),
            Data::Write(data) => esc.pdi_write(address, data),
        });
        if inputs {
            crate::figures::inputs_written(inside_transfer());
        }
        Ok(())
    }

    fn al_event(&self) -> AlEvent {
        self.event
    }
}

/// The ESC's IRQ output, active low: "low" while `AL event & AL event mask` is not empty.
pub struct IrqPin;

impl IrqPin {
    /// Waits until the line is `asserted` (low) or not.
    async fn wait(asserted: bool) {
        poll_fn(|cx| {
            IRQ_WAKER.register(cx.waker());
            if with(|esc| esc.irq()) == asserted {
                Poll::Ready(())
            } else {
                Poll::Pending
            }
        })
        .await
    }
}

impl embedded_hal::digital::ErrorType for IrqPin {
    type Error = Infallible;
}

impl embedded_hal_async::digital::Wait for IrqPin {
    async fn wait_for_low(&mut self) -> Result<(), Infallible> {
        Self::wait(true).await;
        Ok(())
    }

    async fn wait_for_high(&mut self) -> Result<(), Infallible> {
        Self::wait(false).await;
        Ok(())
    }

    async fn wait_for_falling_edge(&mut self) -> Result<(), Infallible> {
        Self::wait(false).await;
        Self::wait(true).await;
        Ok(())
    }

    async fn wait_for_rising_edge(&mut self) -> Result<(), Infallible> {
        Self::wait(true).await;
        Self::wait(false).await;
        Ok(())
    }

    async fn wait_for_any_edge(&mut self) -> Result<(), Infallible> {
        let level = with(|esc| esc.irq());
        Self::wait(!level).await;
        Ok(())
    }
}
