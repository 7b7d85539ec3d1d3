//! The SPI port a driver talks through: one chip-select cycle of a few parts, each clocked out
//! in place or written.
//!
//! The drivers need two kinds of transfer only (the Beckhoff ESC's address phase and read data
//! in place, a write's data; the LAN9252's instruction and DWORDs), so a [`Port`] offers just
//! those. [`Exclusive`] runs them on an `embedded-hal-async` [`SpiBus`] with the chip's
//! chip-select pin: the firmware carries the HAL's in-place transfer and write and nothing else.
//! Any `embedded-hal-async` [`SpiDevice`] is a [`Port`] as well (a bus shared with other chips,
//! the test suites' SPI models): it costs a firmware that does not use it nothing.
//! `embedded-hal-bus`'s `ExclusiveDevice` over the same bus brings the HAL's read and
//! transfer along, which the driver never asks for (docs/performance.md, "Issue #20: the SPI
//! port").

use embedded_hal::digital::OutputPin;
use embedded_hal_async::spi::{Operation, SpiBus, SpiDevice};

/// One part of a chip-select cycle.
#[derive(Debug)]
pub enum Part<'a> {
    /// Clocked out, then overwritten with what came in meanwhile ([`SpiBus::transfer_in_place`]).
    Exchange(&'a mut [u8]),
    /// Clocked out; what comes in meanwhile is dropped ([`SpiBus::write`]).
    Write(&'a [u8]),
}

/// Where an SPI driver's chip select cycles go.
#[allow(async_fn_in_trait)]
pub trait Port {
    /// A bus or chip-select error.
    type Error: core::fmt::Debug;

    /// One chip-select cycle: chip select asserted, the parts clocked in order without a gap
    /// the chip notices, chip select released (after an error too).
    async fn transaction<const N: usize>(
        &mut self,
        parts: [Part<'_>; N],
    ) -> Result<(), Self::Error>;
}

impl<S: SpiDevice> Port for S {
    type Error = S::Error;

    /// One [`SpiDevice::transaction`].
    async fn transaction<const N: usize>(
        &mut self,
        parts: [Part<'_>; N],
    ) -> Result<(), Self::Error> {
        let mut operations = parts.map(|part| match part {
            Part::Exchange(buf) => Operation::TransferInPlace(buf),
            Part::Write(data) => Operation::Write(data),
        });
        SpiDevice::transaction(self, &mut operations).await
    }
}

/// A bus error or a chip-select error of an [`Exclusive`] port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<B, P> {
    /// The SPI bus failed.
    Spi(B),
    /// The chip-select pin failed (never, for the pins of the embassy HALs).
    ChipSelect(P),
}

/// An SPI bus that serves one chip, with the chip's chip-select pin (active low).
#[derive(Debug)]
pub struct Exclusive<B, P> {
    bus: B,
    cs: P,
}

impl<B, P> Exclusive<B, P> {
    /// The port of the chip on `bus` selected by `cs`, which must be high (deasserted) already:
    /// an embassy `Output` created at `Level::High`.
    pub const fn new(bus: B, cs: P) -> Self {
        Self { bus, cs }
    }
}

impl<B: SpiBus, P: OutputPin> Port for Exclusive<B, P> {
    type Error = Error<B::Error, P::Error>;

    /// Chip select low, each part by [`SpiBus::transfer_in_place`] or [`SpiBus::write`] until
    /// one fails, [`SpiBus::flush`], chip select high; the first error.
    #[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
    fn transaction<const N: usize>(
        &mut self,
        mut parts: [Part<'_>; N],
    ) -> impl Future<Output = Result<(), Self::Error>> {
        // An `async` block, not an `async fn`: the arguments are its captures, not kept a
        // second time beside the locals (4 bytes less in each runner's PDI access future,
        // docs/size-history.md, session 13).
        async move {
            self.cs.set_low().map_err(Error::ChipSelect)?;
            let mut result = Ok(());
            for part in parts.iter_mut() {
                result = match part {
                    Part::Exchange(buf) => self.bus.transfer_in_place(buf).await,
                    Part::Write(data) => self.bus.write(data).await,
                };
                if result.is_err() {
                    break;
                }
            }
            let flushed = self.bus.flush().await;
            let released = self.cs.set_high();
            result.and(flushed).map_err(Error::Spi)?;
            released.map_err(Error::ChipSelect)
        }
    }
}
