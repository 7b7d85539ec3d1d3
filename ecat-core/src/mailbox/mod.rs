//! The mailbox (ETG.1000.4 §5.6, ETG.1000.6 §5.4): SM0 carries messages from the MainDevice,
//! SM1 messages to it. This module owns both buffers and the protocol around them:
//!
//! - the 6-byte [`MailboxHeader`]; a message with length 0 or longer than the mailbox is
//!   answered with a mailbox error reply ([`MailboxError`]), and so is a CoE payload shorter
//!   than its service needs (0x0008: an SDO request under 8 bytes, an SDO Information request
//!   without its header and the fixed part of its opcode, [`InfoRequest::parse`]);
//! - counters: a message whose non-zero counter equals the previous one is a repeat and is
//!   dropped; the SubDevice numbers its own messages 1..=7;
//! - flow control: a request is read from SM0 only when its answer can be sent, so nothing is
//!   ever lost or queued unboundedly; what the SubDevice sends on its own (SDO Information
//!   fragments, emergencies) waits until SM1 is free;
//! - repeat: when the MainDevice toggles SM1's repeat request, the last message is written again
//!   before the acknowledge bit follows it;
//! - dispatch by protocol: CoE (SDO, SDO Information); every other protocol gets "protocol not
//!   supported" (0x0002). In BOOT only FoE would be served (ETG.1000.6 §6.4.1, conformance.md
//!   "ESM"), and FoE is not implemented: in BOOT every protocol, FoE included, gets 0x0002.

mod error;
mod header;

pub use error::MailboxError;
pub use header::{MailboxHeader, MailboxType, next_counter};

use crate::AlEvent;
use crate::AlState;
use crate::coe::sdo::{self, Context, SdoServer};
use crate::coe::sdo_info::{InfoRequest, SdoInfo};
use crate::coe::{AbortCode, CoeHeader, Emergency, Service};
use crate::device::{Area, MailboxConfig};
use crate::dictionary::{ObjectDictionary, ObjectHooks};
use crate::ring::Ring;
use crate::time::Instant;

/// How many emergencies wait for SM1 at most; when full the oldest is dropped and counted.
/// They wait only while the MainDevice leaves SM1 unread, and a MainDevice that polls the
/// mailbox takes one per poll; 4 is also what `SharedEsc` holds between two turns of the
/// state-machine runner, so both queues are the same type (one copy of its code).
pub const EMERGENCY_QUEUE: usize = 4;

/// The mailbox state and buffers of a SubDevice whose mailboxes hold at most `N` bytes.
#[derive(Debug)]
pub struct Mailbox<const N: usize> {
    rx: [u8; N],
    tx: [u8; N],
    /// Length of the last message built in `tx` (header included).
    tx_len: usize,
    /// SM0, its length clamped to `N`.
    receive: Area,
    /// SM1, its length clamped to `N` (the error-reply length check and the message capacity).
    send: Area,
    /// SM0 holds a message the SubDevice has not read yet.
    rx_waiting: bool,
    /// `rx` holds a message not yet served.
    rx_pending: bool,
    /// `tx` holds a message not yet written to SM1.
    tx_pending: bool,
    /// SM1 holds a message the MainDevice has not read yet.
    send_busy: bool,
    /// The counter of the last message received (0: none).
    rx_counter: u8,
    /// The counter of the last message sent (0: none).
    tx_counter: u8,
    /// The repeat acknowledge bit as last written to SM1's PDI control.
    repeat_ack: bool,
    /// The repeat request bit as last read from SM1's activate register.
    repeat_request: bool,
    sdo: SdoServer<N>,
    sdo_info: SdoInfo,
    emergencies: Ring<Emergency, EMERGENCY_QUEUE>,
}

impl<const N: usize> Default for Mailbox<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Mailbox<N> {
    /// An idle mailbox.
    pub const fn new() -> Self {
        Self {
            rx: [0; N],
            tx: [0; N],
            tx_len: 0,
            receive: Area::new(0, 0),
            send: Area::new(0, 0),
            rx_waiting: false,
            rx_pending: false,
            tx_pending: false,
            send_busy: false,
            rx_counter: 0,
            tx_counter: 0,
            repeat_ack: false,
            repeat_request: false,
            sdo: SdoServer::new(),
            sdo_info: SdoInfo::new(),
            emergencies: Ring::new(Emergency::NONE),
        }
    }

    /// Starts the mailbox on SM0/SM1 of `config`; the repeat acknowledge starts equal to the
    /// request bit ("copy the request bit into the ack bit at mailbox start").
    pub fn start(&mut self, config: MailboxConfig, repeat_request: bool) {
        *self = Self::new();
        let clamp = |area: Area| {
            let length = usize::from(area.length).min(N);
            Area::new(area.start, u16::try_from(length).unwrap_or(area.length))
        };
        self.receive = clamp(config.receive);
        self.send = clamp(config.send);
        self.repeat_request = repeat_request;
        self.repeat_ack = repeat_request;
    }

    /// Stops the mailbox: everything in flight is dropped, queued emergencies too.
    pub fn stop(&mut self) {
        *self = Self::new();
    }

    /// The MainDevice filled SM0 (AL event bit 8).
    pub fn receive_event(&mut self) {
        self.rx_waiting = true;
    }

    /// The MainDevice read SM1 (AL event bit 9).
    pub fn send_event(&mut self) {
        self.send_busy = false;
    }

    /// SM1's activate register as last read: a toggled repeat request asks for the last message
    /// again.
    pub fn repeat_request(&mut self, request: bool) {
        self.repeat_request = request;
        if self.tx_len == 0 {
            // Nothing was ever sent: nothing to repeat, acknowledge at once.
            self.repeat_ack = request;
        }
    }

    /// The SM0/SM1 bits the AL event mask needs now ([`Mailbox::wants_receive_event`],
    /// [`Mailbox::wants_send_event`]).
    pub fn event_mask(&self) -> AlEvent {
        let mut mask = AlEvent::NONE;
        if self.wants_receive_event() {
            mask |= AlEvent::sync_manager(0);
        }
        if self.wants_send_event() {
            mask |= AlEvent::sync_manager(1);
        }
        mask
    }

    /// Whether SM0 may be read now: its answer could be sent at once.
    pub fn can_receive(&self) -> bool {
        !self.rx_pending && !self.tx_pending && !self.send_busy && !self.repeat_pending()
    }

    /// Whether a repeat request waits for the last message to be written again.
    pub fn repeat_pending(&self) -> bool {
        self.repeat_request != self.repeat_ack
    }

    /// Whether the SM0 event belongs in the AL event mask: always, except while a request
    /// already waits in SM0 that cannot be read yet (its event would hold the IRQ line).
    pub fn wants_receive_event(&self) -> bool {
        !self.rx_waiting || self.can_receive()
    }

    /// Whether the SM1 event belongs in the AL event mask: only while SM1 holds an unread message
    /// and something waits for it to be read (a request, a fragment, an emergency). In the usual
    /// request/answer rhythm the MainDevice reads SM1 before it writes the next request, and the
    /// SM1 bit, still latched in the AL event register, arrives with the SM0 event.
    pub fn wants_send_event(&self) -> bool {
        let more = self.tx_pending
            || self.rx_waiting
            || self.sdo_info.is_pending()
            || !self.emergencies.is_empty();
        self.send_busy && more
    }

    /// Whether SM0 should be read now.
    pub fn read_due(&self) -> bool {
        self.rx_waiting && self.can_receive()
    }

    /// SM0's address and the receive buffer for reading it (SM0's length).
    pub fn rx_buffer(&mut self) -> (u16, &mut [u8]) {
        let size = self.receive_size();
        (
            self.receive.start,
            self.rx.get_mut(..size).unwrap_or_default(),
        )
    }

    fn receive_size(&self) -> usize {
        usize::from(self.receive.length)
    }

    /// Whether a request read from SM0 waits to be served.
    pub fn request_pending(&self) -> bool {
        self.rx_pending
    }

    /// SM0 was read into the receive buffer.
    pub fn received(&mut self) {
        self.rx_waiting = false;
        self.rx_pending = true;
    }

    /// Whether a message must be written to SM1 now: the next message, or the last one again.
    pub fn write_due(&self) -> bool {
        (self.tx_pending && !self.send_busy) || self.repeat_pending()
    }

    /// What writing the message into SM1 takes: SM1's address, the message (the last one built)
    /// and, when it is shorter than SM1, the address of SM1's last byte, whose write hands SM1
    /// to the MainDevice.
    pub fn message(&self) -> (u16, &[u8], Option<u16>) {
        let message = self.tx.get(..self.tx_len).unwrap_or_default();
        let last = self
            .send
            .start
            .saturating_add(self.send.length.saturating_sub(1));
        let short = message.len() < self.send_size();
        (self.send.start, message, short.then_some(last))
    }

    fn send_size(&self) -> usize {
        usize::from(self.send.length)
    }

    /// The message ([`Mailbox::message`]) is now in SM1.
    pub fn written(&mut self) {
        self.tx_pending = false;
        self.send_busy = true;
        self.repeat_ack = self.repeat_request;
    }

    /// The repeat acknowledge bit for SM1's PDI control.
    pub fn repeat_ack(&self) -> bool {
        self.repeat_ack
    }

    /// Queues an emergency; when the queue is full the oldest is dropped (see
    /// [`Mailbox::emergencies_dropped`]).
    pub fn emergency(&mut self, emergency: Emergency) {
        self.emergencies.push(emergency);
    }

    /// Emergencies dropped because the queue was full.
    pub fn emergencies_dropped(&self) -> u16 {
        self.emergencies.dropped()
    }

    /// When [`Mailbox::handle_timeout`] must be called.
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.sdo.poll_timeout()
    }

    /// Expires an SDO transfer that waited too long for its next segment.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.sdo.handle_timeout(now);
    }

    /// Whether [`Mailbox::service`] has anything to do: SM1 is free and a request, an SDO
    /// Information fragment or an emergency waits for it.
    fn has_work(&self) -> bool {
        let free = !self.tx_pending && !self.send_busy && !self.repeat_pending();
        free && (self.rx_pending || self.sdo_info.is_pending() || !self.emergencies.is_empty())
    }

    /// Serves what is due: the received message, or else the next fragment or emergency when SM1
    /// is free. Returns `None` when nothing was due, else whether a message was built (a request
    /// may be dropped without one). Bounded: one message per call.
    #[inline]
    pub fn service<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
    ) -> Option<bool> {
        // Inline: the caller's loop asks once more after each message, and SM1 is busy then.
        if !self.has_work() {
            return None;
        }
        self.serve(cx)
    }

    /// [`Mailbox::service`] once it has work.
    fn serve<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
    ) -> Option<bool> {
        if core::mem::take(&mut self.rx_pending) {
            return Some(self.serve_request(cx));
        }
        let capacity = self.send_size().saturating_sub(MailboxHeader::SIZE);
        let out = self
            .tx
            .get_mut(MailboxHeader::SIZE..MailboxHeader::SIZE + capacity)
            .unwrap_or_default();
        if let Some(len) = self.sdo_info.next_fragment::<D>(out) {
            return Some(self.build(MailboxType::Coe, len));
        }
        let emergency = self.emergencies.pop()?;
        Some(self.build_emergency(emergency))
    }

    fn serve_request<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
    ) -> bool {
        let Some(header) = MailboxHeader::parse(&self.rx) else {
            return false;
        };
        let length = usize::from(header.length);
        if length == 0 {
            return self.build_error(MailboxError::INVALID_HEADER);
        }
        if length > self.receive_size().saturating_sub(MailboxHeader::SIZE) {
            return self.build_error(MailboxError::INVALID_SIZE);
        }
        if header.counter != 0 && header.counter == self.rx_counter {
            return false;
        }
        self.rx_counter = header.counter;
        match header.kind {
            MailboxType::Coe if cx.state != AlState::Boot => self.serve_coe(cx, length),
            _ => self.build_error(MailboxError::UNSUPPORTED_PROTOCOL),
        }
    }

    fn serve_coe<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
        length: usize,
    ) -> bool {
        let start = MailboxHeader::SIZE;
        let message = self.rx.get(start..start + length).unwrap_or_default();
        let Some(coe) = CoeHeader::parse(message) else {
            return self.build_error(MailboxError::INVALID_SIZE);
        };
        let payload = message.get(CoeHeader::SIZE..).unwrap_or_default();
        let capacity = self.send_size().saturating_sub(MailboxHeader::SIZE);
        let out = self.tx.get_mut(start..start + capacity).unwrap_or_default();
        let len = match coe.service {
            Service::SdoRequest if payload.len() < 8 => {
                return self.build_error(MailboxError::INVALID_SIZE);
            }
            Service::SdoRequest => self.sdo.request(cx, payload, out),
            Service::SdoInformation => match InfoRequest::parse(payload) {
                Some(request) => self.sdo_info.request::<D>(request, out),
                None => {
                    self.sdo_info.abandon();
                    return self.build_error(MailboxError::INVALID_SIZE);
                }
            },
            _ => sdo::abort(out, 0, 0, AbortCode::UNSUPPORTED_ACCESS),
        };
        len > 0 && self.build(MailboxType::Coe, len)
    }

    fn build_error(&mut self, error: MailboxError) -> bool {
        let payload = error.payload();
        if let Some(dst) = self
            .tx
            .get_mut(MailboxHeader::SIZE..MailboxHeader::SIZE + payload.len())
        {
            dst.copy_from_slice(&payload);
        }
        self.build(MailboxType::Error, payload.len())
    }

    fn build_emergency(&mut self, emergency: Emergency) -> bool {
        let start = MailboxHeader::SIZE;
        let coe = CoeHeader::new(Service::Emergency).to_bytes();
        if let Some(dst) = self.tx.get_mut(start..start + CoeHeader::SIZE) {
            dst.copy_from_slice(&coe);
        }
        let data = start + CoeHeader::SIZE;
        if let Some(dst) = self.tx.get_mut(data..data + Emergency::SIZE) {
            dst.copy_from_slice(&emergency.to_bytes());
        }
        self.build(MailboxType::Coe, CoeHeader::SIZE + Emergency::SIZE)
    }

    /// Puts the header in front of `len` bytes already in `tx`, with the next counter.
    fn build(&mut self, kind: MailboxType, len: usize) -> bool {
        self.tx_counter = next_counter(self.tx_counter);
        let length = u16::try_from(len).unwrap_or(u16::MAX);
        let header = MailboxHeader::new(kind, length, self.tx_counter).to_bytes();
        if let Some(dst) = self.tx.get_mut(..MailboxHeader::SIZE) {
            dst.copy_from_slice(&header);
        }
        let end = (MailboxHeader::SIZE + len).min(N);
        self.tx_len = end;
        self.tx_pending = true;
        true
    }
}
