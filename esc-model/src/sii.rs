//! The SII EEPROM and its interface registers 0x0500..0x050F (ETG.1000.4 Tables 47–51; ESC
//! datasheet section II, "SII EEPROM"): the MainDevice (or the PDI, when it owns the EEPROM)
//! writes a command into the control/status register, the ESC executes it at once (the busy bit
//! never shows) and reports errors in the same register.
//!
//! Control/status 0x0502: bit 0 write enable, bit 6 "reads 8 bytes" (set: this ESC reads 8
//! bytes like the ET1100), bits 8..10 command (1 read, 2 write, 4 reload), bit 11 checksum error
//! in the configuration area, bit 12 device information error (no EEPROM loaded), bit 13 command
//! error, bit 14 write enable error, bit 15 busy. Address 0x0504 (u32 word address), data
//! 0x0508 (8 bytes read, 2 bytes written).

use alloc::vec::Vec;

use ecat_core::chip::crc8;
use ecat_core::register;

use super::Esc;
use super::access::Side;

/// 0x0502 bit 0: write enable (only for the write command it comes with).
const WRITE_ENABLE: u16 = 1 << 0;
/// 0x0502 bit 6: a read delivers 8 bytes.
const READ_8_BYTES: u16 = 1 << 6;
/// 0x0502 bits 8..10: the command.
const COMMAND_MASK: u16 = 0x0700;
const READ: u16 = 0x0100;
const WRITE: u16 = 0x0200;
const RELOAD: u16 = 0x0400;
/// 0x0502 bit 11: the configuration area's checksum is wrong.
pub(super) const CHECKSUM_ERROR: u16 = 1 << 11;
/// 0x0502 bit 12: no EEPROM (device information could not be loaded).
pub(super) const DEVICE_INFO_ERROR: u16 = 1 << 12;
/// 0x0502 bit 13: unknown or several commands.
const COMMAND_ERROR: u16 = 1 << 13;
/// 0x0502 bit 14: a write without write enable.
const WRITE_ENABLE_ERROR: u16 = 1 << 14;

/// The emulated EEPROM's size: 16 Kbit, what the generated images declare in word 0x3E.
pub const EEPROM_BYTES: usize = 2048;

/// Word 7 of the configuration area holds the CRC of words 0..6 in its low byte.
const CONFIG_BYTES: usize = 14;

impl Esc {
    /// Puts `image` (SII words, little-endian) into the EEPROM and loads the configuration area
    /// as an ESC does at power-on ([`Esc::reload_eeprom`]).
    pub fn load_eeprom(&mut self, image: Vec<u8>) {
        self.eeprom = image;
        self.reload_eeprom();
    }

    /// The EEPROM contents.
    pub fn eeprom(&self) -> &[u8] {
        &self.eeprom
    }

    /// Reloads the configuration area (ESC datasheet section II, "EEPROM configuration area"):
    /// with a correct checksum, word 0 goes to 0x0140/0x0141 (PDI control, ESC configuration),
    /// word 1 to 0x0150/0x0151 (PDI configuration, SYNC/LATCH configuration), word 2 to
    /// 0x0982 (SYNC pulse length), word 3 to 0x0152 (extended PDI configuration) and word 4 to
    /// 0x0012 (configured station alias); with a wrong one the registers keep their values and
    /// 0x0502 bit 11 is set. The reload leaves 0x0502 with no command and only its own error
    /// bits.
    pub fn reload_eeprom(&mut self) {
        let mut status = 0;
        match self.eeprom.get(..CONFIG_BYTES + 2) {
            None => status |= DEVICE_INFO_ERROR,
            Some(config) if crc8(&config[..CONFIG_BYTES]) != config[CONFIG_BYTES] => {
                status |= CHECKSUM_ERROR;
            }
            Some(config) => {
                let word = |n: usize| [config[2 * n], config[2 * n + 1]];
                for (n, register) in [
                    (0, register::PDI_CONTROL),
                    (1, register::PDI_CONFIGURATION),
                    (2, register::DC_SYNC_PULSE_LENGTH),
                    (3, register::EXTENDED_PDI_CONFIGURATION),
                    (4, register::STATION_ALIAS),
                ] {
                    self.memory.write(usize::from(register), &word(n));
                }
            }
        }
        self.set_sii_status(status | READ_8_BYTES);
    }

    /// The port that owns the EEPROM (0x0500 bit 0: 0 = EtherCAT, 1 = PDI): only it writes
    /// 0x0502..0x050F.
    pub(super) fn sii_owner(&self) -> Side {
        if self.memory.byte(usize::from(register::SII_INTERFACE)) & 1 != 0 {
            Side::Pdi
        } else {
            Side::Ecat
        }
    }

    /// After a write by `side` to the SII interface: executes the command it wrote into
    /// 0x0502, if `side` owns the EEPROM (the other port's writes there are ignored).
    pub(super) fn sii_written(&mut self, side: Side, range: core::ops::Range<usize>) {
        let control = usize::from(register::SII_CONTROL);
        if range.end <= control || range.start >= control + 2 {
            return;
        }
        if side != self.sii_owner() {
            return;
        }
        let written = self.sii_status();
        let kept = self.previous_sii_status & (CHECKSUM_ERROR | DEVICE_INFO_ERROR);
        let errors = match written & COMMAND_MASK {
            0 => 0,
            READ => self.sii_read(),
            WRITE if written & WRITE_ENABLE == 0 => WRITE_ENABLE_ERROR,
            WRITE => self.sii_write(),
            RELOAD => {
                self.reload_eeprom();
                return;
            }
            _ => COMMAND_ERROR,
        };
        self.set_sii_status(kept | errors | READ_8_BYTES);
    }

    /// Read: 8 bytes from the word address into 0x0508; beyond the image an erased EEPROM
    /// reads 0xFF.
    fn sii_read(&mut self) -> u16 {
        let word = self.sii_address();
        let mut data = [0xFF; 8];
        for (i, byte) in data.iter_mut().enumerate() {
            let at = word.saturating_mul(2).saturating_add(i);
            *byte = self.eeprom.get(at).copied().unwrap_or(0xFF);
        }
        self.memory.write(usize::from(register::SII_DATA), &data);
        0
    }

    /// Write: the 2 bytes of 0x0508 to the word address; the image grows (erased) to reach it.
    /// An address beyond the EEPROM ([`EEPROM_BYTES`]) is a command error.
    fn sii_write(&mut self) -> u16 {
        let at = self.sii_address().saturating_mul(2);
        if at.saturating_add(2) > EEPROM_BYTES {
            return COMMAND_ERROR;
        }
        let mut data = [0; 2];
        self.memory.read(usize::from(register::SII_DATA), &mut data);
        if self.eeprom.len() < at + 2 {
            self.eeprom.resize(at + 2, 0xFF);
        }
        if let Some(word) = self.eeprom.get_mut(at..at + 2) {
            word.copy_from_slice(&data);
        }
        0
    }

    fn sii_address(&self) -> usize {
        let address = self.memory.u32_le(usize::from(register::SII_ADDRESS));
        usize::try_from(address).unwrap_or(usize::MAX)
    }

    fn sii_status(&self) -> u16 {
        let at = usize::from(register::SII_CONTROL);
        u16::from_le_bytes([self.memory.byte(at), self.memory.byte(at + 1)])
    }

    fn set_sii_status(&mut self, status: u16) {
        self.memory
            .write(usize::from(register::SII_CONTROL), &status.to_le_bytes());
        self.previous_sii_status = status;
    }
}
