//! An ESC with the Beckhoff SPI slave interface (ET1100, ET1200, AX58100), decoding each
//! transaction as ESC datasheet section II, "SPI Slave Interface", describes it.
//!
//! - Address phase: byte 0 = `A[12:5]`, byte 1 = `A[4:0]` and CMD0; CMD0 = 110b (address extension)
//!   adds byte 2 = `A[15:13]`, CMD1 and two reserved bits (00b). Meanwhile the chip shifts out the AL
//!   event register, 0x0220 first, sampled when the transaction starts (before byte 0).
//! - Commands: 000b NOP, 010b read, 011b read with wait state byte, 100b write; 001b, 101b, 111b
//!   and a second address extension are reserved.
//! - Read: the wait state byte must be 0xFF; data bytes are 0x00 except the last, the read
//!   termination 0xFF. A read is one PDI access of all its data bytes, made as soon as the address
//!   phase is complete (before the wait state byte, or before the first data byte without one):
//!   an event that arises during the address phase is not in the AL event shifted out, yet the
//!   read sees its cause (a SyncManager buffer written meanwhile).
//! - Write: all bytes after the address phase are data, written as one PDI access when chip select
//!   rises.
//!
//! What the chip shifts out where the datasheet leaves it undefined (wait state byte, write data
//! phase) is [`UNDEFINED`], so a driver that used it would read nonsense.

use ecat_core::chip::SpiMode;

use crate::emulator::Emulator;
use crate::spi::{Chip, Progress};

/// MISO where the datasheet does not define it.
pub const UNDEFINED: u8 = 0xA5;

/// PDI control (0x0140) value of the SPI slave (ESC datasheet section II, 0x0140).
const PDI_SPI_SLAVE: u8 = 0x05;
/// PDI control register.
const PDI_CONTROL: u16 = 0x0140;
/// PDI configuration register: bits 1:0 the SPI mode (ESC datasheet section II, 0x0150).
const PDI_CONFIGURATION: u16 = 0x0150;

const NOP: u8 = 0b000;
const READ: u8 = 0b010;
const READ_WAIT_STATE: u8 = 0b011;
const WRITE: u8 = 0b100;
const ADDRESS_EXTENSION: u8 = 0b110;

/// The chip; put it behind a [`FakeSpi`](crate::spi::FakeSpi).
pub struct BeckhoffEsc {
    emu: Emulator,
}

impl BeckhoffEsc {
    /// The SPI slave interface of `emu`'s ESC.
    pub fn new(emu: Emulator) -> Self {
        Self { emu }
    }
}

/// A decoded address phase.
struct Header {
    address: u16,
    command: u8,
    /// Address/command bytes: 2 or 3.
    len: usize,
}

impl Header {
    /// Decodes the address phase at the start of `mosi`.
    fn decode(mosi: &[u8], violations: &mut Vec<String>) -> Option<Header> {
        let (&b0, &b1) = (mosi.first()?, mosi.get(1)?);
        let low = u16::from(b0) << 5 | u16::from(b1 >> 3);
        if b1 & 0b111 != ADDRESS_EXTENSION {
            return Some(Header {
                address: low,
                command: b1 & 0b111,
                len: 2,
            });
        }
        let &b2 = mosi.get(2)?;
        if b2 & 0b11 != 0 {
            violations.push(format!("reserved bits of address byte 2 set: {b2:#04x}"));
        }
        Some(Header {
            address: u16::from(b2 >> 5) << 13 | low,
            command: (b2 >> 2) & 0b111,
            len: 3,
        })
    }
}

impl Chip for BeckhoffEsc {
    fn transaction(
        &mut self,
        mosi: &[u8],
        miso: &mut [u8],
        violations: &mut Vec<String>,
        progress: &mut Progress,
    ) {
        miso.fill(UNDEFINED);
        progress.reach(0);
        let event = self.emu.with(|esc| esc.al_event()).bits().to_le_bytes();
        for (out, byte) in miso.iter_mut().zip(event.iter().take(3)) {
            *out = *byte;
        }
        let Some(header) = Header::decode(mosi, violations) else {
            violations.push(format!(
                "transaction ends in the address phase: {mosi:02x?}"
            ));
            return;
        };
        let rest = mosi.get(header.len..).unwrap_or_default();
        // The address phase is complete: a read starts here, a write waits for chip select.
        progress.reach(if header.command == WRITE {
            mosi.len()
        } else {
            header.len
        });
        match header.command {
            NOP => {}
            READ => self.read(header.address, rest, miso.get_mut(header.len..), violations),
            READ_WAIT_STATE => {
                let wait = header.len + 1;
                match rest.first() {
                    Some(&0xFF) => {}
                    other => violations.push(format!("wait state byte {other:02x?}, not 0xFF")),
                }
                let data = mosi.get(wait..).unwrap_or_default();
                self.read(header.address, data, miso.get_mut(wait..), violations);
            }
            WRITE if rest.is_empty() => {}
            WRITE => {
                self.emu.with(|esc| esc.pdi_write(header.address, rest));
            }
            reserved => violations.push(format!("reserved command {reserved:03b}")),
        }
    }

    /// The SPI slave talks only when the EEPROM selected it (0x0140 = 0x05) and in the mode
    /// its PDI configuration (0x0150 bits 1:0) sets: in another mode it samples MOSI and shifts
    /// MISO on the wrong clock edges.
    fn refusal(&self, mode: SpiMode) -> Option<String> {
        let (pdi, configuration) = self
            .emu
            .with(|esc| (esc.register(PDI_CONTROL), esc.register(PDI_CONFIGURATION)));
        if pdi != PDI_SPI_SLAVE {
            return Some(format!(
                "PDI control 0x0140 = {pdi:#04x}, not the SPI slave (0x05): the ESC does not answer"
            ));
        }
        let configured = configuration & 0b11;
        (configured != mode as u8).then(|| {
            format!(
                "bus in SPI mode {}, PDI configuration 0x0150 sets mode {configured}: the ESC does not understand the bus",
                mode as u8
            )
        })
    }
}

impl BeckhoffEsc {
    /// The data phase of a read: `mosi` as sent, `miso` to fill.
    fn read(
        &mut self,
        address: u16,
        mosi: &[u8],
        miso: Option<&mut [u8]>,
        violations: &mut Vec<String>,
    ) {
        let Some((&last, before)) = mosi.split_last() else {
            violations.push("read without data bytes".to_string());
            return;
        };
        if let Some((i, byte)) = before.iter().enumerate().find(|(_, b)| **b != 0x00) {
            violations.push(format!(
                "read data byte {i} sent as {byte:#04x}: only the last byte may be non-zero (0xFF ends the read)"
            ));
        }
        if last != 0xFF {
            violations.push(format!(
                "read not terminated: last byte sent as {last:#04x}, not 0xFF"
            ));
        }
        let mut data = vec![0; mosi.len()];
        self.emu.with(|esc| esc.pdi_read(address, &mut data));
        if let Some(miso) = miso {
            miso.copy_from_slice(&data);
        }
    }
}
