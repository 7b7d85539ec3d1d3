//! The register plan: the accesses the core needs, in order (event mask, reads, PDI control,
//! mailbox, AL status code, AL status, the ERR LED override when the ESC drives ERR), prepared
//! into the core's buffer and completed.

use super::mailbox::MailboxOp;
use super::targets::{Stale, Written};
use super::{Due, ESM_EVENTS, RegisterAccess, SM_CHUNK, SubDevice};
use crate::al::{AlControl, AlEvent, AlState, AlStatusCode};
use crate::indicator::err_pattern;
use crate::register;
use crate::sync_manager::Channel;
use crate::sync_manager::check::Channels;
use crate::sync_parameters::DcSettings;
use crate::time::Instant;

/// The register access in flight, in the order the plan makes them, with what its completion
/// needs: the chunk a SyncManager read covers. A write's value is in the core's buffer and in
/// [`Written`] from the moment the plan chose it: the same access is returned until it is done,
/// and nothing looks at what the ESC holds before then.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum InFlight {
    /// Write the first `len` bytes of the buffer at `address`: the AL event mask (0x0204), PDI
    /// control of a SyncManager (0x0807 + 8·n), AL status code (0x0134), AL status (0x0130)
    /// or the ERR LED override (0x0139).
    Write {
        /// ESC address of the first byte.
        address: u16,
        /// 1, 2 or 4 bytes.
        len: u8,
    },
    /// Read the SyncManager registers from 0x0800 + `start` to 0x0800 + `end`.
    ReadSyncManagers {
        /// The chunk's first byte, from 0x0800.
        start: u8,
        /// One past the chunk's last byte, from 0x0800.
        end: u8,
        /// An SM-change or AL control event came while the read was in flight: its completion
        /// does not count the chunk as read.
        overtaken: bool,
    },
    /// One of the other register reads: its bit in [`read`] (exactly one set).
    Read(u8),
    /// An SM0 read or SM1 write of the mailbox.
    Mailbox(MailboxOp),
}

impl InFlight {
    /// The AL event bits the access clears in the ESC.
    pub(super) const fn clears(self) -> AlEvent {
        match self {
            InFlight::Read(read::AL_CONTROL) => AlEvent::AL_CONTROL,
            InFlight::ReadSyncManagers { .. } => AlEvent::SM_CHANGE,
            InFlight::Mailbox(op) => op.clears(),
            InFlight::Read(read::WATCHDOG_STATUS) => AlEvent::WATCHDOG_PROCESS_DATA,
            _ => AlEvent::NONE,
        }
    }
}

/// The register reads an AL event asks for besides the SyncManagers' (`SubDevice::reads`), in the
/// order they are made: the lowest bit due first.
pub(super) mod read {
    /// The process-data watchdog time (0x0420), with every AL control event: for the watchdog
    /// consistency check at PREOP→SAFEOP.
    pub(crate) const WATCHDOG: u8 = 1 << 0;
    /// The watchdog status (0x0440) after AL event bit 6 in OP; reading it acknowledges the event.
    pub(crate) const WATCHDOG_STATUS: u8 = 1 << 1;
    /// The DC activation (and, on a DC-capable device, the SYNC0 cycle), with every AL control
    /// event: for the DC checks at PREOP→SAFEOP.
    pub(crate) const DC: u8 = 1 << 2;
    /// AL control (0x0120), after all the others.
    pub(crate) const AL_CONTROL: u8 = 1 << 3;
}

impl<'c, const MBX: usize, L: crate::dictionary::Length> SubDevice<'c, MBX, L> {
    /// The next register access the core needs, or `None` when it has nothing to do. Until
    /// [`SubDevice::access_done`] is called the same access is returned again.
    #[inline]
    pub fn poll_access(&mut self) -> Option<RegisterAccess<'_>> {
        match self.in_flight {
            // Settled: the answer costs the driver's loop a test, not a call.
            None if self.stale == Stale::NONE => None,
            // The request/answer rhythm's way: the SM0 read or the answer, made due by the
            // event or the service that needed it (`mailbox_due`).
            Some(InFlight::Mailbox(op)) => Some(self.prepare_mailbox(op)),
            _ => self.next_access(),
        }
    }

    fn next_access(&mut self) -> Option<RegisterAccess<'_>> {
        let op = match self.in_flight {
            Some(in_flight) => in_flight,
            None => self.next_op()?,
        };
        self.in_flight = Some(op);
        Some(self.prepare(op))
    }

    /// Reports that the access returned by [`SubDevice::poll_access`] was performed, with the AL
    /// event register value the driver saw during it.
    #[inline]
    pub fn access_done(&mut self, now: Instant, event: AlEvent) {
        let Some(op) = self.in_flight.take() else {
            return;
        };
        match op {
            // No poll looks at the plan while an access is in flight, so what changed meanwhile
            // is still marked. Reading SM0 changes nothing in the plan: the read was due, so
            // nothing was queued or in SM1 and no repeat asked for; the SM0 event stays wanted
            // and the SM1 event unwanted, and no SM0/SM1 access is due until the request is
            // served.
            InFlight::Mailbox(MailboxOp::Read) => self.mailbox.received(),
            InFlight::Mailbox(MailboxOp::Write) => self.sent(),
            _ => {
                self.stale = Stale::ALL;
                // A write was noted in `Written` when chosen: nothing to complete.
                if !matches!(op, InFlight::Write { .. }) {
                    self.complete_register(now, op);
                }
            }
        }
        self.handle_al_event(event.difference(op.clears()));
    }

    /// The bytes of SyncManager registers the ESC has: 8 per channel
    /// ([`DeviceConfig::sync_manager_count`](crate::DeviceConfig::sync_manager_count), 4 to 16).
    pub(super) fn sm_bytes(&self) -> u8 {
        self.config.sync_manager_count.clamp(4, 16) * Channel::SIZE as u8
    }

    /// Where the last chunk of the SyncManager registers still unread starts: the channels beyond
    /// SM3 are read first, so that SM0..SM3, which the checks use, are read last, right before
    /// AL control.
    fn sm_chunk_start(&self) -> u8 {
        self.sm_unread.saturating_sub(1) & !(SM_CHUNK as u8 - 1)
    }

    /// The next access of the register plan, in order: event mask, reads, PDI control, mailbox,
    /// AL status code, AL status. Only the stale parts are looked at; a part found satisfied is
    /// no longer stale.
    fn next_op(&mut self) -> Option<InFlight> {
        let mut stale = self.stale;
        let next = self.next_op_in(&mut stale);
        self.stale = stale;
        next
    }

    /// [`SubDevice::next_op`] on a copy of the stale parts, stored back once (none of the parts'
    /// questions looks at them).
    fn next_op_in(&mut self, stale: &mut Stale) -> Option<InFlight> {
        // A write's address, length and value, put in the buffer at one place.
        let (address, len, value) = 'write: {
            if stale.contains(Stale::EVENT_MASK) {
                let mask = self.desired_event_mask();
                if self.written.event_mask != mask {
                    self.written.event_mask = mask;
                    break 'write (register::AL_EVENT_MASK, 4, mask);
                }
                stale.remove(Stale::EVENT_MASK);
            }
            if stale.contains(Stale::READS) {
                if let Some(read) = self.next_read() {
                    return Some(read);
                }
                stale.remove(Stale::READS);
            }
            if stale.contains(Stale::PDI_CONTROL) {
                if let Some(write) = self.next_pdi_control() {
                    break 'write write;
                }
                stale.remove(Stale::PDI_CONTROL);
            }
            if stale.contains(Stale::MAILBOX) {
                // Satisfied once its access is under way: the access's completion marks what it
                // makes due (see `access_done`).
                stale.remove(Stale::MAILBOX);
                if let Some(op) = self.next_mailbox_op() {
                    return Some(InFlight::Mailbox(op));
                }
            }
            if stale.contains(Stale::STATUS) {
                if let Some(write) = self.next_status() {
                    break 'write write;
                }
                stale.remove(Stale::STATUS);
            }
            return None;
        };
        if let Some(head) = self.buf.first_chunk_mut() {
            // All four bytes in one store; the write takes the first `len`.
            *head = value.to_le_bytes();
        }
        Some(InFlight::Write { address, len })
    }

    /// The PDI control write due, deactivations first
    /// ([`Written::pdi_control_due`](super::targets::Written::pdi_control_due)), noted as
    /// written: its address, length and value.
    fn next_pdi_control(&mut self) -> Option<(u16, u8, u32)> {
        let (sm, value) = self.written.pdi_control_due(self.desired_pdi_control())?;
        let slot = self.written.pdi_control.get_mut(usize::from(sm))?;
        *slot = value;
        let address = register::sync_manager(sm) + Channel::PDI_CONTROL_OFFSET;
        Some((address, 1, u32::from(value)))
    }

    /// The AL status code write due, or else the AL status write, or else (when the ESC drives
    /// ERR) the ERR LED override's, noted as written: its address, length and value.
    fn next_status(&mut self) -> Option<(u16, u8, u32)> {
        let code = self.al_status_code().0;
        let status = self.al_status().byte();
        // The first code is written whatever its value: with it AL status 0 (nothing written
        // yet) becomes `UNKNOWN` (the code written, the status not yet), never wanted either.
        if self.written.status == 0 || self.written.status_code != code {
            self.written.status_code = code;
            if self.written.status == 0 {
                self.written.status = Written::UNKNOWN;
            }
            Some((register::AL_STATUS_CODE, 2, u32::from(code)))
        } else if self.written.status != status {
            // The ESC clears the override's enable bit with a new AL status.
            (self.written.status, self.written.err_led) = (status, Written::UNKNOWN);
            Some((register::AL_STATUS, 2, u32::from(status)))
        } else if self.config.esc_err_led {
            let error = self.indication.error.then_some(self.code);
            let led = err_pattern(error).override_register();
            if self.written.err_led == led {
                return None;
            }
            self.written.err_led = led;
            Some((register::ERR_LED_OVERRIDE, 1, u32::from(led)))
        } else {
            None
        }
    }

    /// The next register read: the SyncManagers, the watchdog registers and the DC registers
    /// before AL control, so that a transition is checked against what the MainDevice wrote
    /// before requesting it.
    fn next_read(&self) -> Option<InFlight> {
        if self.sm_unread > 0 {
            // A SyncManager read carries its chunk, fixed at the poll: an SM-change event
            // handled before it completes starts the reads over.
            Some(InFlight::ReadSyncManagers {
                start: self.sm_chunk_start(),
                end: self.sm_unread,
                overtaken: false,
            })
        } else if self.reads != 0 {
            // The lowest bit due: the reads' order is their bits'.
            Some(InFlight::Read(self.reads & self.reads.wrapping_neg()))
        } else {
            None
        }
    }

    /// Whether the register read `read` ([`read`]) is due.
    pub(super) fn read_due(&self, read: u8) -> bool {
        self.reads & read != 0
    }

    /// An input of the register targets changed (state, error, code, device ID, process-data
    /// configuration): the next poll looks at every part of the plan.
    pub(super) fn targets_changed(&mut self) {
        self.stale = Stale::ALL;
    }

    /// The AL event mask the plan wants: the state machine's events, the process-data events
    /// the state waits for (the SM2/SM3 trigger; the watchdog in OP with outputs) and, in a
    /// state with a mailbox, the SM0/SM1 events the mailbox waits for.
    fn desired_event_mask(&self) -> u32 {
        let mut mask = ESM_EVENTS;
        if self.state.has_process_data() {
            mask |= self.process_data_trigger();
        }
        if self.state == AlState::Op && self.pd_sizes.outputs > 0 {
            mask |= AlEvent::WATCHDOG_PROCESS_DATA;
        }
        if self.state.has_mailbox() {
            mask |= self.mailbox.event_mask(|| self.coe.has_message());
        }
        mask.bits()
    }

    /// PDI control of SM0..SM3 as the state asks: the mailbox channels active from PREOP (and
    /// in BOOT), SM1 with the mailbox's repeat acknowledge; the process-data channels active in
    /// SAFEOP and OP.
    fn desired_pdi_control(&self) -> [u8; 4] {
        let active = |on: bool| if on { 0 } else { Channel::PDI_DEACTIVATE };
        let mailbox = active(self.state.has_mailbox());
        let process = active(self.state.has_process_data());
        let ack = if self.state.has_mailbox() && self.mailbox.repeat_ack() {
            Channel::PDI_REPEAT_ACK
        } else {
            0
        };
        [mailbox, mailbox | ack, process, process]
    }

    fn prepare(&mut self, op: InFlight) -> RegisterAccess<'_> {
        match op {
            InFlight::Mailbox(op) => self.prepare_mailbox(op),
            _ => self.prepare_register(op),
        }
    }

    /// A register access of the plan: event mask, reads, PDI control, AL status code and status.
    fn prepare_register(&mut self, op: InFlight) -> RegisterAccess<'_> {
        let clears = op.clears();
        let (address, len) = match op {
            InFlight::Write { address, len } => (address, usize::from(len)),
            InFlight::ReadSyncManagers { start, end, .. } => (
                register::SM_BASE + u16::from(start),
                usize::from(end.saturating_sub(start)),
            ),
            InFlight::Read(read) => {
                let address = match read {
                    read::WATCHDOG => register::WATCHDOG_TIME_PROCESS_DATA,
                    read::WATCHDOG_STATUS => register::WATCHDOG_STATUS_PROCESS_DATA,
                    read::DC => register::DC_ACTIVATION,
                    _ => register::AL_CONTROL,
                };
                let len = if read == read::DC {
                    self.dc_read_len()
                } else {
                    2
                };
                (address, len)
            }
            InFlight::Mailbox(_) => (0, 0),
        };
        let buf = self.buf.get_mut(..len).unwrap_or_default();
        if let InFlight::Write { .. } = op {
            RegisterAccess::Write {
                address,
                data: buf,
                clears,
            }
        } else {
            RegisterAccess::Read {
                address,
                buf,
                clears,
            }
        }
    }

    /// Completes a register access (the mailbox's are completed in [`SubDevice::access_done`]);
    /// kept out of line, away from the mailbox's path. A write has nothing left to do: its value
    /// went into [`Written`] when the plan chose it.
    #[inline(never)]
    fn complete_register(&mut self, now: Instant, op: InFlight) {
        match op {
            InFlight::Mailbox(_) | InFlight::Write { .. } => {}
            InFlight::Read(read) => {
                self.reads &= !read;
                self.complete_read(now, read);
            }
            InFlight::ReadSyncManagers {
                start, overtaken, ..
            } => {
                if overtaken {
                    // An SM-change or AL control event came while the chunk was in flight: the
                    // reads start over.
                    return;
                }
                self.sm_unread = start;
                if self.sm_unread > 0 {
                    // A chunk beyond SM3: read for its activation bytes only.
                    return;
                }
                if let Some(bytes) = self.buf.first_chunk() {
                    let starts = |c: &Channels| (c.outputs().start, c.inputs().start);
                    let before = starts(&self.channels);
                    self.channels.update(bytes);
                    if starts(&self.channels) != before {
                        self.due.set(Due::LAYOUT);
                    }
                    let repeat =
                        self.channels.mailbox_send().activate & Channel::ACTIVATE_REPEAT != 0;
                    self.mailbox.repeat_request(repeat);
                }
                if !self.read_due(read::AL_CONTROL) {
                    self.check_sm_change();
                }
            }
        }
    }

    /// Completes the register read `read` ([`read`]), no longer due.
    #[inline(always)]
    fn complete_read(&mut self, now: Instant, read: u8) {
        match read {
            read::WATCHDOG => {
                self.watchdog_time = u16::from_le_bytes([self.buf[0], self.buf[1]]);
            }
            read::DC => {
                let bytes = self.buf.get(..self.dc_read_len()).unwrap_or_default();
                let dc = DcSettings::from_bytes(bytes);
                if dc != self.dc {
                    self.due.set(Due::REFRESH | Due::LAYOUT);
                    self.targets_changed();
                    self.dc = dc;
                }
            }
            read::WATCHDOG_STATUS => {
                let running = self.buf[0] & 1 != 0;
                if !running && self.state == AlState::Op {
                    // ETG.1000.6: SM watchdog in OP → SAFEOP with error 0x001B.
                    self.fail(AlStatusCode::SM_WATCHDOG, AlState::SafeOp);
                }
            }
            _ => {
                let control = AlControl::from_le_bytes([self.buf[0], self.buf[1]]);
                self.on_control(now, control);
                self.check_sm_change();
            }
        }
    }
}
