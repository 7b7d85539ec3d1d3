//! AL events in: what each event bit makes due.

use super::plan::{InFlight, read};
use super::targets::Stale;
use super::{Due, ESM_EVENTS, MAILBOX_EVENTS, SubDevice};
use crate::al::{AlEvent, AlState};

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// Takes the AL event register value the driver saw (with the bits its own access cleared
    /// removed, see [`RegisterAccess::clears`](super::RegisterAccess::clears)). Bits the state machine does
    /// not handle are ignored.
    #[inline]
    pub fn handle_al_event(&mut self, event: AlEvent) {
        // Inline: most accesses bring no news.
        if !event.is_empty() {
            self.handle_news(event);
        }
    }

    /// [`SubDevice::handle_al_event`] with at least one bit set.
    fn handle_news(&mut self, event: AlEvent) {
        if event.intersects(ESM_EVENTS | AlEvent::WATCHDOG_PROCESS_DATA) {
            self.handle_register_events(event);
        }
        if self.state.has_mailbox() && event.intersects(MAILBOX_EVENTS) {
            self.handle_mailbox_events(event);
        }
    }

    /// The events that ask for register reads: AL control, SM change, the watchdog. Out of
    /// line, away from the mailbox's events.
    #[inline(never)]
    fn handle_register_events(&mut self, event: AlEvent) {
        self.stale.insert(Stale::READS);
        // The SyncManagers are read once per AL control event, before AL control: a stale
        // AL control bit seen while that read is still scheduled must not schedule it again.
        let al_control = event.contains(AlEvent::AL_CONTROL) && !self.read_due(read::AL_CONTROL);
        if al_control {
            self.reads |= read::AL_CONTROL | read::WATCHDOG | read::DC;
        }
        if event.contains(AlEvent::SM_CHANGE) {
            self.due.set(Due::SM_CHECK);
        }
        if al_control || event.contains(AlEvent::SM_CHANGE) {
            self.sm_unread = self.sm_bytes();
            if let Some(InFlight::ReadSyncManagers { overtaken, .. }) = &mut self.in_flight {
                *overtaken = true;
            }
        }
        if event.contains(AlEvent::WATCHDOG_PROCESS_DATA) && self.state == AlState::Op {
            self.reads |= read::WATCHDOG_STATUS;
        }
    }
}
