//! The synchronisation modes of the process-data cycle (ETG.1000.6 Table 74, ETG.1020 §6): the
//! value of 0x1C32:01 / 0x1C33:01 and the modes a device supports (0x1C32:04).
//!
//! A leaf of the crate: the device description ([`crate::device`]) and the synchronisation
//! parameter objects ([`crate::sync_parameters`]) build on it; it imports nothing of the crate.

/// The sync mode of 0x1C32:01 / 0x1C33:01 (ETG.1000.6 Table 74).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SyncMode {
    /// 0: free-run, cycles on a local timer.
    FreeRun,
    /// 1: synchronous with the SM2 event (SM3 for an input-only device).
    SmSynchronous,
    /// 2: synchronous with DC SYNC0.
    DcSync0,
    /// 3: synchronous with DC SYNC1.
    DcSync1,
    /// 0x22: synchronous with the SM2 event (0x1C33 only).
    Sm2Synchronous,
    /// Any other value.
    Unknown(u16),
}

impl SyncMode {
    /// The type of the 0x1C32:01 value `code`.
    pub const fn from_code(code: u16) -> Self {
        match code {
            0 => Self::FreeRun,
            1 => Self::SmSynchronous,
            2 => Self::DcSync0,
            3 => Self::DcSync1,
            0x22 => Self::Sm2Synchronous,
            other => Self::Unknown(other),
        }
    }

    /// The 0x1C32:01 value.
    pub const fn code(self) -> u16 {
        match self {
            Self::FreeRun => 0,
            Self::SmSynchronous => 1,
            Self::DcSync0 => 2,
            Self::DcSync1 => 3,
            Self::Sm2Synchronous => 0x22,
            Self::Unknown(code) => code,
        }
    }
}

/// The sync modes a device supports: 0x1C32:04 (ETG.1000.6 Table 74).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SupportedSyncModes(pub u16);

impl SupportedSyncModes {
    /// Bit 0: free-run.
    pub const FREE_RUN: u16 = 0x0001;
    /// Bit 1: SM-synchronous.
    pub const SM: u16 = 0x0002;
    /// Bit 2: DC SYNC0.
    pub const SYNC0: u16 = 0x0004;
    /// Bit 3: DC SYNC1.
    pub const SYNC1: u16 = 0x0008;

    /// Whether the outputs (0x1C32:01) may run with `sync`. DC SYNC1 never may: the stack has no
    /// SYNC1-triggered cycle; 0x22 is a value of 0x1C33 only (inputs latched with the SM2 event).
    pub const fn supports(self, sync: SyncMode) -> bool {
        let bit = match sync {
            SyncMode::FreeRun => Self::FREE_RUN,
            SyncMode::SmSynchronous => Self::SM,
            SyncMode::DcSync0 => Self::SYNC0,
            SyncMode::DcSync1 | SyncMode::Sm2Synchronous | SyncMode::Unknown(_) => return false,
        };
        self.0 & bit != 0
    }

    /// Whether the device can run DC-synchronous, so the SubDevice reads the DC registers.
    pub const fn dc(self) -> bool {
        self.0 & Self::SYNC0 != 0
    }
}
