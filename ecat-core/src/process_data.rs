//! Where the process-data image lives while the SubDevice is in SAFEOP or OP, and which AL event
//! triggers its exchange in SyncManager-synchronous mode.

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
    /// Whether outputs may be applied (OP). In SAFEOP the outputs are read, to keep the buffer
    /// moving, but never handed to the application.
    pub outputs_active: bool,
}
