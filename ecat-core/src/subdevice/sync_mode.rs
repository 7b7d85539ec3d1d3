//! The synchronisation mode in effect (free-run, SM-synchronous, DC SYNC0), its checks at
//! PREOP→SAFEOP, and what the process-data side reports about SYNC0 and sync errors.

use super::SubDevice;
use crate::al::{AlState, AlStatusCode};
use crate::device::ProcessDataSizes;
use crate::sync_mode::{SupportedSyncModes, SyncMode};
use crate::sync_parameters::{self, DcSettings};

/// What [`SubDevice::sync_mode`] says when the dictionary's sync mode cannot be: an unknown type,
/// which no device supports (so `sync_parameters::requested` never yields it) and no mode of the
/// stack matches.
const UNUSABLE_SYNC_MODE: SyncMode = SyncMode::Unknown(u16::MAX);

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// The sync mode in effect: what 0x1C32:01 asks for, or DC SYNC0 when the MainDevice did not
    /// choose and activated SYNC0 ([`sync_parameters::Requested::effective`]);
    /// [`UNUSABLE_SYNC_MODE`] when the dictionary's cannot be.
    pub(super) fn sync_mode(&self) -> SyncMode {
        match self.sync_mode {
            Ok(requested) => requested.effective(self.dc, self.sync_modes()),
            Err(_) => UNUSABLE_SYNC_MODE,
        }
    }

    /// The sync modes the device supports (the dictionary's).
    fn sync_modes(&self) -> SupportedSyncModes {
        SupportedSyncModes(u16::from(self.sync_modes))
    }

    /// The DC registers read with an AL control event: the activation byte, and up to the SYNC0
    /// cycle time for a device that supports DC SYNC0.
    pub(super) fn dc_read_len(&self) -> usize {
        if self.sync_modes().dc() {
            DcSettings::READ_LEN
        } else {
            1
        }
    }

    /// The process-data side saw SYNC0 stop (DC mode): in OP the SubDevice falls back to SAFEOP
    /// with [`AlStatusCode::FATAL_SYNC_ERROR`] (conformance.md "Distributed clocks").
    pub fn sync0_lost(&mut self) {
        if self.state == AlState::Op && matches!(self.sync_mode(), SyncMode::DcSync0) {
            self.fail(AlStatusCode::FATAL_SYNC_ERROR, AlState::SafeOp);
        }
    }

    /// The process-data side's sync error supervision tripped (too many missed SM/SYNC events,
    /// [`crate::sync_error`]): in OP the SubDevice falls back to SAFEOP with
    /// [`AlStatusCode::SYNC_ERROR`] (ETG.1020 §6.3).
    pub fn sync_error(&mut self) {
        if self.state == AlState::Op {
            self.fail(AlStatusCode::SYNC_ERROR, AlState::SafeOp);
        }
    }

    /// The process-data side ran a SYNC0-triggered cycle (DC mode) since SAFEOP was entered: a
    /// SAFEOP→OP in DC mode may complete (with its outputs, if the device has any).
    pub fn sync0_received(&mut self) {
        self.received.sync0 = true;
        if let Some(p) = &mut self.pending {
            p.awaits.sync0 = false;
        }
        self.complete_when_fed();
    }

    /// The sync mode must be supported; free-run needs SM2 in 3-buffer mode (0x0029); a
    /// DC-capable device checks the DC SYNC unit ([`sync_parameters::check_dc`]); the SYNC0 cycle
    /// and a cycle time the MainDevice wrote must suit the sync mode
    /// ([`sync_parameters::check_cycle`]).
    pub(super) fn check_sync_mode(&self, sizes: ProcessDataSizes) -> Result<(), AlStatusCode> {
        self.sync_mode?;
        let sync = self.sync_mode();
        if self.sync_modes().dc() {
            sync_parameters::check_dc(sync, self.dc, self.sync_modes())?;
        } else if self.dc.activation.0 != 0 {
            // DC activated on a device without DC (conformance.md "Distributed clocks").
            return Err(AlStatusCode::INVALID_DC_SYNC_CONFIG);
        }
        sync_parameters::check_cycle(sync, self.writes.chosen.cycle_ns(), self.dc, self.config)?;
        let one_buffer =
            self.channels.outputs().control.mode() == crate::sync_manager::Mode::Mailbox;
        if matches!(sync, SyncMode::FreeRun) && sizes.outputs > 0 && one_buffer {
            return Err(AlStatusCode::FREE_RUN_NEEDS_3_BUFFER);
        }
        Ok(())
    }
}
