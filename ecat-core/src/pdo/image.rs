//! Bit-exact copies between the process image and the dictionary (ETG.1000.6 §5.6.7): entries
//! sit at their bit offsets, little endian, least significant bit first.
//!
//! [`unpack`] and [`pack`] run the code `dictionary!` generates for the dictionary
//! (`ObjectDictionary::unpack_mapped`/`pack_mapped`): for each PDO-mappable field in turn,
//! [`Mapped::unpack`]/[`Mapped::pack`] with the field's offsets from the [`Layout`], inlined
//! with the field's type known, so an entry at a byte boundary is one fixed-width load and store
//! and an unmapped one a compare; only entries that are not whole bytes at a byte boundary (BOOL,
//! BITn, anything after them) go bit by bit.

use super::layout::{BYTE_ALIGNED, Layout, Repeat, UNMAPPED, bit_offset};
use crate::dictionary::{Length, ObjectDictionary, Value};

/// Copies the image's entries into the dictionary (outputs: MainDevice → application). An entry
/// not wholly inside `image` is left as it is.
pub fn unpack<D: ObjectDictionary, R: Length>(layout: &Layout<D, R>, image: &[u8], od: &mut D) {
    od.unpack_mapped(layout.offsets(), image);
}

/// Copies the dictionary's entries into the image (inputs: application → MainDevice). Gaps and
/// the padding after the last entry are zero; an entry not wholly inside `image` is not
/// written.
pub fn pack<D: ObjectDictionary>(layout: &Layout<D>, od: &D, image: &mut [u8]) {
    if layout.has_gaps() {
        image.fill(0);
    }
    od.pack_mapped(layout.offsets(), image);
    for repeat in layout.repeats() {
        repeat_bits(image, repeat);
    }
}

/// Copies a repeated entry's bits, LSB first, from its first place to the repeat's (places of
/// one image never overlap), unless either place is not wholly inside `image`.
fn repeat_bits(image: &mut [u8], repeat: &Repeat) {
    let (from, to, len) = (
        usize::from(repeat.from),
        usize::from(repeat.to),
        usize::from(repeat.len),
    );
    let bits = image.len().saturating_mul(8);
    if from + len > bits || to + len > bits {
        return;
    }
    // Through the entry's (at most 8) bytes: the one bit copier, twice.
    let mut value = [0u8; 8];
    copy_bits(image, from, &mut value, 0, 0, len.min(64));
    copy_bits(&value, 0, image, to, 0, len.min(64));
}

/// A field PDO-mappable entries live in: a value (one entry) or an ARRAY's elements (one entry
/// each, numbered in order). The code `dictionary!` generates calls these once per mappable field
/// with the field's first [entry number](super::layout::number), a constant.
pub trait Mapped {
    /// Copies the field's entries from their offsets in `image`.
    fn unpack(&mut self, image: &[u8], offsets: &[u16], first: usize);
    /// Copies the field's entries into `image` at their offsets.
    fn pack(&self, image: &mut [u8], offsets: &[u16], first: usize);
}

impl<T: Value> Mapped for T {
    #[inline(always)]
    fn unpack(&mut self, image: &[u8], offsets: &[u16], first: usize) {
        if let Some(&at) = offsets.get(first) {
            unpack_value(self, image, at);
        }
    }

    #[inline(always)]
    fn pack(&self, image: &mut [u8], offsets: &[u16], first: usize) {
        if let Some(&at) = offsets.get(first) {
            put::<T>(image, at, self.to_bits());
        }
    }
}

impl<T: Value, const N: usize> Mapped for [T; N] {
    #[inline(always)]
    fn unpack(&mut self, image: &[u8], offsets: &[u16], first: usize) {
        if let Some(offsets) = offsets.get(first..).and_then(<[u16]>::first_chunk::<N>) {
            for (value, &at) in self.iter_mut().zip(offsets) {
                unpack_value(value, image, at);
            }
        }
    }

    #[inline(always)]
    fn pack(&self, image: &mut [u8], offsets: &[u16], first: usize) {
        if let Some(offsets) = offsets.get(first..).and_then(<[u16]>::first_chunk::<N>) {
            for (value, &at) in self.iter().zip(offsets) {
                put::<T>(image, at, value.to_bits());
            }
        }
    }
}

#[inline(always)]
fn unpack_value<T: Value>(value: &mut T, image: &[u8], at: u16) {
    if let Some(v) = get::<T>(image, at).and_then(T::from_bits) {
        *value = v;
    }
}

/// The `T::BIT_LEN` bits of `image` at `stored` (a layout's offset); `None` when unmapped or not
/// inside `image`.
#[inline(always)]
fn get<T: Value>(image: &[u8], stored: u16) -> Option<u64> {
    let i = usize::from(stored);
    match (stored < BYTE_ALIGNED, T::BIT_LEN) {
        (true, 8) => image.get(i).copied().map(u64::from),
        (true, 16) => chunk(image, i).map(|b| u16::from_le_bytes(b).into()),
        (true, 32) => chunk(image, i).map(|b| u32::from_le_bytes(b).into()),
        (true, 64) => chunk(image, i).map(u64::from_le_bytes),
        _ if stored == UNMAPPED => None,
        (_, 1) => {
            let bit = usize::from(bit_offset(stored));
            image.get(bit / 8).map(|b| u64::from(b >> (bit % 8) & 1))
        }
        _ => get_bits(image, bit_offset(stored), u8::try_from(T::BIT_LEN).ok()?),
    }
}

/// Writes the low `T::BIT_LEN` bits of `bits` into `image` at `stored` (a layout's offset),
/// unless unmapped or not inside `image`.
#[inline(always)]
#[allow(clippy::cast_possible_truncation)] // each fast path stores exactly its width
fn put<T: Value>(image: &mut [u8], stored: u16, bits: u64) {
    let i = usize::from(stored);
    match (stored < BYTE_ALIGNED, T::BIT_LEN) {
        (true, 8) => set(image.get_mut(i), bits as u8),
        (true, 16) => set(chunk_mut(image, i), (bits as u16).to_le_bytes()),
        (true, 32) => set(chunk_mut(image, i), (bits as u32).to_le_bytes()),
        (true, 64) => set(chunk_mut(image, i), bits.to_le_bytes()),
        _ if stored == UNMAPPED => {}
        (_, 1) => {
            let bit = usize::from(bit_offset(stored));
            if let Some(byte) = image.get_mut(bit / 8) {
                let set = (bits & 1) as u8;
                *byte = (*byte & !(1 << (bit % 8))) | (set << (bit % 8));
            }
        }
        _ => {
            if let Ok(len) = u8::try_from(T::BIT_LEN) {
                put_bits(image, bit_offset(stored), len, bits);
            }
        }
    }
}

fn set<T>(place: Option<&mut T>, value: T) {
    if let Some(place) = place {
        *place = value;
    }
}

/// The `N` bytes of `image` from `at`, if it has them.
#[inline(always)]
fn chunk<const N: usize>(image: &[u8], at: usize) -> Option<[u8; N]> {
    image.get(at..at.checked_add(N)?)?.try_into().ok()
}

/// The `N` bytes of `image` from `at`, if it has them, for writing.
#[inline(always)]
fn chunk_mut<const N: usize>(image: &mut [u8], at: usize) -> Option<&mut [u8; N]> {
    image.get_mut(at..at.checked_add(N)?)?.try_into().ok()
}

/// `len` bits of `image` from bit `offset`, LSB first; `None` unless all are inside `image`.
fn get_bits(image: &[u8], offset: u16, len: u8) -> Option<u64> {
    let offset = usize::from(offset);
    if offset + usize::from(len) > image.len().saturating_mul(8) {
        return None;
    }
    let mut value = [0u8; 8];
    copy_bits(image, offset, &mut value, 0, 0, usize::from(len));
    Some(u64::from_le_bytes(value))
}

/// Writes the low `len` bits of `bits` into `image` from bit `offset`, LSB first, unless some
/// are beyond `image`.
fn put_bits(image: &mut [u8], offset: u16, len: u8, bits: u64) {
    let offset = usize::from(offset);
    if offset + usize::from(len) > image.len().saturating_mul(8) {
        return;
    }
    copy_bits(
        &bits.to_le_bytes(),
        0,
        image,
        offset,
        0,
        usize::from(len).min(64),
    );
}

/// Copies `len` bits, LSB first, from bit `from` of `src` to bit `to` of a window that starts
/// at byte `skip` of the destination: bits outside the window are left out, bits beyond `src`
/// are 0. The one bit copier of entries: a field that is no whole bytes at a byte boundary
/// ([`Mapped`]) and a complete-access image both ways
/// ([`complete_access`](crate::coe::sdo::complete_access)).
#[inline(never)]
pub(crate) fn copy_bits(
    src: &[u8],
    from: usize,
    window: &mut [u8],
    to: usize,
    skip: usize,
    len: usize,
) {
    for i in 0..len {
        let (s, d) = (from + i, to + i);
        let bit = src.get(s / 8).map_or(0, |b| (b >> (s % 8)) & 1);
        if let Some(byte) = (d / 8).checked_sub(skip).and_then(|b| window.get_mut(b)) {
            *byte = (*byte & !(1 << (d % 8))) | (bit << (d % 8));
        }
    }
}
