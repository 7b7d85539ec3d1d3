//! AL status code, register 0x0134 (ETG.1000.6 Table 11).

/// Why the last transition failed or the state fell back (ETG.1000.6 Table 11).
///
/// Codes are data, not errors: any `u16` is a valid value (0x8000..=0xFFFF are vendor specific), and
/// the explicit device ID travels in the same register. The constants name the codes a SubDevice
/// produces; [`AlStatusCode::name`] describes any code.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct AlStatusCode(pub u16);

macro_rules! codes {
    ($($(#[$doc:meta])* $name:ident = $value:literal, $text:literal;)*) => {
        impl AlStatusCode {
            $($(#[$doc])* pub const $name: Self = Self($value);)*

            /// The meaning of the code as ETG.1000.6 Table 11 words it, `None` for a reserved or
            /// vendor-specific code.
            pub const fn name(self) -> Option<&'static str> {
                match self.0 {
                    $($value => Some($text),)*
                    _ => None,
                }
            }
        }
    };
}

codes! {
    /// 0x0000: no error.
    NO_ERROR = 0x0000, "no error";
    /// 0x0001: unspecified error; also the answer to a transition the application left pending.
    UNSPECIFIED_ERROR = 0x0001, "unspecified error";
    /// 0x0002: no memory.
    NO_MEMORY = 0x0002, "no memory";
    /// 0x0003: invalid device setup.
    INVALID_DEVICE_SETUP = 0x0003, "invalid device setup";
    /// 0x0006: SII/EEPROM information does not match the firmware.
    SII_MISMATCH = 0x0006, "SII/EEPROM does not match firmware";
    /// 0x0007: firmware update failed, old firmware still running.
    FIRMWARE_UPDATE_FAILED = 0x0007, "firmware update failed";
    /// 0x0011: invalid requested state change.
    INVALID_STATE_CHANGE = 0x0011, "invalid requested state change";
    /// 0x0012: unknown requested state.
    UNKNOWN_STATE = 0x0012, "unknown requested state";
    /// 0x0013: bootstrap not supported.
    BOOTSTRAP_NOT_SUPPORTED = 0x0013, "bootstrap not supported";
    /// 0x0014: no valid firmware.
    NO_VALID_FIRMWARE = 0x0014, "no valid firmware";
    /// 0x0015: invalid mailbox configuration (BOOT).
    INVALID_MAILBOX_CONFIG_BOOT = 0x0015, "invalid mailbox configuration (BOOT)";
    /// 0x0016: invalid mailbox configuration (PREOP).
    INVALID_MAILBOX_CONFIG = 0x0016, "invalid mailbox configuration (PREOP)";
    /// 0x0017: invalid SyncManager configuration.
    INVALID_SM_CONFIG = 0x0017, "invalid sync manager configuration";
    /// 0x0018: no valid inputs available.
    NO_VALID_INPUTS = 0x0018, "no valid inputs available";
    /// 0x0019: no valid outputs.
    NO_VALID_OUTPUTS = 0x0019, "no valid outputs";
    /// 0x001A: synchronisation error.
    SYNC_ERROR = 0x001A, "synchronization error";
    /// 0x001B: SyncManager watchdog.
    SM_WATCHDOG = 0x001B, "sync manager watchdog";
    /// 0x001C: invalid SyncManager types.
    INVALID_SM_TYPES = 0x001C, "invalid sync manager types";
    /// 0x001D: invalid output configuration.
    INVALID_OUTPUT_CONFIG = 0x001D, "invalid output configuration";
    /// 0x001E: invalid input configuration.
    INVALID_INPUT_CONFIG = 0x001E, "invalid input configuration";
    /// 0x001F: invalid watchdog configuration.
    INVALID_WATCHDOG_CONFIG = 0x001F, "invalid watchdog configuration";
    /// 0x0020: the SubDevice needs a cold start.
    NEEDS_COLD_START = 0x0020, "slave needs cold start";
    /// 0x0021: the SubDevice needs INIT.
    NEEDS_INIT = 0x0021, "slave needs INIT";
    /// 0x0022: the SubDevice needs PREOP.
    NEEDS_PREOP = 0x0022, "slave needs PREOP";
    /// 0x0023: the SubDevice needs SAFEOP.
    NEEDS_SAFEOP = 0x0023, "slave needs SAFEOP";
    /// 0x0024: invalid input mapping.
    INVALID_INPUT_MAPPING = 0x0024, "invalid input mapping";
    /// 0x0025: invalid output mapping.
    INVALID_OUTPUT_MAPPING = 0x0025, "invalid output mapping";
    /// 0x0026: inconsistent settings.
    INCONSISTENT_SETTINGS = 0x0026, "inconsistent settings";
    /// 0x0027: free-run not supported.
    FREE_RUN_NOT_SUPPORTED = 0x0027, "freerun not supported";
    /// 0x0028: sync mode not supported.
    SYNC_MODE_NOT_SUPPORTED = 0x0028, "synchronization not supported";
    /// 0x0029: free-run needs 3-buffer mode.
    FREE_RUN_NEEDS_3_BUFFER = 0x0029, "freerun needs 3-buffer mode";
    /// 0x002A: background watchdog.
    BACKGROUND_WATCHDOG = 0x002A, "background watchdog";
    /// 0x002B: no valid inputs and outputs.
    NO_VALID_INPUTS_AND_OUTPUTS = 0x002B, "no valid inputs and outputs";
    /// 0x002C: fatal sync error.
    FATAL_SYNC_ERROR = 0x002C, "fatal sync error";
    /// 0x002D: no SYNC received.
    NO_SYNC_ERROR = 0x002D, "no sync error";
    /// 0x002E: cycle time too small.
    CYCLE_TIME_TOO_SMALL = 0x002E, "cycle time too small";
    /// 0x0030: invalid DC SYNC configuration.
    INVALID_DC_SYNC_CONFIG = 0x0030, "invalid DC SYNC configuration";
    /// 0x0031: invalid DC latch configuration.
    INVALID_DC_LATCH_CONFIG = 0x0031, "invalid DC latch configuration";
    /// 0x0032: PLL error.
    PLL_ERROR = 0x0032, "PLL error";
    /// 0x0033: DC sync IO error.
    DC_SYNC_IO_ERROR = 0x0033, "DC sync IO error";
    /// 0x0034: DC sync timeout.
    DC_SYNC_TIMEOUT = 0x0034, "DC sync timeout error";
    /// 0x0035: DC invalid sync cycle time.
    DC_INVALID_SYNC_CYCLE_TIME = 0x0035, "DC invalid sync cycle time";
    /// 0x0036: DC SYNC0 cycle time.
    DC_SYNC0_CYCLE_TIME = 0x0036, "DC SYNC0 cycle time";
    /// 0x0037: DC SYNC1 cycle time.
    DC_SYNC1_CYCLE_TIME = 0x0037, "DC SYNC1 cycle time";
    /// 0x0043: CoE mailbox error.
    MAILBOX_COE = 0x0043, "MBX_COE";
    /// 0x0050: EEPROM no access.
    EEPROM_NO_ACCESS = 0x0050, "EEPROM no access";
    /// 0x0051: EEPROM error.
    EEPROM_ERROR = 0x0051, "EEPROM error";
    /// 0x0052: external hardware not ready.
    EXTERNAL_HARDWARE_NOT_READY = 0x0052, "external hardware not ready";
    /// 0x0060: the SubDevice restarted locally.
    RESTARTED_LOCALLY = 0x0060, "slave restarted locally";
    /// 0x0061: device identification value updated.
    DEVICE_ID_UPDATED = 0x0061, "device identification value updated";
    /// 0x00F0: application controller available.
    APPLICATION_CONTROLLER_AVAILABLE = 0x00F0, "application controller available";
}

impl core::fmt::Debug for AlStatusCode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.name() {
            Some(name) => write!(f, "AlStatusCode({:#06x}: {name})", self.0),
            None => write!(f, "AlStatusCode({:#06x})", self.0),
        }
    }
}

impl core::fmt::Display for AlStatusCode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.name() {
            Some(name) => write!(f, "{:#06x} ({name})", self.0),
            None if self.0 >= 0x8000 => write!(f, "{:#06x} (vendor specific)", self.0),
            None => write!(f, "{:#06x}", self.0),
        }
    }
}
