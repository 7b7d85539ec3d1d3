//! The SDO server (ETG.1000.6 §5.6.2): uploads and downloads, expedited, normal and segmented,
//! single entries and complete access, with the access rights of the current ESM state.
//!
//! | transfer | request → response |
//! |---|---|
//! | expedited download (≤ 4 bytes) | 0x23/0x27/0x2B/0x2F → 0x60 |
//! | normal download | 0x21 (size, data) → 0x60; then segments 0x00/0x10 (+1 last) → 0x20/0x30 |
//! | upload | 0x40 → expedited 0x43/0x47/0x4B/0x4F, or normal 0x41 (size, first data) |
//! | upload segment | 0x60/0x70 → 0x00/0x10 (+ unused bytes, + 1 last) |
//! | complete access | 0x50 / 0x31 and the same responses with bit 4 set |
//! | abort (either side) | 0x80, index, subindex, code |
//!
//! Segments alternate a toggle bit starting at 0 (0x05030000 otherwise). A transfer left
//! unfinished for [`SdoServer::SEGMENT_TIMEOUT`] is dropped; the next segment request gets
//! 0x05040000. A value that continues in segments (other than a DOMAIN's, which streams to the
//! application) is gathered in the server's buffer and stored at its last segment; the buffer
//! is `N` bytes, or as large as the dictionary's largest value ([`largest_download`]). One
//! larger than `N` is refused at its initiate with 0x05040005, one within `N` but larger than
//! the buffer (so than any value the dictionary can store) with 0x06070012. In SAFEOP and OP a
//! download into an entry the RxPDO configuration maps is refused with 0x06010006: the process
//! data owns it.

mod buffer;
mod command;
pub mod complete_access;
mod frame;
mod writes;

pub use buffer::largest_download;
pub use writes::Writes;

use command::{Download, Request, Upload, response};
use frame::Frame;

use super::{AbortCode, CoeHeader, Service};
use crate::AlState;
use crate::device::DeviceConfig;
use crate::dictionary::{
    Access, At, DataType, EntryInfo, Len, Length, Object, ObjectCode, ObjectDictionary,
    ObjectHooks, ObjectInfo,
};
use crate::pdo;
use crate::time::{Duration, Instant};

/// Bytes of an SDO message up to its data: command, index, subindex, 4 data/size bytes.
const SDO_HEADER: usize = 8;
/// Bytes of a response up to its data: the CoE header and the SDO header.
const RESPONSE_HEADER: usize = CoeHeader::SIZE + SDO_HEADER;
/// The CoE header of an SDO response (service 3, number 0), built at compile time.
const SDO_RESPONSE: [u8; 2] = CoeHeader::new(Service::SdoResponse).to_bytes();
/// The CoE header of an SDO request (service 2): what an abort from the server carries.
const SDO_REQUEST: [u8; 2] = CoeHeader::new(Service::SdoRequest).to_bytes();
/// Bytes of a segment up to its data: the command.
const SEGMENT_HEADER: usize = 1;
/// A segment carries at least 7 data bytes (padding included).
const MIN_SEGMENT_DATA: usize = 7;

/// What the server works on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Target {
    index: u16,
    sub: u8,
    complete: bool,
    domain: bool,
}

/// Which way a segmented transfer goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Upload,
    Download,
}

/// A transfer that continues with segments.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Segmented {
    kind: Kind,
    target: Target,
    /// The whole value's size.
    size: usize,
    /// Bytes sent (upload) or received (download) so far.
    done: usize,
    /// The toggle bit the next segment must carry.
    toggle: bool,
    /// When the next segment is due: set by [`SdoServer::request`] after every request that
    /// leaves the transfer under way (one sum for the initiate and each segment).
    deadline: Instant,
}

impl Segmented {
    /// A segment moved the transfer to `done` bytes; it waits for the next segment with the
    /// other toggle (the last one ends it: the server drops the transfer).
    fn advance(&mut self, done: usize) {
        self.done = done;
        self.toggle = !self.toggle;
    }
}

/// What a request is served with: the dictionary, the hooks, the state and the time.
pub struct Context<'a, D, H> {
    /// The dictionary.
    pub od: &'a mut D,
    /// The application's hooks.
    pub hooks: &'a mut H,
    /// The current ESM state (access rights depend on it).
    pub state: AlState,
    /// Now.
    pub now: Instant,
    /// Where successful writes are noted: what they changed of the process-data configuration.
    pub writes: &'a mut Writes,
    /// The device, for what its process RAM can take ([`pdo::process_ram`]): an SI0 written
    /// into a PDO configuration object that makes its image longer than three buffers of it can
    /// hold is refused with 0x06040042 (`pdo::check_length`). `None`: no such limit (an image
    /// over 65 535 bits is refused all the same).
    pub device: Option<&'a DeviceConfig>,
}

/// The SDO server, which takes downloads of at most `N` bytes and gathers a value that
/// continues in segments in a buffer of `L` bytes: by default `N`, or the dictionary's largest
/// value ([`ObjectDictionary::Download`], [`largest_download`]), which `ecat-embassy` gives it.
// `repr(C)`: the small fields first, then the buffer (a dictionary's of a few bytes fills the
// padding before the transfer's 8-byte alignment), the transfer last.
#[repr(C)]
pub struct SdoServer<const N: usize, L: Length = Len<N>> {
    /// The ESM state the transfer's rights were checked in: a download whose state changed
    /// meanwhile is checked again before it stores (access rights, RxPDO-mapped entries). Here
    /// rather than in [`Segmented`], where it would cost 8 bytes of alignment.
    checked_in: AlState,
    timed_out: bool,
    buf: L::Array<u8>,
    transfer: Option<Segmented>,
}

impl<const N: usize, L: Length> core::fmt::Debug for SdoServer<N, L> {
    /// The transfer under way; the buffer's bytes are left out.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SdoServer")
            .field("checked_in", &self.checked_in)
            .field("timed_out", &self.timed_out)
            .field("transfer", &self.transfer)
            .finish_non_exhaustive()
    }
}

impl<const N: usize, L: Length> Default for SdoServer<N, L> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, L: Length> SdoServer<N, L> {
    /// How long a segmented transfer may wait for its next segment.
    pub const SEGMENT_TIMEOUT: Duration = Duration::from_millis(1_000);

    /// A server with no transfer in progress.
    pub fn new() -> Self {
        Self {
            transfer: None,
            checked_in: AlState::Init,
            timed_out: false,
            buf: L::array(0),
        }
    }

    /// Serves one SDO request: `request` is the mailbox data after the CoE header. Writes the
    /// response (CoE header included) into `out`, the mailbox data area of the send mailbox, and
    /// returns its length; 0 when there is nothing to send (an abort from the client).
    pub fn request<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
        request: &[u8],
        out: &mut [u8],
    ) -> usize {
        let frame = match Frame::new_checked(request) {
            Ok(frame) => frame,
            Err(code) => return abort(out, 0, 0, code),
        };
        let (index, sub) = (frame.index(), frame.sub());
        // An initiate's target: bit 4 of either command asks for complete access.
        let target = Target::new(index, sub, frame.command() & command::COMPLETE != 0);
        let result = match Request::from_byte(frame.command()) {
            Request::Upload(request) => self.upload(cx, target, request, out),
            Request::Download(request) => self.download(cx, target, &frame, request, out),
            Request::Abort => {
                self.transfer = None;
                return 0;
            }
            Request::Unknown => Err(AbortCode::COMMAND_SPECIFIER),
        };
        match result {
            Ok(len) => {
                // Whatever the request, a transfer still under way waits for its next segment
                // from now on.
                if let Some(t) = &mut self.transfer {
                    t.deadline = cx.now.saturating_add(Self::SEGMENT_TIMEOUT);
                }
                len
            }
            Err(code) => {
                // The abort names the transfer's entry, if one was under way: it ends here.
                let (index, sub) = self
                    .transfer
                    .take()
                    .map_or((index, sub), |t| (t.target.index, t.target.sub));
                abort(out, index, sub, code)
            }
        }
    }

    /// When [`SdoServer::handle_timeout`] must be called, if a transfer waits for a segment.
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.transfer.map(|t| t.deadline)
    }

    /// Drops a transfer whose next segment did not come in time.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.poll_timeout().is_some_and(|deadline| now >= deadline) {
            self.transfer = None;
            self.timed_out = true;
        }
    }

    /// Drops any transfer (the mailbox stopped).
    pub fn reset(&mut self) {
        self.transfer = None;
        self.timed_out = false;
    }

    /// An upload's initiate or segment: both copy the value's bytes from the transfer's offset
    /// into the answer (an initiate starts a transfer at 0 and says the size, or carries a
    /// value of 1 to 4 bytes in its header; a transfer ends with the segment that sends its
    /// last byte).
    fn upload<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
        target: Target,
        request: Upload,
        out: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let (object, target, at, size, offset) = match request {
            Upload::Initiate => {
                self.transfer = None;
                self.timed_out = false;
                let (object, target) = resolve(&*cx.od, target, cx.state, Direction::Read)?;
                cx.hooks.before_read(cx.od, target.index, target.sub)?;
                let size = 0; // the read says, or for a DOMAIN the hook (below)
                (object, target, RESPONSE_HEADER, size, 0)
            }
            Upload::Segment { toggle } => {
                let t = next_segment(
                    &mut self.transfer,
                    &mut self.timed_out,
                    Kind::Upload,
                    toggle,
                )?;
                let object = D::object(t.target.index).ok_or(AbortCode::NO_OBJECT)?;
                (
                    object,
                    t.target,
                    CoeHeader::SIZE + SEGMENT_HEADER,
                    t.size,
                    t.done,
                )
            }
        };
        // The CoE header, then zeros: a segment's command is set below and the 7 bytes it
        // carries at least are zero where the value does not fill them; an initiate's header
        // is written whole below.
        let [c0, c1] = SDO_RESPONSE;
        *out.first_chunk_mut().ok_or(AbortCode::OUT_OF_MEMORY)? = [c0, c1, 0, 0, 0, 0, 0, 0, 0, 0];
        // Both initiates' answers leave by one header write (below the block): an expedited
        // value's command and value, or a normal one's and the size; a segment's leaves within.
        let (command, word, sent) = 'initiate: {
            // The value is read straight into the answer's data area (a DOMAIN's no further
            // than its size). A send mailbox without room for four bytes behind an initiate's
            // header (the 16 bytes of the smallest) reads into `small`: an expedited value fits
            // it, a longer one sends nothing with the initiate.
            let data = out.get_mut(at..).unwrap_or_default();
            let mut small = [0u8; 4];
            let short = data.len() < small.len();
            let (sent, size) = if is_domain::<D>(target) {
                let size = match request {
                    Upload::Initiate => domain_size(cx, target)?,
                    Upload::Segment { .. } => size,
                };
                let rest = size.saturating_sub(offset);
                let data = match data.get_mut(..rest) {
                    Some(data) => data,
                    None => data,
                };
                (fetch(cx, object, target, offset, data)?, size)
            } else {
                let into: &mut [u8] = if short { &mut small } else { data };
                let read = read(cx.od, object, target, offset, into)?;
                let size = read.size();
                if request == Upload::Initiate && (1..=4).contains(&size) {
                    // Expedited (no transfer): the data moves into the header (ETG.1000.6
                    // Table 37): the four bytes read, of which the value's size count.
                    let bytes = into.first_chunk::<4>().copied().unwrap_or_default();
                    let value = u32::from_le_bytes(bytes) & (u32::MAX >> (32 - 8 * size));
                    let command = response::upload_expedited(size, target.complete);
                    break 'initiate (command, value, 0);
                }
                (if short { 0 } else { read.copied() }, size)
            };
            let done = offset + sent;
            let last = done >= size;
            match (last, request, &mut self.transfer) {
                (true, ..) => self.transfer = None,
                (false, Upload::Initiate, _) => {
                    self.begin(cx, Kind::Upload, target, size, done, false);
                }
                (false, _, Some(t)) => t.advance(done),
                (false, _, None) => {}
            }
            let Upload::Segment { toggle } = request else {
                let size = u32::try_from(size).unwrap_or(u32::MAX);
                break 'initiate (response::upload_normal(target.complete), size, sent);
            };
            let unused = MIN_SEGMENT_DATA.saturating_sub(sent);
            if let Some(command) = out.get_mut(CoeHeader::SIZE) {
                *command = response::upload_segment(toggle, unused as u8, last);
            }
            let len = CoeHeader::SIZE + SEGMENT_HEADER + sent.max(MIN_SEGMENT_DATA);
            return Ok(len.min(out.len()));
        };
        Ok(respond(out, SDO_RESPONSE, command, target, word.to_le_bytes()) + sent)
    }

    /// A download's initiate or segment: both store their bytes at the transfer's offset (an
    /// initiate starts a transfer at 0; one that carries the whole value ends it at once).
    fn download<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
        target: Target,
        frame: &Frame<&[u8]>,
        request: Download,
        out: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let (data, last, command, answered, transfer) = match request {
            Download::Initiate {
                expedited,
                size_indicated,
                unused,
            } => {
                self.transfer = None;
                self.timed_out = false;
                let (object, target) = resolve(&*cx.od, target, cx.state, Direction::Write)?;
                let (size, data) = if expedited {
                    let size = if size_indicated {
                        4 - usize::from(unused)
                    } else {
                        expedited_size(object, target)
                    };
                    let data = frame.expedited(size).ok_or(AbortCode::LENGTH_MISMATCH)?;
                    (data.len(), data)
                } else {
                    let size =
                        usize::try_from(frame.size()).map_err(|_| AbortCode::OUT_OF_MEMORY)?;
                    let here = frame.payload();
                    (size, here.get(..size).unwrap_or(here))
                };
                // Toggle 1: `take` moves the transfer on as after a segment, to toggle 0 for the
                // first one.
                let transfer = self.begin(cx, Kind::Download, target, size, 0, true);
                let command = response::download(target.complete);
                (data, data.len() == size, command, target, transfer)
            }
            Download::Segment {
                toggle,
                unused,
                last,
            } => {
                let transfer = *next_segment(
                    &mut self.transfer,
                    &mut self.timed_out,
                    Kind::Download,
                    toggle,
                )?;
                let command = response::download_segment(toggle);
                // The answer is the command and 7 bytes of padding.
                (
                    segment_data(frame, unused),
                    last,
                    command,
                    Target::new(0, 0, false),
                    transfer,
                )
            }
        };
        self.take(cx, transfer, data, last)?;
        Ok(respond(out, SDO_RESPONSE, command, answered, [0; 4]))
    }

    /// Stores a download's `data` at the offset of `t` (the server's transfer): a DOMAIN
    /// streams it to the application, a value that came whole in one message is stored from
    /// it, any other is gathered in the buffer and stored on the `last` segment.
    fn take<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        cx: &mut Context<'_, D, H>,
        t: Segmented,
        data: &[u8],
        last: bool,
    ) -> Result<(), AbortCode> {
        let (target, size, received) = (t.target, t.size, t.done);
        let object = D::object(target.index).ok_or(AbortCode::NO_OBJECT)?;
        let total = received + data.len();
        if total > size {
            return Err(AbortCode::LENGTH_TOO_HIGH);
        }
        if last && total < size {
            return Err(AbortCode::LENGTH_TOO_LOW);
        }
        if self.checked_in != cx.state {
            // The rights of the initiate's state do not carry over (a download started in PREOP
            // that ends in SAFEOP: 0x08000022 for a PREOP-only entry, 0x06010006 for a mapped one).
            check_entries(&*cx.od, &object.info, target, cx.state, Direction::Write)?;
        }
        let streamed = is_domain::<D>(target);
        let value: &[u8] = if streamed || (last && received == 0) {
            data
        } else {
            // A value the server cannot gather is refused when its transfer starts: over `N`
            // for want of memory, over the buffer as longer than any value of the dictionary.
            if size > N {
                return Err(AbortCode::OUT_OF_MEMORY);
            }
            let buf = (self.buf.as_mut().get_mut(..size)).ok_or(AbortCode::LENGTH_TOO_HIGH)?;
            let here = buf.get_mut(received..total);
            crate::bytes::copy(here.ok_or(AbortCode::OUT_OF_MEMORY)?, data);
            buf
        };
        // One store: a DOMAIN's every piece at its offset, any other value once, whole (the
        // offset and the flag count for a DOMAIN only).
        if streamed || last {
            store(cx, object, target, value, received, last)?;
        }
        match (last, &mut self.transfer) {
            (false, Some(t)) => t.advance(total),
            _ => self.transfer = None,
        }
        Ok(())
    }

    /// Starts a segmented transfer with `done` bytes already moved, waiting for a segment with
    /// `toggle` (the first segment carries 0); returns it.
    fn begin<D, H>(
        &mut self,
        cx: &Context<'_, D, H>,
        kind: Kind,
        target: Target,
        size: usize,
        done: usize,
        toggle: bool,
    ) -> Segmented {
        let transfer = Segmented {
            kind,
            target,
            size,
            done,
            toggle,
            deadline: cx.now,
        };
        self.transfer = Some(transfer);
        self.checked_in = cx.state;
        transfer
    }
}

/// The transfer a segment of `kind` with `toggle` continues (the server's `transfer`, in
/// place): none is 0x05040001 (or 0x05040000 after a timeout, `timed_out`), a toggle that did
/// not alternate 0x05030000.
fn next_segment<'t>(
    transfer: &'t mut Option<Segmented>,
    timed_out: &mut bool,
    kind: Kind,
    toggle: bool,
) -> Result<&'t mut Segmented, AbortCode> {
    match transfer {
        Some(t) if t.kind == kind => match t.toggle == toggle {
            true => Ok(t),
            false => Err(AbortCode::TOGGLE_BIT),
        },
        _ if core::mem::take(timed_out) => Err(AbortCode::TIMEOUT),
        _ => Err(AbortCode::COMMAND_SPECIFIER),
    }
}

/// Whether `target` is a DOMAIN of `D`: `false` at compile time for a dictionary without one,
/// whose firmware then carries no DOMAIN paths.
fn is_domain<D: ObjectDictionary>(target: Target) -> bool {
    let any = const { crate::dictionary::has_domain(D::OBJECTS) };
    any && target.domain
}

impl Target {
    fn new(index: u16, sub: u8, complete: bool) -> Self {
        Self {
            index,
            sub,
            complete,
            domain: false,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Direction {
    Read,
    Write,
}

/// Finds the object and checks the access: existence, subindex, rights in `state`, then for a
/// download that the process data does not own the entries ([`check_not_rx_mapped`]). A single
/// subindex is checked as a complete access of one entry ([`check_entries`]), bar an upload's,
/// which needs the one entry's rights only.
#[inline]
fn resolve<D: ObjectDictionary>(
    od: &D,
    target: Target,
    state: AlState,
    direction: Direction,
) -> Result<(&'static Object<D>, Target), AbortCode> {
    let object = D::object(target.index).ok_or(AbortCode::NO_OBJECT)?;
    let info = &object.info;
    let mut domain = false;
    if !target.complete {
        let entry = (info.dense_entry(target.sub))
            .or_else(|| info.entry(target.sub))
            .ok_or_else(|| missing_entry(info, target.sub))?;
        domain = const { crate::dictionary::has_domain(D::OBJECTS) }
            && entry.data_type == DataType::Domain;
        // An upload's rights are the one entry's: no walk on the expedited upload's way.
        if direction == Direction::Read {
            check_access(entry, state, direction)?;
            return Ok((object, Target { domain, ..target }));
        }
    }
    check_entries(od, info, target, state, direction)?;
    Ok((object, Target { domain, ..target }))
}

/// Why a single access to `object`'s subindex `sub`, which it does not declare, is refused:
/// a gap of a sparse RECORD (below its highest subindex; SDO Information describes it as an
/// empty entry, data type 0 and access 0) with 0x06010000 "unsupported access", as SSC 5.12
/// answers an access to such an entry (`OBJ_Read`/`OBJ_Write`, change V5.12 COE7); any other
/// with 0x06090011 (ETG.1000.6 Table 41).
#[cold]
#[inline(never)]
fn missing_entry(object: &ObjectInfo, sub: u8) -> AbortCode {
    let gap = object.code == ObjectCode::Record && sub > 0 && sub <= object.max_sub;
    if gap {
        AbortCode::UNSUPPORTED_ACCESS
    } else {
        AbortCode::NO_SUBINDEX
    }
}

/// The entries `target` covers in `object`: its subindex, or for a complete access every
/// entry from it (SI0 aside: it carries the count; [`complete_access::check`] first). Every one
/// accessible in `state`, then for a download none of them owned by the process data. Out of
/// line: the one walk of both accesses.
#[inline(never)]
fn check_entries<D: ObjectDictionary>(
    od: &D,
    info: &ObjectInfo,
    target: Target,
    state: AlState,
    direction: Direction,
) -> Result<(), AbortCode> {
    let (first, last) = match target.complete {
        true => {
            complete_access::check(info, target.sub)?;
            (target.sub.max(1), info.max_sub)
        }
        false => (target.sub, target.sub),
    };
    let entries = || complete_access::declared(info, first, last);
    entries().try_for_each(|(_, entry)| check_access(entry, state, direction))?;
    if direction == Direction::Read {
        return Ok(());
    }
    entries()
        .filter(|(_, entry)| entry.access.rxpdo())
        .try_for_each(|(sub, _)| check_not_rx_mapped(od, state, info.index, sub))
}

/// Read or write rights of `entry` in `state` (ETG.1000.6 Table 49).
fn check_access(entry: &EntryInfo, state: AlState, direction: Direction) -> Result<(), AbortCode> {
    // The write triple shifted onto the read triple: one test for both directions.
    let (shift, never) = match direction {
        Direction::Read => (0, AbortCode::WRITE_ONLY),
        Direction::Write => (3, AbortCode::READ_ONLY),
    };
    let rights = Access((entry.access.0 >> shift) & Access::READ.0);
    if !rights.readable() {
        Err(never)
    } else if !rights.readable_in(state) {
        Err(AbortCode::DEVICE_STATE)
    } else {
        Ok(())
    }
}

/// A download into an RxPDO-mappable entry `index`:`sub` that the active RxPDO
/// configuration maps (0x1C12, its mappings) is refused in SAFEOP and OP with 0x06010006
/// (ETG.1000.6 Table 41; conformance.md "CoE SDO"): the process data owns it. Checked by
/// [`resolve`] when a download starts and again before a segmented one stores its value (the
/// state may have reached SAFEOP meanwhile), after the entry's rights. The mappings are walked
/// only in SAFEOP and OP; a dictionary without
/// 0x1C12 (a fixed layout the application copies) or with an unusable mapping refuses nothing.
fn check_not_rx_mapped<D: ObjectDictionary>(
    od: &D,
    state: AlState,
    index: u16,
    sub: u8,
) -> Result<(), AbortCode> {
    // SAFEOP and OP run on a valid configuration: a walk of the assigned mappings answers as
    // its layout would, without building one.
    let mapped =
        state.has_process_data() && pdo::layout::is_mapped(od, pdo::Direction::Rx, index, sub);
    if mapped {
        return Err(AbortCode::MAPPED_TO_RXPDO);
    }
    Ok(())
}

/// The size of the DOMAIN `target`, as the application's hook gives it.
fn domain_size<D, H: ObjectHooks<D>>(
    cx: &mut Context<'_, D, H>,
    target: Target,
) -> Result<usize, AbortCode> {
    let size = cx.hooks.domain_size(target.index, target.sub)?;
    usize::try_from(size).map_err(|_| AbortCode::OUT_OF_MEMORY)
}

/// Reads the target's encoded value from `offset` into `out`: one entry by its object's read,
/// a complete access by [`complete_access::read`]; the bytes copied and the whole size.
fn read<D>(
    od: &D,
    object: &Object<D>,
    target: Target,
    offset: usize,
    out: &mut [u8],
) -> Result<crate::dictionary::Read, AbortCode> {
    if target.complete {
        return complete_access::read(od, object, target.sub, offset, out);
    }
    (object.read)(od, At::new(target.sub, offset), out)
}

/// Copies the target's bytes from `offset` into `out`.
fn fetch<D: ObjectDictionary, H: ObjectHooks<D>>(
    cx: &mut Context<'_, D, H>,
    object: &Object<D>,
    target: Target,
    offset: usize,
    out: &mut [u8],
) -> Result<usize, AbortCode> {
    if is_domain::<D>(target) {
        let offset = u32::try_from(offset).map_err(|_| AbortCode::OUT_OF_MEMORY)?;
        return cx.hooks.domain_read(target.index, target.sub, offset, out);
    }
    Ok(read(cx.od, object, target, offset, out)?.copied())
}

/// Stores downloaded bytes: into the dictionary through the hooks, or streamed to a DOMAIN.
fn store<D: ObjectDictionary, H: ObjectHooks<D>>(
    cx: &mut Context<'_, D, H>,
    object: &Object<D>,
    target: Target,
    data: &[u8],
    offset: usize,
    last: bool,
) -> Result<(), AbortCode> {
    if is_domain::<D>(target) {
        let offset = u32::try_from(offset).map_err(|_| AbortCode::OUT_OF_MEMORY)?;
        return cx
            .hooks
            .domain_write(target.index, target.sub, offset, data, last);
    }
    if !target.complete {
        if target.sub == 0 && const { pdo::configurable(D::OBJECTS) } {
            check_pdo_length(cx, object, data)?;
        }
        return store_entry(cx, object, target.sub, data);
    }
    store_complete(cx, object, target.sub, data)
}

/// The bytes of process RAM the images can occupy, `u32::MAX` without a device.
fn process_ram(device: Option<&DeviceConfig>) -> u32 {
    device.map_or(u32::MAX, pdo::process_ram)
}

/// SI0 := `data` of a PDO mapping or assignment object, by a single access: the image of its
/// direction with the entries the dictionary holds must fit the device ([`pdo::check_length`],
/// 0x06040042). SI0 0 empties, and a count above the capacity or of the wrong size is the
/// object's own write to refuse (0x06090031, 0x0607001x). Out of line: downloads of SI0 only.
#[inline(never)]
fn check_pdo_length<D: ObjectDictionary, H>(
    cx: &Context<'_, D, H>,
    object: &Object<D>,
    data: &[u8],
) -> Result<(), AbortCode> {
    let (&[n], index) = (data, object.info.index) else {
        return Ok(());
    };
    if n == 0 || n > object.info.max_sub || !pdo::configures_process_data(index) {
        return Ok(());
    }
    let od = &*cx.od;
    let entry = |sub| match pdo::Direction::of_assignment(index) {
        Some(_) => object.read_u16(od, sub).map(u32::from),
        None => object.read_u32(od, sub),
    };
    pdo::check_length(od, process_ram(cx.device), index, n, &entry)
}

/// A complete-access download (ETG.1000.6 §5.6.2.1.2). With a writable SI0 (PDO configuration
/// objects) the configuration sequence is followed: SI0 := 0, entries 1..=n, SI0 := n; the
/// image is either the whole object or ends with entry n (what TwinCAT and SOEM send: SI0 and
/// the entries it counts). With a read-only SI0 the image must be the whole object and carry
/// SI0's current value; every entry is written.
fn store_complete<D: ObjectDictionary, H: ObjectHooks<D>>(
    cx: &mut Context<'_, D, H>,
    object: &Object<D>,
    from: u8,
    data: &[u8],
) -> Result<(), AbortCode> {
    // Only a PDO configuration object's SI0 is writable; a dictionary without a writable one
    // has no configuration sequence to follow.
    let writable = const { pdo::configurable(D::OBJECTS) }
        && object
            .info
            .entry(0)
            .is_some_and(|e| e.access.writable_in(cx.state));
    // SI0 travels as one byte and a padding byte.
    let si0 = match (from, data) {
        (0, [n, _, ..]) => Some(*n),
        (0, _) => return Err(AbortCode::LENGTH_MISMATCH),
        _ => None,
    };
    check_complete_length(&object.info, from, data.len(), si0.filter(|_| writable))?;
    let mut last = object.info.max_sub;
    match si0 {
        Some(n) if writable => {
            // Checked before anything is stored: a refused configuration leaves the object as
            // it was (the sequence below empties it first).
            let room = process_ram(cx.device);
            check_configuration(&*cx.od, room, object, from, data, n)?;
            store_entry(cx, object, 0, &[0])?;
            last = n;
        }
        // A read-only SI0 must carry its current value.
        Some(n) if n != object.count(cx.od) => return Err(AbortCode::READ_ONLY),
        _ => {}
    }
    // A gap of a sparse RECORD has no value in the image; SI0 is done.
    for slot in complete_access::slots(&object.info, from, last) {
        if slot.sub == 0 {
            continue;
        }
        let (value, len) = slot.value(data).ok_or(AbortCode::LENGTH_MISMATCH)?;
        store_entry(cx, object, slot.sub, value.get(..len).unwrap_or_default())?;
    }
    match si0 {
        Some(n) if writable => store_entry(cx, object, 0, &[n]),
        _ => Ok(()),
    }
}

/// The entries a complete access to a configuration object (writable SI0) counts with `n`,
/// judged by the PDO configuration rules before anything is stored: SI0 within the capacity
/// ([`pdo::check_counted_write`]), each a valid mapping or assignment entry
/// ([`pdo::check_entry`]), the image they make within what the device can take
/// ([`pdo::check_length`], 0x06040042).
fn check_configuration<D: ObjectDictionary>(
    od: &D,
    process_ram: u32,
    object: &Object<D>,
    from: u8,
    data: &[u8],
    n: u8,
) -> Result<(), AbortCode> {
    pdo::check_counted_write(0, usize::from(object.info.max_sub), 0, &[n])?;
    for sub in 1..=n {
        let (value, len) = complete_access::entry_value(data, &object.info, from, sub)
            .ok_or(AbortCode::LENGTH_MISMATCH)?;
        pdo::check_entry::<D>(object.info.index, value.get(..len).unwrap_or_default())?;
    }
    let entry = |sub| {
        let (value, len) = complete_access::entry_value(data, &object.info, from, sub)?;
        let mut bytes = [0u8; 4];
        crate::bytes::copy(&mut bytes, value.get(..len)?);
        Some(u32::from_le_bytes(bytes))
    };
    pdo::check_length(od, process_ram, object.info.index, n, &entry)
}

/// A complete-access image of `len` bytes from `from` must be the whole object, or, when the
/// MainDevice sets a writable SI0 to `counted`, end with the entry SI0 counts: longer is
/// 0x06070012, shorter 0x06070013.
fn check_complete_length(
    object: &ObjectInfo,
    from: u8,
    len: usize,
    counted: Option<u8>,
) -> Result<(), AbortCode> {
    let (whole, least) = complete_access::sizes(object, from, counted.unwrap_or(u8::MAX));
    if len == whole || len == least {
        Ok(())
    } else if len > whole {
        Err(AbortCode::LENGTH_TOO_HIGH)
    } else if len < least {
        Err(AbortCode::LENGTH_TOO_LOW)
    } else {
        Err(AbortCode::LENGTH_MISMATCH)
    }
}

/// One entry's download: veto hook, typed decode with range check, after-write hook.
fn store_entry<D: ObjectDictionary, H: ObjectHooks<D>>(
    cx: &mut Context<'_, D, H>,
    object: &Object<D>,
    sub: u8,
    data: &[u8],
) -> Result<(), AbortCode> {
    let index = object.info.index;
    cx.hooks.before_write(cx.od, index, sub, data)?;
    (object.write)(cx.od, sub, data)?;
    cx.writes.note(index, sub, data);
    cx.hooks.after_write(cx.od, index, sub);
    Ok(())
}

/// The size of an expedited download without size indication: the entry's own size.
fn expedited_size<D>(object: &Object<D>, target: Target) -> usize {
    object
        .info
        .entry(target.sub)
        .map_or(4, |e| usize::from(e.bit_len).div_ceil(8).clamp(1, 4))
}

/// The data of a download segment: what the mailbox carries after the command, or 7 − unused
/// bytes of a minimum-size segment.
fn segment_data<'a>(frame: &'a Frame<&[u8]>, unused: u8) -> &'a [u8] {
    let data = frame.segment();
    if data.len() == MIN_SEGMENT_DATA {
        data.get(..MIN_SEGMENT_DATA - usize::from(unused))
            .unwrap_or_default()
    } else {
        data
    }
}

/// The fixed part of a response (ETG.1000.6 Tables 33–40): the CoE header `coe`
/// ([`SDO_RESPONSE`], [`SDO_REQUEST`]), the command, index, subindex and four data bytes.
fn header(coe: [u8; 2], command: u8, target: Target, data: [u8; 4]) -> [u8; RESPONSE_HEADER] {
    let [c0, c1] = coe;
    let [i0, i1] = target.index.to_le_bytes();
    let [d0, d1, d2, d3] = data;
    [c0, c1, command, i0, i1, target.sub, d0, d1, d2, d3]
}

/// Writes the fixed part of a response into `out` ([`header`]); returns its length, 0 when
/// `out` is too short.
fn respond(out: &mut [u8], coe: [u8; 2], command: u8, target: Target, data: [u8; 4]) -> usize {
    match out.first_chunk_mut() {
        Some(head) => {
            *head = header(coe, command, target, data);
            RESPONSE_HEADER
        }
        None => 0,
    }
}

/// The SDO abort message for `index:sub` with `code`.
pub fn abort(out: &mut [u8], index: u16, sub: u8, code: AbortCode) -> usize {
    let target = Target::new(index, sub, false);
    let code = code.0.to_le_bytes();
    respond(out, SDO_REQUEST, response::ABORT, target, code)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Sparse {
        first: u8,
        fourth: u16,
    }

    struct Od {
        device_type: u32,
        error_register: u8,
        sparse: Sparse,
    }

    crate::dictionary! {
        minimal Od {
            0x1000 => var(device_type, RO, "Device type", default = 0x0002_0192);
            0x1001 => var(error_register, RO, "Error register", default = 0x81);
            0x2000 => record(sparse: Sparse, "Sparse") {
                1 => first, RW, "First", default = 0x11;
                4 => fourth, RW, "Fourth", default = 0x4444;
            };
        }
    }

    struct WithBlob {
        blob: crate::dictionary::Domain,
    }

    crate::dictionary! {
        minimal WithBlob {
            0x2001 => var(blob, RW, "Blob");
        }
    }

    /// The DOMAIN paths are there for a dictionary with a DOMAIN only: `Od` has none, so a
    /// target it resolved is never taken for one.
    #[test]
    fn only_a_dictionary_with_a_domain_has_domain_targets() {
        let target = Target {
            domain: true,
            ..Target::new(0x2001, 0, false)
        };
        assert!(!is_domain::<Od>(target));
        assert!(is_domain::<WithBlob>(target));
        assert!(!is_domain::<WithBlob>(Target::new(0x2001, 0, false)));
    }

    /// The answer of a fresh server in PREOP to `request` (the bytes after the CoE header): the
    /// buffer and the answer's length.
    fn serve(od: &mut Od, request: &[u8]) -> ([u8; 40], usize) {
        let mut cx = Context {
            od,
            hooks: &mut (),
            state: AlState::PreOp,
            now: Instant::from_micros(0),
            writes: &mut Writes::default(),
            device: None,
        };
        let mut out = [0u8; 40];
        let n = SdoServer::<16>::new().request(&mut cx, request, &mut out);
        (out, n)
    }

    /// A server with a `N`-byte buffer that keeps its transfer between requests, each served
    /// in PREOP into an answer of `room` bytes.
    struct Session<const N: usize> {
        od: Od,
        server: SdoServer<N, <Od as ObjectDictionary>::Download>,
    }

    impl<const N: usize> Session<N> {
        fn new() -> Self {
            Self {
                od: Od::default(),
                server: SdoServer::new(),
            }
        }

        fn serve(&mut self, room: usize, request: &[u8]) -> Answer {
            let mut cx = Context {
                od: &mut self.od,
                hooks: &mut (),
                state: AlState::PreOp,
                now: Instant::from_micros(0),
                writes: &mut Writes::default(),
                device: None,
            };
            let mut out = [0xAA; 40];
            let len = self.server.request(&mut cx, request, &mut out[..room]);
            Answer { out, len }
        }
    }

    /// The bytes of an answer.
    #[derive(Debug)]
    struct Answer {
        out: [u8; 40],
        len: usize,
    }

    impl<const K: usize> PartialEq<[u8; K]> for Answer {
        fn eq(&self, other: &[u8; K]) -> bool {
            self.out[..self.len] == other[..]
        }
    }

    /// 0x05040001 with no transfer under way: the abort names 0000:00.
    const NO_TRANSFER: [u8; 10] = [0x00, 0x20, 0x80, 0, 0, 0, 0x01, 0x00, 0x04, 0x05];
    /// An upload segment request with toggle 0.
    const UPLOAD_SEGMENT: [u8; 8] = [0x60, 0, 0, 0, 0, 0, 0, 0];

    /// The upload's one path in the smallest mailbox (10 bytes of answer): a normal initiate
    /// says the size and carries no data, the segment then sends the value from offset 0 and
    /// ends the transfer; an expedited initiate leaves no transfer behind.
    #[test]
    fn an_upload_into_the_smallest_mailbox_continues_from_offset_0() {
        let mut session = Session::<16>::new();
        let initiate = [0x50, 0x00, 0x20, 0x00, 0, 0, 0, 0];
        assert_eq!(
            session.serve(10, &initiate),
            [0x00, 0x30, 0x51, 0x00, 0x20, 0x00, 5, 0, 0, 0]
        );
        // 5 bytes of the 7 (2 unused), the last.
        assert_eq!(
            session.serve(10, &UPLOAD_SEGMENT),
            [0x00, 0x30, 0x05, 4, 0, 0x11, 0x44, 0x44, 0, 0]
        );
        assert_eq!(session.serve(10, &UPLOAD_SEGMENT), NO_TRANSFER);
        assert_eq!(
            session.serve(10, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
            [0x00, 0x30, 0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
        );
        assert_eq!(session.serve(10, &UPLOAD_SEGMENT), NO_TRANSFER);
    }

    /// The download's one path: a value that comes whole with its initiate is stored from the
    /// message, whatever the buffer (4 bytes here, the value 5); one that continues in segments
    /// must fit the buffer (0x05040005 at the initiate) and is stored at its last segment.
    #[test]
    fn a_download_is_stored_from_its_message_or_from_the_buffer() {
        let answered = [0x00, 0x30, 0x70, 0x00, 0x20, 0x00, 0, 0, 0, 0];
        let whole = [0x31, 0x00, 0x20, 0x00, 5, 0, 0, 0, 4, 0, 0x22, 0x55, 0x55];
        let mut small = Session::<4>::new();
        assert_eq!(small.serve(40, &whole), answered);
        assert_eq!(
            (small.od.sparse.first, small.od.sparse.fourth),
            (0x22, 0x5555)
        );
        let partial = &whole[..11];
        assert_eq!(
            small.serve(40, partial),
            [0x00, 0x20, 0x80, 0x00, 0x20, 0x00, 0x05, 0x00, 0x04, 0x05]
        );
        let mut session = Session::<16>::new();
        assert_eq!(session.serve(40, partial), answered);
        assert_eq!(
            session.od.sparse.first, 0x11,
            "nothing stored before the last segment"
        );
        // 2 bytes of the 7 (5 unused), the last.
        assert_eq!(
            session.serve(40, &[0x0B, 0x55, 0x55, 0, 0, 0, 0, 0]),
            [0x00, 0x30, 0x20, 0, 0, 0, 0, 0, 0, 0]
        );
        assert_eq!(
            (session.od.sparse.first, session.od.sparse.fourth),
            (0x22, 0x5555)
        );
        assert_eq!(session.serve(40, &[0x00, 0, 0, 0, 0, 0, 0, 0]), NO_TRANSFER);
    }

    /// The download buffer is the dictionary's largest value: `Od`'s complete access to
    /// 0x2000 (SI0 and its padding, 1 and 2 bytes; no entry is longer), none for `WithBlob`,
    /// whose one value is a DOMAIN that streams.
    #[test]
    fn the_download_buffer_holds_the_largest_value_a_download_stores() {
        assert_eq!(largest_download(Od::OBJECTS), 5);
        assert_eq!(largest_download(WithBlob::OBJECTS), 0);
    }

    /// A value that continues in segments and is longer than the buffer (so than any value of
    /// the dictionary) is refused at its initiate as too long, 0x06070012; longer than the
    /// server's `N`, for want of memory, 0x05040005, as a server with a buffer of `N` bytes
    /// refuses it. Nothing is stored, no transfer is left.
    #[test]
    fn a_segmented_download_longer_than_the_buffer_is_refused_at_its_initiate() {
        let mut session = Session::<16>::new();
        let abort = |code: [u8; 4]| {
            [
                0x00, 0x20, 0x80, 0x00, 0x20, 0x00, code[0], code[1], code[2], code[3],
            ]
        };
        let initiate = |size: u8| [0x31, 0x00, 0x20, 0x00, size, 0, 0, 0, 4, 0, 0x22];
        assert_eq!(
            session.serve(40, &initiate(6)),
            abort([0x12, 0x00, 0x07, 0x06])
        );
        assert_eq!(
            session.serve(40, &initiate(16)),
            abort([0x12, 0x00, 0x07, 0x06])
        );
        assert_eq!(
            session.serve(40, &initiate(17)),
            abort([0x05, 0x00, 0x04, 0x05])
        );
        assert_eq!(session.serve(40, &[0x00, 0, 0, 0, 0, 0, 0, 0]), NO_TRANSFER);
        assert_eq!(session.od.sparse.first, 0x11);
    }

    /// A gap of a sparse RECORD (0x2000:02, :03 here; 0x1C32:0E..1F on a device), which SDO
    /// Information describes as an empty entry, is refused with 0x06010000 "unsupported access"
    /// for upload and download, as SSC 5.12 refuses an entry of access 0 (change V5.12 COE7);
    /// above the highest subindex 0x06090011 stays.
    #[test]
    fn an_access_to_a_gap_of_a_record_is_unsupported() {
        let mut od = Od::default();
        let abort = |sub: u8, code: [u8; 4]| {
            [
                0x00, 0x20, 0x80, 0x00, 0x20, sub, code[0], code[1], code[2], code[3],
            ]
        };
        let unsupported = [0x00, 0x00, 0x01, 0x06];
        let no_subindex = [0x11, 0x00, 0x09, 0x06];
        for sub in [2, 3] {
            let (out, n) = serve(&mut od, &[0x40, 0x00, 0x20, sub, 0, 0, 0, 0]);
            assert_eq!(out[..n], abort(sub, unsupported), "upload of :{sub}");
            let (out, n) = serve(&mut od, &[0x2F, 0x00, 0x20, sub, 1, 0, 0, 0]);
            assert_eq!(out[..n], abort(sub, unsupported), "download into :{sub}");
        }
        let (out, n) = serve(&mut od, &[0x40, 0x00, 0x20, 5, 0, 0, 0, 0]);
        assert_eq!(out[..n], abort(5, no_subindex));
        let (out, n) = serve(&mut od, &[0x40, 0x00, 0x10, 1, 0, 0, 0, 0]);
        assert_eq!(out[..6], [0x00, 0x20, 0x80, 0x00, 0x10, 1]);
        assert_eq!(out[6..n], no_subindex, "a VAR has SI0 only");
    }

    /// A complete-access upload of a sparse RECORD carries its declared entries; a gap has no
    /// bits (SSC: a gap's bit length is 0).
    #[test]
    fn a_complete_access_upload_of_a_sparse_record_skips_its_gaps() {
        let mut od = Od::default();
        let (out, n) = serve(&mut od, &[0x50, 0x00, 0x20, 0x00, 0, 0, 0, 0]);
        assert_eq!(
            out[..n],
            [
                0x00, 0x30, 0x51, 0x00, 0x20, 0x00, 5, 0, 0, 0, 4, 0, 0x11, 0x44, 0x44
            ]
        );
    }

    #[test]
    fn expedited_upload_carries_the_value_in_the_header_zero_padded() {
        // (data room of the send mailbox, index, answer): 10 bytes is a 16-byte mailbox, with no
        // room behind the 8-byte SDO header.
        let cases = [
            (
                10,
                0x1000,
                [0x00, 0x30, 0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00],
            ),
            (
                40,
                0x1001,
                [0x00, 0x30, 0x4F, 0x01, 0x10, 0x00, 0x81, 0x00, 0x00, 0x00],
            ),
        ];
        for (room, index, answer) in cases {
            let mut od = Od::default();
            let mut cx = Context {
                od: &mut od,
                hooks: &mut (),
                state: AlState::PreOp,
                now: Instant::from_micros(0),
                writes: &mut Writes::default(),
                device: None,
            };
            let [i0, i1] = u16::to_le_bytes(index);
            let mut out = [0xAA; 40];
            let request = [0x40, i0, i1, 0, 0, 0, 0, 0];
            let n = SdoServer::<16>::new().request(&mut cx, &request, &mut out[..room]);
            assert_eq!(out[..n], answer, "{index:#06x} in {room} bytes");
        }
    }
}
