//! Clocks, pins and interrupts (pin assignment and priorities: README.md).

use embassy_stm32::exti::{self, ExtiInput};
use embassy_stm32::gpio::{Input, Level, Output, Pull, Speed};
use embassy_stm32::mode::Async;
use embassy_stm32::rcc::{Pll, PllMul, PllPreDiv, PllRDiv, PllSource, Sysclk};
use embassy_stm32::{bind_interrupts, interrupt};

/// The ETG.1300 RUN (green) and ERR (red) LEDs: PB10 (D6) and PA9 (D8), lit when high.
pub type Leds = ecat_embassy::indicator::RunErr<Output<'static>, Output<'static>>;

/// The digital I/O application (`ecat_dio`) on this board's pins.
pub type DigitalIo = ecat_dio::DigitalIo<Output<'static>, Input<'static>>;

bind_interrupts!(struct Irqs {
    EXTI9_5 => exti::InterruptHandler<interrupt::typelevel::EXTI9_5>;
    EXTI15_10 => exti::InterruptHandler<interrupt::typelevel::EXTI15_10>;
    #[cfg(any(feature = "bootloader", feature = "storage"))]
    FLASH => embassy_stm32::flash::InterruptHandler;
});

#[cfg(not(feature = "fmc"))]
mod esc_bus {
    //! The ESC on SPI1 with DMA.
    use ecat_core::chip::SpiMode;
    use ecat_embassy::spi::port::Exclusive;
    use embassy_stm32::gpio::{Level, Output, Speed};
    use embassy_stm32::mode::Async;
    use embassy_stm32::spi::{self, Spi};
    use embassy_stm32::time::Hertz;
    use embassy_stm32::{Peri, bind_interrupts, dma, peripherals};

    bind_interrupts!(struct Irqs {
        DMA1_CHANNEL1 => dma::InterruptHandler<peripherals::DMA1_CH1>;
        DMA1_CHANNEL2 => dma::InterruptHandler<peripherals::DMA1_CH2>;
    });

    /// SPI1 with DMA and the ESC's chip select: the bus the PDI driver owns.
    pub type EscBus = Exclusive<Spi<'static, Async, spi::mode::Master>, Output<'static>>;

    /// SPI clock: the AX58100 and the LAN9252 (READ instruction) both take 20 MHz; SPI1's kernel
    /// clock (170 MHz) divided by 16 gives 10.6 MHz, the fastest rate not above it.
    const SPI_CLOCK: Hertz = Hertz(20_000_000);

    /// `mode` as embassy-stm32 spells it.
    const fn spi_mode(mode: SpiMode) -> spi::Mode {
        spi::Mode {
            polarity: if mode.idle_high() {
                spi::Polarity::IdleHigh
            } else {
                spi::Polarity::IdleLow
            },
            phase: if mode.capture_on_second_edge() {
                spi::Phase::CaptureOnSecondTransition
            } else {
                spi::Phase::CaptureOnFirstTransition
            },
        }
    }

    /// SPI1 on PB3/PB5/PB4 with DMA1 channels 1 and 2, chip select on PB6.
    pub fn init(
        spi1: Peri<'static, peripherals::SPI1>,
        sck: Peri<'static, peripherals::PB3>,
        mosi: Peri<'static, peripherals::PB5>,
        miso: Peri<'static, peripherals::PB4>,
        cs: Peri<'static, peripherals::PB6>,
        tx: Peri<'static, peripherals::DMA1_CH1>,
        rx: Peri<'static, peripherals::DMA1_CH2>,
    ) -> EscBus {
        let mut config = spi::Config::default();
        // The mode of the ESC's driver, which the SII image's configuration area sets in the ESC.
        config.mode = spi_mode(crate::esc::SPI_MODE);
        config.frequency = SPI_CLOCK;
        let bus = Spi::new(spi1, sck, mosi, miso, tx, rx, Irqs, config);
        let cs = Output::new(cs, Level::High, Speed::VeryHigh);
        Exclusive::new(bus, cs)
    }
}

#[cfg(feature = "fmc")]
mod esc_bus {
    //! The ESC on the FMC (`crate::fmc`).
    pub type EscBus = crate::fmc::FmcBus;
}

pub use esc_bus::EscBus;

/// An input line from the ESC (IRQ, SYNC0) with its EXTI interrupt.
pub type Pin = ExtiInput<'static, Async>;

/// What the firmware gets from the board.
pub struct Board {
    /// The ESC's bus: SPI1, or the FMC (feature `fmc`).
    pub bus: EscBus,
    /// The ESC's PDI interrupt line (active low).
    pub irq: Pin,
    /// The ESC's SYNC0 output (from the distributed clock): push-pull, active high, as the SII
    /// image's configuration area sets it (0x0151 = 0x06, `ecat_core::chip`); the process-data
    /// runner waits for its rising edges.
    pub sync0: Pin,
    /// The application's pins.
    pub io: DigitalIo,
    /// The RUN and ERR LEDs.
    pub leds: Leds,
    /// The chip's flash, for the firmware update (feature `bootloader`) and the stored
    /// parameters (feature `storage`).
    #[cfg(any(feature = "bootloader", feature = "storage"))]
    pub flash: embassy_stm32::flash::Flash<'static>,
}

impl Board {
    /// Clocks at 170 MHz (HSI16 → PLL), then the peripherals.
    pub fn init() -> Self {
        let mut config = embassy_stm32::Config::default();
        config.rcc.pll = Some(Pll {
            source: PllSource::HSI,
            prediv: PllPreDiv::DIV4,
            mul: PllMul::MUL85,
            divp: None,
            divq: None,
            divr: Some(PllRDiv::DIV2),
        });
        config.rcc.sys = Sysclk::PLL1_R;
        config.rcc.boost = true;
        let p = embassy_stm32::init(config);

        #[cfg(not(feature = "fmc"))]
        let bus = esc_bus::init(p.SPI1, p.PB3, p.PB5, p.PB4, p.PB6, p.DMA1_CH1, p.DMA1_CH2);
        #[cfg(feature = "fmc")]
        let bus = {
            crate::fmc_pins!(p);
            crate::fmc::FmcBus::init()
        };

        Self {
            bus,
            irq: ExtiInput::new(p.PA10, p.EXTI10, Pull::Up, Irqs),
            // Pulled to its idle level while the ESC's pin is still an input (before the EEPROM
            // is loaded).
            sync0: ExtiInput::new(p.PA8, p.EXTI8, Pull::Down, Irqs),
            io: DigitalIo::new(
                [
                    Output::new(p.PA5, Level::Low, Speed::Low),
                    Output::new(p.PA6, Level::Low, Speed::Low),
                    Output::new(p.PA7, Level::Low, Speed::Low),
                    Output::new(p.PC7, Level::Low, Speed::Low),
                ],
                [
                    Input::new(p.PC13, Pull::None),
                    Input::new(p.PA0, Pull::Down),
                    Input::new(p.PA1, Pull::Down),
                    Input::new(p.PA4, Pull::Down),
                ],
                // The user button B1 pulls PC13 low when pressed: input 0 reads 1 then.
                0b0001,
            ),
            leds: Leds {
                run: Output::new(p.PB10, Level::Low, Speed::Low),
                err: Output::new(p.PA9, Level::Low, Speed::Low),
            },
            #[cfg(any(feature = "bootloader", feature = "storage"))]
            flash: embassy_stm32::flash::Flash::new(p.FLASH, Irqs),
        }
    }
}
