//! The ESC on the SPI bus, chosen by feature: its PDI driver, its start-up and what it has
//! (SyncManagers, process RAM), for every firmware of this board.

use ecat_core::DeviceConfig;

#[cfg(all(feature = "ax58100", feature = "lan9252"))]
compile_error!("choose one ESC: feature `ax58100` or `lan9252`");

#[cfg(not(feature = "lan9252"))]
mod chip {
    //! AX58100 (or ET1100/ET1200): the Beckhoff SPI protocol, whole regions per transaction.
    pub use ecat_embassy::spi::beckhoff::SPI_MODE;
    use ecat_embassy::spi::beckhoff::{BeckhoffSpi, Config};

    use crate::board::EscSpi;

    pub type Pdi = BeckhoffSpi<EscSpi>;
    /// The AX58100's ESC: 8 SyncManagers, process RAM up to 0x3000 (the ET1100's 8 KiB).
    pub const SYNC_MANAGERS: u8 = 8;
    pub const PROCESS_RAM_END: u32 = 0x3000;

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
    /// The LAN9252's ESC: 4 SyncManagers, 4 KiB of process RAM.
    pub const SYNC_MANAGERS: u8 = 4;
    pub const PROCESS_RAM_END: u32 = 0x2000;

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

pub use chip::{PROCESS_RAM_END, Pdi, SPI_MODE, SYNC_MANAGERS, start_logged};

/// `config` adjusted to this ESC's SyncManagers and process RAM.
pub const fn fit(mut config: DeviceConfig) -> DeviceConfig {
    config.sync_manager_count = SYNC_MANAGERS;
    config.process_ram_end = PROCESS_RAM_END;
    config
}
