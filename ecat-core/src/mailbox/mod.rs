//! The mailbox (ETG.1000.4 §5.6, ETG.1000.6 §5.4): SM0 carries messages from the MainDevice,
//! SM1 messages to it. This module owns both buffers and the protocol around them:
//!
//! - the 6-byte [`MailboxHeader`]; a message with length 0 or longer than the mailbox is
//!   answered with a mailbox error reply ([`MailboxError`]), and so is a CoE payload shorter
//!   than its service needs (0x0008: an SDO request under 8 bytes, an SDO Information request
//!   without its header and the fixed part of its opcode,
//!   [`InfoRequest::parse`](crate::coe::sdo_info::InfoRequest::parse));
//! - counters: a message whose non-zero counter equals the previous one is a repeat and is
//!   dropped; the SubDevice numbers its own messages 1..=7;
//! - the channel (header byte 4, bits 0..5) is reserved and 0 (ETG.1000.4 Table 29): a new
//!   message with another channel gets 0x0003 "invalid channel" (ETG.1000.4 Table 30), checked
//!   after the length and repeat checks, before the protocol. The priority (bits 6..7) and the
//!   address are not judged. SSC 5.12 and SOES never send 0x0003 (they define it and read no
//!   channel); every MainDevice known writes channel 0 (SOEM, IgH, ethercrab), so the error
//!   reaches only a malformed message;
//! - flow control: a request is read from SM0 only when its answer can be sent, so nothing is
//!   ever lost or queued unboundedly; what the SubDevice sends on its own (SDO Information
//!   fragments, emergencies) waits until SM1 is free;
//! - repeat: when the MainDevice toggles SM1's repeat request, the last message is written again
//!   before the acknowledge bit follows it;
//! - dispatch by protocol ([`Handler`]): the first handler (CoE, which the SubDevice keeps
//!   beside the mailbox, `coe::server`) and the handlers the firmware adds ([`Handlers`], e.g.
//!   [`crate::foe::Foe`]); a protocol without a handler, or one its handler does not speak in
//!   the current state, gets "protocol not supported" (0x0002). In BOOT only FoE is served
//!   (ETG.1000.6 §6.4.1, conformance.md "ESM").
//!
//! The mailbox knows protocols only as [`Handler`]s: it imports no protocol (the layering of
//! docs/architecture.md: the protocols sit above the framing).

mod error;
mod handler;
mod header;

pub use error::MailboxError;
pub use handler::{Env, Handler, Handlers, Reply};
pub use header::{MailboxHeader, MailboxType, next_counter};

use crate::device::{Area, MailboxConfig};
use crate::time::Instant;
use crate::{AlEvent, AlState};

/// The bits of [`Mailbox`]'s state: one byte, so that each question the flow control asks
/// (may a request be read, is a write due, is there work) is one test.
mod flag {
    /// SM0 holds a message the SubDevice has not read yet.
    pub(super) const RX_WAITING: u8 = 1 << 0;
    /// The receive buffer holds a request not yet served.
    pub(super) const RX_PENDING: u8 = 1 << 1;
    /// The send buffer holds a message not yet written to SM1.
    pub(super) const TX_PENDING: u8 = 1 << 2;
    /// SM1 holds a message the MainDevice has not read yet.
    pub(super) const SEND_BUSY: u8 = 1 << 3;
    /// SM1's repeat request differs from the acknowledge: the last message is written again,
    /// then the acknowledge follows the request.
    pub(super) const REPEAT_PENDING: u8 = 1 << 4;
    /// The repeat acknowledge bit as last written to SM1's PDI control.
    pub(super) const REPEAT_ACK: u8 = 1 << 5;
    /// One of the handlers beside CoE had a message of its own after the last service.
    pub(super) const HANDLER_MESSAGE: u8 = 1 << 6;
    /// What keeps a request in SM0: its answer could not be written at once.
    pub(super) const BLOCKING: u8 = RX_PENDING | TX_PENDING | SEND_BUSY | REPEAT_PENDING;
    /// What keeps SM1 from taking a new message.
    pub(super) const SM1_TAKEN: u8 = TX_PENDING | SEND_BUSY | REPEAT_PENDING;
}

/// What the handlers beside CoE need from the next service whether SM1 is free or not: a byte
/// of its own beside [`flag`], so that a device without such handlers tests nothing more.
mod due {
    /// The handlers have not been reset since the mailbox stopped.
    pub(super) const RESET: u8 = 1 << 0;
    /// A handler's timeout passed.
    pub(super) const TIMEOUT: u8 = 1 << 1;
}

/// [`Mailbox`]'s handlers' timeout when there is none: the end of time, which a handler's
/// deadline (saturating) reaches only as "never" too.
pub(crate) const NO_TIMEOUT: Instant = Instant::from_micros(u64::MAX);

/// The mailbox of a SubDevice whose mailboxes hold at most `N` bytes: what SM0 and SM1 hold,
/// counters, the repeat handshake and the buffers.
#[derive(Debug)]
// `repr(C)`: the flags, counters and areas first, the buffers last (see `SubDevice`); the
// timeout and the message's length before the flags, an order measured (docs/performance.md,
// session 12).
#[repr(C)]
pub(crate) struct Mailbox<const N: usize> {
    /// The earliest timeout of the handlers beside the first after the last service;
    /// [`NO_TIMEOUT`] when none (an `Option<Instant>` is 16 bytes: the instant has no niche).
    /// First (the one 8-byte field): the small fields behind it, zero in a new mailbox but
    /// `handler_due`, run into the buffers; the state-machine task's mailbox service is 72
    /// bytes smaller this way (docs/size-history.md, session 12).
    handler_timeout: Instant,
    /// Length of the last message built in `tx` (header included): at most SM1's length, a
    /// `u16` like it (a `usize` padded the struct by 8 bytes).
    tx_len: u16,
    /// What SM0 and SM1 hold, what is on its way between them, SM1's repeat handshake
    /// ([`flag`]).
    flags: u8,
    /// What the handlers beside the first need from the next service ([`due`]).
    handler_due: u8,
    /// The counter of the last message received (0: none).
    rx_counter: u8,
    /// The counter of the last message sent (0: none).
    tx_counter: u8,
    /// The detail code of the last error reply to a request not yet taken
    /// ([`Mailbox::take_refused`]); 0: none.
    refused: u16,
    /// SM0, its length clamped to `N`.
    receive: Area,
    /// SM1, its length clamped to `N` (the error-reply length check and the message capacity).
    send: Area,
    rx: [u8; N],
    tx: [u8; N],
}

impl<const N: usize> Default for Mailbox<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Mailbox<N> {
    /// An idle mailbox.
    pub(crate) const fn new() -> Self {
        Self {
            rx: [0; N],
            tx: [0; N],
            tx_len: 0,
            receive: Area::new(0, 0),
            send: Area::new(0, 0),
            flags: 0,
            handler_due: due::RESET,
            rx_counter: 0,
            tx_counter: 0,
            refused: 0,
            handler_timeout: NO_TIMEOUT,
        }
    }

    /// Starts a new or stopped ([`Mailbox::stop`]) mailbox on SM0/SM1 of `config` (it keeps
    /// what a running one holds: only the SubDevice, which stops it first, starts it); the
    /// repeat acknowledge starts equal to the request bit ("copy the request bit into the ack bit
    /// at mailbox start").
    pub(crate) fn start(&mut self, config: MailboxConfig, repeat_request: bool) {
        let clamp = |area: Area| {
            let length = usize::from(area.length).min(N);
            Area::new(area.start, u16::try_from(length).unwrap_or(area.length))
        };
        self.receive = clamp(config.receive);
        self.send = clamp(config.send);
        if repeat_request {
            self.flags = flag::REPEAT_ACK;
        }
    }

    /// Stops the mailbox: everything in flight is dropped. The state is reset field by field
    /// and the buffers are left as they are (no message is in them once the flags and
    /// `tx_len` say so): a copy of a whole new mailbox costs ≈ 40 B of flash more.
    pub(crate) fn stop(&mut self) {
        let Self {
            flags,
            handler_due,
            rx_counter,
            tx_counter,
            refused,
            receive,
            send,
            tx_len,
            handler_timeout,
            rx: _,
            tx: _,
        } = self;
        (*flags, *handler_due, *rx_counter, *tx_counter, *refused) = (0, due::RESET, 0, 0, 0);
        (*receive, *send, *tx_len, *handler_timeout) =
            (Area::new(0, 0), Area::new(0, 0), 0, NO_TIMEOUT);
    }

    /// The MainDevice filled SM0 (AL event bit 8).
    pub(crate) fn receive_event(&mut self) {
        self.flags |= flag::RX_WAITING;
    }

    /// The MainDevice read SM1 (AL event bit 9).
    pub(crate) fn send_event(&mut self) {
        self.flags &= !flag::SEND_BUSY;
    }

    /// SM1's activate register as last read: a toggled repeat request asks for the last message
    /// again.
    pub(crate) fn repeat_request(&mut self, request: bool) {
        if request != self.repeat_ack() && self.tx_len != 0 {
            // The acknowledge stays until the last message is written again.
            self.flags |= flag::REPEAT_PENDING;
        } else {
            // Acknowledged already (or toggled back), or nothing was ever sent: nothing to
            // repeat, the acknowledge follows at once.
            self.flags &= !(flag::REPEAT_PENDING | flag::REPEAT_ACK);
            if request {
                self.flags |= flag::REPEAT_ACK;
            }
        }
    }

    /// The SM0/SM1 bits the AL event mask needs now ([`Mailbox::wants_receive_event`],
    /// [`Mailbox::wants_send_event`]); `first_message` tells whether the first handler has a
    /// message of its own (asked only when it matters).
    pub(crate) fn event_mask(&self, first_message: impl FnOnce() -> bool) -> AlEvent {
        let mut mask = AlEvent::NONE;
        if self.wants_receive_event() {
            mask |= AlEvent::sync_manager(0);
        }
        if self.wants_send_event(first_message) {
            mask |= AlEvent::sync_manager(1);
        }
        mask
    }

    /// Whether SM0 may be read now: its answer could be sent at once.
    pub(crate) fn can_receive(&self) -> bool {
        self.flags & flag::BLOCKING == 0
    }

    /// Whether a repeat request waits for the last message to be written again.
    pub(crate) fn repeat_pending(&self) -> bool {
        self.flags & flag::REPEAT_PENDING != 0
    }

    /// Whether the SM0 event belongs in the AL event mask: always, except while a request
    /// already waits in SM0 that cannot be read yet (its event would hold the IRQ line).
    pub(crate) fn wants_receive_event(&self) -> bool {
        self.flags & flag::RX_WAITING == 0 || self.can_receive()
    }

    /// Whether the SM1 event belongs in the AL event mask: only while SM1 holds an unread message
    /// and something waits for it to be read (a request, a fragment, an emergency). In the usual
    /// request/answer rhythm the MainDevice reads SM1 before it writes the next request, and the
    /// SM1 bit, still latched in the AL event register, arrives with the SM0 event.
    /// `first_message` tells whether the first handler (CoE) has a message of its own: its
    /// messages (emergencies) are queued between services, so the caller asks it, and only when
    /// the answer matters.
    pub(crate) fn wants_send_event(&self, first_message: impl FnOnce() -> bool) -> bool {
        let more = self.flags & (flag::TX_PENDING | flag::RX_WAITING | flag::HANDLER_MESSAGE) != 0
            || first_message();
        self.flags & flag::SEND_BUSY != 0 && more
    }

    /// Whether SM0 should be read now.
    pub(crate) fn read_due(&self) -> bool {
        self.flags & (flag::RX_WAITING | flag::BLOCKING) == flag::RX_WAITING
    }

    /// SM0's address and the receive buffer for reading it (SM0's length).
    pub(crate) fn rx_buffer(&mut self) -> (u16, &mut [u8]) {
        let size = self.receive_size();
        (
            self.receive.start,
            self.rx.get_mut(..size).unwrap_or_default(),
        )
    }

    /// Whether a request read from SM0 waits to be served.
    pub(crate) fn request_pending(&self) -> bool {
        self.flags & flag::RX_PENDING != 0
    }

    /// SM0 was read into the receive buffer.
    pub(crate) fn received(&mut self) {
        self.flags = (self.flags & !flag::RX_WAITING) | flag::RX_PENDING;
    }

    /// Whether a message must be written to SM1 now: the next message, or the last one again.
    pub(crate) fn write_due(&self) -> bool {
        self.flags & (flag::TX_PENDING | flag::SEND_BUSY) == flag::TX_PENDING
            || self.repeat_pending()
    }

    /// What writing the message into SM1 takes: SM1's address, the message (the last one built)
    /// and, when it is shorter than SM1, the address of SM1's last byte, whose write hands SM1
    /// to the MainDevice.
    pub(crate) fn message(&self) -> (u16, &[u8], Option<u16>) {
        let message = self.tx.get(..usize::from(self.tx_len)).unwrap_or_default();
        let last = self
            .send
            .start
            .saturating_add(self.send.length.saturating_sub(1));
        let short = message.len() < self.send_size();
        (self.send.start, message, short.then_some(last))
    }

    /// The message ([`Mailbox::message`]) is now in SM1.
    pub(crate) fn written(&mut self) {
        // The acknowledge follows the request: it toggles if a repeat was pending.
        let toggle = if self.repeat_pending() {
            flag::REPEAT_ACK
        } else {
            0
        };
        self.flags ^= toggle;
        self.flags &= !(flag::TX_PENDING | flag::REPEAT_PENDING);
        self.flags |= flag::SEND_BUSY;
    }

    /// The repeat acknowledge bit for SM1's PDI control.
    pub(crate) fn repeat_ack(&self) -> bool {
        self.flags & flag::REPEAT_ACK != 0
    }

    /// When [`Mailbox::handle_timeout`] must be called: a handler's timeout as of the last
    /// service (the first handler's own the caller asks it for); [`NO_TIMEOUT`] when none.
    pub(crate) fn deadline(&self) -> Instant {
        self.handler_timeout
    }

    /// A handler's timeout that passed makes work for the next service, which hands it on.
    pub(crate) fn handle_timeout(&mut self, now: Instant) {
        // `NO_TIMEOUT` passes only at the end of time, as a handler's saturated deadline would.
        if self.handler_timeout <= now {
            self.handler_due |= due::TIMEOUT;
        }
    }

    /// Whether the mailbox has anything to serve: SM1 is free and a request or a message of a
    /// handler's own (`first_message`: the first handler's, an SDO Information fragment or an
    /// emergency) waits for it, or a handler's timeout passed.
    pub(crate) fn has_work(&self, first_message: impl FnOnce() -> bool) -> bool {
        let free = self.flags & flag::SM1_TAKEN == 0;
        let messages = flag::RX_PENDING | flag::HANDLER_MESSAGE;
        free && (self.flags & messages != 0 || first_message())
            || self.handler_due & due::TIMEOUT != 0
    }

    /// Serves what is due, once [`Mailbox::has_work`] says there is something: the received
    /// message, or else the next message of a handler's own (SM1 is free then). `first` is the
    /// protocol every device with a mailbox speaks (CoE), whose timeouts and messages the caller
    /// keeps track of; `handlers` are the firmware's others. Returns whether a message was built
    /// (a request may be dropped without one). Bounded: one message per call.
    pub(crate) fn serve<F: Handler, P: Handlers>(
        &mut self,
        first: F,
        handlers: &mut P,
        state: AlState,
        now: Instant,
    ) -> bool {
        let env = Env {
            state,
            now,
            max_request: self.receive_size().saturating_sub(MailboxHeader::SIZE),
        };
        if P::NONE {
            return self.serve_handlers(&mut (first, handlers), env);
        }
        if self.handler_due & due::RESET != 0 {
            handlers.reset();
        }
        if self.handler_due & due::TIMEOUT != 0 {
            handlers.handle_timeout(env.now);
        }
        self.handler_due = 0;
        // SM1 may be taken: the service may be for a timeout alone.
        let built = self.flags & flag::SM1_TAKEN == 0
            && self.serve_handlers(&mut (first, &mut *handlers), env);
        self.handler_timeout = handlers.poll_timeout().unwrap_or(NO_TIMEOUT);
        self.flags &= !flag::HANDLER_MESSAGE;
        if handlers.has_message() {
            self.flags |= flag::HANDLER_MESSAGE;
        }
        built
    }

    fn receive_size(&self) -> usize {
        usize::from(self.receive.length)
    }

    fn send_size(&self) -> usize {
        usize::from(self.send.length)
    }

    /// Serves the received request, or else the handlers' next message, and builds the answer
    /// (one place: `build` is inline on the way of every message).
    fn serve_handlers<P: Handlers>(&mut self, handlers: &mut P, env: Env) -> bool {
        let message = if self.flags & flag::RX_PENDING != 0 {
            self.flags &= !flag::RX_PENDING;
            self.serve_request(handlers, env)
        } else {
            let capacity = self.send_size().saturating_sub(MailboxHeader::SIZE);
            let out = self
                .tx
                .get_mut(MailboxHeader::SIZE..MailboxHeader::SIZE + capacity)
                .unwrap_or_default();
            handlers
                .message(env, out)
                .map(|(kind, len)| (kind.code(), len))
        };
        match message {
            Some((code, len)) => {
                self.build(code, len);
                true
            }
            None => false,
        }
    }

    /// The answer to the received request, in `tx` behind the header: its type and length;
    /// `None` for none (a repeat, or a request its handler answers with silence).
    fn serve_request<P: Handlers>(&mut self, handlers: &mut P, env: Env) -> Option<(u8, usize)> {
        let header = MailboxHeader::parse(&self.rx)?;
        let length = usize::from(header.length);
        if length == 0 {
            return Some(self.error_reply(MailboxError::INVALID_HEADER));
        }
        if length > env.max_request {
            return Some(self.error_reply(MailboxError::INVALID_SIZE));
        }
        if header.counter != 0 && header.counter == self.rx_counter {
            return None;
        }
        self.rx_counter = header.counter;
        if header.channel != 0 {
            return Some(self.error_reply(MailboxError::INVALID_CHANNEL));
        }
        let start = MailboxHeader::SIZE;
        let payload = self.rx.get(start..start + length).unwrap_or_default();
        let capacity = self.send_size().saturating_sub(MailboxHeader::SIZE);
        let out = self.tx.get_mut(start..start + capacity).unwrap_or_default();
        let code = header::code(&self.rx);
        match handlers.request(code, env, payload, out) {
            Some(Reply::Send(len)) => Some((code, len)),
            Some(Reply::Silent) => None,
            Some(Reply::Error(error)) => Some(self.error_reply(error)),
            None => Some(self.error_reply(MailboxError::UNSUPPORTED_PROTOCOL)),
        }
    }

    /// The error reply to the last request, once: what the SubDevice logs in the diagnosis
    /// history (ETG.1020 §13: the stack's own events).
    pub(crate) fn take_refused(&mut self) -> Option<MailboxError> {
        // Tested before it is cleared: no store on the service's way when nothing was refused.
        if self.refused == 0 {
            return None;
        }
        Some(MailboxError(core::mem::take(&mut self.refused)))
    }

    /// Writes the error reply `error` behind the header and notes it ([`Mailbox::take_refused`]):
    /// its type and length.
    #[inline(never)] // four callers, none on the answers' way
    fn error_reply(&mut self, error: MailboxError) -> (u8, usize) {
        self.refused = error.0;
        let payload = error.payload();
        if let Some(dst) = self
            .tx
            .get_mut(MailboxHeader::SIZE..MailboxHeader::SIZE + payload.len())
        {
            dst.copy_from_slice(&payload);
        }
        (MailboxType::Error.code(), payload.len())
    }

    /// Puts the header in front of `len` bytes already in `tx`, with the next counter.
    fn build(&mut self, code: u8, len: usize) {
        self.tx_counter = next_counter(self.tx_counter);
        let length = u16::try_from(len).unwrap_or(u16::MAX);
        let header = header::bytes(code, length, self.tx_counter);
        if let Some(dst) = self.tx.get_mut(..MailboxHeader::SIZE) {
            dst.copy_from_slice(&header);
        }
        let end = (MailboxHeader::SIZE + len).min(N);
        self.tx_len = u16::try_from(end).unwrap_or(u16::MAX);
        self.flags |= flag::TX_PENDING;
    }
}
