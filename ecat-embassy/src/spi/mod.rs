//! PDI drivers over `embedded-hal-async` SPI, through a [`port::Port`]: an `SpiBus` with the
//! chip's chip-select pin ([`port::Exclusive`]) or any `SpiDevice`, one transaction per
//! chip-select cycle.
//!
//! | module | chips | how the registers and the process RAM are reached |
//! |---|---|---|
//! | [`beckhoff`] | ET1100, ET1200, AX58100 and other ESCs with the Beckhoff SPI slave interface | directly: every access is one transaction, and the address phase carries the AL event register |
//! | [`lan9252`] | Microchip LAN9252/LAN9253 in SPI mode | ESC registers through the indirect CSR command/data registers, process RAM through the PRAM FIFOs; the AL event register is read only for reads the IRQ line prompted |
//!
//! Both implement [`Pdi`](crate::Pdi), so the runners neither know nor care which chip is fitted.

pub mod beckhoff;
pub mod lan9252;
pub mod port;
