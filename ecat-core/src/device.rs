//! The static description of a device: what the SubDevice checks the MainDevice's configuration
//! against.
//!
//! One `DeviceConfig` per device, usually a `const`. The same values end up in the SII image the
//! MainDevice reads (mailbox words 0x0018..0x001B, SM category), so what the device checks and what
//! it advertises cannot disagree.

use crate::sync_mode::SupportedSyncModes;
use crate::time::Duration;
use crate::{AlStatusCode, register};

/// An area of process RAM guarded by a SyncManager.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Area {
    /// Physical start address.
    pub start: u16,
    /// Length in bytes.
    pub length: u16,
}

impl Area {
    /// `length` bytes at `start`.
    pub const fn new(start: u16, length: u16) -> Self {
        Self { start, length }
    }

    /// One past the last byte, as a `u32` so that an area ending at 0xFFFF is representable.
    pub const fn end(self) -> u32 {
        self.start as u32 + self.length as u32
    }

    /// The area's bytes as a span: the first, and one past the last.
    pub(crate) const fn span(self) -> (u32, u32) {
        (self.start as u32, self.end())
    }

    /// Whether the two areas share a byte.
    pub(crate) const fn overlaps(self, other: Area) -> bool {
        spans_overlap(self.span(), other.span())
    }
}

/// Whether two spans of bytes (the first, one past the last) share a byte; an empty span shares
/// none.
pub(crate) const fn spans_overlap(a: (u32, u32), b: (u32, u32)) -> bool {
    a.0 < b.1 && b.0 < a.1
}

/// The mailbox SyncManagers a device expects (SII words 0x0018..0x001B for the standard mailbox,
/// 0x0014..0x0017 for the bootstrap mailbox).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MailboxConfig {
    /// SM0: the receive mailbox, written by the MainDevice.
    pub receive: Area,
    /// SM1: the send mailbox, read by the MainDevice.
    pub send: Area,
}

impl MailboxConfig {
    /// Smallest mailbox that carries an expedited SDO: 6 bytes mailbox header, 2 bytes CoE
    /// header, 8 bytes SDO.
    pub const MIN_SIZE: u16 = 16;

    /// Both mailboxes of `size` bytes, the receive mailbox at `start` and the send mailbox right
    /// after it.
    pub const fn contiguous(start: u16, size: u16) -> Self {
        Self {
            receive: Area::new(start, size),
            send: Area::new(start.wrapping_add(size), size),
        }
    }
}

/// The process-data image sizes in bytes. A fixed layout for now: configurable PDO mapping
/// computes these from the dictionary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ProcessDataSizes {
    /// Bytes the MainDevice writes (RxPDOs, SM2). 0 for an input-only device.
    pub outputs: u16,
    /// Bytes the device writes (TxPDOs, SM3). 0 for an output-only device.
    pub inputs: u16,
}

/// The identity of a device (ETG.1000.6 Table 4, object 0x1018; SII words 0x08..0x0F). One
/// value serves both: the dictionary declares 0x1018 as a record of this type initialised from
/// the device's constant, and [`crate::sii`] writes the same constant into the EEPROM image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Identity {
    /// 0x1018:01, assigned by the EtherCAT Technology Group.
    pub vendor_id: u32,
    /// 0x1018:02.
    pub product_code: u32,
    /// 0x1018:03.
    pub revision: u32,
    /// 0x1018:04.
    pub serial: u32,
}

/// Why a [`DeviceConfig`] is unusable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConfigError {
    /// A mailbox is smaller than [`MailboxConfig::MIN_SIZE`].
    MailboxTooSmall,
    /// A mailbox area lies outside `PROCESS_RAM..process_ram_end`.
    MailboxOutsideRam,
    /// The receive and send mailboxes overlap.
    MailboxesOverlap,
    /// DC SYNC1 is declared in the dictionary's sync modes ([`DeviceConfig::validate_sync`]): the stack has no SYNC1-triggered
    /// cycle.
    Sync1Unsupported,
    /// DC SYNC0 is declared with a minimum cycle time of 0: any SYNC0 cycle would be accepted.
    NoMinimumCycle,
}

/// The static description of a device that the state machine checks the MainDevice against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
// `repr(C)`: the byte and the halfwords first, within reach of 16-bit loads through the
// SubDevice's reference; the durations (8-aligned) last.
#[repr(C)]
pub struct DeviceConfig {
    /// Number of SyncManager channels the ESC has (8 on ET1100/AX58100, 4 on LAN9252). The
    /// SubDevice reads all their activation registers on an SM-change event, which is what clears
    /// the event in the ESC.
    pub sync_manager_count: u8,
    /// The device shows an explicit device ID (set by the application,
    /// `SubDevice::set_device_id`, e.g. from switches) in the AL status code when the
    /// MainDevice asks with AL control bit 5 (ETG.1000.6 Table 9). The SII General category
    /// ([`crate::sii::FLAG_IDENT_AL_STATUS`]) and the ESI (`Info/IdentificationReg134`) advertise
    /// it, so MainDevices use it. Default: false.
    pub explicit_device_id: bool,
    /// The ERR LED is the ESC's (wired to its ERR output, ESC datasheet section I): after each
    /// write of AL status the SubDevice writes the ERR LED override 0x0139 with ETG.1300's
    /// pattern for its error ([`crate::indicator::err_pattern`] with
    /// [`LED_OVERRIDE`](crate::indicator::LED_OVERRIDE)), which the ESC cannot tell from the
    /// error indication alone, as SSC's `SetALStatus` does with `ESC_SUPPORT_ECAT_LED`. The
    /// ESC drives RUN from AL status by itself either way. Default: false (ERR on a pin of the
    /// firmware, `ecat_embassy::indicator`).
    pub esc_err_led: bool,
    /// Process-data image sizes.
    pub process_data: ProcessDataSizes,
    /// Standard mailbox (PREOP and above).
    pub mailbox: MailboxConfig,
    /// Bootstrap mailbox; `None` when the device does not support BOOT (INIT→BOOT is answered with
    /// 0x0013).
    pub bootstrap_mailbox: Option<MailboxConfig>,
    /// One past the last byte of process RAM (0x3000 for the 8 KiB of an ET1100, 0x2000 for the
    /// 4 KiB of a LAN9252).
    pub process_ram_end: u32,
    /// How long the application may leave an upward transition pending before the SubDevice
    /// answers it with [`AlStatusCode::UNSPECIFIED_ERROR`]. Well below the 5 s MainDevices wait.
    pub transition_timeout: Duration,
    /// The shortest cycle the device keeps up with (0x1C32:05); a DC SYNC0 cycle below it is
    /// refused at PREOP→SAFEOP with 0x0036. Default: 250 µs.
    pub min_cycle_time: Duration,
    /// The cycle of free-run mode. Default: 1 ms.
    pub free_run_cycle: Duration,
}

impl DeviceConfig {
    /// Default for [`DeviceConfig::transition_timeout`]: 1 s.
    pub(crate) const DEFAULT_TRANSITION_TIMEOUT: Duration = Duration::from_millis(1_000);
    /// Default for [`DeviceConfig::process_ram_end`]: 8 KiB of process RAM.
    pub(crate) const DEFAULT_PROCESS_RAM_END: u32 = 0x3000;

    /// A device with the given standard mailbox and process-data sizes, no BOOT support, 8 KiB of
    /// process RAM and the default transition timeout.
    pub const fn new(mailbox: MailboxConfig, process_data: ProcessDataSizes) -> Self {
        Self {
            mailbox,
            bootstrap_mailbox: None,
            process_data,
            process_ram_end: Self::DEFAULT_PROCESS_RAM_END,
            sync_manager_count: 8,
            explicit_device_id: false,
            esc_err_led: false,
            free_run_cycle: Duration::from_millis(1),
            min_cycle_time: Duration::from_micros(250),
            transition_timeout: Self::DEFAULT_TRANSITION_TIMEOUT,
        }
    }

    /// Checks the description itself. Call it in a `const` to turn a bad description into a
    /// compile error: `const _: () = assert!(CONFIG.validate().is_ok());`. The sync modes are
    /// the dictionary's: [`DeviceConfig::validate_sync`] checks them against this description.
    pub const fn validate(&self) -> Result<(), ConfigError> {
        if let Err(e) = self.validate_mailbox(&self.mailbox) {
            return Err(e);
        }
        match &self.bootstrap_mailbox {
            Some(boot) => self.validate_mailbox(boot),
            None => Ok(()),
        }
    }

    /// Checks the dictionary's sync modes (`D::SYNC_MODES`,
    /// [`ObjectDictionary::SYNC_MODES`](crate::dictionary::ObjectDictionary::SYNC_MODES)) against
    /// this description, at compile time in a `const`:
    /// `const _: () = assert!(CONFIG.validate_sync(D::SYNC_MODES).is_ok());`.
    pub const fn validate_sync(&self, modes: SupportedSyncModes) -> Result<(), ConfigError> {
        if modes.0 & SupportedSyncModes::SYNC1 != 0 {
            return Err(ConfigError::Sync1Unsupported);
        }
        if modes.dc() && self.min_cycle_time.as_micros() == 0 {
            return Err(ConfigError::NoMinimumCycle);
        }
        Ok(())
    }

    const fn validate_mailbox(&self, mailbox: &MailboxConfig) -> Result<(), ConfigError> {
        let (rx, tx) = (mailbox.receive, mailbox.send);
        if rx.length < MailboxConfig::MIN_SIZE || tx.length < MailboxConfig::MIN_SIZE {
            return Err(ConfigError::MailboxTooSmall);
        }
        if !self.in_process_ram(rx) || !self.in_process_ram(tx) {
            return Err(ConfigError::MailboxOutsideRam);
        }
        if rx.overlaps(tx) {
            return Err(ConfigError::MailboxesOverlap);
        }
        Ok(())
    }

    /// Whether `area` lies inside the process RAM.
    pub(crate) const fn in_process_ram(&self, area: Area) -> bool {
        area.start >= register::PROCESS_RAM && area.end() <= self.process_ram_end
    }

    /// The mailbox configuration checked when entering `boot` (true) or PREOP (false), with the
    /// code that reports a mismatch. `None` when BOOT is requested but not supported.
    pub(crate) const fn mailbox_for(&self, boot: bool) -> Option<(&MailboxConfig, AlStatusCode)> {
        if !boot {
            return Some((&self.mailbox, AlStatusCode::INVALID_MAILBOX_CONFIG));
        }
        match &self.bootstrap_mailbox {
            Some(m) => Some((m, AlStatusCode::INVALID_MAILBOX_CONFIG_BOOT)),
            None => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> DeviceConfig {
        DeviceConfig::new(
            MailboxConfig::contiguous(0x1000, 128),
            ProcessDataSizes::default(),
        )
    }

    #[test]
    fn validate_checks_the_mailboxes_and_the_sync_support() {
        assert_eq!(config().validate(), Ok(()));
        let mut c = config();
        c.mailbox = MailboxConfig::contiguous(0x1000, 8);
        assert_eq!(c.validate(), Err(ConfigError::MailboxTooSmall));
        c.mailbox = MailboxConfig::contiguous(0x0F00, 128);
        assert_eq!(c.validate(), Err(ConfigError::MailboxOutsideRam));
        c.mailbox.send.start = 0x1040;
        c.mailbox.receive.start = 0x1000;
        assert_eq!(c.validate(), Err(ConfigError::MailboxesOverlap));
        let mut c = config();
        let sync1 = SupportedSyncModes(
            SupportedSyncModes::SM | SupportedSyncModes::SYNC0 | SupportedSyncModes::SYNC1,
        );
        assert_eq!(c.validate_sync(sync1), Err(ConfigError::Sync1Unsupported));
        let dc = SupportedSyncModes(SupportedSyncModes::SM | SupportedSyncModes::SYNC0);
        assert_eq!(c.validate_sync(dc), Ok(()));
        c.min_cycle_time = Duration::from_micros(0);
        assert_eq!(c.validate_sync(dc), Err(ConfigError::NoMinimumCycle));
        assert_eq!(c.validate_sync(SupportedSyncModes::DEFAULT), Ok(()));
    }
}
