//! Where the process-data image lives while the SubDevice is in SAFEOP or OP, and what triggers
//! its exchange: an AL event in SyncManager-synchronous mode, a local timer in free-run, the
//! SYNC0 signal in DC mode.

use crate::AlEvent;
use crate::device::Area;
use crate::time::Duration;

/// What starts a process-data cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// SM-synchronous: an AL event — SM2 written by the MainDevice, or for an input-only device
    /// SM3 read by it (`AlEvent::NONE` without process data).
    Event(AlEvent),
    /// Free-run: a local timer with this period.
    FreeRun(Period),
    /// DC SYNC0: the SYNC0 signal, with this period.
    Sync0(Period),
}

/// The period of a clocked mode, in microseconds, in 32 bits: the cycle times it comes from
/// (0x1C32:02, SYNC0's cycle time 0x09A0) are 32-bit nanoseconds, at most 4.3 s. A
/// [`Duration`] (64 bits, 8-aligned) would make [`Setup`], which both runners keep a copy of,
/// 32 bytes instead of 24.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Period(u32);

impl Period {
    /// The period `duration`, saturating at `u32::MAX` microseconds (71 minutes).
    pub fn new(duration: Duration) -> Self {
        Self(u32::try_from(duration.as_micros()).unwrap_or(u32::MAX))
    }

    /// The period as a [`Duration`].
    pub fn duration(self) -> Duration {
        Duration::from_micros(u64::from(self.0))
    }
}

/// The process-data areas as the MainDevice configured SM2 and SM3, valid in SAFEOP and OP.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
// `repr(C)`: the flag and the areas first, the clock (4-aligned) last.
#[repr(C)]
pub struct Setup {
    /// Whether outputs may be applied (OP). In SAFEOP the outputs are read, to keep the buffer
    /// moving, but never handed to the application.
    pub outputs_active: bool,
    /// The output buffer (SM2), `None` for an input-only device.
    pub outputs: Option<Area>,
    /// The input buffer (SM3), `None` for an output-only device.
    pub inputs: Option<Area>,
    /// What starts a cycle.
    pub clock: Clock,
}

impl Setup {
    /// The AL event that starts a cycle; none in the clocked modes.
    pub fn trigger(&self) -> AlEvent {
        match self.clock {
            Clock::Event(event) => event,
            Clock::FreeRun(_) | Clock::Sync0(_) => AlEvent::NONE,
        }
    }

    /// The period of a clocked mode (free-run or SYNC0), `None` when cycles follow an AL event.
    pub fn period(&self) -> Option<Duration> {
        match self.clock {
            Clock::Event(_) => None,
            Clock::FreeRun(period) | Clock::Sync0(period) => Some(period.duration()),
        }
    }

    /// Whether SYNC0 starts the cycles.
    pub fn sync0(&self) -> bool {
        matches!(self.clock, Clock::Sync0(_))
    }
}
