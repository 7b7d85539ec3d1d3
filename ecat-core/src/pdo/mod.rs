//! Process data objects (ETG.1000.6 §5.6.7, CiA 301 §7.5.2.35–37): which dictionary entries travel
//! in the process image, where, and how they get there.
//!
//! - [`PdoMapping`] (0x1600..0x17FF RxPDOs, 0x1A00..0x1BFF TxPDOs): SI0 = number of mapped
//!   entries, SI1..n = `index << 16 | subindex << 8 | bit length` ([`MappingEntry`]); index 0 is a
//!   gap of that many bits.
//! - [`PdoAssignment`] (0x1C12 for SM2 outputs, 0x1C13 for SM3 inputs): SI0 = number of assigned
//!   PDOs, SI1..n = their mapping indices.
//!
//! Writing follows the PDO configuration rules (conformance.md "CoE SDO"): PREOP only (the access
//! rights say so), SI0 = 0 first, then the entries, then SI0 = n; an entry written while SI0 ≠ 0 is
//! refused with 0x06010003, SI0 above the capacity with 0x06090031, an assignment outside the
//! mapping range or to a missing PDO with 0x06090030, a mapping entry that names no mappable
//! entry of the right direction or with the wrong bit length with 0x06040041, an SI0 that
//! makes the image of its direction longer than the device can take with 0x06040042
//! (`check_length`).

pub mod image;
pub mod layout;
mod width;

use crate::abort::AbortCode;
use crate::device::{DeviceConfig, MailboxConfig};
use crate::dictionary::{Access, At, Object, ObjectCode, ObjectDictionary, Read, write_value};
use width::{Items, Slots, Width};

/// One mapping entry: `index << 16 | subindex << 8 | bit length`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct MappingEntry(pub u32);

impl MappingEntry {
    /// The entry for `index:sub` of `bit_len` bits.
    pub const fn new(index: u16, sub: u8, bit_len: u8) -> Self {
        Self(((index as u32) << 16) | ((sub as u32) << 8) | bit_len as u32)
    }

    /// The mapped object's index (0 for a gap).
    pub const fn index(self) -> u16 {
        (self.0 >> 16) as u16
    }

    /// The mapped subindex.
    pub const fn sub(self) -> u8 {
        (self.0 >> 8) as u8
    }

    /// The length in bits.
    pub const fn bit_len(self) -> u8 {
        self.0 as u8
    }
}

/// An object whose SI0 counts its valid entries: the value of PDO mapping and assignment
/// objects. Reported as an ARRAY (ETG.1000.6 Table 62): every entry has the type `T`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counted<T, const N: usize> {
    /// SI0: how many entries are valid.
    pub count: u8,
    /// SI1..=N.
    pub items: [T; N],
}

/// A PDO mapping object's value: up to `N` [`MappingEntry`] values.
pub type PdoMapping<const N: usize> = Counted<u32, N>;
/// A PDO assignment object's value: up to `N` mapping indices.
pub type PdoAssignment<const N: usize> = Counted<u16, N>;

impl<T: Copy + Default, const N: usize> Counted<T, N> {
    /// The valid entries SI1..=SI0.
    pub fn valid(&self) -> impl Iterator<Item = T> + '_ {
        self.items.iter().take(usize::from(self.count)).copied()
    }
}

impl<const N: usize> Counted<u32, N> {
    /// The mapping of `entries` (at most `N`; more are cut). `const`, for defaults.
    #[allow(clippy::indexing_slicing)] // i < n <= both lengths
    pub const fn mapping(entries: &[MappingEntry]) -> Self {
        let mut items = [0u32; N];
        let n = if entries.len() < N { entries.len() } else { N };
        let mut i = 0;
        while i < n {
            items[i] = entries[i].0;
            i += 1;
        }
        Self {
            count: n as u8,
            items,
        }
    }

    /// The mapped entries.
    pub fn mapped(&self) -> impl Iterator<Item = MappingEntry> + '_ {
        self.valid().map(MappingEntry)
    }
}

impl<const N: usize> Counted<u16, N> {
    /// The assignment of `pdos` (at most `N`). `const`, for defaults.
    #[allow(clippy::indexing_slicing)] // i < n <= both lengths
    pub const fn assignment(pdos: &[u16]) -> Self {
        let mut items = [0u16; N];
        let n = if pdos.len() < N { pdos.len() } else { N };
        let mut i = 0;
        while i < n {
            items[i] = pdos[i];
            i += 1;
        }
        Self {
            count: n as u8,
            items,
        }
    }
}

impl<T: Copy + Default, const N: usize> Default for Counted<T, N> {
    fn default() -> Self {
        Self {
            count: 0,
            items: [T::default(); N],
        }
    }
}

/// Whether `index` configures the process data: a PDO mapping or assignment object, or a sync
/// manager parameter object (0x1C32/0x1C33). A write to one makes the SubDevice recompute its
/// process-data layout and sync type.
pub const fn configures_process_data(index: u16) -> bool {
    // 0x1600..=0x17FF and 0x1A00..=0x1BFF: 0x400 apart, 0x200 long; 0x1C12, 0x1C13, 0x1C32 and
    // 0x1C33: 0x1C12 with bits 0 and 5 free.
    index.wrapping_sub(0x1600) & !0x0400 < 0x0200 || index & !0x0021 == 0x1C12
}

/// Which way a PDO goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// RxPDO: MainDevice → device (outputs, SM2, 0x1600..0x17FF, assigned in 0x1C12).
    Rx,
    /// TxPDO: device → MainDevice (inputs, SM3, 0x1A00..0x1BFF, assigned in 0x1C13).
    Tx,
}

impl Direction {
    /// The assignment object of the direction.
    pub const fn assignment(self) -> u16 {
        match self {
            Self::Rx => 0x1C12,
            Self::Tx => 0x1C13,
        }
    }

    /// Whether `index` is a PDO mapping index of the direction.
    pub const fn is_mapping(self, index: u16) -> bool {
        // 0x1600..=0x17FF and 0x1A00..=0x1BFF: 512 indices each, from a multiple of 512.
        index & !0x01FF
            == match self {
                Self::Rx => 0x1600,
                Self::Tx => 0x1A00,
            }
    }

    /// The direction of mapping object `index`.
    pub const fn of_mapping(index: u16) -> Option<Self> {
        match index & !0x01FF {
            0x1600 => Some(Self::Rx),
            0x1A00 => Some(Self::Tx),
            _ => None,
        }
    }

    /// The direction of assignment object `index`.
    pub const fn of_assignment(index: u16) -> Option<Self> {
        match index {
            0x1C12 => Some(Self::Rx),
            0x1C13 => Some(Self::Tx),
            _ => None,
        }
    }

    /// The direction of PDO configuration object `index`: a mapping or an assignment.
    #[inline]
    pub const fn of_configuration(index: u16) -> Option<Self> {
        match Self::of_mapping(index) {
            Some(direction) => Some(direction),
            None => Self::of_assignment(index),
        }
    }

    /// Whether an entry with `access` may be mapped in this direction.
    pub const fn allows(self, access: Access) -> bool {
        match self {
            Self::Rx => access.rxpdo(),
            Self::Tx => access.txpdo(),
        }
    }
}

/// The object code of the `pdo` kind at `index`: RECORD for a PDO mapping object (its data
/// type is 0x0021, [`ObjectInfo::data_type`](crate::dictionary::ObjectInfo::data_type)), ARRAY of UNSIGNED16 for an assignment object
/// (ETG.1000.6 §5.6.7.4, as SSC's object descriptions and ESI files give them).
#[doc(hidden)]
pub const fn object_code(index: u16) -> ObjectCode {
    match Direction::of_mapping(index) {
        Some(_) => ObjectCode::Record,
        None => ObjectCode::Array,
    }
}

/// `const` check that the PDO configuration objects (mappings 0x1600..0x17FF and
/// 0x1A00..0x1BFF, assignments 0x1C12/0x1C13) are written in PREOP only: none of their entries
/// is writable in SAFEOP or OP, where the process data runs on them (ETG.1000.6 §5.6.7,
/// conformance.md "CoE SDO").
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn configuration_preop_only<D>(objects: &[Object<D>]) -> bool {
    use crate::AlState;
    let mut i = 0;
    while i < objects.len() {
        let index = objects[i].info.index;
        let configures = Direction::of_configuration(index).is_some();
        let entries = objects[i].info.entries;
        let mut j = 0;
        while configures && j < entries.len() {
            let access = entries[j].access;
            if access.writable_in(AlState::SafeOp) || access.writable_in(AlState::Op) {
                return false;
            }
            j += 1;
        }
        i += 1;
    }
    true
}

/// Whether one of `objects`' PDO mapping or assignment objects is ever
/// [written](crate::dictionary::Access::is_written): without
/// one the configuration is fixed, known at compile time, and the SDO server carries none of
/// the configuration checks.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub(crate) const fn configurable<D>(objects: &[Object<D>]) -> bool {
    let mut i = 0;
    while i < objects.len() {
        let info = &objects[i].info;
        let mut j = 0;
        while Direction::of_configuration(info.index).is_some() && j < info.entries.len() {
            if info.entries[j].access.is_written() {
                return true;
            }
            j += 1;
        }
        i += 1;
    }
    false
}

/// Checks a mapping entry written into mapping object `mapping` (ETG.1000.6 PDO rules).
#[doc(hidden)]
pub(crate) fn check_mapping_entry<D: ObjectDictionary>(
    mapping: u16,
    value: u32,
) -> Result<(), AbortCode> {
    let entry = MappingEntry(value);
    if entry.index() == 0 {
        return Ok(());
    }
    match Direction::of_mapping(mapping).and_then(|d| layout::mappable::<D>(entry, d)) {
        Some(_) => Ok(()),
        None => Err(AbortCode::NOT_MAPPABLE),
    }
}

/// Checks an assignment entry written into assignment object `assignment`.
#[doc(hidden)]
pub(crate) fn check_assignment_entry<D: ObjectDictionary>(
    assignment: u16,
    value: u16,
) -> Result<(), AbortCode> {
    let direction = Direction::of_assignment(assignment).ok_or(AbortCode::VALUE_RANGE)?;
    if direction.is_mapping(value) && D::object(value).is_some() {
        Ok(())
    } else {
        Err(AbortCode::VALUE_RANGE)
    }
}

/// Checks that SI0 := `data` of assignment object `index` counts only PDOs among `items`
/// (SI1..): entries written while SI0 was 0 were checked one by one, but an entry never written
/// (0x0000) is no PDO: 0x06090030 (conformance.md "CoE SDO"). A mapping object's entries need no
/// such check: each was checked when written, and one never written (0) is a 0-bit gap.
fn check_counted_entries<D: ObjectDictionary>(
    index: u16,
    items: Items<'_>,
    data: &[u8],
) -> Result<(), AbortCode> {
    if Direction::of_assignment(index).is_none() {
        return Ok(());
    }
    let n = data.first().copied().unwrap_or(0);
    for i in 0..usize::from(n) {
        let Some((value, _)) = items.get(i) else {
            break;
        };
        let pdo = u16::try_from(value).map_err(|_| AbortCode::VALUE_RANGE)?;
        check_assignment_entry::<D>(index, pdo)?;
    }
    Ok(())
}

/// Checks an entry written into PDO configuration object `index` against the dictionary.
#[doc(hidden)]
pub(crate) fn check_entry<D: ObjectDictionary>(index: u16, data: &[u8]) -> Result<(), AbortCode> {
    match (data, Direction::of_assignment(index)) {
        ([a, b, c, d], None) if Direction::of_mapping(index).is_some() => {
            check_mapping_entry::<D>(index, u32::from_le_bytes([*a, *b, *c, *d]))
        }
        ([a, b], Some(_)) => check_assignment_entry::<D>(index, u16::from_le_bytes([*a, *b])),
        _ => Ok(()),
    }
}

impl<T: Width, const N: usize> Counted<T, N> {
    /// Reads SI `sub` of a PDO mapping or assignment object: a call in the code `dictionary!`
    /// generates.
    #[doc(hidden)]
    #[inline]
    pub fn read(&self, at: At, out: &mut [u8]) -> Result<Read, AbortCode> {
        // SI0 one byte, an entry its width: each object's read picks its entry and leaves the
        // copy to the one unsigned reader.
        let (value, size) = match at.sub().checked_sub(1) {
            None => (u32::from(self.count), 1),
            Some(n) => T::items(&self.items)
                .get(usize::from(n))
                .ok_or(AbortCode::NO_SUBINDEX)?,
        };
        Ok(crate::dictionary::read_unsigned(
            value,
            size,
            at.offset(),
            out,
        ))
    }

    /// Writes `data` into SI `sub` of PDO mapping or assignment object `index` after the PDO
    /// configuration rules: a call in the code `dictionary!` generates. `index` last: the
    /// arguments of [`Object::write`] keep their registers (6 B less per object).
    #[doc(hidden)]
    #[inline]
    pub fn write<D: ObjectDictionary>(
        &mut self,
        sub: u8,
        data: &[u8],
        index: u16,
    ) -> Result<(), AbortCode> {
        write_counted::<D>(index, &mut self.count, T::slots(&mut self.items), sub, data)
    }
}

/// Writes `data` into SI `sub` of PDO mapping or assignment object `index` after the PDO
/// configuration rules ([`check_counted_write`], [`check_counted_entries`], [`check_entry`]):
/// one copy per dictionary for both widths.
fn write_counted<D: ObjectDictionary>(
    index: u16,
    count: &mut u8,
    mut items: Slots<'_>,
    sub: u8,
    data: &[u8],
) -> Result<(), AbortCode> {
    check_counted_write(*count, items.items().len(), sub, data)?;
    match sub.checked_sub(1) {
        None => {
            check_counted_entries::<D>(index, items.items(), data)?;
            write_value(count, data, None, None)
        }
        Some(n) => {
            check_entry::<D>(index, data)?;
            items.set(usize::from(n), data)
        }
    }
}

/// The PDO configuration write rules shared by mapping and assignment objects: SI0 up to the
/// capacity `n`; entries only while SI0 is 0 and within the capacity.
#[doc(hidden)]
pub(crate) fn check_counted_write(
    count: u8,
    capacity: usize,
    sub: u8,
    data: &[u8],
) -> Result<(), AbortCode> {
    if sub == 0 {
        let [value] = data else {
            return Err(if data.len() > 1 {
                AbortCode::LENGTH_TOO_HIGH
            } else {
                AbortCode::LENGTH_TOO_LOW
            });
        };
        return if usize::from(*value) > capacity {
            Err(AbortCode::VALUE_TOO_HIGH)
        } else {
            Ok(())
        };
    }
    if usize::from(sub) > capacity {
        return Err(AbortCode::NO_SUBINDEX);
    }
    if count != 0 {
        return Err(AbortCode::SI0_NOT_ZERO);
    }
    Ok(())
}

/// The bytes of process RAM the process images can occupy (`check_length`): from the first
/// 8-aligned byte after the mailboxes (where the SII places SM2, `sii::sync_managers`) to
/// [`DeviceConfig::process_ram_end`].
pub fn process_ram(config: &DeviceConfig) -> u32 {
    let end = |m: &MailboxConfig| m.receive.end().max(m.send.end());
    let bootstrap = config.bootstrap_mailbox.as_ref().map_or(0, end);
    let last = end(&config.mailbox).max(bootstrap);
    config.process_ram_end.saturating_sub(last.div_ceil(8) * 8)
}

/// The 0x06040042 check of a PDO configuration write (ETG.1000.6 Table 41 "the number and
/// length of the objects to be mapped would exceed the PDO length"; conformance.md "CoE SDO"):
/// SI0 := `count` of mapping or assignment object `index`, whose entry `sub` is `entry(sub)`
/// (the dictionary's, or for a complete access the request's), would make the image of its
/// direction longer than the device can take: over 65 535 bits (the image's bit offsets are
/// 16-bit, [`layout::Layout`]) or, in three buffers, more than `room` bytes of process RAM
/// ([`process_ram`]; `u32::MAX`: no such limit). The other direction is not counted: a
/// MainDevice that grows one image before shrinking the other is not refused for the order.
/// A mapping that is not assigned makes no image; entries that are no valid PDO or mapping
/// are left to the other checks (0x06040041, 0x06090030; at PREOP→SAFEOP 0x0024/0x0025).
///
/// SSC 5.12 and SOES never send 0x06040042 (SSC lists it in `cAbortCode` only); SSC refuses
/// an image its SyncManager cannot take at PREOP→SAFEOP, as this stack still does too.
#[doc(hidden)]
pub(crate) fn check_length<D: ObjectDictionary>(
    od: &D,
    room: u32,
    index: u16,
    count: u8,
    entry: &dyn Fn(u8) -> Option<u32>,
) -> Result<(), AbortCode> {
    let Some(direction) = Direction::of_configuration(index) else {
        return Ok(());
    };
    let pending = layout::Pending {
        index,
        count,
        entry,
    };
    let mut bits = 0u32;
    layout::walk(od, direction, Some(&pending), &mut |e| {
        bits += e.map_or(0, |e| u32::from(e.bit_len()));
    });
    let bytes = bits.div_ceil(8);
    if bits > u32::from(u16::MAX) || bytes.saturating_mul(3) > room {
        return Err(AbortCode::PDO_TOO_LONG);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{
        Direction, MappingEntry, PdoAssignment, PdoMapping, configurable, configures_process_data,
    };
    use crate::abort::AbortCode;
    use crate::dictionary::ObjectDictionary;

    const RX: [MappingEntry; 1] = [MappingEntry::new(0x7000, 0, 8)];

    /// A dictionary with 0x1600 of `$access` (0x1C12 read-only).
    macro_rules! with_mapping {
        ($od:ident, $($access:ident)|+) => {
            struct $od {
                rx: PdoMapping<1>,
                rx_assign: PdoAssignment<1>,
                out: u8,
            }

            crate::dictionary! {
                minimal $od {
                    0x1600 => pdo(rx, $($access)|+, "RxPDO", "Mapped object", default = PdoMapping::mapping(&RX));
                    0x1C12 => pdo(rx_assign, RO, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
                    0x7000 => var(out, RW | RXPDO, "Output");
                }
            }
        };
    }

    // A fixed configuration, and one whose mapping the MainDevice may change in PREOP.
    with_mapping!(Fixed, RO);
    with_mapping!(Mapped, RW_PREOP);

    /// A dictionary whose PDO configuration no one writes has no configuration checks to run:
    /// its configuration objects' write is `read_only`, and the SDO server knows it at compile
    /// time. One writable object keeps them all.
    #[test]
    fn only_a_written_configuration_object_carries_the_configuration_rules() {
        assert!(!configurable(Fixed::OBJECTS));
        assert!(configurable(Mapped::OBJECTS));
        let (mut fixed, mut mapped) = (Fixed::default(), Mapped::default());
        let write_fixed = Fixed::object(0x1600).map(|o| o.write);
        let write_mapped = Mapped::object(0x1600).map(|o| o.write);
        assert_eq!(
            write_fixed.map(|w| w(&mut fixed, 0, &[0])),
            Some(Err(AbortCode::READ_ONLY))
        );
        assert_eq!(write_mapped.map(|w| w(&mut mapped, 0, &[0])), Some(Ok(())));
        assert_eq!(mapped.rx.count, 0);
        // The PDO rules stay with the writable object: SI0 above the capacity.
        assert_eq!(
            write_mapped.map(|w| w(&mut mapped, 0, &[2])),
            Some(Err(AbortCode::VALUE_TOO_HIGH))
        );
        assert_eq!((fixed.rx.count, fixed.out, mapped.out), (1, 0, 0));
    }

    /// The PDO mapping and assignment objects and 0x1C32/0x1C33 configure the process data,
    /// no other index does (every index against the ranges as written out).
    #[test]
    fn configuring_indices_are_the_pdo_configuration_and_sync_parameters() {
        for index in 0..=u16::MAX {
            let expected =
                Direction::of_configuration(index).is_some() || matches!(index, 0x1C32 | 0x1C33);
            assert_eq!(configures_process_data(index), expected, "{index:#06x}");
        }
    }
}
