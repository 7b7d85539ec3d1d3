//! The mailbox protocols behind the mailbox: a [`Handler`] serves one mailbox type (ETG.1000.4
//! Table 29: CoE, FoE, EoE, vendor protocols); the mailbox keeps the framing (header, counters,
//! repeat, error replies, flow control) and hands each request to the handler of its type.
//!
//! The shape is embassy-usb's class `Handler`: a small trait whose methods have defaults, so a
//! handler writes only what its protocol does. The firmware picks its protocols at compile time:
//! a tuple of handlers ([`Handlers`]) passed to `SubDevice::service_mailbox_with`; a type
//! without a handler is answered with mailbox error 0x0002 "protocol not supported".

use super::{MailboxError, MailboxType};
use crate::AlState;
use crate::time::{Instant, earliest};

/// What a handler learns about the moment of a call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Env {
    /// The ESM state (PREOP, SAFEOP, OP or BOOT: the states with a mailbox).
    pub state: AlState,
    /// Now.
    pub now: Instant,
    /// The longest payload SM0 carries: the receive mailbox's size less the 6-byte header. A
    /// protocol that segments (FoE) knows a last segment by its being shorter.
    pub max_request: usize,
}

/// A handler's answer to a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    /// No answer (e.g. the last FoE acknowledge of a read, an FoE error from the MainDevice).
    Silent,
    /// An answer of this many bytes, written at the start of the reply buffer.
    Send(usize),
    /// A mailbox error reply (ETG.1000.4 Table 30) instead of an answer.
    Error(MailboxError),
}

/// One mailbox protocol. Only [`Handler::request`] has no default.
pub trait Handler {
    /// The mailbox type served (header byte 5, bits 0..3).
    const KIND: MailboxType;

    /// Whether the protocol is spoken in `state` at all; a request in another state gets mailbox
    /// error 0x0002. Default: the mailbox states but BOOT, where only FoE is served
    /// (ETG.1000.6 §6.4.1).
    fn serves(&self, state: AlState) -> bool {
        state != AlState::Boot
    }

    /// Serves the request `payload` (the message after the mailbox header), writing the answer
    /// into `reply` (the send mailbox's size less the header).
    fn request(&mut self, env: Env, payload: &[u8], reply: &mut [u8]) -> Reply;

    /// Whether the handler has a message of its own to send (continuing work, an unsolicited
    /// message). Default: never.
    fn has_message(&self) -> bool {
        false
    }

    /// Writes the next message of its own into `out` once SM1 is free; its length, 0 for none.
    fn message(&mut self, env: Env, out: &mut [u8]) -> usize {
        let _ = (env, out);
        0
    }

    /// When [`Handler::handle_timeout`] is due. Default: never.
    fn poll_timeout(&self) -> Option<Instant> {
        None
    }

    /// Expires what waited too long.
    fn handle_timeout(&mut self, now: Instant) {
        let _ = now;
    }

    /// The mailbox stopped (the device left the mailbox states): everything in flight is
    /// dropped.
    fn reset(&mut self) {}
}

/// The handlers a firmware serves beside CoE: `()`, one handler `(foe,)`, or a handler and more
/// `(foe, (eoe,))`. Each call goes to the first handler whose type matches.
pub trait Handlers {
    /// Whether there are no handlers (`()`): the mailbox then skips their bookkeeping.
    const NONE: bool = false;
    /// Serves a request of the mailbox type `code` (4 bits); `None` when no handler speaks it in
    /// `env.state`.
    fn request(&mut self, code: u8, env: Env, payload: &[u8], reply: &mut [u8]) -> Option<Reply>;
    /// Whether one of the handlers has a message of its own.
    fn has_message(&self) -> bool;
    /// The next message of a handler's own: its type and length.
    fn message(&mut self, env: Env, out: &mut [u8]) -> Option<(MailboxType, usize)>;
    /// The earliest timeout of the handlers.
    fn poll_timeout(&self) -> Option<Instant>;
    /// Expires what waited too long.
    fn handle_timeout(&mut self, now: Instant);
    /// The mailbox stopped.
    fn reset(&mut self);
}

impl Handlers for () {
    const NONE: bool = true;
    fn request(&mut self, _: u8, _: Env, _: &[u8], _: &mut [u8]) -> Option<Reply> {
        None
    }
    fn has_message(&self) -> bool {
        false
    }
    fn message(&mut self, _: Env, _: &mut [u8]) -> Option<(MailboxType, usize)> {
        None
    }
    fn poll_timeout(&self) -> Option<Instant> {
        None
    }
    fn handle_timeout(&mut self, _: Instant) {}
    fn reset(&mut self) {}
}

impl<A: Handler> Handlers for (A,) {
    fn request(&mut self, code: u8, env: Env, payload: &[u8], reply: &mut [u8]) -> Option<Reply> {
        (code == A::KIND.code() && self.0.serves(env.state))
            .then(|| self.0.request(env, payload, reply))
    }
    fn has_message(&self) -> bool {
        self.0.has_message()
    }
    fn message(&mut self, env: Env, out: &mut [u8]) -> Option<(MailboxType, usize)> {
        match self.0.message(env, out) {
            0 => None,
            len => Some((A::KIND, len)),
        }
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.0.poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        self.0.handle_timeout(now);
    }
    fn reset(&mut self) {
        self.0.reset();
    }
}

impl<A: Handler, B: Handlers> Handlers for (A, B) {
    fn request(&mut self, code: u8, env: Env, payload: &[u8], reply: &mut [u8]) -> Option<Reply> {
        if code == A::KIND.code() && self.0.serves(env.state) {
            return Some(self.0.request(env, payload, reply));
        }
        self.1.request(code, env, payload, reply)
    }
    fn has_message(&self) -> bool {
        self.0.has_message() || self.1.has_message()
    }
    fn message(&mut self, env: Env, out: &mut [u8]) -> Option<(MailboxType, usize)> {
        match self.0.message(env, out) {
            0 => self.1.message(env, out),
            len => Some((A::KIND, len)),
        }
    }
    fn poll_timeout(&self) -> Option<Instant> {
        earliest(self.0.poll_timeout(), self.1.poll_timeout())
    }
    fn handle_timeout(&mut self, now: Instant) {
        self.0.handle_timeout(now);
        self.1.handle_timeout(now);
    }
    fn reset(&mut self) {
        self.0.reset();
        self.1.reset();
    }
}

impl<P: Handlers> Handlers for &mut P {
    fn request(&mut self, code: u8, env: Env, payload: &[u8], reply: &mut [u8]) -> Option<Reply> {
        (**self).request(code, env, payload, reply)
    }
    fn has_message(&self) -> bool {
        (**self).has_message()
    }
    fn message(&mut self, env: Env, out: &mut [u8]) -> Option<(MailboxType, usize)> {
        (**self).message(env, out)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        (**self).poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        (**self).handle_timeout(now);
    }
    fn reset(&mut self) {
        (**self).reset();
    }
}
