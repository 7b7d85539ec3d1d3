//! The ESC on the SPI bus, chosen by feature: its PDI driver (which knows the chip's
//! SyncManagers and process RAM, `ecat_embassy::Pdi::CHIP`) and its start-up, for every
//! firmware of this board.

#[cfg(all(feature = "ax58100", feature = "lan9252"))]
compile_error!("choose one ESC: feature `ax58100` or `lan9252`");

#[cfg(not(feature = "lan9252"))]
mod chip {
    //! AX58100 (or ET1100/ET1200): the Beckhoff SPI protocol, whole regions per transaction.
    pub use ecat_embassy::spi::beckhoff::SPI_MODE;
    use ecat_embassy::spi::beckhoff::{BeckhoffSpi, Config};

    use crate::board::EscSpi;

    pub type Pdi = BeckhoffSpi<EscSpi>;

    /// The driver on `spi` (the ESC needs no start-up sequence over SPI); never `None`.
    pub async fn start_logged(spi: EscSpi) -> Option<Pdi> {
        Some(BeckhoffSpi::new(spi, Config::default()))
    }
}

#[cfg(feature = "lan9252")]
mod chip {
    //! LAN9252: reset, byte-order test, ready check, IRQ output enabled.
    pub use ecat_embassy::spi::lan9252::SPI_MODE;
    use ecat_embassy::spi::lan9252::{Config, Lan9252};

    use crate::board::EscSpi;

    pub type Pdi = Lan9252<EscSpi>;

    /// Resets the chip and waits until it is ready; logs why and returns `None` when it does not
    /// come up.
    pub async fn start_logged(spi: EscSpi) -> Option<Pdi> {
        match Lan9252::start(spi, Config::default()).await {
            Ok(pdi) => Some(pdi),
            Err(e) => {
                defmt::error!("ESC start-up failed: {}", e);
                None
            }
        }
    }
}

pub use chip::{Pdi, SPI_MODE, start_logged};
