//! The register file 0x0000..0x0FFF (ESC datasheet section II; ETG.1000.4 §6): reset values,
//! which port may write which byte, and the side effects of register accesses on the AL event
//! request register and the LED outputs ([`super::leds`]).

use ecat_core::AlState;
use ecat_core::chip::{FEATURE_DC, FEATURE_DC_64, FEATURE_DC_SYNC_ACTIVATION};
use ecat_core::register::{self, DlStatus, Watchdog};
use ecat_core::sync_manager::Channel;

use super::access::Side;
use super::dc::{SYSTEM_TIME_DELAY, SYSTEM_TIME_OFFSET};
use super::memory::Memory;
use super::sync_manager::{
    ACTIVATE_OFFSET, CONFIGURATION_OFFSETS, ChannelState, PDI_CONTROL_OFFSET, STATUS_OFFSET,
};
use super::{Esc, EscConfig};

/// Offset of the FMMU count in the DL information (ETG.1000.4 Table 31); the SM count and the
/// RAM size follow it.
const FMMU_COUNT_OFFSET: u16 = 4;
/// The features bits of the DC unit: bit 2 distributed clocks, bit 3 64-bit system time, bit 8
/// enhanced DC SYNC activation (ETG.1000.4 Table 31); an ESC without DC reports none of them.
const FEATURES_OF_DC: u16 = FEATURE_DC | FEATURE_DC_64 | FEATURE_DC_SYNC_ACTIVATION;
/// 0x0141 bit 0, device emulation: the ESC copies AL control into AL status itself (ESC
/// datasheet section II, 0x0141).
pub(super) const DEVICE_EMULATION: u8 = 1 << 0;
/// DL status: PDI operational, link on port 0, port 0 communication established.
const DL_STATUS_PORT0_UP: u16 =
    DlStatus::PDI_OPERATIONAL | DlStatus::link(0) | DlStatus::communication(0);
/// AL event mask after reset (ESC datasheet section II, 0x0204).
const AL_EVENT_MASK_RESET: u32 = 0x00FF_FF0F;
/// Bytes of the SII EEPROM configuration and access state (ETG.1000.4 Table 48): the
/// MainDevice assigns the EEPROM.
const SII_ASSIGNMENT_SIZE: u16 = 2;
/// Bytes of the SII control/status, address and data registers 0x0502..0x050F (ETG.1000.4
/// Tables 49–51): written by the port that owns the EEPROM.
const SII_COMMAND_SIZE: u16 = 14;

/// The port that may write a register byte (the other port only reads it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Writer {
    /// Read-only for both ports.
    Nobody,
    /// Written by one port.
    Only(Side),
    /// Written by both ports (the LED override registers 0x0138/0x0139).
    Both,
    /// Written by the MainDevice only while SyncManager `n` is disabled (start, length, control).
    EcatWhileDisabled(u8),
    /// Written by the port that owns the SII EEPROM (0x0500 bit 0).
    SiiOwner,
}

/// The registers a single port writes (excluding FMMUs and SyncManagers): first address,
/// length, writer.
const WRITABLE: [(u16, u16, Side); 18] = [
    (register::STATION_ADDRESS, 2, Side::Ecat),
    (register::STATION_ALIAS, 2, Side::Pdi),
    (register::DL_CONTROL, 4, Side::Ecat),
    (register::AL_CONTROL, 2, Side::Ecat),
    (register::AL_STATUS, 2, Side::Pdi),
    (register::AL_STATUS_CODE, 2, Side::Pdi),
    (register::ECAT_EVENT_MASK, 2, Side::Ecat),
    (register::AL_EVENT_MASK, 4, Side::Pdi),
    (register::WATCHDOG_DIVIDER, 2, Side::Ecat),
    (register::WATCHDOG_TIME_PDI, 2, Side::Ecat),
    (register::WATCHDOG_TIME_PROCESS_DATA, 2, Side::Ecat),
    (register::SII_INTERFACE, SII_ASSIGNMENT_SIZE, Side::Ecat),
    (SYSTEM_TIME_OFFSET, 8, Side::Ecat),
    (SYSTEM_TIME_DELAY, 4, Side::Ecat),
    (register::DC_CYCLIC_UNIT_CONTROL, 1, Side::Ecat),
    (register::DC_ACTIVATION, 1, Side::Ecat),
    (register::DC_START_TIME, 8, Side::Ecat),
    (register::DC_SYNC0_CYCLE_TIME, 8, Side::Ecat),
];

/// The offset of `address` in the register `[start, start + len)`, if it falls into it.
fn offset_in(address: usize, start: u16, len: u16) -> Option<usize> {
    address
        .checked_sub(usize::from(start))
        .filter(|&offset| offset < usize::from(len))
}

/// The block of `count` entities of `size` bytes from `base` that `address` falls into, and the
/// offset in it.
fn entity(address: usize, base: u16, size: u16, count: u8) -> Option<(u8, usize)> {
    let relative = address.checked_sub(usize::from(base))?;
    let size = usize::from(size);
    let n = u8::try_from(relative / size).ok().filter(|&n| n < count)?;
    Some((n, relative % size))
}

/// The SyncManager channel whose registers hold `address`, and the offset in its block.
fn sync_manager_register(address: usize, config: &EscConfig) -> Option<(u8, usize)> {
    entity(
        address,
        register::SM_BASE,
        register::SM_SIZE,
        config.sync_managers,
    )
}

/// Who may write the register byte at `address`.
fn writer(address: usize, config: &EscConfig) -> Writer {
    if let Some((n, offset)) = sync_manager_register(address, config) {
        return match offset {
            offset if CONFIGURATION_OFFSETS.contains(&offset) => Writer::EcatWhileDisabled(n),
            ACTIVATE_OFFSET => Writer::Only(Side::Ecat),
            PDI_CONTROL_OFFSET => Writer::Only(Side::Pdi),
            _ => Writer::Nobody,
        };
    }
    if entity(
        address,
        register::FMMU_BASE,
        register::FMMU_SIZE,
        config.fmmus,
    )
    .is_some()
    {
        return Writer::Only(Side::Ecat);
    }
    if offset_in(address, register::SII_CONTROL, SII_COMMAND_SIZE).is_some() {
        return Writer::SiiOwner;
    }
    if offset_in(address, register::RUN_LED_OVERRIDE, 2).is_some() {
        return Writer::Both;
    }
    WRITABLE
        .iter()
        .find(|&&(start, len, _)| offset_in(address, start, len).is_some())
        .map_or(Writer::Nobody, |&(_, _, side)| Writer::Only(side))
}

/// The memory image after power-on, before the EEPROM is loaded: DL information from the
/// configuration (type, revision, FMMUs, SyncManagers, RAM size, port descriptor, features), the
/// fixed status registers, AL status INIT and the reset values of the masks and watchdogs (ESC
/// datasheet section II). PDI control (0x0140) is 0, no PDI, until the EEPROM's configuration area sets it.
pub(super) fn reset_image(config: &EscConfig) -> Memory {
    let mut memory = Memory::new(config.ram_end());
    let at = usize::from;
    let ram_kib = (config.ram_end() - at(register::PROCESS_RAM)) / 1024;
    memory.write(
        at(register::DL_INFORMATION),
        &[config.esc_type, config.chip.revision],
    );
    memory.write(
        at(register::DL_INFORMATION + FMMU_COUNT_OFFSET),
        &[
            config.fmmus,
            config.sync_managers,
            u8::try_from(ram_kib).unwrap_or(u8::MAX),
            config.chip.port_descriptor,
        ],
    );
    let features = if config.dc_supported {
        config.chip.features | FEATURE_DC | FEATURE_DC_64 | FEATURE_DC_SYNC_ACTIVATION
    } else {
        config.chip.features & !FEATURES_OF_DC
    };
    memory.write(at(register::FEATURES), &features.to_le_bytes());
    memory.write(at(register::DL_STATUS), &DL_STATUS_PORT0_UP.to_le_bytes());
    // INIT (section II, 0x0130 reset value): the RUN LED output is dark from power-on.
    memory.write(at(register::AL_STATUS), &[AlState::Init as u8, 0]);
    memory.write(
        at(register::AL_EVENT_MASK),
        &AL_EVENT_MASK_RESET.to_le_bytes(),
    );
    memory.write(
        at(register::WATCHDOG_DIVIDER),
        &Watchdog::RESET.divider.to_le_bytes(),
    );
    for watchdog in [
        register::WATCHDOG_TIME_PDI,
        register::WATCHDOG_TIME_PROCESS_DATA,
    ] {
        memory.write(at(watchdog), &Watchdog::RESET.time.to_le_bytes());
    }
    memory
}

impl Esc {
    /// Reads the register byte at `address` through `side`. The AL event request and the
    /// SyncManager status bytes are live values; a PDI read of AL control (0x0120) or of a
    /// channel's activate byte acknowledges its AL event (ESC datasheet section II, 0x0220).
    pub(super) fn read_register(&mut self, side: Side, address: usize) -> u8 {
        let value = self.register_value(address);
        if side == Side::Pdi {
            self.acknowledge(address);
        }
        value
    }

    /// Writes the register byte at `address` through `side`, if `side` may write it. A
    /// MainDevice write of AL control raises AL event bit 0, of an activate byte AL event bit 4;
    /// toggling a channel's enable or deactivate bit resets its buffer.
    pub(super) fn write_register(&mut self, side: Side, address: usize, value: u8) {
        if !self.may_write(side, address) {
            return;
        }
        let old = self.memory.byte(address);
        self.memory.set_byte(address, value);
        if address == usize::from(register::AL_STATUS) {
            self.al_status_changed(old, value);
        }
        if let Some(offset) = offset_in(address, register::AL_CONTROL, 2) {
            self.al_control_event = true;
            let emulation = self.memory.byte(usize::from(register::ESC_CONFIGURATION));
            if emulation & DEVICE_EMULATION != 0 {
                let status = usize::from(register::AL_STATUS) + offset;
                let before = self.memory.byte(status);
                self.memory.set_byte(status, value);
                if offset == 0 {
                    self.al_status_changed(before, value);
                }
            }
        }
        let Some((offset, state)) = self.channel_register(address) else {
            return;
        };
        let reset_bit = match offset {
            ACTIVATE_OFFSET => {
                state.changed = true;
                Channel::ACTIVATE_ENABLE
            }
            PDI_CONTROL_OFFSET => Channel::PDI_DEACTIVATE,
            _ => return,
        };
        if (old ^ value) & reset_bit != 0 {
            state.reset();
        }
    }

    /// The acknowledgements of a PDI read of the register byte at `address`: AL control clears
    /// AL event bit 0, a channel's activate byte clears its share of AL event bit 4.
    fn acknowledge(&mut self, address: usize) {
        if address == usize::from(register::AL_CONTROL) {
            self.al_control_event = false;
        }
        if address == usize::from(register::WATCHDOG_STATUS_PROCESS_DATA) {
            self.watchdog_event = false;
        }
        if address == usize::from(register::DC_SYNC0_STATUS) {
            self.sync0_active = false;
        }
        if let Some((ACTIVATE_OFFSET, state)) = self.channel_register(address) {
            state.changed = false;
        }
    }

    /// The offset of `address` in a SyncManager channel's register block and the state of that
    /// channel, if `address` is a SyncManager register.
    fn channel_register(&mut self, address: usize) -> Option<(usize, &mut ChannelState)> {
        let (n, offset) = sync_manager_register(address, &self.config)?;
        Some((offset, self.channels.get_mut(usize::from(n))?))
    }

    /// The value of the register byte at `address`, without side effects.
    pub(super) fn register_value(&self, address: usize) -> u8 {
        if let Some(offset) = offset_in(address, register::AL_EVENT_REQUEST, 4) {
            let bytes = self.al_event().bits().to_le_bytes();
            return bytes.get(offset).copied().unwrap_or(0);
        }
        if address == usize::from(register::DC_SYNC0_STATUS) {
            return u8::from(self.sync0_active);
        }
        match sync_manager_register(address, &self.config) {
            Some((n, STATUS_OFFSET)) => self
                .channels
                .get(usize::from(n))
                .map_or(0, |state| state.status(self.memory.channel(n).control)),
            _ => self.memory.byte(address),
        }
    }

    /// Whether `side` may write the register byte at `address` now.
    fn may_write(&self, side: Side, address: usize) -> bool {
        match writer(address, &self.config) {
            Writer::Nobody => false,
            Writer::Only(writer) => writer == side,
            Writer::Both => true,
            Writer::EcatWhileDisabled(n) => side == Side::Ecat && !self.memory.channel(n).enabled(),
            Writer::SiiOwner => side == self.sii_owner(),
        }
    }
}
