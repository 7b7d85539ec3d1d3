//! Complete access: a whole ARRAY or RECORD in one transfer (ETG.1000.6 §5.6.2.1.2).
//!
//! Layout: from subindex 0, SI0 travels as one byte plus one padding byte; from subindex 1, the
//! entries start at once. Entries follow in subindex order, BOOL and BITn entries packed bit by bit,
//! byte-sized entries aligned to the next byte. An upload of an ARRAY or a PDO mapping RECORD
//! ends with the entry SI0 counts ([`upload_last`]); one of another RECORD carries its declared
//! entries, a gap nothing. Variable-length entries (strings, domains) make
//! an object unfit for complete access (0x06010004).

use crate::abort::AbortCode;
use crate::dictionary::{At, EntryInfo, Object, ObjectCode, ObjectInfo, Read};
use crate::pdo::image::copy_bits;

/// One entry's place in the complete-access image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Slot {
    /// The entry's subindex.
    pub(super) sub: u8,
    bit_offset: usize,
    bit_len: usize,
}

impl Slot {
    /// The entry's value bytes in the image `data`, as a single access carries them: its bits
    /// from their place, in the low bits of the first bytes; `None` when `data` ends before
    /// them (or an entry above 64 bits). For an entry SI1..: SI0's slot gives its two bytes,
    /// the count and the padding (the download stores SI0 apart).
    pub(super) fn value(self, data: &[u8]) -> Option<([u8; 8], usize)> {
        let end = (self.bit_offset + self.bit_len).div_ceil(8);
        if self.bit_len > 64 || end > data.len() {
            return None;
        }
        let mut value = [0u8; 8];
        copy_bits(data, self.bit_offset, &mut value, 0, 0, self.bit_len);
        Some((value, self.bit_len.div_ceil(8)))
    }
}

/// Checks that `object` may be accessed completely from `sub`.
pub fn check(object: &ObjectInfo, sub: u8) -> Result<(), AbortCode> {
    if sub > 1 || object.code == ObjectCode::Var {
        return Err(AbortCode::UNSUPPORTED_ACCESS);
    }
    if object
        .entries
        .iter()
        .any(|e| e.data_type.is_variable_length())
    {
        return Err(AbortCode::CA_VARIABLE_LENGTH);
    }
    Ok(())
}

/// The entries a complete access from `sub` covers, with their descriptions.
pub fn entries(object: &ObjectInfo, sub: u8) -> impl Iterator<Item = (u8, &EntryInfo)> {
    declared(object, sub, object.max_sub)
}

/// The entries `object` declares from subindex `first` through `last`, with their
/// descriptions: a gap of a sparse RECORD is skipped.
pub(super) fn declared(object: &ObjectInfo, first: u8, last: u8) -> Declared<'_> {
    Declared {
        object,
        next: u16::from(first),
        last,
    }
}

/// [`declared`]: one walk, out of line, that every walk over an object's entries shares (the
/// complete-access checks, slots and stores, the RxPDO check of a download).
pub(super) struct Declared<'a> {
    object: &'a ObjectInfo,
    /// The next subindex to look at (`u16`: the walk ends after 255).
    next: u16,
    last: u8,
}

impl<'a> Iterator for Declared<'a> {
    type Item = (u8, &'a EntryInfo);

    #[inline(never)]
    fn next(&mut self) -> Option<Self::Item> {
        while let Ok(s) = u8::try_from(self.next) {
            if s > self.last {
                break;
            }
            self.next += 1;
            if let Some(entry) = self.object.entry(s) {
                return Some((s, entry));
            }
        }
        None
    }
}

/// The slots of a complete access from `sub` through subindex `last`, in subindex order.
pub(super) fn slots(object: &ObjectInfo, sub: u8, last: u8) -> Slots<'_> {
    Slots {
        entries: declared(object, sub, last),
        bit: 0,
    }
}

/// [`slots`]: the entries still to place, the image's bits before them.
pub(super) struct Slots<'a> {
    entries: Declared<'a>,
    bit: usize,
}

impl Iterator for Slots<'_> {
    type Item = Slot;

    fn next(&mut self) -> Option<Slot> {
        let (sub, entry) = self.entries.next()?;
        let bit_len = if sub == 0 {
            16
        } else {
            usize::from(entry.bit_len)
        };
        if bit_len.is_multiple_of(8) {
            self.bit = self.bit.div_ceil(8) * 8;
        }
        let slot = Slot {
            sub,
            bit_offset: self.bit,
            bit_len,
        };
        self.bit += bit_len;
        Some(slot)
    }
}

/// Where each entry of a complete access from subindex 0 starts, in bits: `(subindex, bit
/// offset)`. The ESI `DataType` of the object gives its `SubItem`s the same `BitOffs`
/// (ETG.2000 `DataType/SubItem/BitOffs`), so the file and the transfer agree.
pub fn bit_offsets(object: &ObjectInfo) -> impl Iterator<Item = (u8, usize)> + '_ {
    slots(object, 0, object.max_sub).map(|s| (s.sub, s.bit_offset))
}

/// The size in bytes of the complete-access image from `sub`.
pub fn size(object: &ObjectInfo, sub: u8) -> usize {
    sizes(object, sub, u8::MAX).0
}

/// The sizes in bytes of the complete-access image from `sub`, whole and ending with subindex
/// `last`: what a MainDevice sends for a configuration object whose SI0 it sets to `last` (SI0
/// and the entries it counts, TwinCAT's and SOEM's `0x1C12` downloads). One walk for both.
pub fn sizes(object: &ObjectInfo, sub: u8, last: u8) -> (usize, usize) {
    let (mut whole, mut through) = (0, 0);
    for slot in slots(object, sub, object.max_sub) {
        whole = slot.bit_offset + slot.bit_len;
        if slot.sub <= last {
            through = whole;
        }
    }
    (whole.div_ceil(8), through.div_ceil(8))
}

/// The highest subindex a complete-access upload carries. Of an ARRAY, the value of SI0 (0 when
/// it does not read as one byte): the object's current size, SI0 and the entries it counts, as
/// SSC 5.12 sizes and reads an ARRAY
/// (`objdef.c` `OBJ_GetObjectLength`: SI0's value times the element, `OBJ_Read`: entries up to
/// SI0's value). So 0x1C12/0x1C13 (ARRAYs) and the PDO mappings (RECORDs of like entries,
/// [`ObjectInfo::is_uniform`], whose SI0 SSC also reads as the count) show their configured
/// entries, not every slot of their capacity. Of another RECORD, every declared entry; an
/// undeclared one (a gap of a sparse record) has no bits, as SSC's gap descriptions have bit
/// length 0.
pub fn upload_last<D>(od: &D, object: &Object<D>) -> u8 {
    if !object.info.is_uniform() {
        return object.info.max_sub;
    }
    object.count(od).min(object.info.max_sub)
}

/// Copies the bytes of a complete-access upload from `sub` ([`upload_last`]) from `offset` on
/// into `out`: how many, and the image's whole size (as [`Object::read`] of one entry).
pub fn read<D>(
    od: &D,
    object: &Object<D>,
    sub: u8,
    offset: usize,
    out: &mut [u8],
) -> Result<Read, AbortCode> {
    let last = upload_last(od, object);
    // One walk: every byte of `out` zeroed first (what the entries leave is padding), the
    // image's size from the last slot.
    out.fill(0);
    let mut end = 0;
    for slot in slots(&object.info, sub, last) {
        // Every entry fits 8 bytes (`check`: no variable-length entry); SI0's second byte is
        // padding, zero.
        let mut value = [0u8; 8];
        (object.read)(od, At::start(slot.sub), &mut value)?;
        copy_bits(&value, 0, out, slot.bit_offset, offset, slot.bit_len);
        end = slot.bit_offset + slot.bit_len;
    }
    let total = end.div_ceil(8);
    let len = out.len().min(total.saturating_sub(offset));
    Ok(Read::new(len, total))
}

/// The value bytes of entry `entry_sub` (SI1..) in a complete-access image, as a single access
/// carries them: its bits from their place, in the low bits of the first bytes.
pub fn entry_value(
    data: &[u8],
    object: &ObjectInfo,
    sub: u8,
    entry_sub: u8,
) -> Option<([u8; 8], usize)> {
    // The last slot through `entry_sub` is its own, if the object declares it.
    slots(object, sub, entry_sub)
        .last()
        .filter(|s| s.sub == entry_sub)?
        .value(data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::{Access, DataType, Limits, Name};

    const fn entry(sub: u8, data_type: DataType, bit_len: u16) -> EntryInfo {
        EntryInfo {
            sub,
            name: Name::EMPTY,
            data_type,
            bit_len,
            access: Access::RW,
            limits: Limits(0),
        }
    }

    const fn record(entries: &'static [EntryInfo]) -> ObjectInfo {
        ObjectInfo {
            index: 0x2000,
            code: ObjectCode::Record,
            name: Name::EMPTY,
            max_sub: 2,
            entries,
        }
    }

    /// A RECORD with a string or a DOMAIN entry is refused with 0x06010004, from SI0 and SI1;
    /// one of numbers is not; from SI2 on, or on a VAR, the access itself is 0x06010000.
    #[test]
    fn variable_length_entries_refuse_complete_access() {
        const fn with(second: DataType) -> [EntryInfo; 3] {
            let count = EntryInfo {
                access: Access::RO,
                ..entry(0, DataType::Unsigned8, 8)
            };
            [
                count,
                entry(1, DataType::Unsigned16, 16),
                entry(2, second, 64),
            ]
        }
        const STRING: [EntryInfo; 3] = with(DataType::VisibleString);
        const OCTETS: [EntryInfo; 3] = with(DataType::OctetString);
        const DOMAIN: [EntryInfo; 3] = with(DataType::Domain);
        const NUMBERS: [EntryInfo; 3] = with(DataType::Integer64);
        for entries in [&STRING, &OCTETS, &DOMAIN] {
            for sub in [0, 1] {
                let refused = check(&record(entries), sub);
                assert_eq!(refused, Err(AbortCode::CA_VARIABLE_LENGTH));
            }
        }
        let numbers = record(&NUMBERS);
        assert_eq!(check(&numbers, 0), Ok(()));
        assert_eq!(check(&numbers, 2), Err(AbortCode::UNSUPPORTED_ACCESS));
        let var = ObjectInfo {
            code: ObjectCode::Var,
            ..numbers
        };
        assert_eq!(check(&var, 0), Err(AbortCode::UNSUPPORTED_ACCESS));
    }
}
