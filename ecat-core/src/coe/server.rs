//! CoE as a mailbox protocol ([`Handler`] of type 3): the dispatch of a CoE message by its
//! service (ETG.1000.6 Table 29) to the SDO server and SDO Information, and CoE's own messages
//! (SDO Information fragments, emergencies).

use super::sdo::{self, Context, SdoServer};
use super::sdo_info::{InfoRequest, SdoInfo};
use super::{AbortCode, CoeHeader, Emergency, Service};
use crate::dictionary::{Length, ObjectDictionary, ObjectHooks};
use crate::mailbox::{Env, Handler, MailboxError, MailboxType, Reply};
use crate::ring::Ring;
use crate::time::Instant;

/// How many emergencies wait for SM1 at most; when full the oldest is dropped and counted.
/// They wait only while the MainDevice leaves SM1 unread, and a MainDevice that polls the
/// mailbox takes one per poll; 4 is also what `SharedEsc` holds between two turns of the
/// state-machine runner, so both queues are the same type (one copy of its code).
pub const EMERGENCY_QUEUE: usize = 4;

/// The CoE state a SubDevice with mailboxes of `N` bytes keeps between messages (`L`: the
/// bytes of its SDO server's download buffer), beside the mailbox (`SubDevice` composes them;
/// the mailbox knows CoE only as a [`Handler`]).
#[derive(Debug)]
// `repr(C)`: the small fields first, the SDO server last (see `SubDevice`).
#[repr(C)]
pub(crate) struct CoeServer<const N: usize, L: Length> {
    emergencies: Ring<Emergency, EMERGENCY_QUEUE>,
    sdo_info: SdoInfo,
    sdo: SdoServer<N, L>,
}

impl<const N: usize, L: Length> CoeServer<N, L> {
    /// No transfer in progress, no emergency queued.
    pub(crate) fn new() -> Self {
        Self {
            sdo: SdoServer::new(),
            sdo_info: SdoInfo::new(),
            emergencies: const { Ring::new(Emergency::NONE) },
        }
    }

    /// CoE as a mailbox handler over the dictionary and hooks of `cx`, for one service call.
    pub(crate) fn handler<'a, 'c, D: ObjectDictionary, H: ObjectHooks<D>>(
        &'a mut self,
        cx: &'a mut Context<'c, D, H>,
    ) -> Coe<'a, 'c, N, L, D, H> {
        Coe { server: self, cx }
    }

    /// Queues an emergency; when the queue is full the oldest is dropped.
    pub(crate) fn emergency(&mut self, emergency: Emergency) {
        self.emergencies.push(emergency);
    }

    /// Emergencies dropped because the queue was full.
    pub(crate) fn emergencies_dropped(&self) -> u16 {
        self.emergencies.dropped()
    }

    /// Whether an SDO Information fragment or an emergency waits for SM1.
    pub(crate) fn has_message(&self) -> bool {
        self.sdo_info.is_pending() || !self.emergencies.is_empty()
    }

    /// When an SDO transfer waiting for its next segment expires.
    pub(crate) fn poll_timeout(&self) -> Option<Instant> {
        self.sdo.poll_timeout()
    }

    /// Expires an SDO transfer that waited too long for its next segment.
    pub(crate) fn handle_timeout(&mut self, now: Instant) {
        self.sdo.handle_timeout(now);
    }

    /// The mailbox stopped: every transfer in flight and every queued emergency is dropped.
    pub(crate) fn stop(&mut self) {
        self.sdo.reset();
        self.sdo_info = SdoInfo::new();
        self.emergencies.clear();
    }
}

impl<const N: usize, L: Length> Default for CoeServer<N, L> {
    fn default() -> Self {
        Self::new()
    }
}

/// The service codes a request may carry that the server answers (ETG.1000.6 Table 29).
const SDO_REQUEST: u8 = Service::SdoRequest.code();
/// See [`SDO_REQUEST`].
const SDO_INFORMATION: u8 = Service::SdoInformation.code();

/// CoE's [`Handler`]: the [`CoeServer`] with the dictionary and hooks of one service call.
pub(crate) struct Coe<'a, 'c, const N: usize, L: Length, D, H> {
    server: &'a mut CoeServer<N, L>,
    cx: &'a mut Context<'c, D, H>,
}

impl<const N: usize, L: Length, D: ObjectDictionary, H: ObjectHooks<D>> Handler
    for Coe<'_, '_, N, L, D, H>
{
    const KIND: MailboxType = MailboxType::Coe;

    fn request(&mut self, _: Env, payload: &[u8], reply: &mut [u8]) -> Reply {
        // The service's 4-bit code (header bits 12..15) straight from the byte, matched on
        // the codes the server answers (through `Service` it cost a table and a bit test).
        let Some((&[_, high], payload)) = payload.split_first_chunk::<{ CoeHeader::SIZE }>() else {
            return Reply::Error(MailboxError::INVALID_SIZE);
        };
        let server = &mut *self.server;
        let len = match high >> 4 {
            SDO_REQUEST if payload.len() < 8 => {
                return Reply::Error(MailboxError::INVALID_SIZE);
            }
            SDO_REQUEST => server.sdo.request(&mut *self.cx, payload, reply),
            SDO_INFORMATION => match InfoRequest::parse(payload) {
                Some(request) => server.sdo_info.request::<D>(request, reply),
                None => {
                    server.sdo_info.abandon();
                    return Reply::Error(MailboxError::INVALID_SIZE);
                }
            },
            _ => sdo::abort(reply, 0, 0, AbortCode::UNSUPPORTED_ACCESS),
        };
        match len {
            0 => Reply::Silent,
            len => Reply::Send(len),
        }
    }

    fn has_message(&self) -> bool {
        self.server.has_message()
    }

    /// The next SDO Information fragment, or else the oldest emergency.
    fn message(&mut self, _: Env, out: &mut [u8]) -> usize {
        if let Some(len) = self.server.sdo_info.next_fragment::<D>(out) {
            return len;
        }
        match self.server.emergencies.pop() {
            Some(emergency) => write_emergency(emergency, out),
            None => 0,
        }
    }
}

/// An emergency message (CoE header, then the 8 bytes of [`Emergency`]) in `out`: its length, 0
/// when `out` is too short.
fn write_emergency(emergency: Emergency, out: &mut [u8]) -> usize {
    let len = CoeHeader::SIZE + Emergency::SIZE;
    let Some(dst) = out.get_mut(..len) else {
        return 0;
    };
    let (coe, data) = dst.split_at_mut(CoeHeader::SIZE);
    coe.copy_from_slice(&CoeHeader::new(Service::Emergency).to_bytes());
    data.copy_from_slice(&emergency.to_bytes());
    len
}
