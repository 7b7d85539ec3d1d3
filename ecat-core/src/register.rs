//! The ESC register map: the addresses of the registers a SubDevice and a MainDevice use.
//!
//! Addresses are the same on every ESC (ET1100, ET1200, AX58100, LAN9252, …): they are defined by
//! ETG.1000.4 (DL registers) and ETG.1000.6 (AL registers). The typed views of the values live next to
//! the concept they belong to: [`crate::al`] for the AL registers and [`crate::sync_manager`] for the
//! SyncManager channels.
//!
//! Access rights are noted as ECAT/PDI: what the MainDevice and what the SubDevice's controller may do.

/// DL information: ESC type, revision, FMMU/SM count, RAM size, features (ETG.1000.4 Table 31).
/// 10 bytes, ECAT r / PDI r.
pub const DL_INFORMATION: u16 = 0x0000;
/// ESC features supported (part of DL information, bit 2 = DC supported) (ETG.1000.4 Table 31).
pub const FEATURES: u16 = 0x0008;
/// Configured station address (ETG.1000.4 Table 32). u16, ECAT rw / PDI r.
pub const STATION_ADDRESS: u16 = 0x0010;
/// Configured station alias (ETG.1000.4 Table 32). u16, ECAT r / PDI rw.
pub const STATION_ALIAS: u16 = 0x0012;
/// DL control: forwarding and loop control of the ports (ETG.1000.4 Table 33). u32.
pub const DL_CONTROL: u16 = 0x0100;
/// DL status: PDI operational, link and loop state per port (ETG.1000.4 Table 34). u16, read-only.
pub const DL_STATUS: u16 = 0x0110;

/// AL control, written by the MainDevice to request a state (ETG.1000.6 Table 9).
/// u16, ECAT rw / PDI r. A PDI read clears AL event bit 0. See [`crate::AlControl`].
pub const AL_CONTROL: u16 = 0x0120;
/// AL status, written by the SubDevice (ETG.1000.6 Table 10). u16, ECAT r / PDI rw.
/// See [`crate::AlStatus`].
pub const AL_STATUS: u16 = 0x0130;
/// AL status code (ETG.1000.6 Table 11). u16, ECAT r / PDI rw. See [`crate::AlStatusCode`].
pub const AL_STATUS_CODE: u16 = 0x0134;
/// RUN LED override: the LED code (bits 3:0) and its enable (bit 4) for an ESC's own RUN LED
/// output (ESC datasheet section II, 0x0138). u8, ECAT rw / PDI rw. See [`crate::indicator`].
pub const RUN_LED_OVERRIDE: u16 = 0x0138;
/// ERR LED override (0x0139): as [`RUN_LED_OVERRIDE`], for the ERR output.
pub const ERR_LED_OVERRIDE: u16 = 0x0139;
/// PDI control: PDI type and "AL status emulation" (ETG.1000.6 Table 13). u8, loaded from SII word 0.
pub const PDI_CONTROL: u16 = 0x0140;
/// ESC configuration (device emulation, enhanced link detection), loaded from SII word 0 high byte.
pub const ESC_CONFIGURATION: u16 = 0x0141;
/// PDI configuration (ETG.1000.6 Table 14), loaded from SII word 1 low byte.
pub const PDI_CONFIGURATION: u16 = 0x0150;
/// SYNC/LATCH PDI configuration: SYNC0/SYNC1 output or latch input, driver and polarity, mapping
/// to the AL event (ESC datasheet section II, 0x0151), loaded from SII word 1 high byte.
pub const SYNC_LATCH_CONFIGURATION: u16 = 0x0151;
/// Extended PDI configuration (ESC datasheet section II, 0x0152), loaded from SII word 3. u16.
pub const EXTENDED_PDI_CONFIGURATION: u16 = 0x0152;

/// ECAT event mask: which events reach the IRQ field of datagrams (ETG.1000.4 Table 38). u16.
pub const ECAT_EVENT_MASK: u16 = 0x0200;
/// AL event mask: which AL event request bits drive the PDI IRQ line. u32, ECAT r / PDI rw.
/// See [`crate::AlEvent`].
pub const AL_EVENT_MASK: u16 = 0x0204;
/// ECAT event request (ETG.1000.4 Table 38). u16, read-only.
pub const ECAT_EVENT_REQUEST: u16 = 0x0210;
/// AL event request, the DL-user event register: what happened since the PDI last looked.
/// u32, PDI read-only; each bit is cleared by reading its source. See [`crate::AlEvent`].
pub const AL_EVENT_REQUEST: u16 = 0x0220;

/// Watchdog divider: base unit of the watchdogs = (divider + 2) × 40 ns (ETG.1000.4 Table 44). u16.
pub const WATCHDOG_DIVIDER: u16 = 0x0400;
/// PDI watchdog time, in watchdog units (ETG.1000.4 Table 45). u16.
pub const WATCHDOG_TIME_PDI: u16 = 0x0410;
/// Process-data (SyncManager) watchdog time, in watchdog units (ETG.1000.4 Table 45). u16.
pub const WATCHDOG_TIME_PROCESS_DATA: u16 = 0x0420;
/// Process-data watchdog status: bit 0 = 1 while the watchdog has not expired (ETG.1000.4 Table 46).
/// u16, read-only.
pub const WATCHDOG_STATUS_PROCESS_DATA: u16 = 0x0440;
/// Watchdog counters: SM watchdog expiries (low byte) and PDI watchdog expiries (ETG.1000.4 Table 47).
pub const WATCHDOG_COUNTER: u16 = 0x0442;

/// SII EEPROM interface: configuration/owner (0x0500), control/status (0x0502), address (0x0504),
/// data (0x0508) (ETG.1000.4 Tables 48–51). 16 bytes.
pub const SII_INTERFACE: u16 = 0x0500;
/// SII control/status: read/write/reload commands, busy and error bits (ETG.1000.4 Table 49). u16.
pub const SII_CONTROL: u16 = 0x0502;
/// SII word address of the next command (ETG.1000.4 Table 50). u32.
pub const SII_ADDRESS: u16 = 0x0504;
/// SII data: 4 or 8 bytes read, 2 bytes to write (ETG.1000.4 Table 51).
pub const SII_DATA: u16 = 0x0508;

/// First FMMU entity (ETG.1000.4 Table 56). Entities are [`FMMU_SIZE`] bytes apart.
pub const FMMU_BASE: u16 = 0x0600;
/// Size of one FMMU entity in bytes (ETG.1000.4 Table 56).
pub const FMMU_SIZE: u16 = 16;
/// First SyncManager channel (ETG.1000.4 Table 58). Channels are [`SM_SIZE`] bytes apart.
pub const SM_BASE: u16 = 0x0800;
/// Size of one SyncManager channel in bytes (ETG.1000.4 Table 58).
pub const SM_SIZE: u16 = 8;

/// DC system time, local copy of the reference clock (ETG.1000.4 Table 60). u64.
pub const DC_SYSTEM_TIME: u16 = 0x0910;
/// DC cyclic unit control: which side controls SYNC/LATCH (ESC datasheet section II, 0x0980). u8.
pub const DC_CYCLIC_UNIT_CONTROL: u16 = 0x0980;
/// DC activation: bit 0 cyclic operation, bit 1 SYNC0, bit 2 SYNC1 (ESC datasheet section II,
/// 0x0981). u8, written by the MainDevice, checked by the SubDevice at PREOP→SAFEOP.
pub const DC_ACTIVATION: u16 = 0x0981;
/// Pulse length of the SYNC signals in 10 ns; 0: acknowledge mode, a SYNC signal stays active
/// until the PDI reads its status register (ESC datasheet section II, 0x0982). u16, loaded from
/// SII word 2.
pub const DC_SYNC_PULSE_LENGTH: u16 = 0x0982;
/// SYNC0 status: bit 0 the SYNC0 signal; in acknowledge mode a PDI read clears it (ESC
/// datasheet section II, 0x098E). u8.
pub const DC_SYNC0_STATUS: u16 = 0x098E;
/// DC start time of cyclic operation (ESC datasheet section II, 0x0990). u64.
pub const DC_START_TIME: u16 = 0x0990;
/// DC SYNC0 cycle time in ns (ESC datasheet section II, 0x09A0). u32.
pub const DC_SYNC0_CYCLE_TIME: u16 = 0x09A0;
/// DC SYNC1 cycle time in ns (ESC datasheet section II, 0x09A4). u32.
pub const DC_SYNC1_CYCLE_TIME: u16 = 0x09A4;

/// Start of the process RAM, where mailboxes and process data live (ESC datasheet section I).
pub const PROCESS_RAM: u16 = 0x1000;

/// Address of SyncManager channel `n` (0..=15).
pub const fn sync_manager(n: u8) -> u16 {
    SM_BASE + (n as u16 & 0x0F) * SM_SIZE
}

/// Address of FMMU entity `n` (0..=15).
pub const fn fmmu(n: u8) -> u16 {
    FMMU_BASE + (n as u16 & 0x0F) * FMMU_SIZE
}

/// DL status, 0x0110 (ETG.1000.4 Table 34): PDI operational, per-port link and loop state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DlStatus(pub u16);

impl DlStatus {
    /// Bit 0: the PDI is operational (the EEPROM was loaded).
    pub const PDI_OPERATIONAL: u16 = 1 << 0;
    /// Bit 1: the PDI watchdog has not expired.
    pub const PDI_WATCHDOG_OK: u16 = 1 << 1;

    /// Bit 4 + `port`: physical link on port 0..=3.
    pub const fn link(port: u8) -> u16 {
        1 << (4 + (port & 3))
    }

    /// Bit 9 + 2 × `port`: communication established on port 0..=3 (loop open, link up).
    pub const fn communication(port: u8) -> u16 {
        1 << (9 + 2 * (port & 3))
    }
}

/// The PDI type in PDI control, 0x0140 (ETG.1000.6 Table 13), loaded from SII word 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum PdiType {
    /// 0x00: no PDI.
    None = 0x00,
    /// 0x04: 8 digital I/O.
    DigitalIo = 0x04,
    /// 0x05: the Beckhoff SPI slave (ET1100, AX58100; the LAN9252's SPI is 0x80,
    /// [`crate::chip::Chip::pdi_spi`]).
    Spi = 0x05,
    /// 0x08: 16-bit asynchronous microcontroller interface.
    AsyncMcu16 = 0x08,
    /// 0x09: 8-bit asynchronous microcontroller interface.
    AsyncMcu8 = 0x09,
}

/// DC activation, 0x0981 (ESC datasheet section II): what the MainDevice switched on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DcActivation(pub u8);

impl DcActivation {
    /// Bit 0: cyclic operation (the SYNC unit runs).
    pub const CYCLIC_OPERATION: u8 = 1 << 0;
    /// Bit 1: SYNC0 generated.
    pub const SYNC0: u8 = 1 << 1;
    /// Bit 2: SYNC1 generated.
    pub const SYNC1: u8 = 1 << 2;

    /// Whether the SYNC unit runs with SYNC0.
    pub const fn sync0(self) -> bool {
        self.0 & (Self::CYCLIC_OPERATION | Self::SYNC0) == Self::CYCLIC_OPERATION | Self::SYNC0
    }
}

/// The watchdog registers 0x0400 (divider) and 0x0410/0x0420 (times) (ETG.1000.4 Tables 44–45).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Watchdog {
    /// 0x0400: the base unit is (divider + 2) × 40 ns. Reset value 0x09C2 (100 µs).
    pub divider: u16,
    /// 0x0420 (process data) or 0x0410 (PDI), in base units; 0 disables it. Reset value 1000.
    pub time: u16,
}

impl Watchdog {
    /// The ESC's reset values: 100 µs × 1000 = 100 ms.
    pub const RESET: Self = Self {
        divider: 0x09C2,
        time: 1000,
    };
    /// Watchdog status 0x0440 bit 0: 1 while the process-data watchdog has not expired.
    pub const STATUS_OK: u16 = 1 << 0;

    /// The expiry period in nanoseconds, `None` when the watchdog is disabled (time 0).
    pub const fn period_ns(self) -> Option<u64> {
        if self.time == 0 {
            None
        } else {
            Some((self.divider as u64 + 2) * 40 * self.time as u64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reset_watchdog_is_100_ms_and_time_0_disables_it() {
        assert_eq!(Watchdog::RESET.period_ns(), Some(100_000_000));
        assert_eq!(
            Watchdog {
                divider: 0x09C2,
                time: 0
            }
            .period_ns(),
            None
        );
        assert_eq!(
            Watchdog {
                divider: u16::MAX,
                time: u16::MAX
            }
            .period_ns(),
            Some(171_798_691_800)
        );
    }

    #[test]
    fn channel_and_entity_addresses() {
        assert_eq!(
            (sync_manager(0), sync_manager(3), sync_manager(15)),
            (0x0800, 0x0818, 0x0878)
        );
        assert_eq!((fmmu(0), fmmu(2)), (0x0600, 0x0620));
        assert_eq!(DlStatus::link(0) | DlStatus::communication(0), 0x0210);
    }
}
