//! Clocks, pins and interrupts of the Raspberry Pi Pico (pin assignment and priorities:
//! README.md).

use ecat_core::chip::SpiMode;
use ecat_embassy::spi::port::Exclusive;
use embassy_rp::gpio::{Input, Level, Output, Pull};
use embassy_rp::peripherals::{DMA_CH0, DMA_CH1};
use embassy_rp::spi::{self, Async, Phase, Polarity, Spi};
use embassy_rp::{bind_interrupts, dma, peripherals};

/// The ETG.1300 RUN (green) and ERR (red) LEDs: GP14 and GP15, lit when high.
pub type Leds = ecat_embassy::indicator::RunErr<Output<'static>, Output<'static>>;

/// The digital I/O application (`ecat_dio`) on this board's pins.
pub type DigitalIo = ecat_dio::DigitalIo<Output<'static>, Input<'static>>;

bind_interrupts!(struct Irqs {
    DMA_IRQ_0 => dma::InterruptHandler<DMA_CH0>, dma::InterruptHandler<DMA_CH1>;
});

/// SPI0 with DMA and the ESC's chip select: the bus the PDI driver owns.
pub type EscSpi = Exclusive<Spi<'static, peripherals::SPI0, Async>, Output<'static>>;

/// SPI clock: the LAN9252 takes 20 MHz for the READ instruction (mode 0 or 3); clk_peri (125 MHz)
/// divided by 8 gives 15.6 MHz, the fastest rate not above it (embassy-rp rounds down).
const SPI_CLOCK: u32 = 20_000_000;

/// An input line from the ESC (IRQ, SYNC0): a GPIO with its edge interrupt (IO_IRQ_BANK0).
pub type Pin = Input<'static>;

/// What the firmware gets from the board.
pub struct Board {
    /// The ESC's SPI bus.
    pub spi: EscSpi,
    /// The ESC's PDI interrupt line (active low).
    pub irq: Pin,
    /// The ESC's SYNC0 output (from the distributed clock): push-pull, active high, as the SII
    /// image's configuration area sets it (0x0151 = 0x06, `ecat_core::chip`).
    pub sync0: Pin,
    /// The application's pins.
    pub io: DigitalIo,
    /// The RUN and ERR LEDs.
    pub leds: Leds,
}

impl Board {
    /// The default clocks (125 MHz from the 12 MHz crystal), then the peripherals.
    pub fn init() -> Self {
        let p = embassy_rp::init(embassy_rp::config::Config::default());

        let mut config = spi::Config::default();
        // The mode of the ESC's driver, which the SII image's configuration area sets in the ESC.
        let mode: SpiMode = ecat_embassy::spi::lan9252::SPI_MODE;
        config.polarity = if mode.idle_high() {
            Polarity::IdleHigh
        } else {
            Polarity::IdleLow
        };
        config.phase = if mode.capture_on_second_edge() {
            Phase::CaptureOnSecondTransition
        } else {
            Phase::CaptureOnFirstTransition
        };
        config.frequency = SPI_CLOCK;
        let bus = Spi::new(
            p.SPI0, p.PIN_18, p.PIN_19, p.PIN_16, p.DMA_CH0, p.DMA_CH1, Irqs, config,
        );
        let cs = Output::new(p.PIN_17, Level::High);
        let spi = Exclusive::new(bus, cs);

        Self {
            spi,
            irq: Input::new(p.PIN_20, Pull::Up),
            // Pulled to its idle level while the ESC's pin is still an input (before the EEPROM
            // is loaded).
            sync0: Input::new(p.PIN_21, Pull::Down),
            io: DigitalIo::new(
                [
                    // GP25: the Pico's LED.
                    Output::new(p.PIN_25, Level::Low),
                    Output::new(p.PIN_2, Level::Low),
                    Output::new(p.PIN_3, Level::Low),
                    Output::new(p.PIN_4, Level::Low),
                ],
                [
                    Input::new(p.PIN_6, Pull::Down),
                    Input::new(p.PIN_7, Pull::Down),
                    Input::new(p.PIN_8, Pull::Down),
                    Input::new(p.PIN_9, Pull::Down),
                ],
                // All inputs active high.
                0,
            ),
            leds: Leds {
                run: Output::new(p.PIN_14, Level::Low),
                err: Output::new(p.PIN_15, Level::Low),
            },
        }
    }
}
