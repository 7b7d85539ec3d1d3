//! The size baseline for docs/performance.md: the same board, executors, interrupts, SPI with DMA,
//! EXTI lines, defmt and I/O as the firmware, with the ecat runners replaced by a trivial loop (on
//! each PDI IRQ: one SPI transfer, outputs from it, inputs into the next). Firmware minus baseline
//! is what ecat-core, ecat-embassy and the PDI driver cost.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use defmt::{error, info, unwrap};
use defmt_rtt as _;
use ecat_stm32::board::{Board, EscSpi};
use ecat_stm32::io::{self, DigitalIo};

use embassy_stm32::exti::ExtiInput;

use embassy_stm32::mode::Async;
use embedded_hal_async::spi::SpiDevice;
use panic_probe as _;

ecat_stm32::executors!();

#[cortex_m_rt::entry]
fn main() -> ! {
    let Board {
        spi,
        irq,
        sync0,
        io,
        leds: _,
    } = Board::init();
    info!("baseline starting");
    run_executors(|high, spawner| {
        high.spawn(unwrap!(exchange(spi, irq, io)));
        high.spawn(unwrap!(sync(sync0)));
        spawner.spawn(unwrap!(idle()));
    })
}

#[embassy_executor::task]
async fn exchange(mut spi: EscSpi, mut irq: ExtiInput<'static, Async>, mut io: DigitalIo) {
    let mut frame = [0u8; 4];
    loop {
        irq.wait_for_low().await;
        if let Err(e) = spi.transfer_in_place(&mut frame).await {
            error!("SPI failed: {}", e);
        }
        io.apply(frame[3]);
        frame[0] = io::sample();
    }
}

#[embassy_executor::task]
async fn sync(mut sync0: ExtiInput<'static, Async>) {
    loop {
        sync0.wait_for_falling_edge().await;
        io::on_sync0();
    }
}

#[embassy_executor::task]
async fn idle() {
    info!("baseline idle");
}
