//! The diagnosis history (0x10F3, [`crate::diagnosis`]): the AL status codes the stack sets,
//! logged as messages, and the application's own messages; an emergency per new message when
//! 0x10F3:05 bit 0 asks for it.

use super::{Logged, SubDevice};
use crate::coe::Emergency;
use crate::diagnosis::Message;
use crate::dictionary::ObjectDictionary;
use crate::mailbox::MailboxError;
use crate::time::{Duration, Instant};

/// The shortest time between two emergencies for the same AL status code: a MainDevice that
/// repeats a refused request every cycle gets one a second.
pub const EMERGENCY_PERIOD: Duration = Duration::from_millis(1000);

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// Adds `message` to the dictionary's diagnosis history, if it has one; when it is stored
    /// and 0x10F3:05 bit 0 is set, raises its emergency ([`Message::emergency`]). Returns
    /// whether it was stored.
    pub fn diagnose<D: ObjectDictionary>(&mut self, od: &mut D, message: Message) -> bool {
        let register = self.error_register();
        let Some(logged) = od.diagnosis().and_then(|mut h| h.log(message, register)) else {
            return false;
        };
        if let Some(emergency) = logged {
            self.emergency(emergency);
        }
        true
    }

    /// [`SubDevice::diagnose`] with the message made only when the dictionary has a history:
    /// without one (`ObjectDictionary::diagnosis` is `None` at compile time) the stack's own
    /// messages cost no code.
    fn diagnose_with<D: ObjectDictionary>(
        &mut self,
        od: &mut D,
        message: impl FnOnce() -> Message,
    ) -> bool {
        od.diagnosis().is_some() && self.diagnose(od, message())
    }

    /// The error register (0x1001) as the emergencies carry it
    /// ([`Emergency::error_register`]).
    pub fn error_register(&self) -> u8 {
        Emergency::error_register(self.al_status(), self.code)
    }

    /// Logs a request the mailbox answered with an error reply (a warning; no emergency of its
    /// own unless 0x10F3:05 asks for one per message).
    #[cold]
    #[inline(never)] // rare: off the mailbox service's path
    pub(super) fn log_refused<D: ObjectDictionary>(
        &mut self,
        now: Instant,
        od: &mut D,
        error: MailboxError,
    ) {
        self.diagnose_with(od, || Message::mailbox_error(error.0, now));
    }

    /// Logs the AL status codes set since the last call, stamped `now` (the stack sets them
    /// where it has neither the dictionary nor the time: they wait, at most
    /// [`LOGGED`](super::LOGGED), for the next mailbox service): each raises its emergency
    /// ([`Emergency::for_al_status_code`]) unless the same code raised one less than
    /// [`EMERGENCY_PERIOD`] before, then goes into the diagnosis history.
    #[inline(never)] // rare: off the mailbox service's path
    pub(super) fn log_diagnosis<D: ObjectDictionary>(&mut self, now: Instant, od: &mut D) {
        while let Some(Logged { code, state }) = self.logged.pop().flatten() {
            let (last, at) = (self.last_emergency, self.last_emergency_at);
            if last != code || now >= at.saturating_add(EMERGENCY_PERIOD) {
                (self.last_emergency, self.last_emergency_at) = (code, now);
                self.emergency(Emergency::for_al_status_code(code, state));
            }
            self.diagnose_with(od, || Message::al_status_code(code.0, now));
        }
    }
}
