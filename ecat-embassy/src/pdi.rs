//! The Process Data Interface (PDI): how the microcontroller reaches the ESC's registers and
//! process RAM.

use ecat_core::AlEvent;

/// Register and RAM access to the ESC over its PDI (SPI, parallel bus, or an emulator).
///
/// Each access returns the AL event register (0x0220) value: SPI ESCs shift it out during the
/// address phase of every transaction, so the runners learn about events without spending a
/// transaction on it. A driver whose bus does not deliver it reads 0x0220 itself after the access.
/// The value may be sampled before the access: callers discount the bits the access itself clears.
#[allow(async_fn_in_trait)]
pub trait Pdi {
    /// A bus error; the runners stop and hand it to the firmware.
    type Error: core::fmt::Debug;

    /// Reads `buf.len()` bytes starting at `address` in one transaction.
    async fn read(&mut self, address: u16, buf: &mut [u8]) -> Result<AlEvent, Self::Error>;

    /// Writes `data` starting at `address` in one transaction.
    async fn write(&mut self, address: u16, data: &[u8]) -> Result<AlEvent, Self::Error>;
}
