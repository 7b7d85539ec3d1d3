//! The ESC on the SPI bus, chosen by feature: its PDI driver, its start-up and what it has
//! (SyncManagers, process RAM), for every firmware of this board.

use ecat_core::DeviceConfig;

#[cfg(all(feature = "ax58100", feature = "lan9252"))]
compile_error!("choose one ESC: feature `ax58100` or `lan9252`");

#[cfg(not(feature = "lan9252"))]
mod chip {
    //! AX58100 (or ET1100/ET1200): the Beckhoff SPI protocol, whole regions per transaction.
    use ecat_core::chip::Chip;
    pub use ecat_embassy::spi::beckhoff::SPI_MODE;
    use ecat_embassy::spi::beckhoff::{BeckhoffSpi, Config};

    use crate::board::EscSpi;

    pub type Pdi = BeckhoffSpi<EscSpi>;
    /// The chip: its SII image is `ecat-esi --chip ax58100`.
    pub const CHIP: Chip = Chip::AX58100;
    /// The AX58100's ESC: 8 SyncManagers, process RAM up to 0x3000 (the ET1100's 8 KiB).
    pub const SYNC_MANAGERS: u8 = CHIP.sync_managers;
    pub const PROCESS_RAM_END: u32 = CHIP.process_ram_end();

    /// The driver on `spi` (the ESC needs no start-up sequence over SPI); never `None`.
    pub async fn start_logged(spi: EscSpi) -> Option<Pdi> {
        Some(BeckhoffSpi::new(spi, Config::default()))
    }
}

#[cfg(feature = "lan9252")]
mod chip {
    //! LAN9252: reset, byte-order test, ready check, IRQ output enabled.
    use ecat_core::chip::Chip;
    pub use ecat_embassy::spi::lan9252::SPI_MODE;
    use ecat_embassy::spi::lan9252::{Config, Lan9252};

    use crate::board::EscSpi;

    pub type Pdi = Lan9252<EscSpi>;
    /// The chip: its SII image is `ecat-esi --chip lan9252`.
    pub const CHIP: Chip = Chip::LAN9252;
    /// The LAN9252's ESC: 4 SyncManagers, 4 KiB of process RAM.
    pub const SYNC_MANAGERS: u8 = CHIP.sync_managers;
    pub const PROCESS_RAM_END: u32 = CHIP.process_ram_end();

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

pub use chip::{CHIP, PROCESS_RAM_END, Pdi, SPI_MODE, SYNC_MANAGERS, start_logged};

/// `config` adjusted to this ESC's SyncManagers and process RAM.
pub const fn fit(mut config: DeviceConfig) -> DeviceConfig {
    config.sync_manager_count = SYNC_MANAGERS;
    config.process_ram_end = PROCESS_RAM_END;
    config
}
