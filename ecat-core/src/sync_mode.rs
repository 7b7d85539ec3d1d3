//! The synchronisation modes of the process-data cycle (ETG.1000.6 Table 74, ETG.1020 §6): the
//! value of 0x1C32:01 / 0x1C33:01, the modes a device supports (0x1C32:04), and the record that
//! carries them ([`SyncParameters`], the value of 0x1C32/0x1C33).
//!
//! A leaf of the crate: the device description ([`crate::device`]), the communication area
//! ([`crate::dictionary::communication`]) and the synchronisation parameter objects
//! ([`crate::sync_parameters`]: how the record is read, written and filled) build on it; it
//! imports nothing of the crate.

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

/// 0x1C32:01 at power-on.
const OUTPUT_SYNC_DEFAULT: u16 = 1;
/// 0x1C33:01 at power-on.
const INPUT_SYNC_DEFAULT: u16 = 0x22;

/// The value of a sync manager parameter object (0x1C32/0x1C33, ETG.1000.6 Table 74, ETG.1020
/// §6.3) with every subindex SSC carries: SI0 = 0x20; SI 0x0E..0x1F do not exist.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SyncParameters {
    /// SI1: the sync mode ([`SyncMode::code`]), chosen by the MainDevice in PREOP.
    pub sync_type: u16,
    /// SI2: the cycle time in ns (free-run: the local cycle).
    pub cycle_time: u32,
    /// SI3: the shift time in ns: outputs — from SYNC0 to the outputs being valid at the
    /// terminals; inputs — from SYNC0 to the inputs being latched. Set by the application
    /// (its hardware timing); 0 when unknown.
    pub shift_time: u32,
    /// SI4: the supported sync modes ([`SupportedSyncModes`]).
    pub supported: u16,
    /// SI5: the minimum cycle time in ns.
    pub min_cycle_time: u32,
    /// SI6: the calc and copy time in ns: how long the application needs between the SM2
    /// event (outputs) or before SM3 is read (inputs) and the data being ready, which a
    /// MainDevice uses to place SYNC0 in the cycle. Set by the application; 0 when unknown.
    pub calc_copy_time: u32,
    /// SI7: the minimum delay time in ns (the least hardware delay, SI9 being the greatest).
    /// Set by the application; 0 when unknown.
    pub min_delay_time: u32,
    /// SI8: get cycle time, a command word a MainDevice may write in any state (bit 0: measure
    /// the local cycle, bit 1: reset the measured values); 0 by default. The stack stores it:
    /// the times it reports (SI5, SI6) are the device's, not measured.
    pub get_cycle_time: u16,
    /// SI9: the delay time in ns (hardware delay from SYNC0 to the outputs or inputs). Set by
    /// the application; 0 when unknown.
    pub delay_time: u32,
    /// SI 0x0A: the SYNC0 cycle time in ns the ESC runs (0x09A0) while the device runs DC
    /// SYNC0, else 0 (filled by `fill`).
    pub sync0_cycle_time: u32,
    /// SI 0x0B: SM events missed.
    pub sm_event_missed: u16,
    /// SI 0x0C: cycles that took longer than the cycle time.
    pub cycle_time_too_small: u16,
    /// SI 0x0D: shift time too short counter: cycles whose outputs were not ready at the shift
    /// time. The stack does not see the output instant, so it stays 0 unless the application
    /// counts.
    pub shift_time_too_short: u16,
    /// SI 0x20: a synchronisation error occurred.
    pub sync_error: bool,
}

impl SyncParameters {
    /// Everything 0, for `const` initialisers.
    pub const DEFAULT: Self = Self {
        sync_type: 0,
        cycle_time: 0,
        shift_time: 0,
        supported: 0,
        min_cycle_time: 0,
        calc_copy_time: 0,
        min_delay_time: 0,
        get_cycle_time: 0,
        delay_time: 0,
        sync0_cycle_time: 0,
        sm_event_missed: 0,
        cycle_time_too_small: 0,
        shift_time_too_short: 0,
        sync_error: false,
    };

    /// 0x1C32 at power-on: SM-synchronous (SI1 = 1).
    pub const OUTPUTS: Self = Self {
        sync_type: OUTPUT_SYNC_DEFAULT,
        ..Self::DEFAULT
    };

    /// 0x1C33 at power-on: SM2-synchronous (SI1 = 0x22), the inputs' type that follows from
    /// SM-synchronous outputs
    /// ([`input_sync_type`](crate::sync_parameters::input_sync_type); replaced when the
    /// configuration is refreshed).
    pub const INPUTS: Self = Self {
        sync_type: INPUT_SYNC_DEFAULT,
        ..Self::DEFAULT
    };

    /// The highest subindex, SI0.
    #[doc(hidden)]
    pub const MAX_SUB: u8 = 0x20;
}
