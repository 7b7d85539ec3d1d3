//! The ESC, chosen by feature: its PDI driver (which knows the chip's SyncManagers and process
//! RAM, `ecat_embassy::Pdi::CHIP`) and its start-up, for every firmware of this board.

#[cfg(any(
    all(feature = "ax58100", feature = "lan9252"),
    all(feature = "ax58100", feature = "fmc"),
    all(feature = "lan9252", feature = "fmc"),
    not(any(feature = "ax58100", feature = "lan9252", feature = "fmc")),
))]
compile_error!("choose one ESC: feature `ax58100`, `lan9252` or `fmc` (`--no-default-features`)");

#[cfg(feature = "ax58100")]
mod chip {
    //! AX58100 (or ET1100/ET1200): the Beckhoff SPI protocol, whole regions per transaction.
    pub use ecat_embassy::spi::beckhoff::SPI_MODE;
    use ecat_embassy::spi::beckhoff::{BeckhoffSpi, Config};

    use crate::board::EscBus;

    pub type Pdi = BeckhoffSpi<EscBus>;

    /// The driver on `spi` (the ESC needs no start-up sequence over SPI); never `None`.
    pub async fn start_logged(spi: EscBus) -> Option<Pdi> {
        Some(BeckhoffSpi::new(spi, Config::default()))
    }
}

#[cfg(feature = "lan9252")]
mod chip {
    //! LAN9252: reset, byte-order test, ready check, IRQ output enabled.
    pub use ecat_embassy::spi::lan9252::SPI_MODE;
    use ecat_embassy::spi::lan9252::{Config, Lan9252};

    use crate::board::EscBus;

    pub type Pdi = Lan9252<EscBus>;

    /// Resets the chip and waits until it is ready; logs why and returns `None` when it does not
    /// come up.
    pub async fn start_logged(spi: EscBus) -> Option<Pdi> {
        match Lan9252::start(spi, Config::default()).await {
            Ok(pdi) => Some(pdi),
            Err(e) => {
                defmt::error!("ESC start-up failed: {}", e);
                None
            }
        }
    }
}

#[cfg(feature = "fmc")]
mod chip {
    //! AX58100 (or ET1100) on the FMC: the 16-bit asynchronous microcontroller interface.
    use ecat_embassy::mcu::Mcu16;

    use crate::board::EscBus;

    pub type Pdi = Mcu16<EscBus>;

    /// The driver on the FMC bank (the ESC needs no start-up sequence); never `None`.
    pub async fn start_logged(bus: EscBus) -> Option<Pdi> {
        Some(Mcu16::new(bus))
    }
}

#[cfg(not(feature = "fmc"))]
pub use chip::SPI_MODE;
pub use chip::{Pdi, start_logged};
