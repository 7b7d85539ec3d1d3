//! The process image a configuration describes: for each direction, the assigned PDOs' mapped
//! entries, their bit offsets, and the image size the SyncManager must have
//! (ETG.1000.6 §5.6.7; AL status codes 0x0024/0x0025 for an unusable mapping).

use super::{Direction, MappingEntry};
use crate::AlStatusCode;
use crate::dictionary::{Object, ObjectDictionary};

/// How many mapped entries one direction's image may hold.
pub const MAX_ENTRIES: usize = 64;

/// How an entry is copied, decided once when the layout is computed: byte-aligned 8/16/32/64-bit
/// entries as one fixed-width load or store at a byte index, everything else bit by bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// One byte at this index.
    U8(usize),
    /// Two bytes from this index.
    U16(usize),
    /// Four bytes from this index.
    U32(usize),
    /// Eight bytes from this index.
    U64(usize),
    /// `bit_len` bits from `bit_offset`.
    Bits,
}

impl Place {
    fn of(bit_offset: u16, bit_len: u8) -> Self {
        let at = usize::from(bit_offset / 8);
        match (bit_offset.is_multiple_of(8), bit_len) {
            (true, 8) => Self::U8(at),
            (true, 16) => Self::U16(at),
            (true, 32) => Self::U32(at),
            (true, 64) => Self::U64(at),
            _ => Self::Bits,
        }
    }
}

/// One mapped entry's place in the image.
pub struct Slot<D: 'static> {
    /// The mapped object, `None` for a gap.
    pub object: Option<&'static Object<D>>,
    /// The mapped subindex.
    pub sub: u8,
    /// Offset from the start of the image, in bits.
    pub bit_offset: u16,
    /// Length in bits.
    pub bit_len: u8,
    /// How it is copied.
    pub place: Place,
}

impl<D> Slot<D> {
    const EMPTY: Self = Self {
        object: None,
        sub: 0,
        bit_offset: 0,
        bit_len: 0,
        place: Place::Bits,
    };
}

impl<D> Clone for Slot<D> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<D> Copy for Slot<D> {}

/// One direction's image: its slots and its size.
pub struct Layout<D: 'static> {
    slots: [Slot<D>; MAX_ENTRIES],
    len: usize,
    bits: u32,
}

impl<D: ObjectDictionary> Layout<D> {
    /// The image `direction` describes in `od`: the assigned PDOs (0x1C12/0x1C13) in order, their
    /// mapped entries in order. `Ok(None)` when the dictionary has no assignment object (a fixed
    /// layout from the device configuration applies).
    pub fn of(od: &D, direction: Direction) -> Result<Option<Self>, AlStatusCode> {
        let invalid = match direction {
            Direction::Rx => AlStatusCode::INVALID_OUTPUT_MAPPING,
            Direction::Tx => AlStatusCode::INVALID_INPUT_MAPPING,
        };
        let Some(assignment) = D::object(direction.assignment()) else {
            return Ok(None);
        };
        let mut layout = Self {
            slots: [Slot::EMPTY; MAX_ENTRIES],
            len: 0,
            bits: 0,
        };
        for pdo in 1..=count(od, assignment) {
            let index = read_u16(od, assignment, pdo).ok_or(invalid)?;
            let mapping = D::object(index)
                .filter(|_| direction.is_mapping(index))
                .ok_or(invalid)?;
            for sub in 1..=count(od, mapping) {
                let entry = MappingEntry(read_u32(od, mapping, sub).ok_or(invalid)?);
                layout.push(entry, direction).ok_or(invalid)?;
            }
        }
        Ok(Some(layout))
    }

    fn push(&mut self, entry: MappingEntry, direction: Direction) -> Option<()> {
        let object = match entry.index() {
            0 => None,
            index => {
                let object = D::object(index)?;
                let info = object.info.entry(entry.sub())?;
                let mappable =
                    direction.allows(info.access) && info.bit_len == u16::from(entry.bit_len());
                Some(object).filter(|_| mappable)?.into()
            }
        };
        let bit_offset = u16::try_from(self.bits).ok()?;
        let bit_len = entry.bit_len();
        let place = Place::of(bit_offset, bit_len);
        *self.slots.get_mut(self.len)? = Slot {
            object,
            sub: entry.sub(),
            bit_offset,
            bit_len,
            place,
        };
        self.len += 1;
        self.bits += u32::from(entry.bit_len());
        Some(())
    }

    /// The image size in bits.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// The image size in bytes (bits rounded up).
    pub fn bytes(&self) -> u16 {
        u16::try_from(self.bits.div_ceil(8)).unwrap_or(u16::MAX)
    }

    /// The slots in image order.
    pub fn slots(&self) -> &[Slot<D>] {
        self.slots.get(..self.len).unwrap_or_default()
    }
}

pub(crate) fn count<D>(od: &D, object: &Object<D>) -> u8 {
    let mut b = [0u8; 1];
    (object.read)(od, 0, 0, &mut b).map_or(0, |_| b[0])
}

pub(crate) fn read_u16<D>(od: &D, object: &Object<D>, sub: u8) -> Option<u16> {
    let mut b = [0u8; 2];
    (object.read)(od, sub, 0, &mut b)
        .ok()
        .filter(|r| r.copied == 2)
        .map(|_| u16::from_le_bytes(b))
}

pub(crate) fn read_u32<D>(od: &D, object: &Object<D>, sub: u8) -> Option<u32> {
    let mut b = [0u8; 4];
    (object.read)(od, sub, 0, &mut b)
        .ok()
        .filter(|r| r.copied == 4)
        .map(|_| u32::from_le_bytes(b))
}
