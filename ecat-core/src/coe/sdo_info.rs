//! SDO Information (ETG.1000.6 §5.6.3): the MainDevice reads the object dictionary over the
//! mailbox: the lists of object indices, the description of an object and of each entry.
//!
//! ## Messages
//! Every SDO Information message is a CoE message of service 8:
//!
//! | bytes | content |
//! |---|---|
//! | 0..2 | CoE header: number 0, service 8 (ETG.1000.6 Table 29) |
//! | 2 | opcode (bits 0..6), incomplete: more fragments follow (bit 7) ([`Opcode`]) |
//! | 3 | reserved, 0 |
//! | 4..6 | fragments left, u16 LE |
//! | 6.. | the service data of the opcode |
//!
//! [`InfoRequest::parse`] reads a request, [`SdoInfo`] answers the three requests; the
//! service-data formats are documented on the functions that write them.
//!
//! ## Decisions where ETG.1000.6 leaves room
//! - **Fragments**: only an OD list is fragmented. Every fragment carries as many whole 16-bit
//!   words as the message holds; the list type opens the first fragment only. A 16-bit value is
//!   never split across fragments, so SOEM's and IgH's readers (which take a whole number of
//!   indices per fragment) reassemble any capacity.
//! - **Descriptions are never fragmented**: SOEM and IgH read an object or entry description
//!   from a single message. A name that does not fit is cut (at a UTF-8 character boundary);
//!   a default, minimum or maximum that does not fit is left out (below).
//! - **Value info** (entry description): bits 0..2 of the request are reserved and ignored. The
//!   response echoes the bits whose field it carries: the unit (0x08) always (0 means "no
//!   unit"); the default (0x10), minimum (0x20) and maximum (0x40) when the dictionary declares
//!   them and they fit, otherwise the bit is cleared and the field omitted. Each value field is
//!   `ceil(bit length / 8)` bytes in the entry's encoding, zero-padded (a string's default shorter
//!   than its capacity), so the MainDevice can find where the next field starts.
//! - **Short requests** are not SDO Information errors: a request shorter than the SDO
//!   Information header and the fixed part its opcode needs (2 bytes for Get OD List and Get
//!   Object Description, 4 for Get Entry Description, none for other opcodes) is a CoE payload
//!   shorter than required, which the mailbox answers with mailbox error 0x0008 "invalid size"
//!   (ETG.1000.4 Table 30, conformance.md "Mailbox"; [`InfoRequest::parse`] gives `None`). Longer
//!   requests (mailbox padding) are accepted.
//! - **Errors** of well-formed requests (opcode 0x07, ETG.1000.6 Table 41 codes):
//!   - an opcode that is not a request: `0x05040001` ([`AbortCode::COMMAND_SPECIFIER`]);
//!   - a list type above 5: `0x06010000` ([`AbortCode::UNSUPPORTED_ACCESS`], as SOES does);
//!   - missing object `0x06020000`, missing subindex `0x06090011` (above the highest subindex,
//!     or beyond SI0 of a VAR);
//!   - a message too short for a description's fixed part: `0x06010005`
//!     ([`AbortCode::EXCEEDS_MAILBOX`]).
//! - **Gaps of a sparse RECORD** (a subindex up to the highest that the record does not
//!   declare, 0x1C32:0E..1F) are described, not refused, as SSC describes them: data type 0,
//!   bit length 0, access 0, value info 0, name `SubIndex NNN` (`gap_description`). Every
//!   well-formed request for subindex 0..=max of an existing object is answered without an SDO
//!   Info error (SOEM's `ecx_readOE` asks for each of them).
//! - A request with the incomplete bit set is served as if it were clear (requests are never
//!   fragmented).
//! - An `out` shorter than an error response (10 bytes) gets nothing: `request` returns 0 and
//!   `next_fragment` abandons the transfer and returns `None`.
//!
//! ## Work per call
//! Bounded by the message size: every OD list is a table made at compile time
//! ([`ObjectDictionary::OD_LISTS`]), so an OD-list call copies the words that fit.

use super::{AbortCode, CoeHeader, Service};
use crate::dictionary::{
    Access, EntryInfo, Limit, Object, ObjectCode, ObjectDictionary, ObjectInfo,
};

/// The SDO Information opcode (byte 0 of the SDO Information header, bits 0..6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Opcode {
    /// 0x01: Get OD List request.
    GetOdListRequest,
    /// 0x02: Get OD List response.
    GetOdListResponse,
    /// 0x03: Get Object Description request.
    GetObjectDescriptionRequest,
    /// 0x04: Get Object Description response.
    GetObjectDescriptionResponse,
    /// 0x05: Get Entry Description request.
    GetEntryDescriptionRequest,
    /// 0x06: Get Entry Description response.
    GetEntryDescriptionResponse,
    /// 0x07: SDO Info Error request.
    InfoError,
    /// Any other value.
    Unknown(u8),
}

impl Opcode {
    /// The opcode of byte `code`, the incomplete bit (bit 7) ignored.
    pub const fn from_code(code: u8) -> Self {
        match code & 0x7F {
            0x01 => Self::GetOdListRequest,
            0x02 => Self::GetOdListResponse,
            0x03 => Self::GetObjectDescriptionRequest,
            0x04 => Self::GetObjectDescriptionResponse,
            0x05 => Self::GetEntryDescriptionRequest,
            0x06 => Self::GetEntryDescriptionResponse,
            0x07 => Self::InfoError,
            c => Self::Unknown(c),
        }
    }

    /// The 7-bit code.
    pub const fn code(self) -> u8 {
        match self {
            Self::GetOdListRequest => 0x01,
            Self::GetOdListResponse => 0x02,
            Self::GetObjectDescriptionRequest => 0x03,
            Self::GetObjectDescriptionResponse => 0x04,
            Self::GetEntryDescriptionRequest => 0x05,
            Self::GetEntryDescriptionResponse => 0x06,
            Self::InfoError => 0x07,
            Self::Unknown(c) => c & 0x7F,
        }
    }
}

/// The 4-byte SDO Information header that follows the CoE header (ETG.1000.6 §5.6.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InfoHeader {
    /// Byte 0, bits 0..6.
    pub opcode: Opcode,
    /// Byte 0, bit 7: more fragments follow.
    pub incomplete: bool,
    /// Bytes 2..3: how many fragments still follow this one.
    pub fragments_left: u16,
}

impl InfoHeader {
    /// Size on the wire.
    pub const SIZE: usize = 4;

    /// Parses the first four bytes; `None` when there are fewer.
    pub fn parse(bytes: &[u8]) -> Option<Self> {
        let (&[op, _reserved, lo, hi], _) = bytes.split_first_chunk::<4>()?;
        Some(Self {
            opcode: Opcode::from_code(op),
            incomplete: op & 0x80 != 0,
            fragments_left: u16::from_le_bytes([lo, hi]),
        })
    }

    /// The four bytes on the wire (reserved byte 0).
    pub const fn to_bytes(self) -> [u8; 4] {
        Self::bytes(self.opcode.code(), self.incomplete, self.fragments_left)
    }

    /// The four bytes of a header whose opcode has the code `code` (bits 0..6): the responses
    /// take their opcode's code where the opcode is a constant, so no match turns it into one.
    const fn bytes(code: u8, incomplete: bool, fragments_left: u16) -> [u8; 4] {
        let incomplete = if incomplete { 0x80 } else { 0 };
        let [lo, hi] = fragments_left.to_le_bytes();
        [code | incomplete, 0, lo, hi]
    }
}

/// An SDO Information request: the opcode and the fixed part of its service data (ETG.1000.6
/// §5.6.3.3–§5.6.3.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InfoRequest {
    /// Get OD List: the list type (u16, any value; checked when served).
    OdList(u16),
    /// Get Object Description: the index.
    ObjectDescription(u16),
    /// Get Entry Description: the index, the subindex and the value info asked for.
    EntryDescription {
        /// The object.
        index: u16,
        /// The entry.
        sub: u8,
        /// Which optional fields the MainDevice asks for.
        value_info: ValueInfo,
    },
    /// Any other opcode (a response, an error, an unknown code): answered with `0x05040001`.
    Unsupported,
}

impl InfoRequest {
    /// Parses the bytes after the CoE header: the SDO Information header, then the fixed part of
    /// the opcode; bytes after it (mailbox padding) and the incomplete bit are ignored. `None`
    /// when shorter: a CoE payload shorter than required, mailbox error 0x0008.
    pub fn parse(bytes: &[u8]) -> Option<Self> {
        let header = InfoHeader::parse(bytes)?;
        let params = bytes.get(InfoHeader::SIZE..)?;
        let index = || params.first_chunk::<2>().map(|&b| u16::from_le_bytes(b));
        Some(match header.opcode {
            Opcode::GetOdListRequest => Self::OdList(index()?),
            Opcode::GetObjectDescriptionRequest => Self::ObjectDescription(index()?),
            Opcode::GetEntryDescriptionRequest => {
                let &[i0, i1, sub, value_info] = params.first_chunk::<4>()?;
                Self::EntryDescription {
                    index: u16::from_le_bytes([i0, i1]),
                    sub,
                    value_info: ValueInfo(value_info),
                }
            }
            _ => Self::Unsupported,
        })
    }
}

/// Which indices a Get OD List request asks for (ETG.1000.6 §5.6.3, Get OD List request).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u16)]
pub enum ListType {
    /// 0: the lengths of lists 1..=5, five u16 counts.
    Lengths = 0,
    /// 1: every object.
    All = 1,
    /// 2: objects with an RxPDO-mappable entry.
    RxPdo = 2,
    /// 3: objects with a TxPDO-mappable entry.
    TxPdo = 3,
    /// 4: objects with an entry in the backup.
    Backup = 4,
    /// 5: objects with a settings entry.
    Settings = 5,
}

// `ListType::contains` takes list 2 + n's flag as the RxPDO flag shifted by n.
const _: () = assert!(
    Access::TXPDO.0 == Access::RXPDO.0 << 1
        && Access::BACKUP.0 == Access::RXPDO.0 << 2
        && Access::SETTINGS.0 == Access::RXPDO.0 << 3
);

/// The lists whose lengths list type 0 reports, in order.
const OBJECT_LISTS: [ListType; 5] = [
    ListType::All,
    ListType::RxPdo,
    ListType::TxPdo,
    ListType::Backup,
    ListType::Settings,
];

impl ListType {
    /// The list type of `code`, `None` above 5.
    pub const fn from_code(code: u16) -> Option<Self> {
        Some(match code {
            0 => Self::Lengths,
            1 => Self::All,
            2 => Self::RxPdo,
            3 => Self::TxPdo,
            4 => Self::Backup,
            5 => Self::Settings,
            _ => return None,
        })
    }

    /// The code on the wire.
    pub const fn code(self) -> u16 {
        self as u16
    }

    /// Whether `object` is in this list: any of its entries carries the list's access flag.
    /// [`ListType::Lengths`] holds no object.
    #[allow(clippy::indexing_slicing)] // bounded by the loop condition
    pub const fn contains(self, object: &ObjectInfo) -> bool {
        // Lists 2..=5 take the access flags 0x0040 (RxPDO) .. 0x0200 (settings), in order
        // (asserted at compile time above `OBJECT_LISTS`): one shift rather than a match.
        let flag = match self {
            Self::Lengths => return false,
            Self::All => return true,
            list => Access::RXPDO.0 << (list as u16 - Self::RxPdo as u16),
        };
        let mut i = 0;
        while i < object.entries.len() {
            if object.entries[i].access.0 & flag != 0 {
                return true;
            }
            i += 1;
        }
        false
    }
}

/// The length of each list (by its code) of a dictionary of `objects`: what a Get OD List
/// response counts, a table in flash rather than a count of the dictionary at run time.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
const fn list_lengths<D>(objects: &[Object<D>]) -> [u16; 6] {
    let mut lengths = [OBJECT_LISTS.len() as u16, 0, 0, 0, 0, 0];
    let mut l = 0;
    while l < OBJECT_LISTS.len() {
        let list = OBJECT_LISTS[l];
        let mut i = 0;
        while i < objects.len() {
            if list.contains(&objects[i].info) {
                lengths[list as usize] = lengths[list as usize].saturating_add(1);
            }
            i += 1;
        }
        l += 1;
    }
    lengths
}

/// Where each list (by its code, 0..=5) starts in [`ObjectDictionary::OD_LISTS`], and where
/// the last ends: each list is its list type word and then its values. 16-bit positions (a
/// table of 14 bytes in flash): a dictionary of more words does not compile.
#[allow(clippy::indexing_slicing)] // constant positions; evaluated at compile time
const fn list_starts<D>(objects: &[Object<D>]) -> [u16; 7] {
    let lengths = list_lengths(objects);
    let mut starts = [0; 7];
    let mut l = 1;
    while l < starts.len() {
        let end = starts[l - 1] as usize + 1 + lengths[l - 1] as usize;
        assert!(end <= u16::MAX as usize, "at most 65 535 words of OD lists");
        starts[l] = end as u16;
        l += 1;
    }
    starts
}

/// The length of [`ObjectDictionary::OD_LISTS`] for a dictionary of `objects`.
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // a constant position; evaluated at compile time
pub const fn od_lists_len<D>(objects: &[Object<D>]) -> usize {
    list_starts(objects)[6] as usize
}

/// [`ObjectDictionary::OD_LISTS`] of a dictionary of `objects`: lists 0..=5 one after the
/// other, each its list type word (which opens a Get OD List response) and then its values —
/// list 0 the lengths of lists 1..=5, the others their objects' indices in ascending order.
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn od_lists<D, const N: usize>(objects: &[Object<D>]) -> [u16; N] {
    let lengths = list_lengths(objects);
    let mut words = [0; N];
    let mut n = 0;
    let mut l = 0;
    while l < lengths.len() {
        words[n] = l as u16;
        n += 1;
        if l == 0 {
            let mut k = 1;
            while k < lengths.len() {
                words[n] = lengths[k];
                n += 1;
                k += 1;
            }
        } else {
            let list = OBJECT_LISTS[l - 1];
            let mut i = 0;
            while i < objects.len() {
                if list.contains(&objects[i].info) {
                    words[n] = objects[i].info.index;
                    n += 1;
                }
                i += 1;
            }
        }
        l += 1;
    }
    assert!(n == N);
    words
}

/// [`ObjectDictionary::INDICES`] of a dictionary of `objects` whose
/// [`ObjectDictionary::OD_LISTS`] is `lists`: list 1's values, the same words in flash once.
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // a constant position; evaluated at compile time
pub const fn all_indices<D>(objects: &[Object<D>], lists: &'static [u16]) -> &'static [u16] {
    let starts = list_starts(objects);
    // List 1 starts after list 0's six words: its type word, then every index.
    let (_, all) = lists.split_at(starts[1] as usize + 1);
    all.split_at(objects.len()).0
}

/// The value-info byte of a Get Entry Description request and response: which optional fields
/// follow the fixed part (ETG.1000.6 §5.6.3.6). Bits 0..2 are reserved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ValueInfo(pub u8);

impl ValueInfo {
    /// Bit 3: the unit type, u16.
    pub const UNIT_TYPE: u8 = 0x08;
    /// Bit 4: the default value.
    pub const DEFAULT_VALUE: u8 = 0x10;
    /// Bit 5: the minimum value.
    pub const MINIMUM_VALUE: u8 = 0x20;
    /// Bit 6: the maximum value.
    pub const MAXIMUM_VALUE: u8 = 0x40;

    /// Whether `bit` is set.
    pub const fn has(self, bit: u8) -> bool {
        self.0 & bit != 0
    }
}

/// The optional fields of an entry description, in wire order: the unit, then the value fields.
const VALUE_FIELDS: [(u8, Limit); 4] = [
    (ValueInfo::UNIT_TYPE, Limit::Unit),
    (ValueInfo::DEFAULT_VALUE, Limit::Default),
    (ValueInfo::MINIMUM_VALUE, Limit::Min),
    (ValueInfo::MAXIMUM_VALUE, Limit::Max),
];

/// The CoE header and the SDO Information header.
const HEADERS: usize = CoeHeader::SIZE + InfoHeader::SIZE;
/// The smallest message served: an SDO Info Error (headers and a u32 abort code).
const MIN_MESSAGE: usize = HEADERS + 4;
/// Where the value-info byte sits in an entry description's service data.
const VALUE_INFO_AT: usize = 3;

/// The SDO Information server: answers requests and holds the state of a fragmented OD list.
#[derive(Debug, Clone, Default)]
pub struct SdoInfo {
    transfer: Option<ListTransfer>,
}

impl SdoInfo {
    /// No response in progress.
    pub const fn new() -> Self {
        Self { transfer: None }
    }

    /// Handles one SDO Information request ([`InfoRequest::parse`]). Writes the whole first
    /// response message (CoE header included) into `out` (`out.len()` = capacity of one mailbox
    /// message's data after the 6-byte mailbox header) and returns its length: 0 when `out` is
    /// shorter than an error response. A new request abandons a fragmented response in progress.
    #[must_use]
    pub fn request<D: ObjectDictionary>(&mut self, request: InfoRequest, out: &mut [u8]) -> usize {
        self.abandon();
        if out.len() < MIN_MESSAGE {
            return 0;
        }
        let Some(data) = out.get_mut(HEADERS..) else {
            return 0;
        };
        let response = self
            .serve::<D>(request, data)
            .unwrap_or_else(|code| info_error(code, data));
        finish(out, response)
    }

    /// The next fragment of a fragmented response (CoE header included), `None` when none is
    /// pending. An `out` shorter than an error response abandons the response.
    #[must_use]
    pub fn next_fragment<D: ObjectDictionary>(&mut self, out: &mut [u8]) -> Option<usize> {
        let transfer = self.transfer.take()?;
        if out.len() < MIN_MESSAGE {
            return None;
        }
        let data = out.get_mut(HEADERS..)?;
        let response = self.send(transfer, data);
        Some(finish(out, response))
    }

    /// Drops a fragmented response in progress: a new request came, served or not.
    pub fn abandon(&mut self) {
        self.transfer = None;
    }

    /// Whether fragments are pending.
    pub fn is_pending(&self) -> bool {
        self.transfer.is_some()
    }

    /// Writes the next fragment of `transfer` into `data`; keeps the transfer while values remain.
    fn send(&mut self, mut transfer: ListTransfer, data: &mut [u8]) -> Response {
        let response = transfer.fragment(data);
        self.transfer = Some(transfer).filter(|t| !t.words.is_empty());
        response
    }

    /// Serves `request` into `data`.
    fn serve<D: ObjectDictionary>(
        &mut self,
        request: InfoRequest,
        data: &mut [u8],
    ) -> Result<Response, AbortCode> {
        match request {
            InfoRequest::OdList(code) => {
                let transfer = ListTransfer::new::<D>(code).ok_or(AbortCode::UNSUPPORTED_ACCESS)?;
                Ok(self.send(transfer, data))
            }
            InfoRequest::ObjectDescription(index) => object_description::<D>(index, data),
            InfoRequest::EntryDescription {
                index,
                sub,
                value_info,
            } => entry_description::<D>(index, sub, value_info, data),
            InfoRequest::Unsupported => Err(AbortCode::COMMAND_SPECIFIER),
        }
    }
}

/// What the headers of a response say, and how much service data follows them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Response {
    /// The opcode's code ([`Opcode::code`], taken where the opcode is a constant).
    code: u8,
    fragments_left: u16,
    len: usize,
}

impl Response {
    /// An unfragmented response of `len` bytes.
    const fn whole(opcode: Opcode, len: usize) -> Self {
        Self {
            code: opcode.code(),
            fragments_left: 0,
            len,
        }
    }
}

/// Writes the CoE header and the SDO Information header in front of the service data already in
/// `out[HEADERS..]`; returns the message length. The one writer of both headers.
fn finish(out: &mut [u8], response: Response) -> usize {
    const COE: [u8; 2] = CoeHeader::new(Service::SdoInformation).to_bytes();
    let [c0, c1] = COE;
    let [i0, i1, i2, i3] = InfoHeader::bytes(
        response.code,
        response.fragments_left > 0,
        response.fragments_left,
    );
    match out.first_chunk_mut() {
        Some(head) => {
            *head = [c0, c1, i0, i1, i2, i3];
            HEADERS + response.len
        }
        None => 0,
    }
}

/// SDO Info Error (ETG.1000.6 §5.6.3.8): service data = the u32 abort code.
fn info_error(code: AbortCode, data: &mut [u8]) -> Response {
    let w = Writer::starting(data, code.0.to_le_bytes());
    Response::whole(Opcode::InfoError, w.map_or(0, |w| w.len))
}

/// Get Object Description (ETG.1000.6 §5.6.3.5). Request: u16 index. Response: u16 index, u16
/// data type, u8 max subindex, u8 object code, then the name (cut to fit, no terminator).
fn object_description<D: ObjectDictionary>(
    index: u16,
    data: &mut [u8],
) -> Result<Response, AbortCode> {
    let info = &D::object(index).ok_or(AbortCode::NO_OBJECT)?.info;
    let [i0, i1] = index.to_le_bytes();
    let [t0, t1] = info.data_type().to_le_bytes();
    let fixed = [i0, i1, t0, t1, info.max_sub, info.code as u8];
    let mut w = Writer::starting(data, fixed).ok_or(AbortCode::EXCEEDS_MAILBOX)?;
    w.put_name(D::name(info.name).as_bytes());
    Ok(Response::whole(Opcode::GetObjectDescriptionResponse, w.len))
}

/// Get Entry Description (ETG.1000.6 §5.6.3.6). Request: u16 index, u8 subindex, u8 value info.
/// Response: u16 index, u8 subindex, u8 value info (the bits honoured), u16 data type, u16 bit
/// length, u16 object access, then the fields value info announces (unit u16, default, minimum,
/// maximum, see the module documentation), then the name (cut to fit, no terminator).
fn entry_description<D: ObjectDictionary>(
    index: u16,
    sub: u8,
    requested: ValueInfo,
    data: &mut [u8],
) -> Result<Response, AbortCode> {
    let object = D::object(index).ok_or(AbortCode::NO_OBJECT)?;
    let entry = object.info.entry(sub);
    let mut gap_name = *b"SubIndex 000";
    // Data type, bit length and access: a gap's are 0.
    let ((data_type, bit_len, access), name) = match entry {
        Some(entry) => (
            (entry.data_type.code(), entry.bit_len, entry.access.0),
            D::name(entry.name).as_bytes(),
        ),
        None => {
            name_gap(&object.info, sub, &mut gap_name)?;
            ((0, 0, 0), &gap_name[..])
        }
    };
    let [i0, i1] = index.to_le_bytes();
    let [t0, t1] = data_type.to_le_bytes();
    let [b0, b1] = bit_len.to_le_bytes();
    let [a0, a1] = access.to_le_bytes();
    let fixed = [i0, i1, sub, 0, t0, t1, b0, b1, a0, a1];
    let mut w = Writer::starting(data, fixed).ok_or(AbortCode::EXCEEDS_MAILBOX)?;
    let mut honoured = 0;
    if let Some(entry) = entry {
        for (bit, limit) in VALUE_FIELDS {
            if requested.has(bit) && put_value(&mut w, object, sub, entry, limit) {
                honoured |= bit;
            }
        }
    }
    w.put_name(name);
    w.patch(VALUE_INFO_AT, honoured);
    Ok(Response::whole(Opcode::GetEntryDescriptionResponse, w.len))
}

/// The name, into `name`, of a subindex a RECORD does not declare below its highest one (a gap
/// of a sparse record, 0x1C32:0E..1F), whose entry description [`entry_description`] writes as
/// SSC writes it (its records are dense arrays of entry descriptions, a gap `{0x0000, 0, 0}`,
/// Beckhoff SSC 5.12 `objdef.c` `OBJ_GetEntryDesc`/`OBJ_GetDesc`, `coeappl.c`
/// `asEntryDesc0x1C3x`): data type 0, bit length 0, access 0, value info 0 (no optional field,
/// whatever the request asks) and the name SSC gives an entry without one, `SubIndex NNN` (three
/// decimal digits). SOEM's `ecx_readOE` asks for every subindex 0..max of every object and
/// records an SDO Info error for each one refused. Any other missing subindex is `0x06090011`
/// (ETG.1000.6 Table 41).
fn name_gap(object: &ObjectInfo, sub: u8, name: &mut [u8; 12]) -> Result<(), AbortCode> {
    if object.code != ObjectCode::Record || sub == 0 || sub > object.max_sub {
        return Err(AbortCode::NO_SUBINDEX);
    }
    let mut n = sub;
    for digit in name.iter_mut().rev().take(3) {
        *digit = b'0' + n % 10;
        n /= 10;
    }
    Ok(())
}

/// Appends the declared `limit` of `index:sub`: the unit as a u16, 0 for none (always
/// appended when it fits); a value as a field of `ceil(bit length / 8)` bytes, `false`
/// (nothing appended) when it is not declared or does not fit.
fn put_value<D: ObjectDictionary>(
    w: &mut Writer<'_>,
    object: &Object<D>,
    sub: u8,
    entry: &EntryInfo,
    limit: Limit,
) -> bool {
    let unit = limit == Limit::Unit;
    let size = if unit {
        2
    } else {
        usize::from(entry.bit_len).div_ceil(8)
    };
    // An object's `limit` encodes only what the entry declares (0 bytes otherwise).
    w.put_field(size, |field| {
        usize::from(unit) | object.limit(sub, limit, field)
    })
}

/// Get OD List (ETG.1000.6 §5.6.3): a response in progress. Request: u16 list type.
/// Response: u16 list type (first fragment only), then u16 values: the indices of the list's
/// objects in ascending order, or for list type 0 the lengths of lists 1..=5 — every list,
/// its type word first, a table in flash built at compile time
/// ([`ObjectDictionary::OD_LISTS`]), which the fragments copy from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ListTransfer {
    /// The words still to be sent.
    words: &'static [u16],
}

impl ListTransfer {
    /// The transfer of list type `code`, `None` above 5.
    fn new<D: ObjectDictionary>(code: u16) -> Option<Self> {
        // The positions are the objects'; the table must be theirs (as `dictionary!` makes it),
        // or a list would be cut from the wrong words: a dictionary whose table is not does not
        // compile.
        let starts = const {
            assert!(
                D::OD_LISTS.len() == od_lists_len(D::OBJECTS),
                "OD_LISTS is not the OD lists of OBJECTS (`coe::sdo_info::od_lists`)"
            );
            &list_starts(D::OBJECTS)
        };
        let at = usize::from(code);
        let (&start, &end) = (starts.get(at)?, starts.get(at + 1)?);
        let words = D::OD_LISTS.get(usize::from(start)..usize::from(end))?;
        Some(Self { words })
    }

    /// Writes the next fragment's service data into `data`: as many 16-bit words as fit.
    /// The one writer of OD-list fragments, first and following.
    fn fragment(&mut self, data: &mut [u8]) -> Response {
        let (slots, _) = data.as_chunks_mut::<2>();
        let room = slots.len();
        let (now, rest) = self.words.split_at(self.words.len().min(room));
        for (slot, &value) in slots.iter_mut().zip(now) {
            *slot = value.to_le_bytes();
        }
        self.words = rest;
        let fragments_left = rest.len().div_ceil(room.max(1));
        Response {
            code: Opcode::GetOdListResponse.code(),
            fragments_left: u16::try_from(fragments_left).unwrap_or(u16::MAX),
            len: now.len() * 2,
        }
    }
}

/// Appends to a message buffer; what does not fit is not written at all.
struct Writer<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl<'a> Writer<'a> {
    /// A writer that has written `fixed` first (one store of the whole array); `None` when
    /// `buf` is shorter.
    fn starting<const N: usize>(buf: &'a mut [u8], fixed: [u8; N]) -> Option<Self> {
        *buf.first_chunk_mut()? = fixed;
        Some(Self { buf, len: N })
    }

    /// Bytes still free.
    fn room(&self) -> usize {
        self.buf.len().saturating_sub(self.len)
    }

    /// Appends a field of `size` zeroed bytes that `fill` encodes into (returning the bytes it
    /// wrote); `false` (nothing appended) when the field is empty, does not fit or `fill` wrote
    /// nothing.
    fn put_field(&mut self, size: usize, fill: impl FnOnce(&mut [u8]) -> usize) -> bool {
        let end = self.len.saturating_add(size);
        let Some(field) = self.buf.get_mut(self.len..end).filter(|f| !f.is_empty()) else {
            return false;
        };
        field.fill(0);
        if fill(field) == 0 {
            return false;
        }
        self.len = end;
        true
    }

    /// Appends as much of the UTF-8 text `name` as fits, cut at a character boundary (not
    /// before a byte that continues a character). Bytes, not `&str`: the gap's name, built
    /// from digits, needs no UTF-8 validation (300 bytes of firmware).
    fn put_name(&mut self, name: &[u8]) {
        let mut cut = self.room().min(name.len());
        while cut > 0 && name.get(cut).is_some_and(|&b| b & 0xC0 == 0x80) {
            cut -= 1;
        }
        // `cut` is within the room: the copy takes all of it.
        let rest = self.buf.get_mut(self.len..).unwrap_or_default();
        self.len += crate::bytes::copy(rest, name.get(..cut).unwrap_or_default());
    }

    /// Overwrites the byte at `at` of what was written.
    fn patch(&mut self, at: usize, byte: u8) {
        if let Some(slot) = self.buf.get_mut(..self.len).and_then(|b| b.get_mut(at)) {
            *slot = byte;
        }
    }
}
