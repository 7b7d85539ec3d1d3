//! The process-data side: where the image lives, its sizes from the PDO configuration, and
//! the outputs that let SAFEOP→OP complete.

use super::{CycleSigns, Due, SubDevice};
use crate::al::{AlEvent, AlState, AlStatusCode};
use crate::device::{Area, ProcessDataSizes};
use crate::dictionary::ObjectDictionary;
use crate::pdo::Direction;
use crate::pdo::layout::Layout;
use crate::process_data::{Clock, Period, Setup};
use crate::sync_manager::Channel;
use crate::sync_mode::SyncMode;
use crate::sync_parameters;

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// Where the process data lives, in SAFEOP and OP.
    #[inline(never)] // one caller, the driver's loop: out of its state machine
    pub fn process_data(&self) -> Option<Setup> {
        if !self.state.has_process_data() {
            return None;
        }
        let (sizes, sync) = (self.pd_sizes, self.sync_mode());
        let area =
            |channel: &Channel, size: u16| (size > 0).then_some(Area::new(channel.start, size));
        Some(Setup {
            outputs: area(self.channels.outputs(), sizes.outputs),
            inputs: area(self.channels.inputs(), sizes.inputs),
            clock: match sync {
                SyncMode::FreeRun => {
                    Clock::FreeRun(Period::new(self.writes.chosen.free_run_cycle(self.config)))
                }
                SyncMode::DcSync0 => Clock::Sync0(Period::new(self.dc.sync0_cycle())),
                _ => Clock::Event(self.sm_trigger()),
            },
            outputs_active: self.state == AlState::Op,
        })
    }

    /// [`SubDevice::process_data`] at the first call and when it may have changed since the
    /// last (a new state, PDO configuration, sync choice, DC setting or SM2/SM3 address), `None`
    /// when it has not: for a driver that hands the setup to its process-data side only when it
    /// is new, without comparing setups. It may also answer an unchanged setup (a refresh in
    /// SAFEOP/OP that changed nothing).
    pub fn process_data_news(&mut self) -> Option<Option<Setup>> {
        self.due.take(Due::LAYOUT).then(|| self.process_data())
    }

    /// The AL event that triggers a process-data cycle in SyncManager-synchronous mode.
    pub(super) fn process_data_trigger(&self) -> AlEvent {
        if matches!(self.sync_mode(), SyncMode::FreeRun | SyncMode::DcSync0) {
            AlEvent::NONE
        } else {
            self.sm_trigger()
        }
    }

    /// The AL event that triggers a cycle in SyncManager-synchronous mode: SM2's with outputs,
    /// else SM3's with inputs.
    fn sm_trigger(&self) -> AlEvent {
        let sizes = self.pd_sizes;
        if sizes.outputs > 0 {
            AlEvent::sync_manager(2)
        } else if sizes.inputs > 0 {
            AlEvent::sync_manager(3)
        } else {
            AlEvent::NONE
        }
    }

    /// The process-data side received valid outputs (the MainDevice wrote SM2) since SAFEOP was
    /// entered: a SAFEOP→OP transition the application accepted may complete.
    pub fn outputs_received(&mut self) {
        self.received.outputs = true;
        if let Some(p) = &mut self.pending {
            p.awaits.outputs = false;
        }
        self.complete_when_fed();
    }

    /// Completes a SAFEOP→OP the application accepted once the process data it waits for came.
    pub(super) fn complete_when_fed(&mut self) {
        let Some(p) = self.pending else { return };
        if p.accepted && p.awaits == CycleSigns::default() {
            // The transition's end marks the plan stale (`change_state` or `fail`).
            self.finish_transition(p.transition);
        }
    }

    /// Recomputes the process-image sizes from the PDO assignment and mapping objects of `od`
    /// when they may have changed (after an SDO write to the PDO configuration or 0x1C32/0x1C33,
    /// on entering PREOP, on a new DC setting). Call it before the
    /// SubDevice handles AL events; without assignment objects (0x1C12/0x1C13) the device
    /// configuration's fixed sizes apply. An unusable mapping answers PREOP→SAFEOP with 0x0025
    /// (outputs) or 0x0024 (inputs).
    ///
    /// It also takes the sync mode the MainDevice chose (0x1C32:01, see [`crate::sync_parameters`])
    /// and fills what the stack knows into 0x1C32 and 0x1C33 (`sync_parameters::fill`): the
    /// supported types (SI4), the minimum cycle (SI5), the cycle time (SI2, free-run and DC) and
    /// 0x1C33's sync type (SI1).
    #[inline]
    pub fn refresh_process_data<D: ObjectDictionary>(&mut self, od: &mut D) {
        // Inline: it is called after every AL event and rarely has anything to do.
        if self.due.take(Due::REFRESH) {
            self.refresh(od);
        }
    }

    /// [`SubDevice::refresh_process_data`] when the configuration may have changed.
    fn refresh<D: ObjectDictionary>(&mut self, od: &mut D) {
        self.targets_changed();
        self.due.set(Due::LAYOUT);
        self.sync_mode = sync_parameters::requested(od, self.writes.chosen);
        let fixed = self.config.process_data;
        // One call of `Layout::of`, for both directions in turn: the first refusal (the outputs'
        // before the inputs') leaves no image.
        let mut sizes = [fixed.outputs, fixed.inputs];
        let mut unusable = AlStatusCode::NO_ERROR;
        for (size, direction) in sizes.iter_mut().zip([Direction::Rx, Direction::Tx]) {
            match Layout::of(od, direction) {
                Ok(layout) => *size = layout.map_or(*size, |l| l.bytes()),
                Err(code) => {
                    (sizes, unusable) = ([0; 2], code);
                    break;
                }
            }
        }
        let [outputs, inputs] = sizes;
        (self.pd_sizes, self.pd_unusable) = (ProcessDataSizes { outputs, inputs }, unusable);
        let has_outputs = self.pd_sizes.outputs > 0;
        let active = self.sync_mode.is_ok().then(|| self.sync_mode());
        let chosen_cycle = self.writes.chosen.cycle_ns();
        sync_parameters::fill(od, self.config, active, chosen_cycle, self.dc, has_outputs);
    }
}
