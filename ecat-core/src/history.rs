//! The diagnosis history's storage (ETG.1020 §13): the messages and the ring they are logged
//! into, [`DiagnosisHistory<N>`] the dictionary field. A leaf under [`crate::diagnosis`] (which
//! re-exports it and adds object 0x10F3's SDO access and the emergencies) and the dictionary
//! (whose `diagnosis` hook lends the ring out as a [`History`]): it imports nothing of them.

use crate::time::Instant;

/// The subindex of the first message.
pub(crate) const FIRST_MESSAGE: u8 = 6;
/// Parameters a message carries at most.
pub const MAX_PARAMETERS: usize = 2;
/// The largest encoded message: 16 bytes of header, then each parameter's flags and 32-bit
/// value.
pub(crate) const MESSAGE_MAX: usize = 16 + MAX_PARAMETERS * 6;
/// The diag code of a message named by its text ID alone (ETG.1020: 0xE000..0xE7FF
/// manufacturer-specific codes; the text ID says what happened).
pub const DIAG_CODE: u32 = 0x0000_E000;

/// The CoE data type codes of a parameter (ETG.1000.6 Table 64): UNSIGNED8.
const UNSIGNED8: u16 = 0x0005;
/// UNSIGNED16.
const UNSIGNED16: u16 = 0x0006;
/// UNSIGNED32.
const UNSIGNED32: u16 = 0x0007;
/// INTEGER32.
const INTEGER32: u16 = 0x0004;

/// The flags (0x10F3:05).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Flags(pub u16);

impl Flags {
    /// Bit 0: send each new message as an emergency.
    pub(crate) const EMERGENCY: u16 = 1 << 0;
    /// Bit 1: info messages are not stored.
    pub(crate) const DISABLE_INFO: u16 = 1 << 1;
    /// Bit 2: warnings are not stored.
    pub(crate) const DISABLE_WARNING: u16 = 1 << 2;
    /// Bit 3: errors are not stored.
    pub(crate) const DISABLE_ERROR: u16 = 1 << 3;
    /// Bit 4: acknowledge mode (0: overwrite mode).
    pub(crate) const ACKNOWLEDGE_MODE: u16 = 1 << 4;
    /// Bit 5 (read-only): messages were lost unacknowledged.
    pub(crate) const LOST: u16 = 1 << 5;
    /// The bits the MainDevice writes.
    pub const WRITABLE: u16 = 0x1F;

    pub(crate) const fn has(self, bit: u16) -> bool {
        self.0 & bit != 0
    }
}

/// A message's type (flags bits 0..3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(u8)]
pub enum Severity {
    /// 0: information.
    #[default]
    Info = 0,
    /// 1: warning.
    Warning = 1,
    /// 2: error.
    Error = 2,
}

impl Severity {
    /// The flags bit that disables this type.
    const fn disable_bit(self) -> u16 {
        match self {
            Severity::Info => Flags::DISABLE_INFO,
            Severity::Warning => Flags::DISABLE_WARNING,
            Severity::Error => Flags::DISABLE_ERROR,
        }
    }
}

/// One parameter: a numeric value of at most 32 bits and its CoE data type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Parameter {
    data_type: u16,
    size: u8,
    value: u32,
}

impl Parameter {
    /// An UNSIGNED8.
    pub const fn u8(value: u8) -> Self {
        Self::new(UNSIGNED8, 1, value as u32)
    }
    /// An UNSIGNED16.
    pub const fn u16(value: u16) -> Self {
        Self::new(UNSIGNED16, 2, value as u32)
    }
    /// An UNSIGNED32.
    pub const fn u32(value: u32) -> Self {
        Self::new(UNSIGNED32, 4, value)
    }
    /// An INTEGER32.
    pub const fn i32(value: i32) -> Self {
        Self::new(INTEGER32, 4, value as u32)
    }

    const fn new(data_type: u16, size: u8, value: u32) -> Self {
        Self {
            data_type,
            size,
            value,
        }
    }
}

/// The text IDs of the mailbox error replies the stack logs ([`Message::mailbox_error`]): this
/// plus the detail code, 0x0101..=0x0108, above the AL status codes' 0x0001..=0x00FF.
pub const MAILBOX_ERROR_TEXT: u16 = 0x0100;

/// One diagnosis message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Message {
    /// The diag code ([`DIAG_CODE`] for a message its text ID names).
    pub code: u32,
    /// Info, warning or error.
    pub severity: Severity,
    /// The text ID the ESI's `DiagMessages` name.
    pub text_id: u16,
    /// When, on the local clock (flags bit 4 set).
    pub timestamp: Instant,
    parameters: [Parameter; MAX_PARAMETERS],
    count: u8,
}

impl Message {
    /// A message without parameters.
    pub const fn new(severity: Severity, text_id: u16, timestamp: Instant) -> Self {
        Self {
            code: DIAG_CODE,
            severity,
            text_id,
            timestamp,
            parameters: [Parameter::new(UNSIGNED8, 0, 0); MAX_PARAMETERS],
            count: 0,
        }
    }

    /// The stack's message for the AL status code `code` it set: an error whose text ID is the
    /// code.
    pub const fn al_status_code(code: u16, timestamp: Instant) -> Self {
        Self::new(Severity::Error, code, timestamp)
    }

    /// The stack's message for a request it answered with the mailbox error reply `code`
    /// (ETG.1000.4 Table 30): a warning (the device goes on; the MainDevice's request was
    /// refused) whose text ID is [`MAILBOX_ERROR_TEXT`] + the code.
    pub const fn mailbox_error(code: u16, timestamp: Instant) -> Self {
        Self::new(
            Severity::Warning,
            MAILBOX_ERROR_TEXT.wrapping_add(code),
            timestamp,
        )
    }

    /// Adds a parameter; beyond [`MAX_PARAMETERS`] it is ignored.
    #[must_use]
    pub fn with(mut self, parameter: Parameter) -> Self {
        if let Some(slot) = self.parameters.get_mut(usize::from(self.count)) {
            *slot = parameter;
            self.count += 1;
        }
        self
    }

    /// The flags word: type, bit 4 (local timestamp), the parameter count in bits 8..15.
    pub const fn flags(&self) -> u16 {
        self.severity as u16 | 1 << 4 | (self.count as u16) << 8
    }

    /// The message on the wire; returns the buffer and the length used.
    pub fn encode(&self) -> ([u8; MESSAGE_MAX], usize) {
        let mut out = [0; MESSAGE_MAX];
        let mut at = 0;
        let timestamp_ns = self.timestamp.as_micros().saturating_mul(1000);
        let mut put = |bytes: &[u8]| {
            let rest = out.get_mut(at..).unwrap_or_default();
            at += crate::bytes::copy(rest, bytes);
        };
        put(&self.code.to_le_bytes());
        put(&self.flags().to_le_bytes());
        put(&self.text_id.to_le_bytes());
        put(&timestamp_ns.to_le_bytes());
        for p in self.parameters.iter().take(usize::from(self.count)) {
            put(&p.data_type.to_le_bytes());
            let value = p.value.to_le_bytes();
            put(value.get(..usize::from(p.size)).unwrap_or_default());
        }
        (out, at)
    }
}

/// The state of a history apart from its messages: what every `N` shares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Log {
    /// The slot the next message goes to.
    pub(crate) next: u8,
    /// Messages stored (at most N).
    pub(crate) stored: u8,
    /// Of them, the newest ones not acknowledged.
    pub(crate) unacked: u8,
    /// 0x10F3:03 as written.
    pub(crate) acknowledged: u8,
    pub(crate) flags: Flags,
}

/// A history's log and messages, borrowed: what the stack logs into
/// ([`ObjectDictionary::diagnosis`](crate::dictionary::ObjectDictionary::diagnosis)).
#[derive(Debug)]
pub struct History<'a> {
    /// The state.
    pub log: &'a mut Log,
    /// The ring.
    pub messages: &'a mut [Message],
}

impl Log {
    /// The flags (0x10F3:05).
    pub const fn flags(&self) -> Flags {
        self.flags
    }

    /// The SI of the newest message (0x10F3:02), 0 when there is none.
    pub fn newest(&self, capacity: usize) -> u8 {
        if self.stored == 0 {
            return 0;
        }
        let slot = (usize::from(self.next) + capacity - 1) % capacity.max(1);
        FIRST_MESSAGE.saturating_add(slot as u8)
    }

    /// Stores `message` unless its type is disabled or, in acknowledge mode, every slot holds
    /// an unacknowledged message (then flags bit 5 is set). Returns whether it was stored.
    pub fn push(&mut self, messages: &mut [Message], message: Message) -> bool {
        let capacity = messages.len() as u8;
        if self.flags.has(message.severity.disable_bit()) || capacity == 0 {
            return false;
        }
        if self.unacked >= capacity {
            self.flags.0 |= Flags::LOST;
            if self.flags.has(Flags::ACKNOWLEDGE_MODE) {
                return false;
            }
        }
        if let Some(slot) = messages.get_mut(usize::from(self.next)) {
            *slot = message;
        }
        self.next = (self.next + 1) % capacity;
        self.stored = (self.stored + 1).min(capacity);
        self.unacked = (self.unacked + 1).min(capacity);
        true
    }
}

/// A diagnosis history of `N` messages (1..=250), the field the `diagnosis` item of
/// [`dictionary!`](crate::dictionary!) maps at 0x10F3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DiagnosisHistory<const N: usize> {
    /// The state.
    pub log: Log,
    /// The ring.
    pub messages: [Message; N],
}

impl<const N: usize> Default for DiagnosisHistory<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> DiagnosisHistory<N> {
    /// Empty, overwrite mode, no emergencies.
    pub const fn new() -> Self {
        const {
            assert!(
                N >= 1 && N <= 250,
                "a diagnosis history holds 1..=250 messages"
            )
        };
        Self {
            log: Log {
                next: 0,
                stored: 0,
                unacked: 0,
                acknowledged: 0,
                flags: Flags(0),
            },
            messages: [Message::new(Severity::Info, 0, Instant::from_micros(0)); N],
        }
    }

    /// Borrowed as the stack logs into it.
    pub fn history(&mut self) -> History<'_> {
        History {
            log: &mut self.log,
            messages: &mut self.messages,
        }
    }

    /// Stores `message` ([`Log::push`]).
    pub fn push(&mut self, message: Message) -> bool {
        self.log.push(&mut self.messages, message)
    }
}
