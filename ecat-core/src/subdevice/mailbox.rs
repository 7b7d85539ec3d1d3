//! The mailbox glue: SM0/SM1 events and accesses, serving requests, emergencies.

use super::plan::InFlight;
use super::targets::Stale;
use super::{Due, MAILBOX_EVENTS, RegisterAccess, SubDevice};
use crate::al::{AlEvent, AlState};
use crate::coe::Emergency;
use crate::coe::sdo::Context;
use crate::dictionary::{ObjectDictionary, ObjectHooks};
use crate::mailbox::Handlers;
use crate::time::Instant;

/// The SM0/SM1 accesses of the mailbox.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum MailboxOp {
    /// Read SM0 whole (the request).
    Read,
    /// Write the message into SM1, and SM1's last byte after a shorter one
    /// ([`RegisterAccess::Send`]).
    Write,
}

impl MailboxOp {
    /// The AL event bit the access clears in the ESC: reading SM0's buffer bit 8, writing
    /// SM1's buffer bit 9.
    pub(super) const fn clears(self) -> AlEvent {
        match self {
            MailboxOp::Read => AlEvent::sync_manager(0),
            MailboxOp::Write => AlEvent::sync_manager(1),
        }
    }
}

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// SM0 written or SM1 read by the MainDevice, in a state with a mailbox.
    pub(super) fn handle_mailbox_events(&mut self, event: AlEvent) {
        if event.contains(AlEvent::sync_manager(0)) {
            self.mailbox.receive_event();
        }
        if event.contains(AlEvent::sync_manager(1)) {
            self.mailbox.send_event();
        }
        if !self.mailbox_mask_holds() {
            self.stale.insert(Stale::MAILBOX_QUEUE);
        } else if event.contains(AlEvent::sync_manager(0)) {
            // The request can be read (the mask holds because it can).
            self.mailbox_due(MailboxOp::Read);
        } else {
            self.stale.insert(Stale::MAILBOX);
        }
    }

    /// The mailbox access `op` is due: it is the next access when nothing else is (no access in
    /// flight, no part of the plan stale: the SyncManagers are active then), else the plan
    /// finds it.
    fn mailbox_due(&mut self, op: MailboxOp) {
        if self.in_flight.is_none() && self.stale == Stale::NONE {
            self.in_flight = Some(InFlight::Mailbox(op));
        } else {
            self.stale.insert(Stale::MAILBOX);
        }
    }

    /// Whether the AL event mask as written already carries what the mailbox wants after an
    /// SM0/SM1 event, without looking at the plan: in the request/answer rhythm SM1 is free and
    /// the request can be read, so the mailbox wants the SM0 event and not the SM1 event — what
    /// the mask had while it waited for the request.
    fn mailbox_mask_holds(&self) -> bool {
        let written = self.written.event_mask & MAILBOX_EVENTS.bits();
        written == AlEvent::sync_manager(0).bits() && self.mailbox.can_receive()
    }

    /// The SM0/SM1 access due, once SM0 and SM1 are active in a mailbox state: the next message
    /// (or the last again), the next request.
    pub(super) fn next_mailbox_op(&self) -> Option<MailboxOp> {
        if !self.state.has_mailbox() || !self.written.mailbox_active() {
            None
        } else if self.mailbox.write_due() {
            Some(MailboxOp::Write)
        } else if self.mailbox.read_due() {
            Some(MailboxOp::Read)
        } else {
            None
        }
    }

    /// The SM0 read or SM1 write of `op`.
    #[inline]
    pub(super) fn prepare_mailbox(&mut self, op: MailboxOp) -> RegisterAccess<'_> {
        let clears = op.clears();
        match op {
            MailboxOp::Read => {
                let (address, buf) = self.mailbox.rx_buffer();
                RegisterAccess::Read {
                    address,
                    buf,
                    clears,
                }
            }
            MailboxOp::Write => {
                let (address, data, last) = self.mailbox.message();
                RegisterAccess::Send {
                    address,
                    data,
                    last,
                    clears,
                }
            }
        }
    }

    /// The message is complete in SM1: the mailbox waits for the MainDevice to read it, and SM1's
    /// repeat acknowledge follows the request. Until the SM1 event (or a repeat request, read
    /// with an SM-change event) no SM0/SM1 access is due. SM0 stays blocked, by the message
    /// before and by SM1 now; the SM1 event, unwanted while the message was written (unless it
    /// was a repeat), joins the mask when something waits behind the message. PDI control
    /// changes when the acknowledge does.
    pub(super) fn sent(&mut self) {
        let ack = self.mailbox.repeat_ack();
        let repeat = self.mailbox.repeat_pending();
        self.mailbox.written();
        if repeat || self.mailbox.wants_send_event(|| self.coe.has_message()) {
            self.stale.insert(Stale::EVENT_MASK);
        }
        if self.mailbox.repeat_ack() != ack {
            self.stale.insert(Stale::PDI_CONTROL);
        }
    }

    /// Serves the mailbox: the request read from SM0, or the next SDO Information fragment or
    /// emergency. Call it after the accesses are done, and until it returns `false`, with the
    /// accesses it makes due after each `true` (an SM1 write, or after a request dropped without
    /// an answer, the event mask that re-arms SM0). Bounded: at most one message per call.
    #[inline]
    pub fn service_mailbox<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        now: Instant,
        od: &mut D,
        hooks: &mut H,
    ) -> bool {
        self.service_mailbox_with(now, od, hooks, &mut ())
    }

    /// [`SubDevice::service_mailbox`] with mailbox protocols beside CoE: `handlers` is a tuple
    /// of [`crate::mailbox::Handler`]s (e.g. `(foe,)` with a [`crate::foe::Foe`]). Pass the same
    /// handlers on every call: the mailbox keeps no reference to them between calls.
    #[inline]
    pub fn service_mailbox_with<D: ObjectDictionary, H: ObjectHooks<D>, P: Handlers>(
        &mut self,
        now: Instant,
        od: &mut D,
        hooks: &mut H,
        handlers: &mut P,
    ) -> bool {
        if !self.logged.is_empty() {
            self.log_diagnosis(now, od);
        }
        // Nothing due, nothing changed. Nothing is served either while an access is in flight:
        // an SM0 read the request's event made due (`mailbox_due`) goes first, so that the
        // request's answer finds SM1 free.
        if !self.state.has_mailbox()
            || self.in_flight.is_some()
            || !self.mailbox.has_work(|| self.coe.has_message())
        {
            return false;
        }
        let request = self.mailbox.request_pending();
        let mut cx = Context {
            od,
            hooks,
            state: self.state,
            now,
            writes: &mut self.writes,
            device: Some(self.config),
        };
        let built = self
            .mailbox
            .serve(self.coe.handler(&mut cx), handlers, self.state, now);
        // A write to 0x1C32 changes the sync choices at once, the rest with the refresh.
        let configured = u8::from(core::mem::take(&mut self.writes.configured));
        self.due.set(configured * (Due::REFRESH | Due::LAYOUT));
        // Only a dictionary with a diagnosis history logs it (none: known at compile time).
        if od.diagnosis().is_some()
            && let Some(error) = self.mailbox.take_refused()
        {
            self.log_refused(now, od, error);
        }
        // An answer to a request takes the request's place: SM0 stays blocked and SM1 free, so
        // the events the mask wants stay; only the answer's write is new. A message of the
        // SubDevice's own or a request dropped without answer may change both.
        if request && built {
            self.mailbox_due(MailboxOp::Write);
        } else {
            self.stale.insert(Stale::MAILBOX_QUEUE);
        }
        true
    }

    /// Raises an emergency: queued, and sent when SM1 is free. Refused (returns `false`) below
    /// PREOP and in BOOT, where there is no CoE. When the queue is full the oldest is dropped and
    /// counted ([`SubDevice::emergencies_dropped`]).
    pub fn emergency(&mut self, emergency: Emergency) -> bool {
        if !self.state.has_mailbox() || self.state == AlState::Boot {
            return false;
        }
        self.stale.insert(Stale::MAILBOX_QUEUE);
        self.coe.emergency(emergency);
        true
    }

    /// Emergencies dropped because the queue was full.
    pub fn emergencies_dropped(&self) -> u16 {
        self.coe.emergencies_dropped()
    }
}
