//! The process image a configuration describes (ETG.1000.6 §5.6.7): for each direction, where the
//! assigned PDOs put each mapped entry and the image size the SyncManager must have (AL status
//! codes 0x0024/0x0025 for an unusable mapping).
//!
//! A [`Layout`] is a copy plan, computed once when the configuration is accepted and used every
//! cycle by [`image`](super::image): it holds the bit offset of every PDO-mappable entry of the
//! dictionary, indexed by the entry's [`number`] (`UNMAPPED` where the
//! configuration does not map it). The copy itself is code `dictionary!` generates per dictionary
//! (`ObjectDictionary::unpack_mapped`/`pack_mapped`): a straight line over the mappable fields, so
//! a cycle costs no lookup and no dispatch per entry.

use super::{Direction, MappingEntry};
use crate::AlStatusCode;
use crate::dictionary::{
    EntryInfo, Len, Length, Object, ObjectDictionary, ObjectInfo, PerMappable,
};

/// The offset of an entry the configuration does not map.
pub(crate) const UNMAPPED: u16 = u16::MAX;

/// How a layout stores a bit offset: rotated right by 3, the byte index in bits 0..13 and the bit
/// within the byte in bits 13..16, so an entry at a byte boundary is stored as its byte index
/// (below `BYTE_ALIGNED`) and the copy needs no shift. `UNMAPPED` stores as itself.
pub const fn stored(bit_offset: u16) -> u16 {
    bit_offset.rotate_right(3)
}

/// The bit offset a layout stored ([`stored`]).
pub const fn bit_offset(stored: u16) -> u16 {
    stored.rotate_left(3)
}

/// Stored offsets below this are byte indices of entries at a byte boundary.
pub(crate) const BYTE_ALIGNED: u16 = 1 << 13;

/// How many entries a TxPDO configuration may map a second time (the image carries the value
/// at each place).
pub const MAX_REPEATS: usize = 8;

/// A TxPDO entry mapped again: after packing, `len` bits are copied from `from` to `to`.
/// Packed, 5 bytes rather than 6: a layout keeps [`MAX_REPEATS`] of them, in the process-data
/// runner's RAM (the fields are read by value, never borrowed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(C, packed)]
pub struct Repeat {
    /// The bit offset of the entry's first place.
    pub from: u16,
    /// The bit offset of the repeated place.
    pub to: u16,
    /// The entry's length in bits.
    pub len: u8,
}

impl Repeat {
    /// An unused slot of a layout's repeats.
    pub(crate) const EMPTY: Self = Self {
        from: 0,
        to: 0,
        len: 0,
    };
}

/// [`ObjectDictionary::Repeatable`] for a dictionary of `objects`: room for as many repeats
/// as a TxPDO configuration of its objects can hold, at most [`MAX_REPEATS`]. A walk sees at
/// most the TxPDO assignment's capacity (0x1C13's highest subindex) times the largest TxPDO
/// mapping's entries, the first of which is no repeat; none without a TxPDO-mappable entry (a
/// layout of such a dictionary then carries no room for repeats). More than the room can never
/// be mapped, so the room changes no answer: it only keeps the process-data runner's layout
/// no larger than the dictionary's configurations need (the digital I/O's: 4 repeats, 20 bytes
/// less).
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn repeat_room<D>(objects: &[Object<D>]) -> usize {
    let (mut assigned, mut largest, mut mappable) = (0, 0, false);
    let mut i = 0;
    while i < objects.len() {
        let info = &objects[i].info;
        if info.index == Direction::Tx.assignment() {
            assigned = info.max_sub as usize;
        } else if Direction::Tx.is_mapping(info.index) && info.max_sub as usize > largest {
            largest = info.max_sub as usize;
        }
        let mut j = 0;
        while j < info.entries.len() {
            mappable |= info.entries[j].access.txpdo();
            j += 1;
        }
        i += 1;
    }
    let room = (assigned * largest).saturating_sub(1);
    if !mappable {
        0
    } else if room < MAX_REPEATS {
        room
    } else {
        MAX_REPEATS
    }
}

/// One direction's image: the offset of every mappable entry and the image size, with room `R`
/// for the entries a TxPDO configuration maps again ([`ObjectDictionary::Repeatable`]; none in
/// an [`RxLayout`]).
pub struct Layout<D: ObjectDictionary, R: Length = <D as ObjectDictionary>::Repeatable> {
    offsets: PerMappable<D, u16>,
    bits: u16,
    gaps: bool,
    repeats: R::Array<Repeat>,
    repeat_count: u8,
}

/// The layout of the outputs (RxPDOs) as the process-data side keeps it: an RxPDO entry mapped
/// twice takes its value from its last place, so it carries no room for repeats
/// ([`Layout::outputs`]).
pub type RxLayout<D> = Layout<D, Len<0>>;

impl<D: ObjectDictionary> RxLayout<D> {
    /// [`Layout::of`] the outputs (`Direction::Rx`), moved into a layout without room for
    /// repeats: one copy of [`Layout::of`]'s code serves both directions.
    pub fn outputs(od: &D) -> Result<Option<Self>, AlStatusCode> {
        let layout = Layout::of(od, Direction::Rx)?;
        Ok(layout.map(|l| Self {
            offsets: l.offsets,
            bits: l.bits,
            gaps: l.gaps,
            repeats: [],
            repeat_count: 0,
        }))
    }
}

impl<D: ObjectDictionary> Layout<D> {
    /// The image `direction` describes in `od`: the assigned PDOs (0x1C12/0x1C13) in order, their
    /// mapped entries in order. `Ok(None)` when the dictionary has no assignment object (a fixed
    /// layout from the device configuration applies).
    ///
    /// Refused with 0x0025 (outputs) or 0x0024 (inputs): an assignment naming a missing PDO or
    /// one of the other direction, a mapping entry naming a missing or unmappable entry or with
    /// the wrong bit length, an image over 65 535 bits, more than [`MAX_REPEATS`] entries of a
    /// TxPDO mapped again. An RxPDO entry mapped twice takes its value from its last place.
    pub fn of(od: &D, direction: Direction) -> Result<Option<Self>, AlStatusCode> {
        let mut layout = Self {
            offsets: <D::Mappable as Length>::array(UNMAPPED),
            bits: 0,
            gaps: false,
            repeats: <D::Repeatable as Length>::array(Repeat::EMPTY),
            repeat_count: 0,
        };
        // A broken entry marks the layout by a repeat count no layout reaches.
        let building = &mut layout;
        let assigned = walk(od, direction, None, &mut move |entry| {
            if entry.and_then(|e| building.push(e, direction)).is_none() {
                building.repeat_count = u8::MAX;
            }
        });
        if !assigned {
            return Ok(None);
        }
        if usize::from(layout.repeat_count) > MAX_REPEATS {
            return Err(match direction {
                Direction::Rx => AlStatusCode::INVALID_OUTPUT_MAPPING,
                Direction::Tx => AlStatusCode::INVALID_INPUT_MAPPING,
            });
        }
        layout.gaps |= !layout.bits.is_multiple_of(8);
        Ok(Some(layout))
    }

    fn push(&mut self, entry: MappingEntry, direction: Direction) -> Option<()> {
        let at = self.bits;
        self.bits = at.checked_add(entry.bit_len().into())?;
        if entry.index() == 0 {
            self.gaps = true;
            return Some(());
        }
        let number = mappable::<D>(entry, direction)?;
        let offset = self.offsets.as_mut().get_mut(number)?;
        let first = *offset;
        if direction == Direction::Tx && first != UNMAPPED {
            // The entry keeps its first place; the image repeats it here.
            return self.repeat(bit_offset(first), at, entry.bit_len());
        }
        *offset = stored(at);
        Some(())
    }

    fn repeat(&mut self, from: u16, to: u16, len: u8) -> Option<()> {
        *self
            .repeats
            .as_mut()
            .get_mut(usize::from(self.repeat_count))? = Repeat { from, to, len };
        self.repeat_count += 1;
        Some(())
    }
}

impl<D: ObjectDictionary, R: Length> Layout<D, R> {
    /// The image size in bits.
    pub fn bits(&self) -> u32 {
        self.bits.into()
    }

    /// The image size in bytes (bits rounded up).
    pub fn bytes(&self) -> u16 {
        self.bits.div_ceil(8)
    }

    /// The offset of every mappable entry, by [entry number](number), as [`stored`].
    pub fn offsets(&self) -> &PerMappable<D, u16> {
        &self.offsets
    }

    /// The bit offset of `index:sub` in the image, `None` if the layout does not map it (for a
    /// TxPDO entry mapped more than once: its first place).
    pub fn offset(&self, index: u16, sub: u8) -> Option<u16> {
        let number = number::<D>(index, sub)?;
        self.offsets
            .as_ref()
            .get(number)
            .copied()
            .filter(|&at| at != UNMAPPED)
            .map(bit_offset)
    }

    /// Whether the image has bits no entry fills (gaps, padding after the last entry): they are
    /// zeroed before packing.
    pub fn has_gaps(&self) -> bool {
        self.gaps
    }

    /// The TxPDO entries mapped again, in image order.
    pub fn repeats(&self) -> &[Repeat] {
        self.repeats
            .as_ref()
            .get(..usize::from(self.repeat_count))
            .unwrap_or_default()
    }
}

/// The number of PDO-mappable entries in `objects` (the length of
/// [`ObjectDictionary::Mappable`]): an ARRAY's (a uniform RECORD's) element entry counts once
/// per element. At most 65 535: a layout keeps a 16-bit offset per mappable entry, and a
/// dictionary with more does not compile.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn mappable_entries<D>(objects: &[Object<D>]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < objects.len() {
        let info = &objects[i].info;
        let mut j = 0;
        while j < info.entries.len() {
            if is_mappable(&info.entries[j]) {
                n += elements(info) as usize;
            }
            j += 1;
        }
        i += 1;
    }
    assert!(
        n <= u16::MAX as usize,
        "at most 65 535 PDO-mappable entries"
    );
    n
}

/// Whether `entry` may be mapped in a PDO, in either direction.
const fn is_mappable(entry: &EntryInfo) -> bool {
    entry.access.rxpdo() || entry.access.txpdo()
}

/// How many subindices each entry of `info` stands for: an ARRAY's (a uniform RECORD's)
/// element entry all of 1..=max_sub, any other one its own.
const fn elements(info: &ObjectInfo) -> u8 {
    if info.is_uniform() { info.max_sub } else { 1 }
}

/// The number of the PDO-mappable entry `index:sub` of `D`: the mappable entries (RxPDO or
/// TxPDO) counted in index order, subindex order within a RECORD, element by element within an
/// ARRAY — their place in [`ObjectDictionary::MAPPABLE`]. `None` when `index:sub` is not
/// mappable or does not exist. A binary search of that table, by index and subindex; `const`,
/// so the code `dictionary!` generates gets every field's number as a constant, and the one
/// search at run time (a mapping entry's check, a layout). No indexing (no panic path).
pub const fn number<D: ObjectDictionary>(index: u16, sub: u8) -> Option<usize> {
    let wanted = MappingEntry::new(index, sub, 0).0 >> 8;
    let keys = D::MAPPABLE;
    // The last key at or below `wanted`, by halving (as `slice::binary_search`).
    let (mut base, mut size) = (0, keys.len());
    while size > 1 {
        let half = size / 2;
        if let Some((_, [key, ..])) = keys.split_at_checked(base + half)
            && *key >> 8 <= wanted
        {
            base += half;
        }
        size -= half;
    }
    match keys.split_at_checked(base) {
        Some((_, [key, ..])) if *key >> 8 == wanted => Some(base),
        _ => None,
    }
}

/// The [number](number) of the entry `entry` maps, when it names a PDO-mappable entry of `D`
/// that `direction` may map, with the entry's bit length: what a mapping entry must be, when it
/// is written (0x06040041, [`check_mapping_entry`](super::check_mapping_entry)) and when the
/// layout is made (0x0024/0x0025). `dictionary!` asserts that every PDO-mappable entry has a
/// mappable type. One search of the [keys](mappable_key) the dictionary's table gives at
/// compile time, no walk of its descriptions. Out of line: one copy for both.
#[inline(never)]
pub(crate) fn mappable<D: ObjectDictionary>(
    entry: MappingEntry,
    direction: Direction,
) -> Option<usize> {
    let number = number::<D>(entry.index(), entry.sub())?;
    let key = *D::MAPPABLE.get(number)?;
    let fits = key & BIT_LEN == u32::from(entry.bit_len()).wrapping_sub(1);
    let flag = match direction {
        Direction::Rx => RX_KEY,
        Direction::Tx => TX_KEY,
    };
    (fits && key & flag != 0).then_some(number)
}

/// A [key](mappable_key)'s bit length less one (mappable entries are 1..=64 bits).
const BIT_LEN: u32 = 0x3F;
/// A [key](mappable_key)'s flag: RxPDO-mappable.
const RX_KEY: u32 = 0x40;
/// A [key](mappable_key)'s flag: TxPDO-mappable.
const TX_KEY: u32 = 0x80;

/// The key of a PDO-mappable entry in [`ObjectDictionary::MAPPABLE`]: `index << 16 | sub << 8`,
/// then bit 7 TxPDO-mappable, bit 6 RxPDO-mappable, bits 0..6 the bit length less one.
const fn mappable_key(index: u16, sub: u8, entry: &EntryInfo) -> u32 {
    assert!(
        entry.bit_len >= 1 && entry.bit_len <= 64,
        "a PDO-mappable entry has 1..=64 bits"
    );
    let mut key = (index as u32) << 16 | (sub as u32) << 8 | (entry.bit_len as u32 - 1);
    if entry.access.rxpdo() {
        key |= RX_KEY;
    }
    if entry.access.txpdo() {
        key |= TX_KEY;
    }
    key
}

/// The key of every PDO-mappable entry of `objects`, by [`number`]:
/// [`ObjectDictionary::MAPPABLE`], `N` = [`mappable_entries`]. A key is `index << 16 | sub << 8`,
/// then bit 7 TxPDO-mappable, bit 6 RxPDO-mappable, bits 0..6 the bit length less one;
/// ascending, as the objects and their entries are.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn mappable_keys<D, const N: usize>(objects: &[Object<D>]) -> [u32; N] {
    let mut keys = [0; N];
    let mut n = 0;
    let mut i = 0;
    while i < objects.len() {
        let info = &objects[i].info;
        let mut j = 0;
        while j < info.entries.len() {
            let entry = &info.entries[j];
            if is_mappable(entry) {
                let mut k = 0;
                while k < elements(info) {
                    keys[n] = mappable_key(info.index, entry.sub + k, entry);
                    n += 1;
                    k += 1;
                }
            }
            j += 1;
        }
        i += 1;
    }
    assert!(n == N);
    keys
}

/// A PDO configuration object's value that a walk ([`walk`]) takes instead of the
/// dictionary's: SI0 of object `index` about to become `count`, its entry n `entry(n)` (the
/// checks of a download before it stores, [`check_length`](super::check_length)).
pub(crate) struct Pending<'a> {
    /// The mapping or assignment object.
    pub index: u16,
    /// Its new SI0.
    pub count: u8,
    /// Its entries, by subindex.
    pub entry: &'a dyn Fn(u8) -> Option<u32>,
}

/// Walks the image `direction` describes: the PDOs the assignment object names, in order, and
/// the entries each maps, in order, with `pending` in place of the dictionary's value of its
/// object. `visit` sees each mapping entry; `None` where the configuration is broken: an
/// assignment entry that cannot be read, a PDO that does not exist or is of the other
/// direction, a mapping entry that cannot be read. `false` when the dictionary has no
/// assignment object for `direction` (nothing to walk). The one walk behind [`Layout::of`],
/// [`is_mapped`] and the length check of a PDO configuration write: out of line, one copy per
/// dictionary.
#[inline(never)]
pub(crate) fn walk<D: ObjectDictionary>(
    od: &D,
    direction: Direction,
    pending: Option<&Pending<'_>>,
    visit: &mut dyn FnMut(Option<MappingEntry>),
) -> bool {
    let Some(assignment) = D::object(direction.assignment()) else {
        return false;
    };
    let pending_of = |object: &Object<D>| pending.filter(|p| p.index == object.info.index);
    let assigned = pending_of(assignment);
    let pdos = assigned.map_or_else(|| assignment.count(od), |p| p.count);
    // 1..=n as 0..n shifted: no inclusive range's exhaustion state.
    for pdo in (0..pdos).map(|i| i + 1) {
        let index = match assigned {
            Some(p) => (p.entry)(pdo).and_then(|v| u16::try_from(v).ok()),
            None => assignment.read_u16(od, pdo),
        };
        let Some(mapping) = index
            .filter(|i| direction.is_mapping(*i))
            .and_then(D::object)
        else {
            visit(None);
            continue;
        };
        let changed = pending_of(mapping);
        let entries = changed.map_or_else(|| mapping.count(od), |p| p.count);
        for sub in (0..entries).map(|i| i + 1) {
            let value = match changed {
                Some(p) => (p.entry)(sub),
                None => mapping.read_u32(od, sub),
            };
            visit(value.map(MappingEntry));
        }
    }
    true
}

/// Whether `index:sub` is mapped in a PDO assigned for `direction`: a walk of the assignment
/// object and the mapping objects it names, without a layout. Where a layout exists (a valid
/// configuration, as in SAFEOP and OP) it answers as [`Layout::offset`] does.
pub(crate) fn is_mapped<D: ObjectDictionary>(
    od: &D,
    direction: Direction,
    index: u16,
    sub: u8,
) -> bool {
    let mut mapped = false;
    // The entry's index and subindex in one compare: the bit length aside.
    let wanted = MappingEntry::new(index, sub, 0).0 >> 8;
    walk(od, direction, None, &mut |entry| {
        mapped |= entry.is_some_and(|e| e.0 >> 8 == wanted);
    });
    mapped
}
