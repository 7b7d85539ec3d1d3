//! The size baseline for docs/performance.md: the same board, executors, interrupts, SPI with DMA,
//! EXTI lines, defmt and I/O as the firmware, with the ecat runners replaced by a trivial loop (on
//! each PDI IRQ: one SPI transfer, outputs from it, inputs into the next). Firmware minus baseline
//! is what ecat-core, ecat-embassy and the PDI driver cost.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use core::cell::RefCell;

#[cfg(not(feature = "fmc"))]
use defmt::error;
use defmt::{info, unwrap};
use defmt_rtt as _;
#[cfg(not(feature = "fmc"))]
use ecat_embassy::spi::port::{Part, Port};
use ecat_stm32::board::{Board, DigitalIo, EscBus, Pin};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use panic_probe as _;

/// The application, shared by the exchange and the SYNC0 task as the firmware's runners share
/// it (a critical-section mutex).
static IO: Mutex<CriticalSectionRawMutex, RefCell<Option<DigitalIo>>> =
    Mutex::new(RefCell::new(None));

ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let Board {
        bus,
        irq,
        sync0,
        io,
        leds: _,
        ..
    } = Board::init();
    info!("baseline starting");
    IO.lock(|cell| cell.replace(Some(io)));
    run_executors(|high, spawner| {
        high.spawn(unwrap!(exchange(bus, irq)));
        high.spawn(unwrap!(sync(sync0)));
        spawner.spawn(unwrap!(idle()));
    })
}

#[embassy_executor::task]
async fn exchange(mut bus: EscBus, mut irq: Pin) {
    let mut frame = [0u8; 4];
    loop {
        irq.wait_for_low().await;
        #[cfg(not(feature = "fmc"))]
        if let Err(e) = bus.transaction([Part::Exchange(&mut frame)]).await {
            error!("SPI failed: {}", e);
        }
        #[cfg(feature = "fmc")]
        fmc_transfer(&mut bus, &mut frame);
        frame[0] = with_io(|io| {
            io.apply(frame[3]);
            io.sample()
        });
    }
}

/// The FMC's counterpart of the SPI transfer: `frame` written as two words, then read back.
#[cfg(feature = "fmc")]
fn fmc_transfer(bus: &mut EscBus, frame: &mut [u8; 4]) {
    use ecat_embassy::mcu::Bus16;
    let [a, b, c, d] = *frame;
    bus.write(0x1000, u16::from_le_bytes([a, b]));
    bus.write(0x1002, u16::from_le_bytes([c, d]));
    let [a, b] = bus.read(0x1000).to_le_bytes();
    let [c, d] = bus.read(0x1002).to_le_bytes();
    *frame = [a, b, c, d];
}

#[embassy_executor::task]
async fn sync(mut sync0: Pin) {
    loop {
        sync0.wait_for_falling_edge().await;
        with_io(DigitalIo::on_sync0);
    }
}

/// Runs `f` on the application, locked.
fn with_io<R: Default>(f: impl FnOnce(&mut DigitalIo) -> R) -> R {
    IO.lock(|cell| cell.borrow_mut().as_mut().map(f).unwrap_or_default())
}

#[embassy_executor::task]
async fn idle() {
    info!("baseline idle");
}
