//! A fake ET1100/AX58100 16-bit asynchronous microcontroller interface in front of the emulated
//! ESC (ET1100 datasheet section II, "Asynchronous 8/16 bit microcontroller interface"):
//! [`FakeBus16`] implements `ecat_embassy::mcu::Bus16`, performs each bus cycle as the chip does
//! and records it ([`Cycle`]), and counts cycles through a [`Probe`] as a logic analyser on the
//! bus would (a transaction per bus cycle, its data bytes).
//!
//! The chip as modelled:
//! - it answers only when its EEPROM selected the 16-bit asynchronous microcontroller interface
//!   (PDI control 0x0140 = 0x08); otherwise it drives nothing (reads 0xFFFF) and writes reach
//!   nothing;
//! - a word cycle (ADR\[0\] = 0, BHE low) is one PDI access of the two bytes at an even address,
//!   little-endian (the even byte on D\[7:0\]); a word cycle at an odd address is a violation;
//! - a byte write writes its lane alone (one PDI access of one byte);
//! - it does not shift out the AL event: a driver reads 0x0220.

use core::cell::RefCell;
use std::rc::Rc;

use ecat_core::chip::{Chip, ConfigArea};
use ecat_embassy::mcu::Bus16;

use crate::emulator::Emulator;
use crate::esc::EscConfig;
use crate::spi::Probe;

/// PDI control (0x0140) value of the 16-bit asynchronous microcontroller interface (ET1100
/// datasheet section II, register 0x0140).
pub const PDI_MCU16_ASYNC: u8 = 0x08;
/// PDI control register.
const PDI_CONTROL: u16 = 0x0140;
/// What the data lines read when the chip does not drive them (pulled up).
pub const NOT_DRIVEN: u16 = 0xFFFF;

/// An ET1100 as [`EscConfig::of`] makes it, its EEPROM selecting the 16-bit asynchronous
/// microcontroller interface instead of SPI.
pub fn et1100() -> EscConfig {
    let chip = Chip::ET1100;
    EscConfig {
        eeprom: Some(ConfigArea {
            pdi_control: PDI_MCU16_ASYNC,
            ..ConfigArea::new(&chip, chip.has_dc())
        }),
        ..EscConfig::of(chip)
    }
}

/// One bus cycle as the chip saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cycle {
    /// A word read at the address: the value on D\[15:0\].
    Read(u16, u16),
    /// A word write at the address.
    Write(u16, u16),
    /// A byte write at the address, its lane alone.
    WriteByte(u16, u8),
}

/// The test's view of the cycles a [`FakeBus16`] ran; cloning gives another view of the same bus.
#[derive(Clone, Default)]
pub struct Cycles(Rc<RefCell<Vec<Cycle>>>);

impl Cycles {
    /// The cycles since the last call.
    pub fn take(&self) -> Vec<Cycle> {
        core::mem::take(&mut self.0.borrow_mut())
    }
}

/// The bus with the chip at its far end.
pub struct FakeBus16 {
    emu: Emulator,
    probe: Probe,
    cycles: Cycles,
}

impl FakeBus16 {
    /// The microcontroller interface of `emu`'s ESC, watched by `probe` and `cycles`.
    pub fn new(emu: Emulator, probe: Probe, cycles: Cycles) -> Self {
        Self { emu, probe, cycles }
    }

    /// One cycle: `access` performs it on the ESC when the chip answers and returns the data
    /// lines' bytes; a refusal or a misaligned word is recorded as a violation.
    fn cycle(
        &mut self,
        address: u16,
        word: bool,
        access: impl FnOnce(&Emulator) -> Vec<u8>,
    ) -> Vec<u8> {
        let emu = &self.emu;
        self.probe.cycle(|violations, progress| {
            progress.reach(0);
            let pdi = emu.with(|esc| esc.register(PDI_CONTROL));
            if pdi != PDI_MCU16_ASYNC {
                let why = format!(
                    "PDI control 0x0140 = {pdi:#04x}, not the 16-bit asynchronous µC interface (0x08): the ESC does not answer"
                );
                if violations.last() != Some(&why) {
                    violations.push(why);
                }
                return NOT_DRIVEN.to_le_bytes()[..if word { 2 } else { 1 }].to_vec();
            }
            if word && address % 2 == 1 {
                violations.push(format!(
                    "word cycle at odd address {address:#06x}: ADR[0] = 1 with BHE low is no word access"
                ));
            }
            access(emu)
        })
    }
}

impl Bus16 for FakeBus16 {
    fn read(&mut self, address: u16) -> u16 {
        let data = self.cycle(address, true, |emu| {
            let mut word = [0; 2];
            emu.with(|esc| esc.pdi_read(address, &mut word));
            word.to_vec()
        });
        let value = u16::from_le_bytes([data[0], data[1]]);
        self.cycles.0.borrow_mut().push(Cycle::Read(address, value));
        value
    }

    fn write(&mut self, address: u16, value: u16) {
        self.cycle(address, true, |emu| {
            emu.with(|esc| esc.pdi_write(address, &value.to_le_bytes()));
            value.to_le_bytes().to_vec()
        });
        self.cycles
            .0
            .borrow_mut()
            .push(Cycle::Write(address, value));
    }

    fn write_byte(&mut self, address: u16, value: u8) {
        self.cycle(address, false, |emu| {
            emu.with(|esc| esc.pdi_write(address, &[value]));
            vec![value]
        });
        self.cycles
            .0
            .borrow_mut()
            .push(Cycle::WriteByte(address, value));
    }
}
