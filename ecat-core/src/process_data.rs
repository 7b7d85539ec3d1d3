//! Where the process-data image lives while the SubDevice is in SAFEOP or OP, and what triggers
//! its exchange: an AL event in SyncManager-synchronous mode, a local timer in free-run, the
//! SYNC0 signal in DC mode.

use crate::AlEvent;
use crate::device::Area;
use crate::time::Duration;

/// The process-data areas as the MainDevice configured SM2 and SM3, valid in SAFEOP and OP.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// The output buffer (SM2), `None` for an input-only device.
    pub outputs: Option<Area>,
    /// The input buffer (SM3), `None` for an output-only device.
    pub inputs: Option<Area>,
    /// The AL event that starts a cycle: SM2 written by the MainDevice, or for an input-only device
    /// SM3 read by it.
    pub trigger: AlEvent,
    /// Free-run: a cycle every this long on a local timer, and no trigger event.
    pub free_run: Option<Duration>,
    /// DC SYNC0 mode: a cycle on every SYNC0 pulse, and no trigger event.
    pub sync0: bool,
    /// The nominal cycle of a clocked mode: the free-run cycle or the SYNC0 cycle.
    pub cycle: Option<Duration>,
    /// Whether outputs may be applied (OP). In SAFEOP the outputs are read, to keep the buffer
    /// moving, but never handed to the application.
    pub outputs_active: bool,
}

impl Layout {
    /// Whether cycles come from a clock (the local timer or SYNC0) rather than an AL event.
    pub fn clocked(&self) -> bool {
        self.free_run.is_some() || self.sync0
    }
}
