//! What the dictionary knows about each object and entry: the metadata SDO access, SDO
//! Information, PDO mapping, the SII image and the ESI file are all built from
//! (ETG.1000.6 §5.6.3 object description and entry description).

use super::{Access, DataType};

/// The object code (ETG.1000.6 Table 62).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum ObjectCode {
    /// A single value, subindex 0.
    Var = 7,
    /// Entries of one type, subindex 1..=n; subindex 0 holds n.
    Array = 8,
    /// Entries of different types; subindex 0 holds the highest subindex.
    Record = 9,
}

/// Where a name lies in its dictionary's table of names ([`ObjectDictionary::NAMES`]): what
/// the descriptions keep instead of a `&'static str` (3 bytes, byte-aligned, instead of 8 on a
/// 32-bit target; the text is [`ObjectDictionary::name`]'s).
///
/// [`ObjectDictionary::NAMES`]: super::ObjectDictionary::NAMES
/// [`ObjectDictionary::name`]: super::ObjectDictionary::name
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Name {
    /// The first byte's offset in the table, little endian (bytes: no padding in an
    /// [`EntryInfo`]).
    offset: [u8; 2],
    /// The length in bytes.
    len: u8,
}

impl Name {
    /// The empty name (the text of no dictionary's name: every declared name has some).
    pub const EMPTY: Self = Self::new(0, 0);

    /// `len` bytes from `offset` on.
    pub(super) const fn new(offset: u16, len: u8) -> Self {
        Self {
            offset: offset.to_le_bytes(),
            len,
        }
    }

    /// Its offset and length, at compile time.
    pub(super) const fn parts(self) -> (u16, u8) {
        (u16::from_le_bytes(self.offset), self.len)
    }

    /// Where its bytes lie in the table.
    pub(super) fn range(self) -> core::ops::Range<usize> {
        let start = usize::from(u16::from_le_bytes(self.offset));
        start..start + usize::from(self.len)
    }
}

/// The description of one entry (ETG.1000.6 §5.6.3.6 "entry description"). `S` is how the
/// name is kept: a [`Name`] in a dictionary's table
/// ([`ObjectDictionary::OBJECTS`](super::ObjectDictionary::OBJECTS), 10 bytes an entry), the text in what [`dictionary!`](crate::dictionary!) declares (a
/// [`Declaration`](super::Declaration), evaluated at compile time only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EntryInfo<S = Name> {
    /// The subindex (for an ARRAY element: 1, standing for every element).
    pub sub: u8,
    /// The name ([`ObjectDictionary::name`](super::ObjectDictionary::name) gives its text).
    pub name: S,
    /// The data type.
    pub data_type: DataType,
    /// The bit length (the capacity for strings).
    pub bit_len: u16,
    /// Access rights and flags.
    pub access: Access,
    /// Which of default, minimum, maximum and unit the dictionary declares (their values: the
    /// dictionary's [`LIMITS`](super::ObjectDictionary::LIMITS), by
    /// [`Object::limit`](super::Object::limit)).
    pub limits: Limits,
}

/// Which value limits an entry declares (the value-info bits 0x10/0x20/0x40 of ETG.1000.6
/// Table 53 shifted to bits 0..2), and whether it declares a unit (bit 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Limits(pub u8);

impl Limits {
    /// A default value is declared.
    pub const DEFAULT: u8 = 1 << 0;
    /// A minimum is declared.
    pub const MIN: u8 = 1 << 1;
    /// A maximum is declared.
    pub const MAX: u8 = 1 << 2;
    /// A unit is declared.
    pub const UNIT: u8 = 1 << 3;

    /// Whether `limit` is declared.
    pub const fn has(self, limit: Limit) -> bool {
        self.0 & (limit as u8) != 0
    }
}

/// One of an entry's declared values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Limit {
    /// The default value.
    Default = Limits::DEFAULT,
    /// The minimum.
    Min = Limits::MIN,
    /// The maximum.
    Max = Limits::MAX,
    /// The unit type sent in the SDO Information entry description (UNSIGNED16, ETG.1000.6
    /// §5.6.3.6 "Get Entry Description"); an entry without one has unit 0.
    Unit = Limits::UNIT,
}

impl EntryInfo<&'static str> {
    /// SI0 of an ARRAY or RECORD: UNSIGNED8, read-only.
    pub const fn subindex_count(name: &'static str) -> Self {
        Self {
            sub: 0,
            name,
            data_type: DataType::Unsigned8,
            bit_len: 8,
            access: Access::RO,
            limits: Limits(0),
        }
    }
}

/// The description of one object (ETG.1000.6 §5.6.3.5 "object description"); `S` as for
/// [`EntryInfo`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjectInfo<S: 'static = Name> {
    /// The index.
    pub index: u16,
    /// VAR, ARRAY or RECORD.
    pub code: ObjectCode,
    /// The name ([`ObjectDictionary::name`](super::ObjectDictionary::name) gives its text).
    pub name: S,
    /// The highest subindex (0 for a VAR; the number of elements of an ARRAY).
    pub max_sub: u8,
    /// A VAR: its entry. An ARRAY: SI0 and the element. A RECORD: SI0 and every entry, sorted by
    /// subindex.
    pub entries: &'static [EntryInfo<S>],
}

impl<S> ObjectInfo<S> {
    /// Whether SI1..=`max_sub` share one description, the second of `entries`: every ARRAY,
    /// and a RECORD that describes only SI1 below a higher `max_sub` — how a PDO mapping object
    /// (0x1600..0x17FF, 0x1A00..0x1BFF: a RECORD of UNSIGNED32 mapping entries, ETG.1000.6
    /// §5.6.7.4, data type 0x0021) keeps its like entries, as compact as an ARRAY.
    pub const fn is_uniform(&self) -> bool {
        match (self.code, self.entries) {
            (ObjectCode::Var, _) => false,
            (ObjectCode::Array, _) => true,
            (ObjectCode::Record, [_, element]) => element.sub == 1 && self.max_sub > 1,
            (ObjectCode::Record, _) => false,
        }
    }

    /// Whether `sub` shares its description with other subindices: an entry of a uniform
    /// object, or one of a RECORD's entries from its last declared on when `max_sub` is beyond
    /// it (0x10F3's messages).
    pub fn is_repeated(&self, sub: u8) -> bool {
        let last = self.entries.last().map_or(0, |e| e.sub);
        sub > 0 && (self.is_uniform() || (last < self.max_sub && sub >= last))
    }

    /// The description of subindex `sub`, `None` if it does not exist: an entry of a uniform
    /// object shares the second description; otherwise the entry declared for `sub`, and a
    /// RECORD's entries beyond the last declared repeat it (0x10F3's messages). A walk, not a
    /// search: the tables are short, and the SDO server finds most entries at their position
    /// first (`ObjectInfo::dense_entry`).
    pub fn entry(&self, sub: u8) -> Option<&EntryInfo<S>> {
        if sub > self.max_sub {
            return None;
        }
        // A uniform object's second description is its last, SI1: from SI1 on it is the
        // entry, as the last declared entry of a RECORD is for the subindices beyond it.
        let last = self.entries.last()?;
        if sub >= last.sub {
            return Some(last);
        }
        self.entries.iter().find(|e| e.sub == sub)
    }

    /// The description of subindex `sub` where a dense object keeps it, at position `sub`: SI0,
    /// every entry of most records, an ARRAY's SI1. `None` when it is elsewhere or missing
    /// ([`ObjectInfo::entry`] looks further). Inline, for the SDO server's way without a call.
    #[inline]
    pub(crate) fn dense_entry(&self, sub: u8) -> Option<&EntryInfo<S>> {
        self.entries
            .get(usize::from(sub))
            .filter(|entry| entry.sub == sub && sub <= self.max_sub)
    }

    /// The data type SDO Information reports for the object (ETG.1000.6 Table 64, as SSC's
    /// object descriptions): the VAR's type, the ARRAY element's type, for a RECORD the
    /// standard type its index has — 0x0021 PDO mapping (0x1600..0x17FF, 0x1A00..0x1BFF),
    /// 0x0023 identity (0x1018), 0x0029 sync manager parameter (0x1C30..0x1C4F, ETG.1020) —
    /// and 0x0000 for an application's record (no type of its own).
    pub fn data_type(&self) -> u16 {
        match self.code {
            // A VAR's one entry, an ARRAY's element after SI0: the last.
            ObjectCode::Var | ObjectCode::Array => {
                self.entries.last().map_or(0, |e| e.data_type.code())
            }
            ObjectCode::Record => record_type(self.index),
        }
    }

    /// The subindices that exist, in order: 0..=max_sub for VAR, ARRAY and a uniform RECORD,
    /// the declared ones for another RECORD, then those up to `max_sub` its last entry
    /// describes.
    pub fn subindices(&self) -> impl Iterator<Item = u8> + '_ {
        let dense = self.is_uniform() || self.code != ObjectCode::Record;
        let declared = self.entries.iter().map(|e| e.sub).filter(move |_| !dense);
        // The entries beyond the last declared, which repeat it.
        let last = self.entries.last().map_or(0, |e| e.sub);
        let tail = (last..=self.max_sub)
            .skip(1)
            .filter(move |_| !dense && last > 0);
        (0..=self.max_sub)
            .filter(move |_| dense)
            .chain(declared)
            .chain(tail)
    }
}

/// The data type of the standard RECORD at `index` (ETG.1000.6 Table 64: PDO_MAPPING 0x0021,
/// IDENTITY 0x0023; ETG.1020: SYNC_PAR 0x0029), 0 for any other index.
const fn record_type(index: u16) -> u16 {
    match index {
        0x1600..=0x17FF | 0x1A00..=0x1BFF => 0x0021,
        0x1018 => 0x0023,
        0x1C30..=0x1C4F => 0x0029,
        _ => 0,
    }
}

/// `const` check of a dictionary table: indices strictly ascending and every RECORD's entries
/// strictly ascending by subindex. Used by [`dictionary!`](crate::dictionary!) in a `const`
/// assertion, so a bad table does not compile.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn is_well_formed<D>(objects: &[super::Object<D>]) -> bool {
    let mut i = 0;
    while i < objects.len() {
        if i > 0 && objects[i - 1].info.index >= objects[i].info.index {
            return false;
        }
        let entries = objects[i].info.entries;
        let mut j = 1;
        while j < entries.len() {
            if entries[j - 1].sub >= entries[j].sub {
                return false;
            }
            j += 1;
        }
        i += 1;
    }
    true
}

/// `const` check that every PDO-mappable entry has a mappable type.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn mappable_types_only<D>(objects: &[super::Object<D>]) -> bool {
    let mut i = 0;
    while i < objects.len() {
        let entries = objects[i].info.entries;
        let mut j = 0;
        while j < entries.len() {
            let e = &entries[j];
            if (e.access.rxpdo() || e.access.txpdo()) && !e.data_type.is_pdo_mappable() {
                return false;
            }
            j += 1;
        }
        i += 1;
    }
    true
}

/// Whether an entry of `objects` is a DOMAIN: a dictionary without one has no use for the SDO
/// server's DOMAIN paths (the hooks' streaming), known at compile time
/// (`coe::sdo`'s `is_domain`).
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub(crate) const fn has_domain<D>(objects: &[super::Object<D>]) -> bool {
    let mut i = 0;
    while i < objects.len() {
        let entries = objects[i].info.entries;
        let mut j = 0;
        while j < entries.len() {
            if matches!(entries[j].data_type, DataType::Domain) {
                return true;
            }
            j += 1;
        }
        i += 1;
    }
    false
}
