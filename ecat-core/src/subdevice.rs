//! The sans-IO SubDevice: AL events in, register accesses and application events out.
//!
//! The driver's loop, in the shape of `quinn-proto`:
//!
//! ```text
//! loop {
//!     while let Some(access) = sub.poll_access() {     // register accesses the core needs
//!         let event = perform(access);                  // the AL event register comes back with it
//!         sub.access_done(now, event);
//!     }
//!     while let Some(event) = sub.poll_event() { … }    // tell the application; answer transitions
//!     wait for the IRQ (AL event & mask) or sub.poll_timeout();
//!     sub.handle_al_event(event) / sub.handle_timeout(now);
//! }
//! ```
//!
//! The core decides what to read: an AL control event makes it read the SyncManager registers and
//! then AL control (0x0120), so every transition is checked against the SyncManager configuration
//! the MainDevice wrote before it. It writes AL status code before AL status, so a MainDevice that
//! sees the error indication always reads the matching code. Each call does a bounded amount of
//! work; nothing panics.

use crate::al::{AlControl, AlEvent, AlState, AlStatus, AlStatusCode};
use crate::coe::Emergency;
use crate::coe::sdo::Context;
use crate::device::{Area, DeviceConfig, MailboxConfig, ProcessDataSizes};
use crate::dictionary::{ObjectDictionary, ObjectHooks};
use crate::esm::{self, Decision, Transition};
use crate::mailbox::{Handlers, Mailbox};
use crate::pdo::Direction;
use crate::pdo::layout::Layout as PdoLayout;
use crate::process_data::{Clock, Layout, Writes};
use crate::register;
use crate::ring::Ring;
use crate::sync::{self, DcSettings, SyncType};
use crate::sync_manager::Channel;
use crate::sync_manager::check::{self, Channels};
use crate::time::Instant;

mod targets;

use targets::{Stale, Written};

/// The AL events of the state machine proper (the mailbox adds SM0/SM1 while it needs them).
pub const ESM_EVENTS: AlEvent = AlEvent::AL_CONTROL.union(AlEvent::SM_CHANGE);
// Every AL event mask the core writes carries them: 0 can stand for "not written yet".
const _: () = assert!(!ESM_EVENTS.is_empty());

/// What [`SubDevice::sync`] says when the dictionary's sync type cannot be: an unknown type, which
/// no device supports (so `sync::requested` never yields it) and no mode of the stack matches.
const UNUSABLE_SYNC: SyncType = SyncType::Unknown(u16::MAX);

/// The AL events of the mailbox: SM0 written by the MainDevice, SM1 read by it.
const MAILBOX_EVENTS: AlEvent = AlEvent::sync_manager(0).union(AlEvent::sync_manager(1));

/// The SyncManager registers are read four channels (32 bytes) at a time: SM0..SM3, which
/// [`Channels`] parses, and the channels beyond, read only for their activation bytes.
const SM_CHUNK: usize = Channels::SIZE;
// A chunk starts where the unread bytes' last multiple of `SM_CHUNK` does (a mask).
const _: () = assert!(SM_CHUNK.is_power_of_two() && SM_CHUNK < 256);

/// Marks a SyncManager read in flight (its chunk in the low bytes of the plan's value) that an
/// SM-change or AL control event overtook: its completion must not count the chunk as read.
const SM_READ_OVERTAKEN: u32 = 1 << 16;

/// The register buffer: one chunk of SyncManager registers or the DC registers, whichever is
/// longer.
const BUF_LEN: usize = if SM_CHUNK > DcSettings::READ_LEN {
    SM_CHUNK
} else {
    DcSettings::READ_LEN
};

/// One register access the driver must perform for the core, then report with
/// [`SubDevice::access_done`].
#[derive(Debug, PartialEq, Eq)]
pub enum Access<'a> {
    /// Read `buf.len()` bytes at `address` into `buf`.
    Read {
        /// ESC address of the first byte.
        address: u16,
        /// Where the bytes go; the core reads them in `access_done`.
        buf: &'a mut [u8],
        /// The AL event bits this access clears (see [`Access::clears`]).
        clears: AlEvent,
    },
    /// Write `data` at `address`.
    Write {
        /// ESC address of the first byte.
        address: u16,
        /// The bytes to write.
        data: &'a [u8],
        /// The AL event bits this access clears (see [`Access::clears`]).
        clears: AlEvent,
    },
    /// Write a mailbox message into SM1: `data` at `address`, then, when the message is shorter
    /// than SM1, one byte of value 0 at `last`, SM1's last byte. The ESC hands a mailbox buffer
    /// to the MainDevice once its last byte is written (a SyncManager in mailbox mode), so the
    /// second write completes the first; perform them in this order and
    /// report the AL event of the last one.
    Send {
        /// ESC address of SM1's first byte.
        address: u16,
        /// The message, mailbox header included.
        data: &'a [u8],
        /// SM1's last byte, when the message ends before it.
        last: Option<u16>,
        /// The AL event bits this access clears (see [`Access::clears`]).
        clears: AlEvent,
    },
}

impl Access<'_> {
    /// The AL event bits this access clears in the ESC (reading AL control clears bit 0,
    /// reading the SyncManager activation registers bit 4, reading SM0's buffer bit 8, writing
    /// SM1's buffer bit 9). An SPI ESC samples the AL event register before the access, so
    /// these bits in the value it returns are stale and must not be taken as news.
    pub fn clears(&self) -> AlEvent {
        match self {
            Access::Read { clears, .. }
            | Access::Write { clears, .. }
            | Access::Send { clears, .. } => *clears,
        }
    }
}

/// What the application must hear about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A valid upward transition passed the SyncManager checks and waits for the application's
    /// consent: answer with [`SubDevice::complete_transition`] before [`SubDevice::poll_timeout`].
    TransitionRequested(Transition),
    /// A transition waiting for the application ended without its answer: it timed out (the
    /// MainDevice got [`AlStatusCode::UNSPECIFIED_ERROR`]), or a new request or an error replaced it.
    TransitionAborted(Transition),
    /// The state changed: an accepted upward transition, a downward transition, or a fall back after
    /// an error.
    StateChanged(Transition),
}

/// The register accesses the core may need, in the order it performs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Op {
    WriteEventMask,
    ReadSyncManagers,
    ReadWatchdog,
    ReadWatchdogStatus,
    ReadDc,
    ReadAlControl,
    WritePdiControl(u8),
    Mailbox(MailboxOp),
    WriteStatusCode,
    WriteStatus,
}

impl Op {
    /// The AL event bits the access clears in the ESC.
    const fn clears(self) -> AlEvent {
        match self {
            Op::ReadAlControl => AlEvent::AL_CONTROL,
            Op::ReadSyncManagers => AlEvent::SM_CHANGE,
            Op::Mailbox(MailboxOp::Read) => AlEvent::sync_manager(0),
            Op::ReadWatchdogStatus => AlEvent::WATCHDOG_PROCESS_DATA,
            Op::Mailbox(MailboxOp::Write) => AlEvent::sync_manager(1),
            _ => AlEvent::NONE,
        }
    }
}

/// The register reads an AL event asks for besides the SyncManagers' (`SubDevice::reads`), in the
/// order they are made.
mod read {
    /// The process-data watchdog time (0x0420), with every AL control event: for the watchdog
    /// consistency check at PREOP→SAFEOP.
    pub const WATCHDOG: u8 = 1 << 0;
    /// The watchdog status (0x0440) after AL event bit 6 in OP; reading it acknowledges the event.
    pub const WATCHDOG_STATUS: u8 = 1 << 1;
    /// The DC activation (and, on a DC-capable device, the SYNC0 cycle), with every AL control
    /// event: for the DC checks at PREOP→SAFEOP.
    pub const DC: u8 = 1 << 2;
    /// AL control (0x0120), after all the others.
    pub const AL_CONTROL: u8 = 1 << 3;
}

/// The SM0/SM1 accesses of the mailbox.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MailboxOp {
    /// Read SM0 whole (the request).
    Read,
    /// Write the message into SM1, and SM1's last byte after a shorter one ([`Access::Send`]).
    Write,
}

/// A transition waiting for the application.
#[derive(Debug, Clone, Copy)]
struct Pending {
    transition: Transition,
    deadline: Instant,
    /// The application accepted; the transition still waits for the first outputs.
    accepted: bool,
    /// SAFEOP→OP of a device with outputs: waits until valid outputs were received.
    needs_outputs: bool,
    /// SAFEOP→OP in DC SYNC0 mode: waits until a SYNC0-triggered cycle ran.
    needs_sync: bool,
}

/// The sans-IO EtherCAT SubDevice: state machine, SyncManager checks and mailbox, for mailboxes of
/// at most `MBX` bytes (a configured mailbox larger than that is refused with 0x0002 "no memory").
#[derive(Debug)]
// `repr(C)`: the fields stay in this order, the small ones the state machine reads and writes
// most first (the pending transition, the access in flight, the flags and bytes, then
// halfwords, then words, without padding), the mailbox and the buffers last, so that Thumb's
// 16-bit loads and stores reach them from the start of the struct (bytes within 32, halfwords
// within 64, words within 128 bytes); the compiler's own order put the mailbox, and its
// buffers, first.
#[repr(C)]
pub struct SubDevice<'c, const MBX: usize = 128> {
    pending: Option<Pending>,
    in_flight: Option<(Op, u32)>,
    state: AlState,
    /// The parts of the register plan that may not be satisfied: what the next poll looks at.
    stale: Stale,
    /// The other register reads due, a bit each ([`read`]).
    reads: u8,
    /// The bytes of SyncManager registers still to read, from 0x0800 on: read in chunks of
    /// [`SM_CHUNK`] from the end, the channels beyond SM3 first and SM0..SM3 last; 0 when no read
    /// is due.
    sm_unread: u8,
    error: bool,
    id_requested: bool,
    /// The PDO configuration may have changed since `pd_sizes` was computed.
    pd_stale: bool,
    sm_changed: bool,
    /// Valid outputs arrived since SAFEOP was entered.
    outputs_received: bool,
    /// A SYNC0-triggered cycle ran since SAFEOP was entered (DC mode).
    sync_received: bool,
    code: AlStatusCode,
    device_id: u16,
    /// 0x0420 as last read.
    watchdog_time: u16,
    /// Why the current PDO configuration is unusable (0x0024, 0x0025); [`AlStatusCode::NO_ERROR`]
    /// when it is usable.
    pd_unusable: AlStatusCode,
    /// The process-image sizes of the current PDO configuration (none when it is unusable).
    pd_sizes: ProcessDataSizes,
    /// The sync type the dictionary asks for, or why it cannot be.
    sync: Result<sync::Requested, AlStatusCode>,
    config: &'c DeviceConfig,
    written: Written,
    /// What SDO writes changed since PREOP was entered from INIT: the entries of 0x1C32 the
    /// MainDevice wrote, and whether the process-data configuration changed since the last
    /// [`SubDevice::refresh_process_data`] (taken into `pd_stale` after each message).
    writes: Writes,
    /// The DC registers as last read.
    dc: DcSettings,
    mailbox: Mailbox<MBX>,
    events: Ring<Event, 8>,
    channels: Channels,
    buf: [u8; BUF_LEN],
}

impl<'c, const MBX: usize> SubDevice<'c, MBX> {
    /// A SubDevice in INIT. Its first accesses write the AL event mask, deactivate the
    /// SyncManagers through their PDI control registers and present INIT in AL status.
    pub fn new(config: &'c DeviceConfig) -> Self {
        Self {
            config,
            state: AlState::Init,
            error: false,
            code: AlStatusCode::NO_ERROR,
            id_requested: false,
            device_id: 0,
            channels: Channels::default(),
            sm_unread: 0,
            reads: 0,
            watchdog_time: 0,
            dc: DcSettings::default(),
            sm_changed: false,
            written: Written::new(),
            in_flight: None,
            pending: None,
            events: Ring::new(Event::StateChanged(Transition {
                from: AlState::Init,
                to: AlState::Init,
            })),
            buf: [0; BUF_LEN],
            mailbox: Mailbox::new(),
            stale: Stale::ALL,
            pd_sizes: config.process_data,
            pd_unusable: AlStatusCode::NO_ERROR,
            pd_stale: true,
            outputs_received: false,
            sync_received: false,
            sync: Ok(sync::Requested {
                sync: SyncType::SmSynchronous,
                chosen: false,
            }),
            writes: Writes::default(),
        }
    }

    /// The device description this SubDevice checks against.
    pub fn config(&self) -> &'c DeviceConfig {
        self.config
    }

    /// The current state.
    pub fn state(&self) -> AlState {
        self.state
    }

    /// The AL status as presented (or about to be presented) in 0x0130.
    pub fn al_status(&self) -> AlStatus {
        AlStatus {
            state: self.state,
            error: self.error,
            id_loaded: self.id_requested && !self.error,
        }
    }

    /// The value presented in AL status code 0x0134: the error code, or the device ID while the
    /// MainDevice requests it and there is no error.
    pub fn al_status_code(&self) -> AlStatusCode {
        if self.al_status().id_loaded {
            AlStatusCode(self.device_id)
        } else {
            self.code
        }
    }

    /// Sets the explicit device ID (for example read from rotary switches) presented when the
    /// MainDevice sets AL control bit 5.
    pub fn set_device_id(&mut self, id: u16) {
        self.targets_changed();
        self.device_id = id;
    }

    /// The AL event mask as last written to the ESC: the events that may assert the IRQ line.
    pub fn event_mask(&self) -> AlEvent {
        AlEvent(self.written.event_mask)
    }

    /// The SyncManager registers as last read.
    pub fn sync_managers(&self) -> &Channels {
        &self.channels
    }

    /// Where the process data lives, in SAFEOP and OP.
    pub fn process_data(&self) -> Option<Layout> {
        if !self.state.has_process_data() {
            return None;
        }
        let sizes = self.pd_sizes;
        let area =
            |channel: &Channel, size: u16| (size > 0).then_some(Area::new(channel.start, size));
        Some(Layout {
            outputs: area(self.channels.outputs(), sizes.outputs),
            inputs: area(self.channels.inputs(), sizes.inputs),
            clock: match self.sync() {
                SyncType::FreeRun => Clock::FreeRun(self.writes.chosen.free_run_cycle(self.config)),
                SyncType::DcSync0 => Clock::Sync0(self.dc.sync0_cycle()),
                _ => Clock::Event(self.process_data_trigger()),
            },
            outputs_active: self.state == AlState::Op,
        })
    }

    /// The AL event that triggers a process-data cycle in SyncManager-synchronous mode.
    fn process_data_trigger(&self) -> AlEvent {
        let sizes = self.pd_sizes;
        if matches!(self.sync(), SyncType::FreeRun | SyncType::DcSync0) {
            AlEvent::NONE
        } else if sizes.outputs > 0 {
            AlEvent::sync_manager(2)
        } else if sizes.inputs > 0 {
            AlEvent::sync_manager(3)
        } else {
            AlEvent::NONE
        }
    }

    /// Takes the AL event register value the driver saw (with the bits its own access cleared
    /// removed, see [`Access::clears`]). Bits the state machine does not handle are ignored.
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
            self.sm_changed = true;
        }
        if al_control || event.contains(AlEvent::SM_CHANGE) {
            self.sm_unread = self.sm_bytes();
            if let Some((Op::ReadSyncManagers, chunk)) = &mut self.in_flight {
                *chunk |= SM_READ_OVERTAKEN;
            }
        }
        if event.contains(AlEvent::WATCHDOG_PROCESS_DATA) && self.state == AlState::Op {
            self.reads |= read::WATCHDOG_STATUS;
        }
    }

    /// SM0 written or SM1 read by the MainDevice, in a state with a mailbox.
    fn handle_mailbox_events(&mut self, event: AlEvent) {
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
            self.in_flight = Some((Op::Mailbox(op), 0));
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

    /// The next register access the core needs, or `None` when it has nothing to do. Until
    /// [`SubDevice::access_done`] is called the same access is returned again.
    #[inline]
    pub fn poll_access(&mut self) -> Option<Access<'_>> {
        match self.in_flight {
            // Settled: the answer costs the driver's loop a test, not a call.
            None if self.stale == Stale::NONE => None,
            // Only the mailbox's accesses may be due.
            None if self.stale == Stale::MAILBOX => self.mailbox_access(),
            // The request/answer rhythm's way: the SM0 read or the answer, made due by the
            // event or the service that needed it (`mailbox_due`).
            Some((Op::Mailbox(op), _)) => Some(self.prepare_mailbox(op)),
            _ => self.next_access(),
        }
    }

    /// The mailbox part of the plan alone ([`SubDevice::next_op`] when nothing else is stale).
    fn mailbox_access(&mut self) -> Option<Access<'_>> {
        self.stale = Stale::NONE;
        let op = self.next_mailbox_op()?;
        self.in_flight = Some((Op::Mailbox(op), 0));
        Some(self.prepare_mailbox(op))
    }

    fn next_access(&mut self) -> Option<Access<'_>> {
        let (op, value) = match self.in_flight {
            Some(in_flight) => in_flight,
            None => self.next_op()?,
        };
        self.in_flight = Some((op, value));
        Some(self.prepare(op, value))
    }

    /// Reports that the access returned by [`SubDevice::poll_access`] was performed, with the AL
    /// event register value the driver saw during it.
    #[inline]
    pub fn access_done(&mut self, now: Instant, event: AlEvent) {
        let Some((op, value)) = self.in_flight.take() else {
            return;
        };
        match op {
            // No poll looks at the plan while an access is in flight, so what changed meanwhile
            // is still marked. Reading SM0 changes nothing in the plan: the read was due, so
            // nothing was queued or in SM1 and no repeat asked for; the SM0 event stays wanted
            // and the SM1 event unwanted, and no SM0/SM1 access is due until the request is
            // served.
            Op::Mailbox(MailboxOp::Read) => self.mailbox.received(),
            Op::Mailbox(MailboxOp::Write) => self.sent(),
            _ => {
                self.stale = Stale::ALL;
                self.complete_register(now, op, value);
            }
        }
        self.handle_al_event(event.difference(op.clears()));
    }

    /// The next application event.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.events.pop()
    }

    /// When [`SubDevice::handle_timeout`] must be called next, if ever.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        let transition = self.pending.map(|p| p.deadline);
        match (transition, self.mailbox.poll_timeout()) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Expires what is due at `now`: a transition the application left pending is refused with
    /// [`AlStatusCode::UNSPECIFIED_ERROR`], a SAFEOP→OP still waiting for SYNC0 with
    /// [`AlStatusCode::NO_SYNC_ERROR`], one still waiting for outputs with
    /// [`AlStatusCode::SM_WATCHDOG`]; an SDO transfer missing its next segment is dropped.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.stale = Stale::ALL;
        self.mailbox.handle_timeout(now);
        if let Some(p) = self.pending
            && now >= p.deadline
        {
            // SAFEOP→OP in DC mode without any SYNC0 is a missing sync; without outputs an SM
            // watchdog case (SSC); anything else the application left unanswered.
            let code = if p.needs_sync {
                AlStatusCode::NO_SYNC_ERROR
            } else if p.needs_outputs {
                AlStatusCode::SM_WATCHDOG
            } else {
                AlStatusCode::UNSPECIFIED_ERROR
            };
            self.fail(code, p.transition.from);
        }
    }

    /// The transition waiting for the application, if any.
    pub fn pending_transition(&self) -> Option<Transition> {
        self.pending.map(|p| p.transition)
    }

    /// Whether the pending transition still waits for the application's answer.
    pub fn awaits_application(&self) -> bool {
        self.pending.is_some_and(|p| !p.accepted)
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
        let waits = match &mut self.pending {
            Some(p) if p.transition == transition && !p.accepted => {
                p.accepted = result.is_ok();
                p.needs_outputs || p.needs_sync
            }
            _ => return,
        };
        self.stale = Stale::ALL;
        if result.is_ok() && waits {
            return;
        }
        self.finish_transition(transition, result);
    }

    /// The process-data side received valid outputs (the MainDevice wrote SM2) since SAFEOP was
    /// entered: a SAFEOP→OP transition the application accepted may complete.
    pub fn outputs_received(&mut self) {
        self.outputs_received = true;
        if let Some(p) = &mut self.pending {
            p.needs_outputs = false;
        }
        self.complete_when_fed();
    }

    /// Completes a SAFEOP→OP the application accepted once the process data it waits for came.
    fn complete_when_fed(&mut self) {
        let Some(p) = self.pending else { return };
        if p.accepted && !p.needs_outputs && !p.needs_sync {
            self.stale = Stale::ALL;
            self.finish_transition(p.transition, Ok(()));
        }
    }

    /// The sync type in effect: what 0x1C32:01 asks for, or DC SYNC0 when the MainDevice did
    /// not choose and activated SYNC0 ([`sync::Requested::effective`]); [`UNUSABLE_SYNC`] when
    /// the dictionary's cannot be.
    fn sync(&self) -> SyncType {
        match self.sync {
            Ok(requested) => requested.effective(self.dc, self.config),
            Err(_) => UNUSABLE_SYNC,
        }
    }

    /// The bytes of SyncManager registers the ESC has: 8 per channel
    /// ([`DeviceConfig::sync_manager_count`], 4 to 16).
    fn sm_bytes(&self) -> u8 {
        self.config.sync_manager_count.clamp(4, 16) * Channel::SIZE as u8
    }

    /// Where the last chunk of the SyncManager registers still unread starts: the channels beyond
    /// SM3 are read first, so that SM0..SM3, which the checks use, are read last, right before
    /// AL control.
    fn sm_chunk_start(&self) -> u8 {
        self.sm_unread.saturating_sub(1) & !(SM_CHUNK as u8 - 1)
    }

    /// The DC registers read with an AL control event: the activation byte, and up to the SYNC0
    /// cycle time for a device that supports DC SYNC0.
    fn dc_read_len(&self) -> usize {
        if self.config.sync.dc() {
            DcSettings::READ_LEN
        } else {
            1
        }
    }

    /// The process-data side saw SYNC0 stop (DC mode): in OP the SubDevice falls back to SAFEOP
    /// with [`AlStatusCode::FATAL_SYNC_ERROR`] (conformance.md "Distributed clocks").
    pub fn sync_lost(&mut self) {
        if self.state == AlState::Op && self.sync() == SyncType::DcSync0 {
            self.stale = Stale::ALL;
            self.fail(AlStatusCode::FATAL_SYNC_ERROR, AlState::SafeOp);
        }
    }

    /// The process-data side's sync error supervision tripped (too many missed SM/SYNC events,
    /// [`crate::sync_error`]): in OP the SubDevice falls back to SAFEOP with
    /// [`AlStatusCode::SYNC_ERROR`] (ETG.1020 §6.3).
    pub fn sync_error(&mut self) {
        if self.state == AlState::Op {
            self.stale = Stale::ALL;
            self.fail(AlStatusCode::SYNC_ERROR, AlState::SafeOp);
        }
    }

    /// The process-data side ran a SYNC0-triggered cycle (DC mode) since SAFEOP was entered: a
    /// SAFEOP→OP in DC mode may complete (with its outputs, if the device has any).
    pub fn sync_received(&mut self) {
        self.sync_received = true;
        if let Some(p) = &mut self.pending {
            p.needs_sync = false;
        }
        self.complete_when_fed();
    }

    fn finish_transition(&mut self, transition: Transition, result: Result<(), AlStatusCode>) {
        self.pending = None;
        let verified = result
            .map_err(|code| match code {
                AlStatusCode::NO_ERROR => (AlStatusCode::UNSPECIFIED_ERROR, transition.from),
                code => (code, transition.from),
            })
            .and_then(|()| self.verify(transition.to));
        match verified {
            Ok(()) => self.change_state(transition),
            Err((code, fallback)) => self.fail(code, fallback),
        }
    }

    /// The next access of the register plan, in order: event mask, reads, PDI control, mailbox,
    /// AL status code, AL status. Only the stale parts are looked at; a part found satisfied is
    /// no longer stale.
    fn next_op(&mut self) -> Option<(Op, u32)> {
        let mut stale = self.stale;
        let next = self.next_op_in(&mut stale);
        self.stale = stale;
        next
    }

    /// [`SubDevice::next_op`] on a copy of the stale parts, stored back once (none of the parts'
    /// questions looks at them).
    fn next_op_in(&mut self, stale: &mut Stale) -> Option<(Op, u32)> {
        if stale.contains(Stale::EVENT_MASK) {
            let mask = self.desired_event_mask();
            if self.written.event_mask != mask {
                return Some((Op::WriteEventMask, mask));
            }
            stale.remove(Stale::EVENT_MASK);
        }
        if stale.contains(Stale::READS) {
            if let Some(read) = self.next_read() {
                // A SyncManager read carries its chunk (start and end), fixed at the poll: an
                // SM-change event handled before it completes starts the reads over.
                let chunk = u32::from(self.sm_chunk_start()) | u32::from(self.sm_unread) << 8;
                return Some((
                    read,
                    if read == Op::ReadSyncManagers {
                        chunk
                    } else {
                        0
                    },
                ));
            }
            stale.remove(Stale::READS);
        }
        if stale.contains(Stale::PDI_CONTROL) {
            if let Some(write) = self.next_pdi_control() {
                return Some(write);
            }
            stale.remove(Stale::PDI_CONTROL);
        }
        if stale.contains(Stale::MAILBOX) {
            // Satisfied once its access is under way: the access's completion marks what it
            // makes due (see `access_done`).
            stale.remove(Stale::MAILBOX);
            if let Some(op) = self.next_mailbox_op() {
                return Some((Op::Mailbox(op), 0));
            }
        }
        if stale.contains(Stale::STATUS) {
            if let Some(write) = self.next_status() {
                return Some(write);
            }
            stale.remove(Stale::STATUS);
        }
        None
    }

    /// The PDI control write due, deactivations first ([`Written::pdi_control_due`]).
    fn next_pdi_control(&self) -> Option<(Op, u32)> {
        let (n, value) = self.written.pdi_control_due(self.desired_pdi_control())?;
        Some((Op::WritePdiControl(n), u32::from(value)))
    }

    /// The AL status code write due, or else the AL status write.
    fn next_status(&self) -> Option<(Op, u32)> {
        let code = u32::from(self.al_status_code().0);
        let status = u32::from(self.al_status().bits());
        if self.written.status_code != code {
            Some((Op::WriteStatusCode, code))
        } else if self.written.status != status {
            Some((Op::WriteStatus, status))
        } else {
            None
        }
    }

    /// The SM0/SM1 access due, once SM0 and SM1 are active in a mailbox state: the next message
    /// (or the last again), the next request.
    fn next_mailbox_op(&self) -> Option<MailboxOp> {
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

    /// The next register read: the SyncManagers, the watchdog registers and the DC registers
    /// before AL control, so that a transition is checked against what the MainDevice wrote
    /// before requesting it.
    fn next_read(&self) -> Option<Op> {
        if self.sm_unread > 0 {
            Some(Op::ReadSyncManagers)
        } else if self.read_due(read::WATCHDOG) {
            Some(Op::ReadWatchdog)
        } else if self.read_due(read::WATCHDOG_STATUS) {
            Some(Op::ReadWatchdogStatus)
        } else if self.read_due(read::DC) {
            Some(Op::ReadDc)
        } else if self.read_due(read::AL_CONTROL) {
            Some(Op::ReadAlControl)
        } else {
            None
        }
    }

    /// Whether the register read `read` ([`read`]) is due.
    fn read_due(&self, read: u8) -> bool {
        self.reads & read != 0
    }

    /// An input of the register targets changed (state, error, code, device ID, process-data
    /// configuration): the next poll looks at every part of the plan.
    fn targets_changed(&mut self) {
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
            mask |= self.mailbox.event_mask();
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

    fn prepare(&mut self, op: Op, value: u32) -> Access<'_> {
        match op {
            Op::Mailbox(op) => self.prepare_mailbox(op),
            _ => self.prepare_register(op, value),
        }
    }

    /// The SM0 read or SM1 write of `op`.
    #[inline]
    fn prepare_mailbox(&mut self, op: MailboxOp) -> Access<'_> {
        let clears = Op::Mailbox(op).clears();
        match op {
            MailboxOp::Read => {
                let (address, buf) = self.mailbox.rx_buffer();
                Access::Read {
                    address,
                    buf,
                    clears,
                }
            }
            MailboxOp::Write => {
                let (address, data, last) = self.mailbox.message();
                Access::Send {
                    address,
                    data,
                    last,
                    clears,
                }
            }
        }
    }

    /// A register access of the plan: event mask, reads, PDI control, AL status code and status.
    fn prepare_register(&mut self, op: Op, value: u32) -> Access<'_> {
        let (address, len, write) = match op {
            Op::WriteEventMask => (register::AL_EVENT_MASK, 4, true),
            Op::ReadSyncManagers => {
                let [start, end, ..] = value.to_le_bytes();
                (
                    register::SM_BASE + u16::from(start),
                    usize::from(end.saturating_sub(start)),
                    false,
                )
            }
            Op::ReadWatchdog => (register::WATCHDOG_TIME_PROCESS_DATA, 2, false),
            Op::ReadWatchdogStatus => (register::WATCHDOG_STATUS_PROCESS_DATA, 2, false),
            Op::ReadDc => (register::DC_ACTIVATION, self.dc_read_len(), false),
            Op::ReadAlControl => (register::AL_CONTROL, 2, false),
            Op::WritePdiControl(n) => (
                register::sync_manager(n) + Channel::PDI_CONTROL_OFFSET,
                1,
                true,
            ),
            Op::WriteStatusCode => (register::AL_STATUS_CODE, 2, true),
            Op::WriteStatus => (register::AL_STATUS, 2, true),
            Op::Mailbox(_) => (0, 0, false),
        };
        let buf = self.buf.get_mut(..len).unwrap_or_default();
        if write {
            let bytes = value.to_le_bytes();
            for (dst, src) in buf.iter_mut().zip(bytes) {
                *dst = src;
            }
            Access::Write {
                address,
                data: buf,
                clears: op.clears(),
            }
        } else {
            Access::Read {
                address,
                buf,
                clears: op.clears(),
            }
        }
    }

    /// Completes a register access (the mailbox's are completed in [`SubDevice::access_done`]);
    /// kept out of line, away from the mailbox's path.
    #[inline(never)]
    fn complete_register(&mut self, now: Instant, op: Op, value: u32) {
        match op {
            Op::Mailbox(_) => {}
            Op::WriteEventMask => self.written.event_mask = value,
            Op::WritePdiControl(n) => {
                if let Some(slot) = self.written.pdi_control.get_mut(usize::from(n)) {
                    *slot = u8::try_from(value).unwrap_or(Written::UNKNOWN);
                }
            }
            Op::WriteStatusCode => self.written.status_code = value,
            Op::WriteStatus => self.written.status = value,
            Op::ReadWatchdog => {
                self.reads &= !read::WATCHDOG;
                self.watchdog_time = u16::from_le_bytes([self.buf[0], self.buf[1]]);
            }
            Op::ReadDc => {
                self.reads &= !read::DC;
                let bytes = self.buf.get(..self.dc_read_len()).unwrap_or_default();
                let dc = DcSettings::from_bytes(bytes);
                if dc != self.dc {
                    self.pd_stale = true;
                    self.targets_changed();
                    self.dc = dc;
                }
            }
            Op::ReadWatchdogStatus => {
                self.reads &= !read::WATCHDOG_STATUS;
                let running = self.buf[0] & 1 != 0;
                if !running && self.state == AlState::Op {
                    // ETG.1000.6: SM watchdog in OP → SAFEOP with error 0x001B.
                    self.fail(AlStatusCode::SM_WATCHDOG, AlState::SafeOp);
                }
            }
            Op::ReadSyncManagers => {
                if value & SM_READ_OVERTAKEN != 0 {
                    // An SM-change or AL control event came while the chunk was in flight: the
                    // reads start over.
                    return;
                }
                let [start, ..] = value.to_le_bytes();
                self.sm_unread = start;
                if self.sm_unread > 0 {
                    // A chunk beyond SM3: read for its activation bytes only.
                    return;
                }
                if let Some(bytes) = self.buf.first_chunk() {
                    self.channels = Channels::from_bytes(bytes);
                    let repeat =
                        self.channels.mailbox_send().activate & Channel::ACTIVATE_REPEAT != 0;
                    self.mailbox.repeat_request(repeat);
                }
                if !self.read_due(read::AL_CONTROL) {
                    self.check_sm_change();
                }
            }
            Op::ReadAlControl => {
                self.reads &= !read::AL_CONTROL;
                let control = AlControl::from_le_bytes([self.buf[0], self.buf[1]]);
                self.on_control(now, control);
                self.check_sm_change();
            }
        }
    }

    /// The message is complete in SM1: the mailbox waits for the MainDevice to read it, and SM1's
    /// repeat acknowledge follows the request. Until the SM1 event (or a repeat request, read
    /// with an SM-change event) no SM0/SM1 access is due. SM0 stays blocked, by the message
    /// before and by SM1 now; the SM1 event, unwanted while the message was written (unless it
    /// was a repeat), joins the mask when something waits behind the message. PDI control
    /// changes when the acknowledge does.
    fn sent(&mut self) {
        let ack = self.mailbox.repeat_ack();
        let repeat = self.mailbox.repeat_pending();
        self.mailbox.written();
        if repeat || self.mailbox.wants_send_event() {
            self.stale.insert(Stale::EVENT_MASK);
        }
        if self.mailbox.repeat_ack() != ack {
            self.stale.insert(Stale::PDI_CONTROL);
        }
    }

    /// Handles one AL control value (ETG.1000.6 §6.4.1).
    fn on_control(&mut self, now: Instant, control: AlControl) {
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
        self.error = false;
        self.code = AlStatusCode::NO_ERROR;
        self.id_requested = control.device_id_request();
        match decision {
            Decision::Ignore | Decision::Stay => {}
            Decision::Refuse(code) => self.fail(code, self.state),
            Decision::Down(t) => self.change_state(t),
            Decision::Up(t) => self.begin_upward(now, t),
        }
    }

    fn begin_upward(&mut self, now: Instant, t: Transition) {
        if let Err((code, fallback)) = self.verify(t.to) {
            self.fail(code, fallback);
            return;
        }
        let deadline = now.saturating_add(self.config.transition_timeout);
        let outputs = self.pd_sizes.outputs > 0;
        self.pending = Some(Pending {
            transition: t,
            deadline,
            accepted: false,
            needs_outputs: t.to == AlState::Op && outputs && !self.outputs_received,
            needs_sync: t.to == AlState::Op
                && self.sync() == SyncType::DcSync0
                && !self.sync_received,
        });
        self.events.push(Event::TransitionRequested(t));
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
            self.check_sync(sizes).map_err(|c| (c, AlState::PreOp))?;
            check::watchdog(&self.channels, sizes, self.watchdog_time)
                .map_err(|c| (c, AlState::PreOp))?;
        }
        Ok(())
    }

    /// The sync type must be supported; free-run needs SM2 in 3-buffer mode (0x0029); a
    /// DC-capable device checks the DC SYNC unit ([`sync::check_dc`]); a cycle time the
    /// MainDevice wrote must suit the sync type ([`sync::check_cycle`]).
    fn check_sync(&self, sizes: ProcessDataSizes) -> Result<(), AlStatusCode> {
        self.sync?;
        let sync = self.sync();
        if self.config.sync.dc() {
            sync::check_dc(sync, self.dc, self.config)?;
        } else if self.dc.activation.0 != 0 {
            // DC activated on a device without DC (conformance.md "Distributed clocks").
            return Err(AlStatusCode::INVALID_DC_SYNC_CONFIG);
        }
        sync::check_cycle(sync, self.writes.chosen.cycle_ns(), self.dc, self.config)?;
        let one_buffer =
            self.channels.outputs().control.mode() == crate::sync_manager::Mode::Mailbox;
        if sync == SyncType::FreeRun && sizes.outputs > 0 && one_buffer {
            return Err(AlStatusCode::FREE_RUN_NEEDS_3_BUFFER);
        }
        Ok(())
    }

    /// After an SM-change event: the configuration must still be valid for the current state
    /// (0x0016 and back to INIT for the mailboxes, 0x001D/0x001E and back to PREOP for process data).
    fn check_sm_change(&mut self) {
        if !core::mem::take(&mut self.sm_changed) {
            return;
        }
        if let Err((code, fallback)) = self.verify(self.state) {
            self.fail(code, fallback);
        }
    }

    /// Sets the error indication with `code` and falls back to `state` when it is lower.
    fn fail(&mut self, code: AlStatusCode, state: AlState) {
        self.abort_pending();
        // A lower rank is another state.
        if state.rank() < self.state.rank() {
            self.change_state(Transition {
                from: self.state,
                to: state,
            });
        }
        self.targets_changed();
        self.error = true;
        self.code = code;
    }

    fn change_state(&mut self, t: Transition) {
        self.abort_pending();
        self.targets_changed();
        self.state = t.to;
        if t.to == AlState::SafeOp {
            self.outputs_received = false;
            self.sync_received = false;
        }
        if t.from.has_mailbox() != t.to.has_mailbox() {
            // The mailbox starts or stops: either way from nothing in flight (`Mailbox::start`
            // takes a stopped one). An SM0 read or SM1 write made due by an event or a service
            // (`mailbox_due`) before a call that stopped the mailbox is moot.
            self.mailbox.stop();
            if let Some((Op::Mailbox(_), _)) = self.in_flight {
                self.in_flight = None;
            }
        }
        if !t.from.has_mailbox() && t.to.has_mailbox() {
            self.pd_stale = true;
            self.writes = Writes::default();
            let repeat = self.channels.mailbox_send().activate & Channel::ACTIVATE_REPEAT != 0;
            self.mailbox.start(self.active_mailbox(), repeat);
        }
        self.events.push(Event::StateChanged(t));
    }

    fn abort_pending(&mut self) {
        if let Some(p) = self.pending.take() {
            self.events.push(Event::TransitionAborted(p.transition));
        }
    }

    /// The mailbox layout of the current state: the bootstrap mailbox in BOOT.
    fn active_mailbox(&self) -> MailboxConfig {
        match (self.state, self.config.bootstrap_mailbox) {
            (AlState::Boot, Some(boot)) => boot,
            _ => self.config.mailbox,
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
        // Nothing due, nothing changed. Nothing is served either while an access is in flight:
        // an SM0 read the request's event made due (`mailbox_due`) goes first, so that the
        // request's answer finds SM1 free.
        if !self.state.has_mailbox() || self.in_flight.is_some() || !self.mailbox.has_work() {
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
        let built = self.mailbox.serve(&mut cx, handlers);
        self.pd_stale |= core::mem::take(&mut self.writes.configured);
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

    /// Recomputes the process-image sizes from the PDO assignment and mapping objects of `od`
    /// when they may have changed (after an SDO write to the PDO configuration or 0x1C32/0x1C33,
    /// on entering PREOP, on a new DC setting). Call it before the
    /// SubDevice handles AL events; without assignment objects (0x1C12/0x1C13) the device
    /// configuration's fixed sizes apply. An unusable mapping answers PREOP→SAFEOP with 0x0025
    /// (outputs) or 0x0024 (inputs).
    ///
    /// It also takes the sync type the MainDevice chose (0x1C32:01, see [`crate::sync`]) and
    /// fills what the stack knows into 0x1C32 and 0x1C33 ([`sync::fill`]): the supported types
    /// (SI4), the minimum cycle (SI5), the cycle time (SI2, free-run and DC) and 0x1C33's sync
    /// type (SI1).
    #[inline]
    pub fn refresh_process_data<D: ObjectDictionary>(&mut self, od: &mut D) {
        // Inline: it is called after every AL event and rarely has anything to do.
        if core::mem::take(&mut self.pd_stale) {
            self.refresh(od);
        }
    }

    /// [`SubDevice::refresh_process_data`] when the configuration may have changed.
    fn refresh<D: ObjectDictionary>(&mut self, od: &mut D) {
        self.targets_changed();
        self.sync = sync::requested(od, self.config, self.writes.chosen);
        let fixed = self.config.process_data;
        let size = |direction, fixed| match PdoLayout::of(od, direction) {
            Ok(Some(layout)) => Ok(layout.bytes()),
            Ok(None) => Ok(fixed),
            Err(code) => Err(code),
        };
        let sizes = size(Direction::Rx, fixed.outputs).and_then(|outputs| {
            Ok(ProcessDataSizes {
                outputs,
                inputs: size(Direction::Tx, fixed.inputs)?,
            })
        });
        (self.pd_sizes, self.pd_unusable) = match sizes {
            Ok(sizes) => (sizes, AlStatusCode::NO_ERROR),
            Err(code) => (ProcessDataSizes::default(), code),
        };
        let has_outputs = self.pd_sizes.outputs > 0;
        let active = self.sync.is_ok().then(|| self.sync());
        let chosen_cycle = self.writes.chosen.cycle_ns();
        sync::fill(od, self.config, active, chosen_cycle, self.dc, has_outputs);
    }

    /// Raises an emergency: queued, and sent when SM1 is free. Refused (returns `false`) below
    /// PREOP and in BOOT, where there is no CoE. When the queue is full the oldest is dropped and
    /// counted ([`SubDevice::emergencies_dropped`]).
    pub fn emergency(&mut self, emergency: Emergency) -> bool {
        if !self.state.has_mailbox() || self.state == AlState::Boot {
            return false;
        }
        self.stale.insert(Stale::MAILBOX_QUEUE);
        self.mailbox.emergency(emergency);
        true
    }

    /// Emergencies dropped because the queue was full.
    pub fn emergencies_dropped(&self) -> u16 {
        self.mailbox.emergencies_dropped()
    }
}
