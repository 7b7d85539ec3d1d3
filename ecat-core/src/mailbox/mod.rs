//! The mailbox (ETG.1000.4 §5.6, ETG.1000.6 §5.4): SM0 carries messages from the MainDevice,
//! SM1 messages to it. This module owns both buffers and the protocol around them:
//!
//! - the 6-byte [`MailboxHeader`]; a message with length 0 or longer than the mailbox is
//!   answered with a mailbox error reply ([`MailboxError`]), and so is a CoE payload shorter
//!   than its service needs (0x0008: an SDO request under 8 bytes, an SDO Information request
//!   without its header and the fixed part of its opcode, [`InfoRequest::parse`]);
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

/// The bits of [`Mailbox`]'s state: one byte, so that each question the flow control asks
/// (may a request be read, is a write due, is there work) is one test.
mod flag {
    /// SM0 holds a message the SubDevice has not read yet.
    pub const RX_WAITING: u8 = 1 << 0;
    /// The receive buffer holds a request not yet served.
    pub const RX_PENDING: u8 = 1 << 1;
    /// The send buffer holds a message not yet written to SM1.
    pub const TX_PENDING: u8 = 1 << 2;
    /// SM1 holds a message the MainDevice has not read yet.
    pub const SEND_BUSY: u8 = 1 << 3;
    /// SM1's repeat request differs from the acknowledge: the last message is written again,
    /// then the acknowledge follows the request.
    pub const REPEAT_PENDING: u8 = 1 << 4;
    /// The repeat acknowledge bit as last written to SM1's PDI control.
    pub const REPEAT_ACK: u8 = 1 << 5;
    /// What keeps a request in SM0: its answer could not be written at once.
    pub const BLOCKING: u8 = RX_PENDING | TX_PENDING | SEND_BUSY | REPEAT_PENDING;
    /// What keeps SM1 from taking a new message.
    pub const SM1_TAKEN: u8 = TX_PENDING | SEND_BUSY | REPEAT_PENDING;
}

/// The mailbox state and buffers of a SubDevice whose mailboxes hold at most `N` bytes.
#[derive(Debug)]
// `repr(C)`: the flags, counters and areas first, the buffers last (see `SubDevice`).
#[repr(C)]
pub struct Mailbox<const N: usize> {
    /// What SM0 and SM1 hold, what is on its way between them, SM1's repeat handshake
    /// ([`flag`]).
    flags: u8,
    /// The counter of the last message received (0: none).
    rx_counter: u8,
    /// The counter of the last message sent (0: none).
    tx_counter: u8,
    /// SM0, its length clamped to `N`.
    receive: Area,
    /// SM1, its length clamped to `N` (the error-reply length check and the message capacity).
    send: Area,
    /// Length of the last message built in `tx` (header included).
    tx_len: usize,
    emergencies: Ring<Emergency, EMERGENCY_QUEUE>,
    sdo_info: SdoInfo,
    sdo: SdoServer<N>,
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
    pub const fn new() -> Self {
        Self {
            rx: [0; N],
            tx: [0; N],
            tx_len: 0,
            receive: Area::new(0, 0),
            send: Area::new(0, 0),
            flags: 0,
            rx_counter: 0,
            tx_counter: 0,
            sdo: SdoServer::new(),
            sdo_info: SdoInfo::new(),
            emergencies: Ring::new(Emergency::NONE),
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

    /// Stops the mailbox: everything in flight is dropped, queued emergencies too.
    pub fn stop(&mut self) {
        *self = Self::new();
    }

    /// The MainDevice filled SM0 (AL event bit 8).
    pub fn receive_event(&mut self) {
        self.flags |= flag::RX_WAITING;
    }

    /// The MainDevice read SM1 (AL event bit 9).
    pub fn send_event(&mut self) {
        self.flags &= !flag::SEND_BUSY;
    }

    /// SM1's activate register as last read: a toggled repeat request asks for the last message
    /// again.
    pub fn repeat_request(&mut self, request: bool) {
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
        self.flags & flag::BLOCKING == 0
    }

    /// Whether a repeat request waits for the last message to be written again.
    pub fn repeat_pending(&self) -> bool {
        self.flags & flag::REPEAT_PENDING != 0
    }

    /// Whether the SM0 event belongs in the AL event mask: always, except while a request
    /// already waits in SM0 that cannot be read yet (its event would hold the IRQ line).
    pub fn wants_receive_event(&self) -> bool {
        self.flags & flag::RX_WAITING == 0 || self.can_receive()
    }

    /// Whether the SM1 event belongs in the AL event mask: only while SM1 holds an unread message
    /// and something waits for it to be read (a request, a fragment, an emergency). In the usual
    /// request/answer rhythm the MainDevice reads SM1 before it writes the next request, and the
    /// SM1 bit, still latched in the AL event register, arrives with the SM0 event.
    pub fn wants_send_event(&self) -> bool {
        let more = self.flags & (flag::TX_PENDING | flag::RX_WAITING) != 0
            || self.sdo_info.is_pending()
            || !self.emergencies.is_empty();
        self.flags & flag::SEND_BUSY != 0 && more
    }

    /// Whether SM0 should be read now.
    pub fn read_due(&self) -> bool {
        self.flags & (flag::RX_WAITING | flag::BLOCKING) == flag::RX_WAITING
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
        self.flags & flag::RX_PENDING != 0
    }

    /// SM0 was read into the receive buffer.
    pub fn received(&mut self) {
        self.flags = (self.flags & !flag::RX_WAITING) | flag::RX_PENDING;
    }

    /// Whether a message must be written to SM1 now: the next message, or the last one again.
    pub fn write_due(&self) -> bool {
        self.flags & (flag::TX_PENDING | flag::SEND_BUSY) == flag::TX_PENDING
            || self.repeat_pending()
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
    pub fn repeat_ack(&self) -> bool {
        self.flags & flag::REPEAT_ACK != 0
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

    /// Whether the mailbox has anything to serve: SM1 is free and a request, an SDO Information
    /// fragment or an emergency waits for it.
    pub fn has_work(&self) -> bool {
        let free = self.flags & flag::SM1_TAKEN == 0;
        free && (self.request_pending()
            || self.sdo_info.is_pending()
            || !self.emergencies.is_empty())
    }

    /// Serves what is due, once [`Mailbox::has_work`] says there is something: the received
    /// message, or else the next fragment or emergency (SM1 is free then). Returns whether a
    /// message was built (a request may be dropped without one). Bounded: one message per call.
    pub(crate) fn serve<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
    ) -> bool {
        if self.request_pending() {
            self.flags &= !flag::RX_PENDING;
            return self.serve_request(cx);
        }
        let capacity = self.send_size().saturating_sub(MailboxHeader::SIZE);
        let out = self
            .tx
            .get_mut(MailboxHeader::SIZE..MailboxHeader::SIZE + capacity)
            .unwrap_or_default();
        if let Some(len) = self.sdo_info.next_fragment::<D>(out) {
            return self.build(MailboxType::Coe, len);
        }
        match self.emergencies.pop() {
            Some(emergency) => self.build_emergency(emergency),
            None => false,
        }
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
        if header.channel != 0 {
            return self.refuse_channel();
        }
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

    /// The reply to a message on a channel other than 0: out of line, away from the requests'
    /// way.
    #[cold]
    #[inline(never)]
    fn refuse_channel(&mut self) -> bool {
        self.build_error(MailboxError::INVALID_CHANNEL)
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
        self.flags |= flag::TX_PENDING;
        true
    }
}
