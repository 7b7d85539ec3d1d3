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
    /// Free-run and SM-synchronous: what a dictionary supports unless it says otherwise
    /// ([`ObjectDictionary::SYNC_MODES`](crate::dictionary::ObjectDictionary::SYNC_MODES)).
    pub const DEFAULT: Self = Self(Self::FREE_RUN | Self::SM);

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
///
/// Kept as the object's encoded value: each entry little-endian, in subindex order (SI0 the
/// first byte, always 0x20; SI 0x20 the last), so that a read copies its entry's bytes and a write patches them
/// in place. [`SyncParameters::get`] and [`SyncParameters::set`] reach an entry by its
/// subindex (the constants below name them):
///
/// | SI | entry | type | set by |
/// |---|---|---|---|
/// | 1 | sync mode ([`SyncMode::code`]) | UNSIGNED16 | the MainDevice in PREOP (0x1C33's: the stack) |
/// | 2 | cycle time in ns (free-run: the local cycle) | UNSIGNED32 | the MainDevice, else the stack |
/// | 3 | shift time in ns: from SYNC0 to the outputs valid at the terminals / the inputs latched | UNSIGNED32 | the application (its hardware timing); 0 when unknown |
/// | 4 | supported sync modes ([`SupportedSyncModes`]) | UNSIGNED16 | the stack |
/// | 5 | minimum cycle time in ns | UNSIGNED32 | the stack |
/// | 6 | calc and copy time in ns: from the SM2 event (outputs) or until SM3 is read (inputs) to the data ready | UNSIGNED32 | the application; 0 when unknown |
/// | 7 | minimum delay time in ns (the least hardware delay) | UNSIGNED32 | the application; 0 when unknown |
/// | 8 | get cycle time: bit 0 measure the local cycle, bit 1 reset the measured values; stored as written | UNSIGNED16 | the MainDevice, in any state |
/// | 9 | delay time in ns (the hardware delay from SYNC0) | UNSIGNED32 | the application; 0 when unknown |
/// | 0x0A | SYNC0 cycle time in ns: the ESC's 0x09A0 while the device runs DC SYNC0, else 0 | UNSIGNED32 | the stack |
/// | 0x0B | SM events missed | UNSIGNED16 | the stack |
/// | 0x0C | cycle time too small: cycles that took longer than the cycle time | UNSIGNED16 | the stack |
/// | 0x0D | shift time too short: outputs not ready at the shift time (the stack does not see that instant) | UNSIGNED16 | the application; 0 |
/// | 0x20 | sync error | BOOLEAN (one byte, 0 or 1) | the stack |
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(align(4))]
pub struct SyncParameters([u8; RECORD_LEN]);

/// Where each entry of [`SyncParameters`] starts, by subindex (SI 0x20's at 0x0E), and the
/// record's end last: entry `sub` is `ENTRY_STARTS[sub]..ENTRY_STARTS[sub + 1]`.
const ENTRY_STARTS: [u8; 16] = [0, 1, 3, 7, 11, 13, 17, 21, 25, 27, 31, 35, 37, 39, 41, 42];

/// The record's bytes.
const RECORD_LEN: usize = ENTRY_STARTS[15] as usize;

/// Where entry `sub` lies in the record's bytes, `None` for a subindex the object lacks.
#[inline(always)]
const fn span(sub: u8) -> Option<(usize, usize)> {
    let at = match sub {
        0..=0x0D => sub as usize,
        0x20 => 0x0E,
        _ => return None,
    };
    // `at + 1` is at most 0x0F: inside the table.
    #[allow(clippy::indexing_slicing)]
    Some((ENTRY_STARTS[at] as usize, ENTRY_STARTS[at + 1] as usize))
}

impl Default for SyncParameters {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl SyncParameters {
    /// SI1: the sync mode ([`SyncMode::code`]).
    pub const SYNC_TYPE: u8 = 1;
    /// SI2: the cycle time in ns.
    pub const CYCLE_TIME: u8 = 2;
    /// SI3: the shift time in ns.
    pub const SHIFT_TIME: u8 = 3;
    /// SI4: the supported sync modes ([`SupportedSyncModes`]).
    pub const SYNC_TYPES_SUPPORTED: u8 = 4;
    /// SI5: the minimum cycle time in ns.
    pub const MIN_CYCLE_TIME: u8 = 5;
    /// SI6: the calc and copy time in ns.
    pub const CALC_COPY_TIME: u8 = 6;
    /// SI7: the minimum delay time in ns.
    pub const MIN_DELAY_TIME: u8 = 7;
    /// SI8: get cycle time.
    pub const GET_CYCLE_TIME: u8 = 8;
    /// SI9: the delay time in ns.
    pub const DELAY_TIME: u8 = 9;
    /// SI 0x0A: the SYNC0 cycle time in ns.
    pub const SYNC0_CYCLE_TIME: u8 = 0x0A;
    /// SI 0x0B: the SM-event-missed counter.
    pub const SM_EVENT_MISSED: u8 = 0x0B;
    /// SI 0x0C: the cycle-time-too-small counter.
    pub const CYCLE_TIME_TOO_SMALL: u8 = 0x0C;
    /// SI 0x0D: the shift-time-too-short counter.
    pub const SHIFT_TIME_TOO_SHORT: u8 = 0x0D;
    /// SI 0x20: sync error (a BOOLEAN).
    pub const SYNC_ERROR: u8 = 0x20;

    /// The highest subindex, SI0.
    #[doc(hidden)]
    pub const MAX_SUB: u8 = 0x20;

    /// Everything 0 but SI0 (0x20), for `const` initialisers.
    pub const DEFAULT: Self = {
        let mut bytes = [0; RECORD_LEN];
        bytes[0] = Self::MAX_SUB;
        Self(bytes)
    };

    /// 0x1C32 at power-on: SM-synchronous (SI1 = 1).
    pub const OUTPUTS: Self = Self::DEFAULT.with(Self::SYNC_TYPE, OUTPUT_SYNC_DEFAULT as u32);

    /// 0x1C33 at power-on: SM2-synchronous (SI1 = 0x22), the inputs' type that follows from
    /// SM-synchronous outputs
    /// ([`input_sync_type`](crate::sync_parameters::input_sync_type); replaced when the
    /// configuration is refreshed).
    pub const INPUTS: Self = Self::DEFAULT.with(Self::SYNC_TYPE, INPUT_SYNC_DEFAULT as u32);

    /// The record with entry `sub` set to the low bytes of `value` ([`SyncParameters::set`] for
    /// `const` initialisers; SI0 stays 0x20; SI 0x20, a BOOLEAN, is 1 for any `value` but 0).
    pub const fn with(mut self, sub: u8, value: u32) -> Self {
        if let (1.., Some((start, end))) = (sub, span(sub)) {
            let value = match sub {
                Self::SYNC_ERROR if value != 0 => 1,
                _ => value,
            };
            let bytes = value.to_le_bytes();
            let mut i = start;
            while i < end {
                // `i` is inside the record (the table's spans are) and `i - start` below 4.
                #[allow(clippy::indexing_slicing)]
                {
                    self.0[i] = bytes[i - start];
                }
                i += 1;
            }
        }
        self
    }

    /// The encoded value of entry `sub`, `None` for a subindex the object lacks.
    #[inline(always)]
    pub(crate) fn entry(&self, sub: u8) -> Option<&[u8]> {
        let (start, end) = span(sub)?;
        self.0.get(start..end)
    }

    /// The record's bytes, to patch in place.
    #[inline(always)]
    pub(crate) fn bytes_mut(&mut self) -> &mut [u8] {
        &mut self.0
    }

    /// The value of entry `sub` (a BOOLEAN is 0 or 1; a subindex the object lacks reads 0).
    #[inline]
    pub fn get(&self, sub: u8) -> u32 {
        let mut bytes = [0; 4];
        crate::bytes::copy(&mut bytes, self.entry(sub).unwrap_or_default());
        u32::from_le_bytes(bytes)
    }

    /// Sets entry `sub` to the low bytes of `value` (as many as the entry has; nothing for SI0
    /// and a subindex the object lacks). What the application sets: the times it knows (SI3,
    /// SI6, SI7, SI9) and SI 0x0D; the stack fills the others (`sync_parameters::fill`).
    pub fn set(&mut self, sub: u8, value: u32) {
        *self = self.with(sub, value);
    }

    /// Stores `bytes` as entry `SUB`, whose size they are: one store at an offset known at
    /// compile time (the stack's own fills).
    #[inline(always)]
    pub(crate) fn put<const SUB: u8, const N: usize>(&mut self, bytes: [u8; N]) {
        let start = Entry::<SUB, N>::START;
        if let Some(dst) = self.0.get_mut(start..).and_then(|s| s.first_chunk_mut()) {
            *dst = bytes;
        }
    }

    /// The `N` bytes of entry `SUB` (the stack's own reads, as [`SyncParameters::put`]).
    #[inline(always)]
    pub(crate) fn take<const SUB: u8, const N: usize>(&self) -> [u8; N] {
        let start = Entry::<SUB, N>::START;
        self.0
            .get(start..)
            .and_then(|s| s.first_chunk())
            .copied()
            .unwrap_or([0; N])
    }
}

/// Entry `SUB` of the record as compile-time constants: [`Entry::SPAN`] (its start and size)
/// and, for an entry of `N` bytes, [`Entry::START`]. A subindex the object lacks, or `N` not
/// the entry's size, fails the build. The checks live in associated constants, which are only
/// ever evaluated by the compiler: no code path at run time can reach them.
pub(crate) struct Entry<const SUB: u8, const N: usize = 0>;

impl<const SUB: u8, const N: usize> Entry<SUB, N> {
    /// Where the entry starts in the record, and its size in bytes.
    #[allow(clippy::panic)] // a constant: a build error, never a run-time panic
    pub(crate) const SPAN: (usize, usize) = match span(SUB) {
        Some((start, end)) => (start, end - start),
        None => panic!("no such entry"),
    };

    /// Where the entry starts, checked to be `N` bytes long ([`SyncParameters::put`],
    /// [`SyncParameters::take`]).
    #[allow(clippy::panic)] // a constant: a build error, never a run-time panic
    pub(crate) const START: usize = match Self::SPAN {
        (start, n) if n == N => start,
        _ => panic!("not the entry's size"),
    };
}
