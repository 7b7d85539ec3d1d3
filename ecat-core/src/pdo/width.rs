//! The entry types a [`Counted`](super::Counted) object reads (each object picks its entry, the
//! one unsigned reader copies it) and writes through the one shared writer: UNSIGNED32 mapping
//! entries, UNSIGNED16 assigned PDOs (a private module: the trait is sealed, its types are
//! nobody else's).

use crate::abort::AbortCode;
use crate::dictionary::write_value;

/// An entry type of a PDO configuration object, as the shared reader and writer see it.
pub trait Width: Sized {
    /// The entries, by width.
    fn items(items: &[Self]) -> Items<'_>;
    /// The entries to write into, by width.
    fn slots(items: &mut [Self]) -> Slots<'_>;
}

impl Width for u32 {
    fn items(items: &[Self]) -> Items<'_> {
        Items::U32(items)
    }
    fn slots(items: &mut [Self]) -> Slots<'_> {
        Slots::U32(items)
    }
}

impl Width for u16 {
    fn items(items: &[Self]) -> Items<'_> {
        Items::U16(items)
    }
    fn slots(items: &mut [Self]) -> Slots<'_> {
        Slots::U16(items)
    }
}

/// The entries SI1.. of a [`Counted`](super::Counted) value by their width: UNSIGNED32 mapping
/// entries or UNSIGNED16 assigned PDOs. One write serves both.
#[derive(Clone, Copy)]
pub enum Items<'a> {
    /// Assigned PDOs.
    U16(&'a [u16]),
    /// Mapping entries.
    U32(&'a [u32]),
}

impl Items<'_> {
    /// How many entries there are (the capacity).
    pub(super) fn len(self) -> usize {
        match self {
            Self::U16(items) => items.len(),
            Self::U32(items) => items.len(),
        }
    }

    /// Entry `i` (SI `i + 1`) and its encoded size in bytes.
    pub(super) fn get(self, i: usize) -> Option<(u32, usize)> {
        match self {
            Self::U16(items) => items.get(i).map(|&v| (u32::from(v), 2)),
            Self::U32(items) => items.get(i).map(|&v| (v, 4)),
        }
    }
}

/// [`Items`] to write into.
pub enum Slots<'a> {
    /// Assigned PDOs.
    U16(&'a mut [u16]),
    /// Mapping entries.
    U32(&'a mut [u32]),
}

impl Slots<'_> {
    /// The entries, to read.
    pub(super) fn items(&self) -> Items<'_> {
        match self {
            Self::U16(items) => Items::U16(items),
            Self::U32(items) => Items::U32(items),
        }
    }

    /// Decodes `data` into entry `i` (exactly the entry's width, as any UNSIGNED16/32 entry).
    pub(super) fn set(&mut self, i: usize, data: &[u8]) -> Result<(), AbortCode> {
        let slot = match self {
            Self::U16(items) => items
                .get_mut(i)
                .map(|slot| write_value(slot, data, None, None)),
            Self::U32(items) => items
                .get_mut(i)
                .map(|slot| write_value(slot, data, None, None)),
        };
        slot.unwrap_or(Err(AbortCode::NO_SUBINDEX))
    }
}
