//! The emulated EtherCAT SubDevice Controller (ESC): the dual-ported memory that the SubDevice's
//! controller (over the PDI) and the MainDevice (over the EtherCAT port) share, with the register
//! access rights, the AL event request register, the SyncManager buffer logic and the RUN/ERR
//! LED outputs of a real ESC such as the ET1100 (ESC datasheet sections I and II; ETG.1000.4
//! Tables 31–58).
//!
//! [`Esc`] is synchronous and deterministic. An access may span several areas: the register file,
//! the buffer of an effective SyncManager, plain process RAM and the non-existent memory beyond
//! it; each byte follows the rules of the area it falls into. No input makes it panic.
//!
//! `no_std` with `alloc` (the 64 KiB address space and the EEPROM image are on the heap): the
//! host emulator (`ecat-emu`, which re-exports it as `ecat_emu::esc`) and the QEMU firmware
//! (`examples/qemu`) run this one model.
#![no_std]

extern crate alloc;

mod access;
mod area;
pub mod datagram;
mod dc;
pub mod fmmu;
mod leds;
mod memory;
mod registers;
pub mod sii;
mod sync_manager;
#[cfg(test)]
mod tests;

use alloc::vec::Vec;
use core::cell::{Ref, RefCell};

use ecat_core::chip::{Chip, ConfigArea};
use ecat_core::{AlEvent, register};

use access::{Access, Side};
use area::{Area, AreaMap, MAX_CHANNELS};
use memory::Memory;
use sync_manager::{Buffer, ChannelState};

/// Size of the ESC address space (16-bit physical addresses, ETG.1000.4 §5.2).
const ADDRESS_SPACE: usize = 0x1_0000;

/// The hardware configuration of the emulated ESC: what a real ESC fixes in silicon and reports
/// in its DL information registers (ETG.1000.4 Table 31), and what the board's EEPROM holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EscConfig {
    /// SyncManager channels (register 0x0005), at most 16.
    pub sync_managers: u8,
    /// FMMU entities (register 0x0004), at most 16.
    pub fmmus: u8,
    /// First address after the process RAM, between 0x1000 and 0x10000 (register 0x0006 reports
    /// the RAM size in KiB).
    pub process_ram_end: u32,
    /// ESC type (register 0x0000); 0x11 is the ET1100.
    pub esc_type: u8,
    /// Distributed clocks supported: the DC bits of the chip's features (register 0x0008 bits 2,
    /// 3 and 8) and a DC unit that answers 0x0900..0x09FF. False: an ESC without DC.
    pub dc_supported: bool,
    /// The chip: revision (0x0001), port descriptor (0x0007), features (0x0008).
    pub chip: Chip,
    /// The configuration area (SII words 0..7) the board's EEPROM holds at power-on, loaded by
    /// [`Esc::new`] as the ESC loads its EEPROM; `None`: no EEPROM (PDI control 0x0140 stays 0,
    /// no PDI).
    pub eeprom: Option<ConfigArea>,
}

impl Default for EscConfig {
    /// An ET1100 with DC whose EEPROM holds the configuration area the stack writes for a DC
    /// device ([`EscConfig::of`]).
    fn default() -> Self {
        Self::of(Chip::ET1100)
    }
}

impl EscConfig {
    /// `chip` as it is: its SyncManagers, FMMUs, process RAM, type and DC unit, on a board whose
    /// EEPROM holds the configuration area the stack writes for a DC SYNC0 device on it
    /// ([`ConfigArea::new`]).
    pub const fn of(chip: Chip) -> Self {
        Self {
            sync_managers: chip.sync_managers,
            fmmus: chip.fmmus,
            process_ram_end: chip.process_ram_end(),
            esc_type: chip.esc_type,
            dc_supported: chip.has_dc(),
            eeprom: Some(ConfigArea::new(&chip, chip.has_dc())),
            chip,
        }
    }

    /// The configuration limited to what the register map can express.
    fn normalised(self) -> Self {
        let max = u8::try_from(MAX_CHANNELS).unwrap_or(u8::MAX);
        Self {
            sync_managers: self.sync_managers.min(max),
            fmmus: self.fmmus.min(max),
            ..self
        }
    }

    /// First address after the process RAM, within the address space.
    fn ram_end(&self) -> usize {
        usize::try_from(self.process_ram_end)
            .unwrap_or(ADDRESS_SPACE)
            .clamp(usize::from(register::PROCESS_RAM), ADDRESS_SPACE)
    }
}

/// Counters of the PDI traffic, as a logic analyser on the SPI bus of a real SubDevice would
/// measure it: accesses and bytes requested, whatever the ESC did with them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PdiStats {
    /// Read accesses.
    pub reads: u64,
    /// Write accesses.
    pub writes: u64,
    /// Bytes requested by the reads.
    pub bytes_read: u64,
    /// Bytes carried by the writes.
    pub bytes_written: u64,
}

impl PdiStats {
    /// Counts one access of `len` bytes into `accesses` and `bytes`.
    fn count(accesses: &mut u64, bytes: &mut u64, len: usize) {
        *accesses = accesses.saturating_add(1);
        *bytes = bytes.saturating_add(u64::try_from(len).unwrap_or(u64::MAX));
    }
}

/// An emulated ESC with a PDI port and an EtherCAT port (ESC datasheet section I).
///
/// Models the register access rights of both ports, the AL event request register and its PDI
/// IRQ line, the SyncManager mailbox and 3-buffer handshakes (ETG.1000.4 Table 58) and the RUN
/// and ERR LED outputs with their override registers ([`Esc::run_led`], [`Esc::err_led`]). The
/// EEPROM's configuration area sets the PDI and SYNC registers at load; the frame-level port
/// (`datagram`, `fmmu`, `sii`, `dc`) adds FMMUs, the SII interface and the DC unit.
pub struct Esc {
    /// The configuration, limited to the register map.
    config: EscConfig,
    /// Registers and process RAM.
    memory: Memory,
    /// The buffer state of each SyncManager channel.
    channels: [ChannelState; MAX_CHANNELS],
    /// AL event bit 0: the MainDevice wrote AL control since the PDI last read it.
    al_control_event: bool,
    /// AL event bit 6: the process-data watchdog expired; a PDI read of 0x0440 acknowledges it.
    watchdog_event: bool,
    /// The MainDevice completed a buffer of a watchdog-triggering SyncManager since the last
    /// [`Esc::take_watchdog_trigger`].
    watchdog_triggered: bool,
    /// PDI traffic counters.
    stats: PdiStats,
    /// The SII EEPROM contents, words little-endian.
    eeprom: Vec<u8>,
    /// The SII control/status register as the ESC last set it.
    previous_sii_status: u16,
    /// The local clock of the DC unit, ns.
    local_time_ns: u64,
    /// SYNC0 in acknowledge mode (pulse length 0) is active until the PDI reads 0x098E.
    sync0_active: bool,
    /// ERR double-flashes: the process-data watchdog expired in OP, no ESM state change since
    /// ([`leds`]).
    watchdog_led: bool,
    /// The area map as the SyncManager registers defined it at a [`Memory::channels_version`]:
    /// rebuilt only when they changed, not on every access.
    /// `None`: not built yet.
    areas: RefCell<(Option<u64>, AreaMap)>,
}

impl Esc {
    /// An ESC just after power-on: registers at their reset values, process RAM zeroed, all
    /// SyncManagers disabled, then the EEPROM loaded when the board has one
    /// ([`EscConfig::eeprom`]: its configuration area into 0x0012, 0x0140..0x0153 and 0x0982).
    pub fn new(config: EscConfig) -> Self {
        let config = config.normalised();
        let mut esc = Self {
            memory: registers::reset_image(&config),
            config,
            channels: Default::default(),
            al_control_event: false,
            watchdog_event: false,
            watchdog_triggered: false,
            stats: PdiStats::default(),
            eeprom: Vec::new(),
            previous_sii_status: 0,
            local_time_ns: 0,
            sync0_active: false,
            watchdog_led: false,
            areas: RefCell::new((None, AreaMap::default())),
        };
        if let Some(area) = config.eeprom {
            esc.load_eeprom(area.bytes().to_vec());
        }
        esc
    }

    /// A register byte as the hardware holds it, without the side effects of a port's read:
    /// what the ESC's own logic (and a fake SPI chip in front of it) sees.
    pub fn register(&self, address: u16) -> u8 {
        self.register_value(usize::from(address))
    }

    /// A PDI read of `buf.len()` bytes from `address`. Returns the AL event request register as
    /// it was before the access: SPI ESCs shift it out during the address phase (ESC datasheet
    /// section II, "SPI slave interface").
    pub fn pdi_read(&mut self, address: u16, buf: &mut [u8]) -> AlEvent {
        let event = self.al_event();
        PdiStats::count(&mut self.stats.reads, &mut self.stats.bytes_read, buf.len());
        self.access(Side::Pdi, address, Access::Read(buf));
        event
    }

    /// A PDI write of `data` at `address`. Returns the AL event request register as it was
    /// before the access, like [`Esc::pdi_read`].
    pub fn pdi_write(&mut self, address: u16, data: &[u8]) -> AlEvent {
        let event = self.al_event();
        PdiStats::count(
            &mut self.stats.writes,
            &mut self.stats.bytes_written,
            data.len(),
        );
        self.access(Side::Pdi, address, Access::Write(data));
        event
    }

    /// The PDI IRQ line: asserted while an AL event request bit is set that the AL event mask
    /// (0x0204) lets through (ESC datasheet section II, 0x0204 and 0x0220).
    pub fn irq(&self) -> bool {
        let mask = self.memory.u32_le(usize::from(register::AL_EVENT_MASK));
        self.al_event().intersects(AlEvent(mask))
    }

    /// The AL event request register (0x0220): AL control written (bit 0), SyncManager
    /// activation changed (bit 4), SyncManager buffer events (bit 8 + n).
    pub fn al_event(&self) -> AlEvent {
        let mut event = AlEvent::NONE;
        if self.al_control_event {
            event |= AlEvent::AL_CONTROL;
        }
        if self.watchdog_event {
            event |= AlEvent::WATCHDOG_PROCESS_DATA;
        }
        let areas = self.area_map();
        for (n, state) in (0..self.config.sync_managers).zip(&self.channels) {
            if state.changed {
                event |= AlEvent::SM_CHANGE;
            }
            let buffer = areas.buffer(n);
            if buffer.is_some_and(|buffer| state.pdi_event(&buffer)) {
                event |= AlEvent::sync_manager(n);
            }
        }
        event
    }

    /// A MainDevice read of `buf.len()` bytes from `address` (APRD/FPRD/BRD). Returns whether the
    /// ESC served it, i.e. whether a real ESC would count it in the working counter: not when it
    /// touches an empty mailbox (`buf` keeps its contents there) or memory beyond the process RAM.
    pub fn ecat_read(&mut self, address: u16, buf: &mut [u8]) -> bool {
        self.access(Side::Ecat, address, Access::Read(buf))
    }

    /// A MainDevice write of `data` at `address` (APWR/FPWR/BWR). Returns whether the ESC took it:
    /// not when it touches a full mailbox, a buffer the MainDevice only reads, or memory beyond
    /// the process RAM. Bytes of read-only registers are silently ignored.
    pub fn ecat_write(&mut self, address: u16, data: &[u8]) -> bool {
        self.access(Side::Ecat, address, Access::Write(data))
    }

    /// Whether the MainDevice completed a buffer of a SyncManager with the watchdog trigger bit
    /// (control bit 6) since the last call: the process-data watchdog restarts (ESC datasheet
    /// section I, "Watchdog"). The time is kept by the caller (the emulator's virtual clock).
    pub fn take_watchdog_trigger(&mut self) -> bool {
        core::mem::take(&mut self.watchdog_triggered)
    }

    /// The process-data watchdog runs: 0x0440 bit 0 = 1.
    pub fn restart_watchdog(&mut self) {
        self.memory
            .write(usize::from(register::WATCHDOG_STATUS_PROCESS_DATA), &[1, 0]);
    }

    /// The process-data watchdog expired: 0x0440 bit 0 = 0, AL event bit 6, the SM watchdog
    /// counter (0x0442) counts it, ERR double-flashes in OP ([`Esc::err_led`]).
    pub fn expire_watchdog(&mut self) {
        self.memory
            .write(usize::from(register::WATCHDOG_STATUS_PROCESS_DATA), &[0, 0]);
        let counter = usize::from(register::WATCHDOG_COUNTER);
        let count = self.memory.byte(counter).saturating_add(1);
        self.memory.set_byte(counter, count);
        self.watchdog_event = true;
        self.watchdog_expired_led();
    }

    /// Sets register bytes as the ESC's own hardware does (link status, …), whatever the port
    /// rights say.
    pub fn set_register(&mut self, address: u16, data: &[u8]) {
        self.memory.write(usize::from(address), data);
    }

    /// The PDI traffic so far.
    pub fn stats(&self) -> PdiStats {
        self.stats
    }

    /// One access by `side`, split into runs of bytes of the same area; stops at the end of the
    /// address space. Returns whether every byte was served.
    fn access(&mut self, side: Side, address: u16, mut access: Access<'_>) -> bool {
        let start = usize::from(address);
        let end = start.saturating_add(access.len()).min(ADDRESS_SPACE);
        let write = matches!(access, Access::Write(_));
        let mut served = end - start == access.len();
        let mut position = start;
        while position < end {
            let (area, run_end) = self.area_map().run(position, end);
            let part = access.part(position - start..run_end - start);
            served &= self.access_area(side, area, position..run_end, part);
            position = run_end;
        }
        if write {
            self.sii_written(side, start..end);
        }
        served
    }

    /// The areas as the SyncManager registers define them now.
    fn area_map(&self) -> Ref<'_, AreaMap> {
        let version = self.memory.channels_version();
        if self.areas.borrow().0 != Some(version) {
            let map = self.build_area_map();
            *self.areas.borrow_mut() = (Some(version), map);
        }
        Ref::map(self.areas.borrow(), |(_, map)| map)
    }

    /// The areas as the SyncManager registers define them, computed afresh.
    fn build_area_map(&self) -> AreaMap {
        let mut buffers = [None; MAX_CHANNELS];
        let mut locked = [const { None }; MAX_CHANNELS];
        for ((buffer, lock), n) in buffers
            .iter_mut()
            .zip(&mut locked)
            .zip(0..self.config.sync_managers)
        {
            let channel = self.memory.channel(n);
            *buffer = Buffer::effective(channel);
            *lock = Buffer::locked(channel);
        }
        AreaMap::new(self.config.ram_end(), buffers, locked)
    }

    /// The part of an access that falls into one area, at the addresses `range`.
    fn access_area(
        &mut self,
        side: Side,
        area: Area,
        range: core::ops::Range<usize>,
        access: Access<'_>,
    ) -> bool {
        match (area, access) {
            (Area::Registers, Access::Read(buf)) => {
                for (byte, address) in buf.iter_mut().zip(range) {
                    *byte = self.read_register(side, address);
                }
                true
            }
            (Area::Registers, Access::Write(data)) => {
                for (&value, address) in data.iter().zip(range) {
                    self.write_register(side, address, value);
                }
                true
            }
            (Area::SyncManager(n, buffer), access) => {
                let offsets = buffer.offset(range.start)..buffer.offset(range.end);
                let completes =
                    matches!(access, Access::Write(_)) && offsets.end == buffer.length();
                if side == Side::Ecat && completes && self.memory.channel(n).control.watchdog() {
                    self.watchdog_triggered = true;
                }
                self.channels.get_mut(usize::from(n)).is_some_and(|state| {
                    state.access(&buffer, side, &offsets, access, &mut self.memory)
                })
            }
            // Closed to the MainDevice: nothing read or written, not counted.
            (Area::Locked, _) if side == Side::Ecat => false,
            (Area::Ram | Area::Locked | Area::Absent, Access::Read(buf)) => {
                self.memory.read(range.start, buf);
                area != Area::Absent
            }
            (Area::Ram | Area::Locked | Area::Absent, Access::Write(data)) => {
                self.memory.write(range.start, data);
                area != Area::Absent
            }
        }
    }
}
