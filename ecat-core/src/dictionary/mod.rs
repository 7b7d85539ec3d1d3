//! The CoE object dictionary (ETG.1000.6 §5.6.3, CiA 301 §7.4).
//!
//! ## How a device declares it
//! The application writes its dictionary as a plain Rust struct — typed fields it reads and
//! writes directly — and maps indices onto the fields with [`dictionary!`](crate::dictionary!):
//!
//! ```
//! use ecat_core::device::Identity;
//! use ecat_core::dictionary::{Communication, DeviceInfo, ObjectDictionary};
//! use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
//!
//! /// The description constants of the communication area (0x1000..0x1018).
//! pub const INFO: DeviceInfo = DeviceInfo {
//!     device_type: 0x0002_0192,
//!     name: "ecat drive",
//!     hardware_version: "A",
//!     software_version: "0.1.0",
//!     identity: Identity { vendor_id: 0xE000_0001, product_code: 1, revision: 1, serial: 1 },
//! };
//!
//! pub struct Limits { pub min: i32, pub max: i32 }
//!
//! pub struct Od {
//!     pub area: Communication,
//!     pub rx: PdoMapping<2>,
//!     pub rx_assign: PdoAssignment<1>,
//!     pub tx_assign: PdoAssignment<1>,
//!     pub gains: [i16; 4],
//!     pub controlword: u16,
//!     pub target_position: i32,
//!     pub limits: Limits,
//! }
//!
//! const RX: [MappingEntry; 2] = [MappingEntry::new(0x6040, 0, 16), MappingEntry::new(0x607A, 0, 32)];
//!
//! ecat_core::dictionary! {
//!     Od {
//!         communication(area, INFO);
//!         0x1600 => pdo(rx, RO, "RxPDO", "Mapped object", default = PdoMapping::mapping(&RX));
//!         0x1C12 => pdo(rx_assign, RO, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
//!         0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[]));
//!         0x2000 => array(gains, RW, "Gains", "Gain", default = 10, min = 0, max = 1000);
//!         0x6040 => var(controlword, RW | RXPDO, "Controlword");
//!         0x607A => var(target_position, RW | RXPDO, "Target position", min = -1_000_000, max = 1_000_000);
//!         0x607D => record(limits: Limits, "Software position limit") {
//!             1 => min, RW, "Min position limit";
//!             2 => max, RW, "Max position limit", default = 1_000_000;
//!         };
//!     }
//! }
//!
//! let od = Od::default();
//! assert_eq!(od.area.identity.vendor_id, 0xE000_0001);
//! assert_eq!(od.limits.max, 1_000_000);
//! // The 8 objects of the communication area and the application's 7, in index order.
//! assert_eq!(Od::OBJECTS.len(), 15);
//! ```
//!
//! The communication area (0x1000, 0x1008/0x1009/0x100A, 0x1018, 0x1C00, 0x1C32/0x1C33) is
//! the stack's: one `communication(field, INFO)` item makes it from the description constants
//! ([`communication`]); a CoE device's declaration without it, or without the PDO
//! assignments 0x1C12/0x1C13, does not compile.
//!
//! What this buys:
//! - one declaration gives the typed values *and* the metadata every other feature reads (SDO
//!   access rights, SDO Information, PDO mappability, SII and ESI generation);
//! - data types and bit lengths come from the Rust field types, so they cannot disagree;
//! - `const` assertions reject unsorted or duplicate indices and PDO-mappable strings at compile
//!   time; a missing or misspelt field is a compile error;
//! - lookup is a binary search over a `const` table: O(log n), no heap, no global state — every
//!   test builds its own dictionary value;
//! - the generated code is typed: a download decodes into the field's type and checks the
//!   declared range before storing.
//!
//! Application hooks (veto a write, react after it, compute a value before a read, stream a
//! DOMAIN) are the [`ObjectHooks`] trait, implemented by the application beside the dictionary.

mod access;
pub mod communication;
#[doc(hidden)]
pub mod compact;
mod data_type;
#[doc(hidden)]
pub mod limits;
mod object;
pub mod parameters;
mod value;

pub use access::Access;
pub use communication::{Communication, DeviceInfo};
pub use compact::Declaration;
pub use data_type::DataType;
pub(crate) use object::has_domain;
pub use object::{
    EntryInfo, Limit, Limits, Name, ObjectCode, ObjectInfo, is_well_formed, mappable_types_only,
};
pub use value::{Bits, ByteString, Domain, OctetString, UnicodeString, Value, VisibleString};

use crate::abort::AbortCode;
use crate::sync_mode::SupportedSyncModes;

/// A dictionary: the `const` table of its objects. Implemented by [`dictionary!`](crate::dictionary!).
pub trait ObjectDictionary: Sized + 'static {
    /// Every object, sorted by index: what [`dictionary!`](crate::dictionary!) makes at compile
    /// time of [`Self::DECLARATION`] (`dictionary::compact`), names in [`Self::NAMES`].
    const OBJECTS: &'static [Object<Self>];

    /// The objects as declared, names as text: what [`Self::OBJECTS`] and [`Self::NAMES`] are
    /// made of at compile time, never read at run time (so not in the program).
    #[doc(hidden)]
    const DECLARATION: &'static [Declaration<Self>] = &[];

    /// The names of every object and entry, each text once (none that a longer name holds),
    /// one after the other: what a description's [`Name`] points into ([`Self::name`]).
    const NAMES: &'static str = "";

    /// The synchronisation modes the device supports (0x1C32:04, ETG.1000.6 Table 74), stated
    /// once, at compile time: [`dictionary!`](crate::dictionary!) sets it from its
    /// `sync(MODES);` item. A device without DC SYNC0 here carries no DC
    /// code: the runners' SYNC0 paths are `if D::SYNC_MODES.dc()`. Default: free-run and
    /// SM-synchronous.
    const SYNC_MODES: SupportedSyncModes = SupportedSyncModes::DEFAULT;

    /// Every object's index, parallel to [`Self::OBJECTS`]: what [`Self::object`] searches, two
    /// bytes a step instead of a whole [`Object`]. [`dictionary!`](crate::dictionary!) takes it
    /// from OD list 1 in [`Self::OD_LISTS`] (the same words, in flash once).
    const INDICES: &'static [u16];

    /// The number of PDO-mappable entries (RxPDO or TxPDO), as a [`Length`]: the PDO layout
    /// keeps one bit offset per entry, indexed by its
    /// [number](crate::pdo::layout::number) ([`PerMappable`]).
    type Mappable: Length;

    /// How many TxPDO entries a configuration may map a second time, as a [`Length`]:
    /// [`repeat_room`](crate::pdo::layout::repeat_room) of the objects — as many as its TxPDO
    /// configurations can hold, none for a dictionary without TxPDO-mappable entries, whose
    /// layouts then take no space for them.
    type Repeatable: Length;

    /// The most bytes a download stores, as a [`Length`]:
    /// [`largest_download`](crate::coe::sdo::largest_download) of the objects. What
    /// `SubDevice<'c, MBX, D::Download>` sizes its SDO server's segmented-download buffer by: a
    /// dictionary whose values are a few bytes long keeps a buffer of a few bytes, not one of
    /// the mailbox's size.
    type Download: Length;

    /// Every PDO-mappable entry's key, by [number](crate::pdo::layout::number)
    /// ([`mappable_keys`](crate::pdo::layout::mappable_keys)): its index and subindex, the
    /// directions it may be mapped in and its bit length, one word each, ascending. What a
    /// mapping entry is checked against and a layout made from at run time: one binary search,
    /// no walk of the descriptions.
    const MAPPABLE: &'static [u32];

    /// SDO Information's OD lists 0..=5 (ETG.1000.6 Table 43: the lengths of lists 1..=5, then
    /// all objects, RxPDO-, TxPDO-mappable, backup, settings), one after the other, each its
    /// list type word and then its values (indices ascending): built by
    /// [`dictionary!`](crate::dictionary!) at compile time, so a Get OD List response copies
    /// words from a table instead of testing every object's entries. The default is the lists
    /// of a dictionary without objects.
    #[doc(hidden)]
    const OD_LISTS: &'static [u16] = &[0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5];

    /// Every declared default, minimum, maximum and unit, encoded at compile time by
    /// [`dictionary!`](crate::dictionary!) as records of index, subindex, kind, length and
    /// bytes: what [`Object::limit`] walks, no code per object. Empty by default (a dictionary
    /// without declared values).
    const LIMITS: &'static [u8] = &[];

    /// Copies every RxPDO-mappable entry from its offset in `image` into its field (generated: one
    /// [`Mapped::unpack`](crate::pdo::image::Mapped::unpack) per field, no lookup).
    fn unpack_mapped(&mut self, offsets: &PerMappable<Self, u16>, image: &[u8]);

    /// Copies every TxPDO-mappable entry into `image` at its offset (generated: one
    /// [`Mapped::pack`](crate::pdo::image::Mapped::pack) per field).
    fn pack_mapped(&self, offsets: &PerMappable<Self, u16>, image: &mut [u8]);

    /// The diagnosis history (0x10F3) the stack logs its events into, when the dictionary
    /// declares one (`dictionary!`'s `diagnosis` item).
    fn diagnosis(&mut self) -> Option<crate::history::History<'_>> {
        None
    }

    /// The communication area's values (0x1018, 0x1C32, 0x1C33): `None` for a dictionary
    /// without it (the default), the field of `dictionary!`'s `communication` item. The stack
    /// fills the sync parameters and keeps their diagnostics in their records, the objects'
    /// bytes ([`crate::sync_parameters`]): no lookup, no encoding.
    fn communication(&mut self) -> Option<&mut Communication> {
        None
    }

    /// The state of 0x1010/0x1011 ([`parameters`]): `None` for a device without storage (the
    /// default), the `stored` field of a `communication(area, INFO, stored = field)` item.
    fn stored_parameters(&mut self) -> Option<&mut parameters::StoredParameters> {
        None
    }

    /// The text of `name`, a name of one of [`Self::OBJECTS`] (empty for one outside
    /// [`Self::NAMES`]).
    fn name(name: Name) -> &'static str {
        Self::NAMES.get(name.range()).unwrap_or_default()
    }

    /// The object at `index`, by a search of [`Self::INDICES`]: a walk in a dictionary of up
    /// to 16 objects (less code, as few steps), a binary search in a larger one.
    fn object(index: u16) -> Option<&'static Object<Self>> {
        let i = if const { Self::INDICES.len() <= SHORT_DICTIONARY } {
            Self::INDICES.iter().position(|&i| i == index)?
        } else {
            Self::INDICES.binary_search(&index).ok()?
        };
        Self::OBJECTS.get(i)
    }
}

/// The most objects [`ObjectDictionary::object`] walks rather than halves: at this size the
/// walk's code is smaller (16 bytes on Cortex-M, SOES's digital I/O dictionary of 14 objects)
/// and its steps about as many (`bench/callgrind.sh`: an expedited upload of 0x1018, the fifth
/// object of ten, 11 instructions fewer).
const SHORT_DICTIONARY: usize = 16;

/// The empty dictionary: a device that is no CoE device (the state-machine tests). A CoE device's
/// dictionary comes from [`dictionary!`](crate::dictionary!) with its communication area.
impl ObjectDictionary for () {
    const OBJECTS: &'static [Object<Self>] = &[];
    const INDICES: &'static [u16] = &[];
    type Mappable = Len<0>;
    type Repeatable = Len<0>;
    type Download = Len<0>;
    const MAPPABLE: &'static [u32] = &[];
    fn unpack_mapped(&mut self, _: &[u16; 0], _: &[u8]) {}
    fn pack_mapped(&self, _: &[u16; 0], _: &mut [u8]) {}
}

/// A length as a type, for arrays of any element: what a dictionary tells the PDO layout about
/// its shape ([`ObjectDictionary::Mappable`]) without naming the layout's types.
pub trait Length {
    /// `[T; N]`.
    type Array<T: Copy>: AsRef<[T]> + AsMut<[T]> + Copy;

    /// `[value; N]`.
    fn array<T: Copy>(value: T) -> Self::Array<T>;
}

/// The length `N`.
#[derive(Debug)]
pub struct Len<const N: usize>;

impl<const N: usize> Length for Len<N> {
    type Array<T: Copy> = [T; N];

    fn array<T: Copy>(value: T) -> [T; N] {
        [value; N]
    }
}

/// One `T` per PDO-mappable entry of `D`: `[T; N]`.
pub type PerMappable<D, T> = <<D as ObjectDictionary>::Mappable as Length>::Array<T>;

/// What [`Object::read`] returns: bytes copied and the entry's whole size, 16 bits each in one
/// word.
///
/// An entry's size is at most 8 191 bytes (its bit length is a `u16`, [`EntryInfo::bit_len`],
/// as in SDO Information, ETG.1000.6 Table 44). One word makes `Result<Read, AbortCode>` a pair
/// of scalars, which every read function returns in two registers rather than through memory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Read(u32);

impl Read {
    /// `copied` bytes of a value of `size` bytes; each is taken modulo 65 536 (no entry is that
    /// large).
    #[allow(clippy::cast_possible_truncation)] // the sizes of entries, at most 8 191
    pub const fn new(copied: usize, size: usize) -> Self {
        Self((size as u32) << 16 | (copied as u32 & 0xFFFF))
    }

    /// Bytes copied into the output.
    pub const fn copied(self) -> usize {
        (self.0 & 0xFFFF) as usize
    }

    /// The encoded size of the whole value.
    pub const fn size(self) -> usize {
        (self.0 >> 16) as usize
    }
}

/// Where [`Object::read`] starts: a subindex and a byte offset into its value, in one word
/// (subindex in the low byte, offset above it).
///
/// One word keeps every read function's arguments in the four argument registers of the Arm
/// procedure call standard (the dictionary, this, `out`'s pointer and length) instead of one on
/// the stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct At(u32);

impl At {
    /// Subindex `sub` from byte `offset` of its value on; the offset is taken modulo 2²⁴ (no
    /// entry is that large: at most 8 191 bytes, [`Read`]).
    #[allow(clippy::cast_possible_truncation)] // as documented
    pub const fn new(sub: u8, offset: usize) -> Self {
        Self((offset as u32) << 8 | sub as u32)
    }

    /// Subindex `sub` from its first byte.
    pub const fn start(sub: u8) -> Self {
        Self::new(sub, 0)
    }

    /// The subindex.
    #[allow(clippy::cast_possible_truncation)] // the low byte
    pub const fn sub(self) -> u8 {
        self.0 as u8
    }

    /// The byte offset into the value.
    pub const fn offset(self) -> usize {
        (self.0 >> 8) as usize
    }
}

/// One object: its description and the typed code that reaches its fields. `S` is how names
/// are kept ([`EntryInfo`]): [`Name`]s in the dictionary's table, text in its
/// [`Declaration`].
pub struct Object<D, S: 'static = Name> {
    /// The description.
    pub info: ObjectInfo<S>,
    /// Copies the encoded value of a subindex from an offset ([`At`]) into `out`.
    pub read: fn(&D, At, &mut [u8]) -> Result<Read, AbortCode>,
    /// Decodes `data` into a subindex, after the range check.
    pub write: fn(&mut D, u8, &[u8]) -> Result<(), AbortCode>,
}

// Not derived: a description and two `fn` pointers copy whatever `D` is (the
// communication area's table is merged with the application's at compile time).
impl<D, S: Copy> Clone for Object<D, S> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<D, S: Copy> Copy for Object<D, S> {}

impl<D: ObjectDictionary> Object<D> {
    /// Encodes the declared default, minimum, maximum or unit of subindex `sub` ([`Limit`])
    /// into `out`; 0 bytes when not declared. From the dictionary's [`ObjectDictionary::LIMITS`].
    pub fn limit(&self, sub: u8, which: Limit, out: &mut [u8]) -> usize {
        limits::find(D::LIMITS, self.info.index, sub, which, out)
    }
}

/// Typed reads of the unsigned entries the stack itself looks at (PDO assignment and mapping
/// entries, sync parameters, limits): `None` when the entry is missing or of another size.
impl<D> Object<D> {
    /// Subindex 0 (the number of entries of an ARRAY or RECORD), 0 when it cannot be read.
    pub(crate) fn count(&self, od: &D) -> u8 {
        self.read_uint(od, 0, 1).map_or(0, |n| n as u8)
    }

    /// A 16-bit entry.
    pub(crate) fn read_u16(&self, od: &D, sub: u8) -> Option<u16> {
        self.read_uint(od, sub, 2).map(|v| v as u16)
    }

    /// A 32-bit entry.
    pub(crate) fn read_u32(&self, od: &D, sub: u8) -> Option<u32> {
        self.read_uint(od, sub, 4)
    }

    /// The first `width` bytes (1, 2 or 4) of an entry, little endian; `None` when it cannot
    /// be read or gives fewer. One copy for the three readers above.
    #[inline(never)]
    fn read_uint(&self, od: &D, sub: u8, width: usize) -> Option<u32> {
        let mut bytes = [0u8; 4];
        let buf = bytes.get_mut(..width)?;
        let read = (self.read)(od, At::start(sub), buf).ok()?;
        (read.copied() == width).then(|| u32::from_le_bytes(bytes))
    }
}

/// The application's say in SDO access, implemented beside the dictionary. Every method has a
/// default that does nothing special.
pub trait ObjectHooks<D> {
    /// Before a download stores `data` into `index:sub`: `Err` vetoes it with that abort code.
    fn before_write(&mut self, od: &D, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let _ = (od, index, sub, data);
        Ok(())
    }

    /// After a download stored a value into `index:sub`.
    fn after_write(&mut self, od: &mut D, index: u16, sub: u8) {
        let _ = (od, index, sub);
    }

    /// Before an upload reads `index:sub`: refresh a computed value, or refuse.
    fn before_read(&mut self, od: &mut D, index: u16, sub: u8) -> Result<(), AbortCode> {
        let _ = (od, index, sub);
        Ok(())
    }

    /// The size of the DOMAIN `index:sub` about to be uploaded.
    fn domain_size(&mut self, index: u16, sub: u8) -> Result<u32, AbortCode> {
        let _ = (index, sub);
        Err(AbortCode::UNSUPPORTED_ACCESS)
    }

    /// Reads the DOMAIN `index:sub` from `offset` into `out`; returns the bytes read.
    fn domain_read(
        &mut self,
        index: u16,
        sub: u8,
        offset: u32,
        out: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let _ = (index, sub, offset, out);
        Err(AbortCode::UNSUPPORTED_ACCESS)
    }

    /// Writes `data` at `offset` of the DOMAIN `index:sub`; `last` on the final piece.
    fn domain_write(
        &mut self,
        index: u16,
        sub: u8,
        offset: u32,
        data: &[u8],
        last: bool,
    ) -> Result<(), AbortCode> {
        let _ = (index, sub, offset, data, last);
        Err(AbortCode::UNSUPPORTED_ACCESS)
    }
}

/// No hooks.
impl<D> ObjectHooks<D> for () {}

// --- helpers for the code `dictionary!` generates -------------------------------------------

#[doc(hidden)]
pub const fn data_type_of<S, T: Value>(_: fn(&S) -> &T) -> DataType {
    T::DATA_TYPE
}

#[doc(hidden)]
pub const fn bit_len_of<S, T: Value>(_: fn(&S) -> &T) -> u16 {
    T::BIT_LEN
}

#[doc(hidden)]
pub const fn element_type_of<S, T: Value, const N: usize>(_: fn(&S) -> &[T; N]) -> DataType {
    T::DATA_TYPE
}

#[doc(hidden)]
pub const fn element_bit_len_of<S, T: Value, const N: usize>(_: fn(&S) -> &[T; N]) -> u16 {
    T::BIT_LEN
}

#[doc(hidden)]
pub const fn array_len_of<S, T, const N: usize>(_: fn(&S) -> &[T; N]) -> u8 {
    assert!(N >= 1 && N <= 255, "an ARRAY has 1..=255 elements");
    N as u8
}

/// An ARRAY's default: every element `value`, stored as one constant where `value` is one
/// (`core::array::from_fn` left a run-time loop per array in the firmware's start-up).
#[doc(hidden)]
pub const fn filled<T: Copy, const N: usize>(value: T) -> [T; N] {
    [value; N]
}

#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // compile time only, on a non-empty literal list
pub const fn last_sub(subs: &[u8]) -> u8 {
    subs[subs.len() - 1]
}

#[doc(hidden)]
pub fn read_value<T: Value>(value: &T, offset: usize, out: &mut [u8]) -> Read {
    Read::new(value.read_at(offset, out), value.size())
}

/// Reads the low `size` bytes (1, 2 or 4) of an UNSIGNED8/16/32 `value`, little endian, from
/// `offset` on: the one read of the stack's records whose entries differ only in width (the PDO
/// configuration objects, 0x1C32/0x1C33).
pub(crate) fn read_unsigned(value: u32, size: usize, offset: usize, out: &mut [u8]) -> Read {
    let bytes = value.to_le_bytes();
    Read::new(
        value::copy_from(bytes.get(..size).unwrap_or_default(), offset, out),
        size,
    )
}

#[doc(hidden)]
pub fn write_value<T: Value + PartialOrd>(
    slot: &mut T,
    data: &[u8],
    min: Option<T>,
    max: Option<T>,
) -> Result<(), AbortCode> {
    let value = T::decode(data)?;
    if min.is_some_and(|min| value < min) {
        return Err(AbortCode::VALUE_TOO_LOW);
    }
    if max.is_some_and(|max| value > max) {
        return Err(AbortCode::VALUE_TOO_HIGH);
    }
    *slot = value;
    Ok(())
}

/// Reads a VAR (SI0 only). One copy per type for every VAR of every dictionary: the code
/// `dictionary!` generates per object is a call.
#[doc(hidden)]
#[inline]
pub fn read_var<T: Value>(value: &T, at: At, out: &mut [u8]) -> Result<Read, AbortCode> {
    match at.sub() {
        0 => Ok(read_value(value, at.offset(), out)),
        _ => Err(AbortCode::NO_SUBINDEX),
    }
}

/// Writes `data` into a VAR (SI0 only) after the range check; one copy per type, never
/// inlined: the code `dictionary!` generates per VAR stays a call, where an inlined decode
/// and range check cost 40 B and more per object.
#[doc(hidden)]
#[inline(never)]
pub fn write_var<T: Value + PartialOrd>(
    slot: &mut T,
    sub: u8,
    data: &[u8],
    min: Option<T>,
    max: Option<T>,
) -> Result<(), AbortCode> {
    match sub {
        0 => write_value(slot, data, min, max),
        _ => Err(AbortCode::NO_SUBINDEX),
    }
}

/// Reads SI `sub` of an ARRAY: SI0 its length (at most 255, `array_len_of`), SI n element n.
/// One copy per element type for every ARRAY of every dictionary: the code `dictionary!`
/// generates per object is a call.
#[doc(hidden)]
pub fn read_element<T: Value>(items: &[T], at: At, out: &mut [u8]) -> Result<Read, AbortCode> {
    let offset = at.offset();
    match at.sub().checked_sub(1) {
        None => Ok(read_value(&(items.len() as u8), offset, out)),
        Some(n) => items
            .get(usize::from(n))
            .map(|v| read_value(v, offset, out))
            .ok_or(AbortCode::NO_SUBINDEX),
    }
}

/// Writes `data` into SI `sub` of an ARRAY after the range check (SI0 is read-only). One copy
/// per element type, as [`read_element`].
#[doc(hidden)]
pub fn write_element<T: Value + PartialOrd>(
    items: &mut [T],
    sub: u8,
    data: &[u8],
    min: Option<T>,
    max: Option<T>,
) -> Result<(), AbortCode> {
    match sub.checked_sub(1) {
        None => Err(AbortCode::READ_ONLY),
        Some(n) => match items.get_mut(usize::from(n)) {
            Some(slot) => write_value(slot, data, min, max),
            None => Err(AbortCode::NO_SUBINDEX),
        },
    }
}
