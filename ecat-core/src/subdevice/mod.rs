//! The sans-IO SubDevice: AL events in, register accesses and application events out.
//!
//! The driver's loop, in the shape of `quinn-proto` ([`SubDevice`] lists every method in
//! call order):
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
//!
//! One `impl` block per concern, one file each (smoltcp's `iface/interface` layout):
//!
//! | file | concern |
//! |---|---|
//! | `mod.rs` | the struct, construction, what the core presents, application events, timeouts |
//! | `events.rs` | AL events in: what each event bit makes due |
//! | `plan.rs` | the register plan: the next access, prepared into the core's buffer, completed |
//! | `targets.rs` | the registers the core keeps at a value, and what it last wrote there |
//! | `transitions.rs` | the state machine: AL control, transitions verified, completed, refused |
//! | `process_data.rs` | the process-data areas and sizes, outputs received |
//! | `sync_mode.rs` | the synchronisation mode in effect, its checks, SYNC0 and sync errors |
//! | `mailbox.rs` | the SM0/SM1 accesses, serving the mailbox, emergencies |
//! | `diagnosis.rs` | the diagnosis history: the stack's AL status codes logged, the application's messages |

use crate::al::{AlEvent, AlState, AlStatus, AlStatusCode};
use crate::coe::sdo::Writes;
use crate::coe::server::CoeServer;
use crate::device::{DeviceConfig, ProcessDataSizes};
use crate::dictionary::{Len, Length};
use crate::esm::Transition;
use crate::mailbox::{Mailbox, NO_TIMEOUT};
use crate::ring::Ring;
use crate::sync_manager::check::Channels;
use crate::sync_mode::SyncMode;
use crate::sync_parameters::{self, DcSettings};
use crate::time::Instant;

mod diagnosis;
pub use diagnosis::EMERGENCY_PERIOD;
mod events;
mod mailbox;
mod plan;
mod process_data;
mod sync_mode;
mod targets;
mod transitions;

use plan::InFlight;
use targets::{Stale, Written};

/// The AL events of the state machine proper (the mailbox adds SM0/SM1 while it needs them).
pub(crate) const ESM_EVENTS: AlEvent = AlEvent::AL_CONTROL.union(AlEvent::SM_CHANGE);
// Every AL event mask the core writes carries them: 0 can stand for "not written yet".
const _: () = assert!(!ESM_EVENTS.is_empty());

/// How many AL status codes wait to be logged in the diagnosis history at most (the oldest is
/// dropped).
pub(crate) const LOGGED: usize = 4;

/// The AL events of the mailbox: SM0 written by the MainDevice, SM1 read by it.
const MAILBOX_EVENTS: AlEvent = AlEvent::sync_manager(0).union(AlEvent::sync_manager(1));

/// The SyncManager registers are read four channels (32 bytes) at a time: SM0..SM3, which
/// [`Channels`] parses, and the channels beyond, read only for their activation bytes.
const SM_CHUNK: usize = Channels::SIZE;
// A chunk starts where the unread bytes' last multiple of `SM_CHUNK` does (a mask).
const _: () = assert!(SM_CHUNK.is_power_of_two() && SM_CHUNK < 256);

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
pub enum RegisterAccess<'a> {
    /// Read `buf.len()` bytes at `address` into `buf`.
    Read {
        /// ESC address of the first byte.
        address: u16,
        /// Where the bytes go; the core reads them in `access_done`.
        buf: &'a mut [u8],
        /// The AL event bits this access clears (see [`RegisterAccess::clears`]).
        clears: AlEvent,
    },
    /// Write `data` at `address`.
    Write {
        /// ESC address of the first byte.
        address: u16,
        /// The bytes to write.
        data: &'a [u8],
        /// The AL event bits this access clears (see [`RegisterAccess::clears`]).
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
        /// The AL event bits this access clears (see [`RegisterAccess::clears`]).
        clears: AlEvent,
    },
}

impl RegisterAccess<'_> {
    /// The AL event bits this access clears in the ESC (reading AL control clears bit 0,
    /// reading the SyncManager activation registers bit 4, reading SM0's buffer bit 8, writing
    /// SM1's buffer bit 9). An SPI ESC samples the AL event register before the access, so
    /// these bits in the value it returns are stale and must not be taken as news.
    pub fn clears(&self) -> AlEvent {
        match self {
            RegisterAccess::Read { clears, .. }
            | RegisterAccess::Write { clears, .. }
            | RegisterAccess::Send { clears, .. } => *clears,
        }
    }
}

/// What the application must hear about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
// The variants numbered from 1: rustc then makes an `Option<Event>`'s `None` the tag 0, so the
// SubDevice's queue of events is built by zeroing rather than copied from a filler in flash
// (docs/size-history.md, "Session 13: … (branch sync9)"; a matter of size, not of correctness).
#[repr(u8)]
pub enum Event {
    /// A valid upward transition passed the SyncManager checks and waits for the application's
    /// consent: answer with [`SubDevice::complete_transition`] before [`SubDevice::poll_timeout`].
    TransitionRequested(Transition) = 1,
    /// A transition waiting for the application ended without its answer: it timed out (the
    /// MainDevice got [`AlStatusCode::UNSPECIFIED_ERROR`]), or a new request or an error replaced
    /// it.
    TransitionAborted(Transition) = 2,
    /// The state changed: an accepted upward transition, a downward transition, or a fall back
    /// after an error.
    StateChanged(Transition) = 3,
}

/// An AL status code the stack set, and the state it was in then.
#[derive(Debug, Clone, Copy)]
struct Logged {
    code: AlStatusCode,
    state: AlState,
}

/// A transition waiting for the application.
#[derive(Debug, Clone, Copy)]
struct Pending {
    transition: Transition,
    deadline: Instant,
    /// The application accepted; the transition still waits for [`Pending::awaits`].
    accepted: bool,
    /// What SAFEOP→OP still waits for: valid outputs (a device with outputs), a SYNC0-triggered
    /// cycle (DC SYNC0 mode).
    awaits: CycleSigns,
}

/// The signs of a running process-data cycle that SAFEOP→OP waits for, reported by the
/// process-data side: valid outputs received (the MainDevice wrote SM2), a SYNC0-triggered cycle
/// run (DC SYNC0 mode).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct CycleSigns {
    outputs: bool,
    sync0: bool,
}

/// AL status's indication bits as the core presents them (ETG.1000.6 Table 12).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Indication {
    /// Bit 4: the error indication, with the code in 0x0134.
    error: bool,
    /// AL control bit 5 asked for the device ID: 0x0134 shows it (bit 5, when there is no error).
    id_requested: bool,
}

/// Work an event left for later, done when its inputs are there: a bit each (one byte, in the
/// SubDevice's bytes without padding).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Due(u8);

impl Due {
    /// The PDO configuration may have changed since `pd_sizes` was computed:
    /// [`SubDevice::refresh_process_data`] recomputes it.
    const REFRESH: u8 = 1 << 0;
    /// An SM-change event came: the configuration is checked against the state once the
    /// SyncManagers are read.
    const SM_CHECK: u8 = 1 << 1;
    /// What [`SubDevice::process_data`] answers may have changed since
    /// [`SubDevice::process_data_news`] took it (or was never taken): the state, the PDO
    /// configuration, the sync choices, the DC settings or an address of SM2/SM3 changed.
    const LAYOUT: u8 = 1 << 2;

    /// Makes the work of `bits` due.
    fn set(&mut self, bits: u8) {
        self.0 |= bits;
    }

    /// Whether the work of `bit` was due; it no longer is.
    fn take(&mut self, bit: u8) -> bool {
        let due = self.0 & bit != 0;
        self.0 &= !bit;
        due
    }
}

/// The sans-IO EtherCAT SubDevice: state machine, SyncManager checks and mailbox, for mailboxes of
/// at most `MBX` bytes (a configured mailbox larger than that is refused with 0x0002 "no memory").
/// Its SDO server gathers a download that continues in segments in `L` bytes: by default `MBX`,
/// or the dictionary's largest value, `SubDevice<'c, MBX, D::Download>`
/// ([`ObjectDictionary::Download`](crate::dictionary::ObjectDictionary::Download)), as
/// `ecat-embassy` makes it: a few bytes for a dictionary of numbers.
///
/// # Methods in call order
///
/// Like `quinn-proto`'s `Connection`, every method says when the driver (or the application)
/// calls it. In the order of one pass of the driver's loop:
///
/// 1. **Once:** [`new`](Self::new) (a SubDevice in INIT); [`set_device_id`](Self::set_device_id)
///    whenever the device ID changes (e.g. rotary switches).
/// 2. **Before AL events are handled:** [`refresh_process_data`](Self::refresh_process_data)
///    with the dictionary (cheap when nothing changed), then what the process-data side
///    reported since the last pass: [`outputs_received`](Self::outputs_received),
///    [`sync0_received`](Self::sync0_received), [`sync0_lost`](Self::sync0_lost),
///    [`sync_error`](Self::sync_error), and the application's [`emergency`](Self::emergency).
/// 3. **After an AL event** (the IRQ, or the AL event register that came back with an access):
///    [`handle_al_event`](Self::handle_al_event).
/// 4. **Until [`poll_access`](Self::poll_access) returns `None`:** perform the access, then
///    [`access_done`](Self::access_done) with the AL event register seen during it. After
///    each access the process-data side may look at [`process_data`](Self::process_data) and
///    [`event_mask`](Self::event_mask).
/// 5. **Serve the mailbox:** [`service_mailbox`](Self::service_mailbox) (or
///    [`service_mailbox_with`](Self::service_mailbox_with), with FoE or other protocol handlers)
///    until it returns `false`, with step 4 after each `true`.
/// 6. **Application events:** [`poll_event`](Self::poll_event) until `None`; answer
///    [`Event::TransitionRequested`] with [`complete_transition`](Self::complete_transition)
///    (step 4 again after it). [`pending_transition`](Self::pending_transition) and
///    [`awaits_application`](Self::awaits_application) tell whether an answer is still wanted.
/// 7. **Wait** for the IRQ or [`poll_timeout`](Self::poll_timeout), whichever comes first; at
///    the deadline [`handle_timeout`](Self::handle_timeout), then step 4.
///
/// What the core presents, at any time: [`state`](Self::state),
/// [`al_status`](Self::al_status), [`al_status_code`](Self::al_status_code),
/// [`sync_managers`](Self::sync_managers), [`config`](Self::config),
/// [`emergencies_dropped`](Self::emergencies_dropped).
#[derive(Debug)]
// `repr(C)`: the fields stay in this order, the small ones the state machine reads and writes
// most first (the pending transition, the access in flight, the flags and bytes, then
// halfwords, then words, without padding), the mailbox and the buffers last, so that Thumb's
// 16-bit loads and stores reach them from the start of the struct (bytes within 32, halfwords
// within 64, words within 128 bytes); the compiler's own order put the mailbox, and its
// buffers, first.
#[repr(C)]
pub struct SubDevice<'c, const MBX: usize = 128, L: Length = Len<MBX>> {
    pending: Option<Pending>,
    in_flight: Option<InFlight>,
    state: AlState,
    /// The parts of the register plan that may not be satisfied: what the next poll looks at.
    stale: Stale,
    /// The other register reads due, a bit each ([`read`](plan::read)).
    reads: u8,
    /// The bytes of SyncManager registers still to read, from 0x0800 on: read in chunks of
    /// [`SM_CHUNK`] from the end, the channels beyond SM3 first and SM0..SM3 last; 0 when no read
    /// is due.
    sm_unread: u8,
    indication: Indication,
    due: Due,
    /// What the process-data side reported since SAFEOP was entered.
    received: CycleSigns,
    code: AlStatusCode,
    device_id: u16,
    /// 0x0420 as last read.
    watchdog_time: u16,
    /// Why the current PDO configuration is unusable (0x0024, 0x0025); [`AlStatusCode::NO_ERROR`]
    /// when it is usable.
    pd_unusable: AlStatusCode,
    /// The process-image sizes of the current PDO configuration (none when it is unusable).
    pd_sizes: ProcessDataSizes,
    /// The sync mode the dictionary asks for, or why it cannot be.
    sync_mode: Result<sync_parameters::Requested, AlStatusCode>,
    config: &'c DeviceConfig,
    written: Written,
    /// What SDO writes changed since PREOP was entered from INIT: the entries of 0x1C32 the
    /// MainDevice wrote, and whether the process-data configuration changed since the last
    /// [`SubDevice::refresh_process_data`] (taken into `due` after each message).
    writes: Writes,
    /// The DC registers as last read.
    dc: DcSettings,
    mailbox: Mailbox<MBX>,
    /// CoE, the protocol every mailbox here speaks, beside the mailbox that frames it.
    coe: CoeServer<MBX, L>,
    /// When `last_emergency` raised its emergency. Apart from the code: a pair pads the code to
    /// the instant's 8 bytes.
    last_emergency_at: Instant,
    /// The application events not yet polled. The rings' free slots are `None` (the same size
    /// as the values): a constant of zeros (`Option<Event>`'s tag, `Option<Logged>`'s state),
    /// which the constructor writes with one `memclr` rather than copying a filler from flash.
    events: Ring<Option<Event>, 8>,
    /// The AL status codes set and not yet logged.
    logged: Ring<Option<Logged>, LOGGED>,
    channels: Channels,
    /// The last AL status code that raised an emergency (when: `last_emergency_at`). Last, by
    /// the byte buffer: among the halfwords it would pad the mailbox's start to 8 bytes; read
    /// only when a code is logged.
    last_emergency: AlStatusCode,
    buf: [u8; BUF_LEN],
    /// The low byte of the dictionary's
    /// [`ObjectDictionary::SYNC_MODES`](crate::dictionary::ObjectDictionary::SYNC_MODES), given
    /// to [`SubDevice::new`]: the modes' bits (free-run, SM, SYNC0, SYNC1). A byte, last: it
    /// takes the struct's tail padding (a `u16` among the halfwords cost 8 bytes of RAM).
    sync_modes: u8,
}
impl<'c, const MBX: usize, L: Length> SubDevice<'c, MBX, L> {
    /// A SubDevice in INIT. Its first accesses write the AL event mask, deactivate the
    /// SyncManagers through their PDI control registers and present INIT in AL status.
    /// The sync modes are the dictionary `D`'s
    /// ([`ObjectDictionary::SYNC_MODES`](crate::dictionary::ObjectDictionary::SYNC_MODES)).
    pub fn new<D: crate::dictionary::ObjectDictionary>(config: &'c DeviceConfig) -> Self {
        Self {
            config,
            sync_modes: D::SYNC_MODES.0 as u8,
            state: AlState::Init,
            indication: Indication::default(),
            code: AlStatusCode::NO_ERROR,
            device_id: 0,
            channels: Channels::default(),
            sm_unread: 0,
            reads: 0,
            watchdog_time: 0,
            dc: DcSettings::default(),
            written: Written::new(),
            in_flight: None,
            pending: None,
            events: const { Ring::new(None) },
            buf: [0; BUF_LEN],
            logged: const { Ring::new(None) },
            last_emergency: AlStatusCode::NO_ERROR,
            last_emergency_at: Instant::from_micros(0),
            mailbox: Mailbox::new(),
            coe: CoeServer::new(),
            stale: Stale::ALL,
            pd_sizes: config.process_data,
            pd_unusable: AlStatusCode::NO_ERROR,
            due: Due(Due::REFRESH | Due::LAYOUT),
            received: CycleSigns::default(),
            sync_mode: Ok(sync_parameters::Requested {
                mode: SyncMode::SmSynchronous,
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
            error: self.indication.error,
            id_loaded: self.indication.id_requested && !self.indication.error,
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
    /// A mask write counts from the [`poll_access`](Self::poll_access) that returns it: ask
    /// after [`access_done`](Self::access_done), as the driver's loop does.
    pub fn event_mask(&self) -> AlEvent {
        AlEvent(self.written.event_mask)
    }

    /// The SyncManager registers as last read.
    pub fn sync_managers(&self) -> &Channels {
        &self.channels
    }

    /// The next application event. Call it after the accesses are done, until it returns
    /// `None`.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.events.pop().flatten()
    }

    /// When [`SubDevice::handle_timeout`] must be called next, if ever. Ask before each wait:
    /// every call may move it.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        // The earliest as instants, the end of time standing for none (a deadline saturated
        // there is never reached either): one compare each, not an `Option` each.
        let transition = self.pending.map_or(NO_TIMEOUT, |p| p.deadline);
        let sdo = self.coe.poll_timeout().unwrap_or(NO_TIMEOUT);
        let first = transition.min(self.mailbox.deadline()).min(sdo);
        (first != NO_TIMEOUT).then_some(first)
    }

    /// The transition waiting for the application, if any.
    pub fn pending_transition(&self) -> Option<Transition> {
        self.pending.map(|p| p.transition)
    }

    /// Whether the pending transition still waits for the application's answer.
    pub fn awaits_application(&self) -> bool {
        self.pending.is_some_and(|p| !p.accepted)
    }
}
