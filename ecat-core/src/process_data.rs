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
    FreeRun(Duration),
    /// DC SYNC0: the SYNC0 signal, with this period.
    Sync0(Duration),
}

/// The process-data areas as the MainDevice configured SM2 and SM3, valid in SAFEOP and OP.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
// `repr(C)`: the flag and the areas first, the clock (8-aligned) last.
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
            Clock::FreeRun(period) | Clock::Sync0(period) => Some(period),
        }
    }

    /// Whether SYNC0 starts the cycles.
    pub fn sync0(&self) -> bool {
        matches!(self.clock, Clock::Sync0(_))
    }
}
