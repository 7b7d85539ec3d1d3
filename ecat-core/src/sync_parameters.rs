//! Synchronisation of the process-data cycle (ETG.1020 §6 / ETG.1000.6 Table 74, objects 0x1C32
//! for the outputs and 0x1C33 for the inputs): what triggers a cycle, and the parameters the
//! MainDevice reads and sets.
//!
//! | sync mode (0x1C32:01) | cycle trigger |
//! |---|---|
//! | 0 free-run | a local timer, [`DeviceConfig::free_run_cycle`](crate::DeviceConfig::free_run_cycle) |
//! | 1 SM-synchronous | SM2 written by the MainDevice (SM3 read, for an input-only device) |
//! | 2 DC SYNC0 | the SYNC0 signal of the ESC's distributed-clocks unit |
//! | 3 DC SYNC1 | not supported: refused with 0x0028 |
//!
//! The SubDevice reads the DC activation (0x0981) with every AL control event, and a device that
//! supports DC SYNC0 also the SYNC0 cycle time (0x09A0); PREOP→SAFEOP checks them (`check_dc`;
//! a device without DC refuses any activation with 0x0030).
//!
//! 0x1C32 and 0x1C33 are records of [`SyncParameters`] with SSC's subindices, part of the
//! communication area every CoE dictionary gets from `dictionary!`'s `communication` item
//! ([`crate::dictionary::communication`]); the stack reads the sync mode the MainDevice chose
//! and fills the rest.

use crate::AlStatusCode;
use crate::abort::AbortCode;
use crate::device::DeviceConfig;
use crate::dictionary::limits::Declared;
use crate::dictionary::{
    Access, At, DataType, EntryInfo, Limit, Limits, Object, ObjectDictionary, Read,
};
use crate::register::DcActivation;
pub use crate::sync_mode::SyncParameters;
use crate::sync_mode::{Entry, SupportedSyncModes, SyncMode};
use crate::time::{Duration, Instant};

impl SyncParameters {
    /// Copies the encoded value of a subindex from an offset ([`At`]) into `out` (the read of
    /// the standard record: one function for 0x1C32 and 0x1C33 of every dictionary): the
    /// entry's bytes.
    pub fn read(&self, at: At, out: &mut [u8]) -> Result<Read, AbortCode> {
        let entry = self.entry(at.sub()).ok_or(AbortCode::NO_SUBINDEX)?;
        Ok(crate::dictionary::communication::copy(
            entry,
            at.offset(),
            out,
        ))
    }

    /// Decodes `data` into `sub`: what an SDO download stores after the access check. Only
    /// the entries a MainDevice may write are written here (SI1, SI2, SI8:
    /// [`PARAMETER_ENTRIES`]); the others are read-only, 0x06010002, and the stack fills them
    /// in itself (`fill`, [`CycleMonitor`]). The value must have the entry's size (0x06070012
    /// longer, 0x06070013 shorter); its bytes are the entry's.
    pub fn write(&mut self, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let (start, size) = match sub {
            Self::SYNC_TYPE => Entry::<{ Self::SYNC_TYPE }>::SPAN,
            Self::CYCLE_TIME => Entry::<{ Self::CYCLE_TIME }>::SPAN,
            Self::GET_CYCLE_TIME => Entry::<{ Self::GET_CYCLE_TIME }>::SPAN,
            0..=0x0D | 0x20 => return Err(AbortCode::READ_ONLY),
            _ => return Err(AbortCode::NO_SUBINDEX),
        };
        match data.len().cmp(&size) {
            core::cmp::Ordering::Greater => Err(AbortCode::LENGTH_TOO_HIGH),
            core::cmp::Ordering::Less => Err(AbortCode::LENGTH_TOO_LOW),
            core::cmp::Ordering::Equal => {
                crate::bytes::copy(self.bytes_mut().get_mut(start..).unwrap_or_default(), data);
                Ok(())
            }
        }
    }
}

impl SyncParameters {
    /// [`SyncParameters::write`] of 0x1C33: SI1 must name a sync mode of the inputs
    /// ([`check_input_sync_write`]).
    #[doc(hidden)]
    pub fn write_input(&mut self, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        check_input_sync_write(sub, data)?;
        self.write(sub, data)
    }
}

/// The declared default of 0x1C32:01, SM-synchronous.
const OUTPUT_SYNC_DEFAULT: u16 = SyncMode::SmSynchronous.code();
/// The declared default of 0x1C33:01, SM2-synchronous.
const INPUT_SYNC_DEFAULT: u16 = SyncMode::Sm2Synchronous.code();

/// The declared defaults of 0x1C32:01 and 0x1C33:01 (SM-synchronous, SM2-synchronous), as
/// the records read them (UNSIGNED16).
#[doc(hidden)]
pub const DECLARED: &[Declared] = &[
    Declared::new(
        0x1C32,
        1,
        Limit::Default,
        &OUTPUT_SYNC_DEFAULT.to_le_bytes(),
    ),
    Declared::new(0x1C33, 1, Limit::Default, &INPUT_SYNC_DEFAULT.to_le_bytes()),
];

/// The entries of 0x1C32 and 0x1C33 (ETG.1000.6 Table 74, SSC's `asEntryDesc0x1C3x`): SI1 and
/// SI2 writable in PREOP (the MainDevice's choice of sync mode and cycle), SI8 (get cycle time)
/// writable in every state, the rest read-only; SI1 declares its default.
#[doc(hidden)]
pub const PARAMETER_ENTRIES: &[EntryInfo<&'static str>] = &[
    EntryInfo::subindex_count("Highest sub-index supported"),
    sync_entry(
        1,
        "Synchronization type",
        DataType::Unsigned16,
        Access::RW_PREOP,
        true,
    ),
    sync_entry(
        2,
        "Cycle time",
        DataType::Unsigned32,
        Access::RW_PREOP,
        false,
    ),
    sync_entry(3, "Shift time", DataType::Unsigned32, Access::RO, false),
    sync_entry(
        4,
        "Synchronization types supported",
        DataType::Unsigned16,
        Access::RO,
        false,
    ),
    sync_entry(
        5,
        "Minimum cycle time",
        DataType::Unsigned32,
        Access::RO,
        false,
    ),
    sync_entry(
        6,
        "Calc and copy time",
        DataType::Unsigned32,
        Access::RO,
        false,
    ),
    sync_entry(
        7,
        "Minimum delay time",
        DataType::Unsigned32,
        Access::RO,
        false,
    ),
    sync_entry(8, "Get cycle time", DataType::Unsigned16, Access::RW, false),
    sync_entry(9, "Delay time", DataType::Unsigned32, Access::RO, false),
    sync_entry(
        0x0A,
        "Sync0 cycle time",
        DataType::Unsigned32,
        Access::RO,
        false,
    ),
    sync_entry(
        0x0B,
        "SM event missed counter",
        DataType::Unsigned16,
        Access::RO,
        false,
    ),
    sync_entry(
        0x0C,
        "Cycle time too small counter",
        DataType::Unsigned16,
        Access::RO,
        false,
    ),
    sync_entry(
        0x0D,
        "Shift time too short counter",
        DataType::Unsigned16,
        Access::RO,
        false,
    ),
    sync_entry(0x20, "Sync error", DataType::Boolean, Access::RO, false),
];

const fn sync_entry(
    sub: u8,
    name: &'static str,
    data_type: DataType,
    access: Access,
    default: bool,
) -> EntryInfo<&'static str> {
    let bit_len = match data_type {
        DataType::Boolean => 1,
        DataType::Unsigned16 => 16,
        _ => 32,
    };
    EntryInfo {
        sub,
        name,
        data_type,
        bit_len,
        access,
        limits: Limits(if default { Limits::DEFAULT } else { 0 }),
    }
}

/// What the MainDevice configured in the ESC's DC SYNC unit (ESC datasheet section II,
/// 0x0981 and 0x09A0), as the SubDevice read it with the last AL control event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct DcSettings {
    /// 0x0981.
    pub(crate) activation: DcActivation,
    /// 0x09A0: the SYNC0 cycle in ns.
    pub(crate) sync0_cycle_ns: u32,
}

impl DcSettings {
    /// The bytes the SubDevice reads: 0x0981 up to the end of 0x09A0.
    pub(crate) const READ_LEN: usize = 0x09A4 - 0x0981;

    /// The SYNC0 cycle (µs resolution).
    pub(crate) const fn sync0_cycle(self) -> Duration {
        Duration::from_micros(self.sync0_cycle_ns as u64 / 1_000)
    }

    /// The settings in the bytes read from 0x0981 on.
    pub(crate) fn from_bytes(bytes: &[u8]) -> Self {
        let cycle = bytes
            .get(0x09A0 - 0x0981..)
            .and_then(|b| b.first_chunk())
            .map_or(0, |b| u32::from_le_bytes(*b));
        Self {
            activation: DcActivation(bytes.first().copied().unwrap_or(0)),
            sync0_cycle_ns: cycle,
        }
    }
}

/// The DC configuration check at PREOP→SAFEOP (conformance.md "Distributed clocks"): the SYNC
/// unit activated without SYNC0, SYNC1 without SYNC0, SYNC1 activated on a device that does not
/// support it (0x1C32:04 without 0x0008; 0x0981 = 0x07 on a SYNC0-only device), DC SYNC0
/// requested without SYNC0 running, or SYNC0 running while the device is told to run free or
/// SM-synchronous: 0x0030 (ETG.1000.6 Table 11 "invalid DC SYNC configuration"; SSC 5.12
/// `ecatslv.c` `CheckDcSettings` refuses a SYNC signal the supported sync modes lack with the
/// same code). The SYNC0 cycle itself is [`check_cycle`]'s.
pub(crate) fn check_dc(
    sync: SyncMode,
    dc: DcSettings,
    modes: SupportedSyncModes,
) -> Result<(), AlStatusCode> {
    let bits = dc.activation.0;
    let cyclic = bits & DcActivation::CYCLIC_OPERATION != 0;
    let sync0 = bits & DcActivation::SYNC0 != 0;
    let sync1 = bits & DcActivation::SYNC1 != 0;
    let wanted = matches!(sync, SyncMode::DcSync0);
    let without_sync0 = (cyclic || sync1) && !sync0;
    let unsupported_sync1 = sync1 && modes.0 & SupportedSyncModes::SYNC1 == 0;
    if without_sync0 || unsupported_sync1 || wanted != dc.activation.sync0() {
        return Err(AlStatusCode::INVALID_DC_SYNC_CONFIG);
    }
    Ok(())
}

/// Whether a cycle of `ns` nanoseconds is shorter than the device's minimum cycle (SI5, whole
/// microseconds): `ns < min · 1000` exactly when `⌊ns / 1000⌋ < min`, which needs no 64-bit
/// product.
fn below_min_cycle(ns: u32, device: &DeviceConfig) -> bool {
    u64::from(ns / 1_000) < device.min_cycle_time.as_micros()
}

/// The output sync manager parameter object.
pub(crate) const OUTPUT_PARAMETERS: u16 = 0x1C32;
/// The input sync manager parameter object.
pub(crate) const INPUT_PARAMETERS: u16 = 0x1C33;

/// Where object `index` is in `objects`.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
const fn position<D>(objects: &[Object<D>], index: u16) -> Option<usize> {
    let mut i = 0;
    while i < objects.len() {
        if objects[i].info.index == index {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// The sync mode of the inputs (0x1C33:01) that follows from the outputs' (ETG.1020 §6.3): in
/// SM-synchronous mode the inputs are latched with the SM2 event when there are outputs
/// (0x22), with the SM3 event otherwise (1); free-run and DC modes are the same for both.
pub const fn input_sync_type(output: SyncMode, has_outputs: bool) -> SyncMode {
    match output {
        SyncMode::SmSynchronous if has_outputs => SyncMode::Sm2Synchronous,
        other => other,
    }
}

/// A write of 0x1C33:01 must name a sync mode of the inputs (ETG.1000.6 Table 74: free-run 0,
/// SM3-synchronous 1, DC SYNC0 2, DC SYNC1 3, SM2-synchronous 0x22), else 0x06090030. What it
/// shows afterwards is the inputs' type in effect ([`input_sync_type`], filled by [`fill`]): the
/// inputs follow the outputs' 0x1C32:01 (or, without 0x1C32, the ESC's SYNC0 activation).
#[doc(hidden)]
pub fn check_input_sync_write(sub: u8, data: &[u8]) -> Result<(), AbortCode> {
    match (sub, data) {
        (1, &[lo, hi]) => match u16::from_le_bytes([lo, hi]) {
            0x00..=0x03 | 0x22 => Ok(()),
            _ => Err(AbortCode::VALUE_RANGE),
        },
        _ => Ok(()),
    }
}

/// Fills what the stack knows into 0x1C32 and 0x1C33 (those the dictionary has): the supported
/// sync modes (SI4), the minimum cycle time (SI5) and, unless the MainDevice wrote one
/// (`chosen_cycle`, [`Chosen::cycle_ns`]), the cycle time in ns (SI2: the local cycle in
/// free-run, the SYNC0 cycle in DC mode), the SYNC0 cycle time (SI 0x0A: the ESC's 0x09A0 while
/// the device runs DC SYNC0, else 0, as SSC); in 0x1C33 also the inputs' sync mode (SI1,
/// [`input_sync_type`]) of the `active` sync mode.
///
/// The stack writes the records themselves ([`ObjectDictionary::communication`]): read-only is
/// the MainDevice's restriction, not the stack's; 0x1C33:01 gets a sync mode the device
/// supports, a code [`check_input_sync_write`] accepts.
pub(crate) fn fill<D: ObjectDictionary>(
    od: &mut D,
    device: &DeviceConfig,
    active: Option<SyncMode>,
    chosen_cycle: Option<u32>,
    dc: DcSettings,
    has_outputs: bool,
) {
    let cycle_ns = match (active, chosen_cycle) {
        (_, Some(_)) => None,
        (Some(SyncMode::FreeRun), None) => Some(nanoseconds(device.free_run_cycle.as_micros())),
        (Some(SyncMode::DcSync0), None) => Some(dc.sync0_cycle_ns),
        _ => None,
    };
    let min_ns = nanoseconds(device.min_cycle_time.as_micros());
    let sync0_ns = match active {
        Some(SyncMode::DcSync0) => dc.sync0_cycle_ns,
        _ => 0,
    };
    let Some(area) = od.communication() else {
        return;
    };
    for p in [&mut area.outputs, &mut area.inputs] {
        p.put::<{ SyncParameters::SYNC_TYPES_SUPPORTED }, 2>(D::SYNC_MODES.0.to_le_bytes());
        p.put::<{ SyncParameters::MIN_CYCLE_TIME }, 4>(min_ns.to_le_bytes());
        if let Some(ns) = cycle_ns {
            p.put::<{ SyncParameters::CYCLE_TIME }, 4>(ns.to_le_bytes());
        }
        p.put::<{ SyncParameters::SYNC0_CYCLE_TIME }, 4>(sync0_ns.to_le_bytes());
    }
    if let Some(output) = active {
        let code = input_sync_type(output, has_outputs).code();
        area.inputs
            .put::<{ SyncParameters::SYNC_TYPE }, 2>(code.to_le_bytes());
    }
}

/// A count of microseconds in nanoseconds, as the UNSIGNED32 of 0x1C32/0x1C33: saturated (at
/// 4 294 967 µs and above), in 32-bit arithmetic.
#[inline(never)]
fn nanoseconds(micros: u64) -> u32 {
    nanoseconds_of(saturated(micros))
}

/// [`nanoseconds`] of a count already in 32 bits (saturated: 4 294 967 µs and above).
fn nanoseconds_of(micros: u32) -> u32 {
    micros.saturating_mul(1_000)
}

/// A count of microseconds in 32 bits, saturated at `u32::MAX` (71 minutes): the spans the
/// cycle monitor compares, so that its arithmetic is 32-bit.
fn saturated(micros: u64) -> u32 {
    u32::try_from(micros).unwrap_or(u32::MAX)
}

/// What the MainDevice wrote into 0x1C32 over SDO since the SubDevice entered PREOP from INIT:
/// its choices, as against the declared defaults and the values the stack fills in (SI2 in
/// SM-synchronous mode shows the measured cycle, [`CycleMonitor`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Chosen {
    /// 0x1C32:01, the sync mode, was written.
    pub sync_type: bool,
    /// 0x1C32:02, the cycle time in ns, as last written (0 takes the choice back).
    pub cycle_time: Option<u32>,
}

impl Chosen {
    /// Notes a successful SDO write of `data` into `index:sub`.
    pub fn note(&mut self, index: u16, sub: u8, data: &[u8]) {
        match (index, sub, data) {
            (OUTPUT_PARAMETERS, 1, _) => self.sync_type = true,
            (OUTPUT_PARAMETERS, 2, &[a, b, c, d]) => {
                self.cycle_time = Some(u32::from_le_bytes([a, b, c, d]));
            }
            _ => {}
        }
    }

    /// The cycle time the MainDevice chose, if any.
    pub fn cycle_ns(self) -> Option<u32> {
        self.cycle_time.filter(|&ns| ns != 0)
    }

    /// The period of the local timer in free-run: the cycle time the MainDevice chose, else
    /// [`DeviceConfig::free_run_cycle`].
    pub(crate) fn free_run_cycle(self, device: &DeviceConfig) -> Duration {
        self.cycle_ns().map_or(device.free_run_cycle, |ns| {
            Duration::from_micros(u64::from(ns) / 1_000)
        })
    }
}

/// What the dictionary's 0x1C32 says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Requested {
    /// The synchronisation mode.
    pub(crate) mode: SyncMode,
    /// The MainDevice chose it: it wrote 0x1C32:01, or 0x1C32:01 differs from its declared
    /// default. Otherwise the SubDevice follows the ESC: DC SYNC0 when the MainDevice activated
    /// SYNC0 (as SSC does for MainDevices that configure DC but never write 0x1C32, e.g.
    /// ethercrab).
    pub(crate) chosen: bool,
}

impl Requested {
    /// The sync mode in effect with the DC unit as `dc` says.
    /// `modes`: the device's ([`ObjectDictionary::SYNC_MODES`]).
    pub(crate) fn effective(self, dc: DcSettings, modes: SupportedSyncModes) -> SyncMode {
        let follow_dc = !self.chosen && dc.activation.sync0() && modes.dc();
        if follow_dc {
            SyncMode::DcSync0
        } else {
            self.mode
        }
    }
}

/// The sync mode the dictionary's 0x1C32:01 asks for, checked against the device
/// (conformance.md "Sync parameters"): unsupported free-run is 0x0027, any other unsupported type
/// 0x0028. `chosen` tells whether the MainDevice wrote it. Without 0x1C32 the device runs
/// SM-synchronous when it supports it, else free-run.
pub(crate) fn requested<D: ObjectDictionary>(
    od: &mut D,
    chosen: Chosen,
) -> Result<Requested, AlStatusCode> {
    let Some(area) = od.communication() else {
        let sm = D::SYNC_MODES.supports(SyncMode::SmSynchronous);
        let mode = if sm {
            SyncMode::SmSynchronous
        } else {
            SyncMode::FreeRun
        };
        return Ok(Requested {
            mode,
            chosen: false,
        });
    };
    let code = u16::from_le_bytes(area.outputs.take::<{ SyncParameters::SYNC_TYPE }, 2>());
    // 0x1C32:01's declared default ([`output_limit`]).
    let default_kept = code == OUTPUT_SYNC_DEFAULT;
    match SyncMode::from_code(code) {
        mode if D::SYNC_MODES.supports(mode) => Ok(Requested {
            mode,
            chosen: chosen.sync_type || !default_kept,
        }),
        SyncMode::FreeRun => Err(AlStatusCode::FREE_RUN_NOT_SUPPORTED),
        _ => Err(AlStatusCode::SYNC_MODE_NOT_SUPPORTED),
    }
}

/// The cycle times checked at PREOP→SAFEOP against the sync mode in effect, after
/// [`check_dc`] (conformance.md AL status codes, "Distributed clocks"). In DC SYNC0 mode the
/// SYNC0 cycle (0x09A0) of 0 (single shot) or below the device's minimum cycle (SI5) is 0x0036,
/// a cycle time the MainDevice wrote into 0x1C32:02 other than the SYNC0 cycle 0x0035; in
/// free-run or SM-synchronous mode the written cycle time below the minimum cycle is 0x002E, in
/// free-run also below the local timer's 1 µs. One cycle, one floor and one code per mode: a
/// single comparison with the minimum. `cycle_ns` is never `Some(0)` ([`Chosen::cycle_ns`]), so
/// SM-synchronous mode's floor of 1 ns refuses nothing (a floor of 0 made the compiler copy the
/// comparison for that mode: +16 bytes).
pub(crate) fn check_cycle(
    sync: SyncMode,
    cycle_ns: Option<u32>,
    dc: DcSettings,
    device: &DeviceConfig,
) -> Result<(), AlStatusCode> {
    let (ns, floor, code) = match (sync, cycle_ns) {
        (SyncMode::DcSync0, _) => (dc.sync0_cycle_ns, 1, AlStatusCode::DC_SYNC0_CYCLE_TIME),
        (SyncMode::FreeRun, Some(ns)) => (ns, 1_000, AlStatusCode::CYCLE_TIME_TOO_SMALL),
        (SyncMode::SmSynchronous, Some(ns)) => (ns, 1, AlStatusCode::CYCLE_TIME_TOO_SMALL),
        _ => return Ok(()),
    };
    if ns < floor || below_min_cycle(ns, device) {
        return Err(code);
    }
    match cycle_ns {
        Some(chosen) if chosen != ns => Err(AlStatusCode::DC_INVALID_SYNC_CYCLE_TIME),
        _ => Ok(()),
    }
}

/// Watches the process-data cycles and keeps the diagnostic entries of 0x1C32/0x1C33 (ETG.1020
/// §6.3, conformance.md "Sync parameters") up to date:
/// - SI2 in SM-synchronous mode: the measured time between the last two cycles (in free-run and
///   DC mode SI2 is the configured cycle, see `fill`);
/// - SI 0x0B, SM-event missed: DC-mode cycles in OP for which the MainDevice had not written new
///   outputs (SM2) since the previous SYNC0;
/// - SI 0x0C, cycle time too small: clocked cycles (free-run, SYNC0) that started more than 1.5
///   cycles after the previous one, i.e. a cycle was lost because the last one took too long;
/// - SI 0x20, sync error: whether the last cycle missed its SM event or overran, or the sync
///   error supervision tripped in the current or last OP session ([`crate::sync_error`]).
///
/// The counters restart when the process data restarts ([`CycleMonitor::reset`] at SAFEOP).
///
/// It also runs the sync error supervision of 0x10F1 ([`crate::sync_error`]) over the cycles
/// that expect outputs (DC mode in OP): [`CycleMonitor::cycle`] says when it trips.
#[derive(Debug, Clone, Copy)]
pub struct CycleMonitor {
    /// The sync error counter of the current OP session.
    supervision: crate::sync_error::SyncSupervision,
    /// When the last cycle started, [`NO_CYCLE`] before the first (an `Option<Instant>` is 16
    /// bytes: the instant has no niche).
    last: Instant,
    missed: u16,
    overruns: u16,
}

/// [`CycleMonitor`]'s last cycle before the first: the end of time, later than any cycle's
/// start, so the time since it does not exist (`checked_sub`).
const NO_CYCLE: Instant = Instant::from_micros(u64::MAX);

impl Default for CycleMonitor {
    fn default() -> Self {
        Self {
            supervision: crate::sync_error::SyncSupervision::new(),
            last: NO_CYCLE,
            missed: 0,
            overruns: 0,
        }
    }
}

/// What one process-data cycle saw.
#[derive(Debug, Clone, Copy)]
pub struct CycleReport {
    /// When the cycle started.
    pub now: Instant,
    /// The nominal cycle of a clocked mode (free-run timer, SYNC0), `None` when event-driven.
    pub nominal: Option<Duration>,
    /// DC mode in OP: the cycle is expected to find new outputs.
    pub expects_outputs: bool,
    /// The MainDevice wrote new outputs (SM2 event) since the previous cycle.
    pub new_outputs: bool,
}

impl CycleMonitor {
    /// Forgets the past cycles and zeroes the counters.
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// Accounts for one cycle and stores the diagnostics into `od`'s 0x1C32/0x1C33. A dictionary
    /// without either keeps no diagnostics: known at compile time, so its firmware carries no
    /// monitor code. Returns `true` when the sync error supervision trips with this cycle: the
    /// SubDevice leaves OP with 0x001A. The supervision, too, runs only with 0x1C32/0x1C33
    /// (which ETG.1020 requires of a device with DC: the only mode it supervises).
    pub fn cycle<D: ObjectDictionary>(&mut self, od: &mut D, report: CycleReport) -> bool {
        if !const { has_sync_parameters(D::OBJECTS) } {
            return false;
        }
        let tripped = self.supervise(od, &report);
        let last = core::mem::replace(&mut self.last, report.now);
        // Before the first cycle `NO_CYCLE` is later than any start: no elapsed time (nor for a
        // clock stepping back, which measured 0 before; the runners' clocks are monotonic).
        // Spans in 32 bits (saturated at 71 minutes): one 64-bit subtraction per cycle.
        let elapsed = report
            .now
            .as_micros()
            .checked_sub(last.as_micros())
            .map(saturated);
        let missed = report.expects_outputs && !report.new_outputs;
        let overrun = match (elapsed, report.nominal) {
            (Some(elapsed), Some(cycle)) => overran(elapsed, saturated(cycle.as_micros())),
            _ => false,
        };
        self.missed = self.missed.saturating_add(u16::from(missed));
        self.overruns = self.overruns.saturating_add(u16::from(overrun));
        let measured_ns = elapsed
            .filter(|_| report.nominal.is_none())
            .map(nanoseconds_of);
        let counters = [self.missed, self.overruns];
        let error = missed || overrun || self.supervision.tripped();
        store(od, measured_ns, counters, error);
        tripped
    }

    /// The sync error supervision's share of a cycle: only cycles that expect outputs count
    /// (the limit is looked up only for them).
    fn supervise<D: ObjectDictionary>(&mut self, od: &D, report: &CycleReport) -> bool {
        let expect = report.expects_outputs;
        let limit = if expect {
            crate::sync_error::limit(od)
        } else {
            0
        };
        self.supervision.cycle(expect, !report.new_outputs, limit)
    }
}

/// Whether a clocked cycle started `elapsed` µs after the previous one is late by more than half
/// its nominal `cycle` (µs): `2 · elapsed > 3 · cycle`, as `elapsed > ⌊1.5 · cycle⌋` (no 64-bit
/// products), in 32 bits: both spans saturated at 71 minutes.
fn overran(elapsed: u32, cycle: u32) -> bool {
    elapsed > cycle.saturating_add(cycle / 2)
}

/// Whether `objects` has 0x1C32 or 0x1C33.
const fn has_sync_parameters<D>(objects: &[Object<D>]) -> bool {
    position(objects, OUTPUT_PARAMETERS).is_some() || position(objects, INPUT_PARAMETERS).is_some()
}

/// Stores the diagnostics into 0x1C32/0x1C33: a few stores into the records' bytes, every cycle
/// (cheaper in flash than remembering what was stored to skip them). Out of line: inlined
/// into the process-data task it is larger.
///
/// The arguments are separate (no struct of the four): they come in registers.
#[inline(never)]
fn store<D: ObjectDictionary>(
    od: &mut D,
    measured_ns: Option<u32>,
    counters: [u16; 2],
    error: bool,
) {
    let Some(area) = od.communication() else {
        return;
    };
    store_into(&mut area.outputs, measured_ns, counters, error);
    store_into(&mut area.inputs, measured_ns, counters, error);
}

/// [`store`] into one record: inlined twice, no loop over the two.
#[inline(always)]
fn store_into(p: &mut SyncParameters, measured_ns: Option<u32>, counters: [u16; 2], error: bool) {
    if let Some(ns) = measured_ns {
        p.put::<{ SyncParameters::CYCLE_TIME }, 4>(ns.to_le_bytes());
    }
    let [missed, overruns] = counters;
    p.put::<{ SyncParameters::SM_EVENT_MISSED }, 2>(missed.to_le_bytes());
    p.put::<{ SyncParameters::CYCLE_TIME_TOO_SMALL }, 2>(overruns.to_le_bytes());
    p.put::<{ SyncParameters::SYNC_ERROR }, 1>([u8::from(error)]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The comparison in whole microseconds is the comparison in nanoseconds.
    #[test]
    fn below_min_cycle_compares_as_nanoseconds() {
        use crate::device::{MailboxConfig, ProcessDataSizes};
        let mut device = DeviceConfig::new(
            MailboxConfig::contiguous(0x1000, 128),
            ProcessDataSizes::default(),
        );
        for min in [0, 1, 250, 1_000, 4_294_967, 4_294_968, u64::MAX] {
            device.min_cycle_time = Duration::from_micros(min);
            let at = min.saturating_mul(1_000).min(u64::from(u32::MAX));
            for ns in [0, 1, 999, 1_000, 249_999, 250_000, u32::MAX] {
                for ns in [ns, u32::try_from(at).unwrap_or(u32::MAX)] {
                    for ns in [ns.saturating_sub(1), ns, ns.saturating_add(1)] {
                        let expected = u64::from(ns) < min.saturating_mul(1_000);
                        assert_eq!(below_min_cycle(ns, &device), expected, "{ns} ns, {min} µs");
                    }
                }
            }
        }
    }

    /// The cycle checks give each mode's code at every edge, in ETG's order: in DC SYNC0 mode
    /// a SYNC0 cycle of 0 or below the minimum (0x0036) before a written cycle time other than
    /// it (0x0035); in free-run under 1 µs or below the minimum, in SM-synchronous mode below the
    /// minimum (0x002E); nothing written, nothing refused but the SYNC0 cycle.
    #[test]
    fn cycle_checks_give_each_modes_code_at_the_edges() {
        use crate::device::{MailboxConfig, ProcessDataSizes};
        let mut device = DeviceConfig::new(
            MailboxConfig::contiguous(0x1000, 128),
            ProcessDataSizes::default(),
        );
        let edges = [0, 1, 999, 1_000, 1_001, 249_999, 250_000, 250_001, u32::MAX];
        for min in [0, 1, 250, 4_294_967, 4_294_968] {
            device.min_cycle_time = Duration::from_micros(min);
            let below = |ns: u32| u64::from(ns) < min * 1_000;
            for sync0 in edges {
                let dc = DcSettings {
                    activation: DcActivation(0x03),
                    sync0_cycle_ns: sync0,
                };
                // A written cycle time is never 0 (`Chosen::cycle_ns`).
                let written = Some(sync0).filter(|&ns| ns != 0);
                for chosen in [
                    None,
                    Some(1),
                    Some(999),
                    Some(1_000),
                    Some(250_000),
                    written,
                ] {
                    let check = |sync| check_cycle(sync, chosen, dc, &device);
                    let dc_expected = if sync0 == 0 || below(sync0) {
                        Err(AlStatusCode::DC_SYNC0_CYCLE_TIME)
                    } else if chosen.is_some_and(|ns| ns != sync0) {
                        Err(AlStatusCode::DC_INVALID_SYNC_CYCLE_TIME)
                    } else {
                        Ok(())
                    };
                    let too_small = |refused: bool| match refused {
                        true => Err(AlStatusCode::CYCLE_TIME_TOO_SMALL),
                        false => Ok(()),
                    };
                    let free_run = chosen.is_some_and(|ns| ns < 1_000 || below(ns));
                    let sm = chosen.is_some_and(below);
                    let got = [
                        SyncMode::DcSync0,
                        SyncMode::FreeRun,
                        SyncMode::SmSynchronous,
                    ]
                    .map(check);
                    let expected = [dc_expected, too_small(free_run), too_small(sm)];
                    assert_eq!(got, expected, "min {min} µs, SYNC0 {sync0} ns, {chosen:?}");
                    for other in [SyncMode::DcSync1, SyncMode::Sm2Synchronous] {
                        assert_eq!(check(other), Ok(()), "{other:?}, {sync0} ns, {chosen:?}");
                    }
                }
            }
        }
    }

    /// A cycle overran exactly when it started more than 1.5 nominal cycles after the previous
    /// one (`2 · elapsed > 3 · cycle`), odd cycles included.
    #[test]
    fn a_cycle_overruns_past_one_and_a_half_cycles() {
        for cycle in 0..300u32 {
            for elapsed in 0..600u32 {
                assert_eq!(
                    overran(elapsed, cycle),
                    2 * elapsed > 3 * cycle,
                    "{elapsed} µs after a {cycle} µs cycle"
                );
            }
        }
        assert!(!overran(u32::MAX, u32::MAX));
        assert!(overran(u32::MAX, u32::MAX / 2));
    }

    /// Microseconds become the UNSIGNED32 nanoseconds of 0x1C32/0x1C33, saturated.
    #[test]
    fn nanoseconds_saturate_at_u32_max() {
        assert_eq!(nanoseconds(0), 0);
        assert_eq!(nanoseconds(1_000), 1_000_000);
        assert_eq!(nanoseconds(4_294_967), 4_294_967_000);
        assert_eq!(nanoseconds(4_294_968), u32::MAX);
        assert_eq!(nanoseconds(1 << 32), u32::MAX);
        assert_eq!(nanoseconds(u64::MAX), u32::MAX);
    }

    /// A free-run cycle the local timer cannot count (under 1 µs) is refused even on a device
    /// without a minimum cycle; a written 0 takes the choice back.
    #[test]
    fn free_run_cycles_under_a_microsecond_are_0x002e() {
        use crate::device::{MailboxConfig, ProcessDataSizes};
        let mut device = DeviceConfig::new(
            MailboxConfig::contiguous(0x1000, 128),
            ProcessDataSizes::default(),
        );
        device.min_cycle_time = Duration::from_micros(0);
        let check = |ns| check_cycle(SyncMode::FreeRun, Some(ns), DcSettings::default(), &device);
        assert_eq!(check(999), Err(AlStatusCode::CYCLE_TIME_TOO_SMALL));
        assert_eq!(check(1_000), Ok(()));
        let mut chosen = Chosen::default();
        chosen.note(OUTPUT_PARAMETERS, 2, &500u32.to_le_bytes());
        assert_eq!(chosen.cycle_ns(), Some(500));
        chosen.note(OUTPUT_PARAMETERS, 2, &0u32.to_le_bytes());
        assert_eq!((chosen.sync_type, chosen.cycle_ns()), (false, None));
    }

    struct Od {
        area: crate::dictionary::Communication,
    }

    const INFO: crate::dictionary::DeviceInfo = crate::dictionary::DeviceInfo {
        device_type: 0,
        name: "sync test",
        hardware_version: "1",
        software_version: "1",
        identity: crate::device::Identity {
            vendor_id: 1,
            product_code: 1,
            revision: 1,
            serial: 1,
        },
    };

    crate::dictionary! {
        // A test of 0x1C32/0x1C33 alone: no PDOs.
        minimal Od {
            communication(area, INFO);
        }
    }

    /// SI 0x0A shows the SYNC0 cycle while the device runs DC SYNC0, 0 in any other mode (SSC's
    /// `u32Sync0CycleTime`); SI2 follows the SYNC0 cycle unless the MainDevice wrote one.
    #[test]
    fn fill_shows_the_sync0_cycle_in_dc_mode_only() {
        use crate::device::{MailboxConfig, ProcessDataSizes};
        let device = DeviceConfig::new(
            MailboxConfig::contiguous(0x1000, 128),
            ProcessDataSizes::default(),
        );
        let dc = DcSettings {
            activation: DcActivation(0x03),
            sync0_cycle_ns: 1_000_000,
        };
        let mut od = Od::default();
        fill(&mut od, &device, Some(SyncMode::DcSync0), None, dc, true);
        for p in [od.area.outputs, od.area.inputs] {
            let cycles = (
                p.get(SyncParameters::SYNC0_CYCLE_TIME),
                p.get(SyncParameters::CYCLE_TIME),
            );
            assert_eq!(cycles, (1_000_000, 1_000_000));
        }
        assert_eq!(
            od.area.inputs.get(SyncParameters::SYNC_TYPE),
            2,
            "the inputs follow the outputs"
        );
        fill(
            &mut od,
            &device,
            Some(SyncMode::SmSynchronous),
            None,
            dc,
            true,
        );
        for p in [od.area.outputs, od.area.inputs] {
            assert_eq!(p.get(SyncParameters::SYNC0_CYCLE_TIME), 0);
        }
        assert_eq!(od.area.inputs.get(SyncParameters::SYNC_TYPE), 0x22);
        fill(
            &mut od,
            &device,
            Some(SyncMode::DcSync0),
            Some(500_000),
            dc,
            true,
        );
        assert_eq!(
            od.area.outputs.get(SyncParameters::SYNC0_CYCLE_TIME),
            1_000_000,
            "not the written cycle"
        );
    }

    /// Each entry reads as its little-endian bytes, SI0 as 0x20 whatever is set; a write
    /// patches only its entry.
    #[test]
    fn the_record_holds_each_entry_as_its_bytes() {
        let mut p = SyncParameters::OUTPUTS;
        p.set(0, 7);
        p.set(SyncParameters::SHIFT_TIME, 0x0403_0201);
        p.set(SyncParameters::SYNC_ERROR, 1);
        let mut out = [0xFF; 4];
        let read = p
            .read(At::new(0, 0), &mut out)
            .map(|r| (r.copied(), r.size()));
        assert_eq!((read, out[0]), (Ok((1, 1)), 0x20));
        let read = p
            .read(At::new(3, 0), &mut out)
            .map(|r| (r.copied(), r.size()));
        assert_eq!((read, out), (Ok((4, 4)), [1, 2, 3, 4]));
        let read = p.read(At::new(3, 2), &mut out).map(|r| r.copied());
        assert_eq!((read, &out[..2]), (Ok(2), &[3, 4][..]));
        assert_eq!(p.write(2, &[5, 6, 7, 8]), Ok(()));
        assert_eq!(p.write(2, &[5, 6, 7]), Err(AbortCode::LENGTH_TOO_LOW));
        assert_eq!(p.write(8, &[5, 6, 7]), Err(AbortCode::LENGTH_TOO_HIGH));
        assert_eq!(p.write(3, &[0; 4]), Err(AbortCode::READ_ONLY));
        assert_eq!(p.write(0x0E, &[0; 4]), Err(AbortCode::NO_SUBINDEX));
        let values = [0, 1, 2, 3, 0x0B, 0x20].map(|sub| p.get(sub));
        assert_eq!(values, [0x20, 1, 0x0807_0605, 0x0403_0201, 0, 1]);
        assert_eq!(
            p.read(At::new(0x21, 0), &mut out),
            Err(AbortCode::NO_SUBINDEX)
        );
        // SI 0x20 is a BOOLEAN: any value but 0 is stored as 1.
        p.set(SyncParameters::SYNC_ERROR, 2);
        assert_eq!(p.get(SyncParameters::SYNC_ERROR), 1);
        p.set(SyncParameters::SYNC_ERROR, 0);
        assert_eq!(p.get(SyncParameters::SYNC_ERROR), 0);
    }

    #[test]
    fn inputs_follow_the_outputs_sync_type() {
        use SyncMode::*;
        assert_eq!(input_sync_type(SmSynchronous, true), Sm2Synchronous);
        assert_eq!(input_sync_type(SmSynchronous, false), SmSynchronous);
        assert_eq!(input_sync_type(FreeRun, true), FreeRun);
        assert_eq!(input_sync_type(DcSync0, false), DcSync0);
    }

    #[test]
    fn dc_settings_come_from_0x0981_and_0x09a0() {
        let mut bytes = [0u8; DcSettings::READ_LEN];
        bytes[0] = 0x03;
        bytes[0x09A0 - 0x0981..].copy_from_slice(&500_000u32.to_le_bytes());
        let dc = DcSettings::from_bytes(&bytes);
        assert_eq!(dc.activation, DcActivation(0x03));
        assert_eq!(dc.sync0_cycle_ns, 500_000);
        assert_eq!(
            DcSettings::from_bytes(&[]),
            DcSettings::default(),
            "short read"
        );
    }
}
