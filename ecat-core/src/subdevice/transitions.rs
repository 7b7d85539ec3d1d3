//! The EtherCAT state machine: AL control handled, transitions begun, verified against the
//! SyncManagers, completed, refused or timed out (ETG.1000.6 §6.4).

use super::plan::InFlight;
use super::targets::Stale;
use super::{CycleSigns, Due, Event, Logged, Pending, SubDevice};
use crate::al::{AlControl, AlState, AlStatusCode};
use crate::coe::sdo::Writes;
use crate::esm::{self, Decision, Transition};
use crate::sync_manager::Channel;
use crate::sync_manager::check;
use crate::sync_mode::SyncMode;
use crate::time::Instant;

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// Expires what is due at `now`: a transition the application left pending is refused with
    /// [`AlStatusCode::UNSPECIFIED_ERROR`], a SAFEOP→OP still waiting for SYNC0 with
    /// [`AlStatusCode::NO_SYNC_ERROR`], one still waiting for outputs with
    /// [`AlStatusCode::SM_WATCHDOG`]; an SDO transfer missing its next segment is dropped.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.stale = Stale::ALL;
        self.mailbox.handle_timeout(now);
        self.coe.handle_timeout(now);
        if let Some(p) = self.pending
            && now >= p.deadline
        {
            // SAFEOP→OP in DC mode without any SYNC0 is a missing sync; without outputs an SM
            // watchdog case (SSC); anything else the application left unanswered.
            let code = if p.awaits.sync0 {
                AlStatusCode::NO_SYNC_ERROR
            } else if p.awaits.outputs {
                AlStatusCode::SM_WATCHDOG
            } else {
                AlStatusCode::UNSPECIFIED_ERROR
            };
            self.fail(code, p.transition.from);
        }
    }

    /// The application's answer to [`Event::TransitionRequested`]: `Ok` completes the transition,
    /// `Err(code)` refuses it with `code` ([`AlStatusCode::UNSPECIFIED_ERROR`] if `code` is
    /// [`AlStatusCode::NO_ERROR`]: a refusal always shows a code). Ignored when `transition` is
    /// no longer pending.
    pub fn complete_transition(
        &mut self,
        transition: Transition,
        result: Result<(), AlStatusCode>,
    ) {
        match &mut self.pending {
            Some(p) if p.transition == transition && !p.accepted => p.accepted = result.is_ok(),
            _ => return,
        }
        self.stale = Stale::ALL;
        match result {
            // Completed now unless it still waits for the process data.
            Ok(()) => self.complete_when_fed(),
            // The refusal shows a code: 0x0001 for none.
            Err(code) => {
                self.pending = None;
                let code = if code == AlStatusCode::NO_ERROR {
                    AlStatusCode::UNSPECIFIED_ERROR
                } else {
                    code
                };
                self.fail(code, transition.from);
            }
        }
    }

    /// Completes the accepted `transition` if the configuration is still valid for its state.
    pub(super) fn finish_transition(&mut self, transition: Transition) {
        self.pending = None;
        if self.checked(transition.to) {
            self.change_state(transition);
        }
    }

    /// Handles one AL control value (ETG.1000.6 §6.4.1).
    pub(super) fn on_control(&mut self, now: Instant, control: AlControl) {
        if let Some(p) = self.pending {
            let same = control.requested() == Some(p.transition.to) && !control.acknowledge();
            if same {
                return;
            }
            self.abort_pending();
        }
        let decision = esm::decide(
            self.al_status(),
            control,
            self.config.bootstrap_mailbox.is_some(),
        );
        if decision == Decision::Ignore {
            return;
        }
        self.targets_changed();
        self.indication.error = false;
        self.code = AlStatusCode::NO_ERROR;
        self.indication.id_requested = control.device_id_request();
        match decision {
            Decision::Ignore | Decision::Stay => {}
            Decision::Refuse(code) => self.fail(code, self.state),
            Decision::Down(t) => self.change_state(t),
            Decision::Up(t) => self.begin_upward(now, t),
        }
    }

    fn begin_upward(&mut self, now: Instant, t: Transition) {
        if !self.checked(t.to) {
            return;
        }
        let deadline = now.saturating_add(self.config.transition_timeout);
        let outputs = self.pd_sizes.outputs > 0;
        self.pending = Some(Pending {
            transition: t,
            deadline,
            accepted: false,
            awaits: CycleSigns {
                outputs: t.to == AlState::Op && outputs && !self.received.outputs,
                sync0: t.to == AlState::Op
                    && matches!(self.sync_mode(), SyncMode::DcSync0)
                    && !self.received.sync0,
            },
        });
        self.events.push(Some(Event::TransitionRequested(t)));
    }

    /// Checks the SyncManagers a SubDevice in `state` relies on. On failure: the code, and the
    /// highest state in which the configuration is still valid.
    fn verify(&self, state: AlState) -> Result<(), (AlStatusCode, AlState)> {
        if state.has_mailbox() {
            let (mailbox, code) = self
                .config
                .mailbox_for(state == AlState::Boot)
                .ok_or((AlStatusCode::BOOTSTRAP_NOT_SUPPORTED, AlState::Init))?;
            check::mailbox(&self.channels, mailbox, code).map_err(|c| (c, AlState::Init))?;
            let largest = mailbox.receive.length.max(mailbox.send.length);
            if usize::from(largest) > MBX {
                return Err((AlStatusCode::NO_MEMORY, AlState::Init));
            }
        }
        if state.has_process_data() {
            if self.pd_unusable != AlStatusCode::NO_ERROR {
                return Err((self.pd_unusable, AlState::PreOp));
            }
            let sizes = self.pd_sizes;
            check::process_data(&self.channels, sizes, self.config)
                .map_err(|c| (c, AlState::PreOp))?;
            self.check_sync_mode(sizes)
                .map_err(|c| (c, AlState::PreOp))?;
            check::watchdog(&self.channels, sizes, self.watchdog_time)
                .map_err(|c| (c, AlState::PreOp))?;
        }
        Ok(())
    }

    /// After an SM-change event: the configuration must still be valid for the current state
    /// (0x0016 and back to INIT for the mailboxes, 0x001D/0x001E and back to PREOP for process
    /// data).
    pub(super) fn check_sm_change(&mut self) {
        if !self.due.take(Due::SM_CHECK) {
            return;
        }
        self.checked(self.state);
    }

    /// [`SubDevice::verify`] for `state`, failing on its code: whether the configuration is
    /// valid. One place for the three callers' failing.
    #[inline(never)]
    fn checked(&mut self, state: AlState) -> bool {
        match self.verify(state) {
            Ok(()) => true,
            Err((code, fallback)) => {
                self.fail(code, fallback);
                false
            }
        }
    }

    /// Sets the error indication with `code` and falls back to `state` when it is lower. The
    /// code is logged, for the diagnosis history and its emergency, at the next mailbox service
    /// ([`SubDevice::log_diagnosis`]).
    pub(super) fn fail(&mut self, code: AlStatusCode, state: AlState) {
        self.logged.push(Some(Logged {
            code,
            state: self.state,
        }));
        self.abort_pending();
        // A lower rank is another state.
        if state.rank() < self.state.rank() {
            self.change_state(Transition {
                from: self.state,
                to: state,
            });
        }
        self.targets_changed();
        self.indication.error = true;
        self.code = code;
    }

    fn change_state(&mut self, t: Transition) {
        self.abort_pending();
        self.targets_changed();
        self.due.set(Due::LAYOUT);
        self.state = t.to;
        if t.to == AlState::SafeOp {
            self.received = CycleSigns::default();
        }
        if t.from.has_mailbox() != t.to.has_mailbox() {
            // The mailbox starts or stops: either way from nothing in flight (`Mailbox::start`
            // takes a stopped one). An SM0 read or SM1 write made due by an event or a service
            // (`mailbox_due`) before a call that stopped the mailbox is moot.
            self.mailbox.stop();
            self.coe.stop();
            if let Some(InFlight::Mailbox(_)) = self.in_flight {
                self.in_flight = None;
            }
            if t.to.has_mailbox() {
                self.due.set(Due::REFRESH);
                self.writes = Writes::default();
                let repeat = self.channels.mailbox_send().activate & Channel::ACTIVATE_REPEAT != 0;
                // The layout `verify` checked: the bootstrap mailbox in BOOT (a device without
                // one never gets there).
                if let Some((layout, _)) = self.config.mailbox_for(t.to == AlState::Boot) {
                    self.mailbox.start(*layout, repeat);
                }
            }
        }
        self.events.push(Some(Event::StateChanged(t)));
    }

    fn abort_pending(&mut self) {
        if let Some(p) = self.pending.take() {
            self.events
                .push(Some(Event::TransitionAborted(p.transition)));
        }
    }
}
