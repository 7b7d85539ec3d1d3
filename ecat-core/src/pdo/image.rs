//! Bit-exact copies between the process image and the dictionary (ETG.1000.6 §5.6.7): entries
//! sit at their bit offsets, little endian, least significant bit first.
//!
//! Each entry moves as a `u64` through its object's typed accessors (`Object::load` /
//! `Object::store`). How it is copied ([`Place`]) is decided once when the layout is computed:
//! byte-aligned 8/16/32/64-bit entries are one fixed-width load or store, others go bit by bit.

use super::layout::{Layout, Place, Slot};
use crate::dictionary::ObjectDictionary;

/// Copies the image's entries into the dictionary (outputs: MainDevice → application).
pub fn unpack<D: ObjectDictionary>(layout: &Layout<D>, image: &[u8], od: &mut D) {
    for slot in layout.slots() {
        if let Some(object) = slot.object {
            (object.store)(od, slot.sub, get(image, slot));
        }
    }
}

/// Copies the dictionary's entries into the image (inputs: application → MainDevice). Gaps and
/// the padding after the last entry are zero.
pub fn pack<D: ObjectDictionary>(layout: &Layout<D>, od: &D, image: &mut [u8]) {
    for slot in layout.slots() {
        let bits = slot.object.map_or(0, |object| (object.load)(od, slot.sub));
        put(image, slot, bits);
    }
    let end = layout.bits();
    let padding = (8 - end % 8) % 8;
    if let (Ok(offset), Ok(padding @ 1..)) = (u16::try_from(end), u8::try_from(padding)) {
        put_bits(image, offset, padding, 0);
    }
}

/// The slot's bits in `image`; bits beyond the image read as 0.
fn get<D>(image: &[u8], slot: &Slot<D>) -> u64 {
    let value = match slot.place {
        Place::U8(at) => image.get(at).map(|&b| u64::from(b)),
        Place::U16(at) => chunk(image, at).map(|b| u64::from(u16::from_le_bytes(b))),
        Place::U32(at) => chunk(image, at).map(|b| u64::from(u32::from_le_bytes(b))),
        Place::U64(at) => chunk(image, at).map(u64::from_le_bytes),
        Place::Bits => None,
    };
    value.unwrap_or_else(|| get_bits(image, slot.bit_offset, slot.bit_len))
}

/// The `N` bytes of `image` from `at`, if it has them.
fn chunk<const N: usize>(image: &[u8], at: usize) -> Option<[u8; N]> {
    image.get(at..)?.first_chunk().copied()
}

/// The `N` bytes of `image` from `at`, if it has them, for writing.
fn chunk_mut<const N: usize>(image: &mut [u8], at: usize) -> Option<&mut [u8; N]> {
    image.get_mut(at..)?.first_chunk_mut()
}

/// Writes the slot's bits into `image`; bits beyond the image are dropped.
#[allow(clippy::cast_possible_truncation)] // each fast path stores exactly its width
fn put<D>(image: &mut [u8], slot: &Slot<D>, bits: u64) {
    let done = match slot.place {
        Place::U8(at) => image.get_mut(at).map(|b| *b = bits as u8),
        Place::U16(at) => chunk_mut(image, at).map(|b| *b = (bits as u16).to_le_bytes()),
        Place::U32(at) => chunk_mut(image, at).map(|b| *b = (bits as u32).to_le_bytes()),
        Place::U64(at) => chunk_mut(image, at).map(|b| *b = bits.to_le_bytes()),
        Place::Bits => None,
    };
    if done.is_none() {
        put_bits(image, slot.bit_offset, slot.bit_len, bits);
    }
}

/// `len` bits of `image` from bit `offset`, LSB first.
fn get_bits(image: &[u8], offset: u16, len: u8) -> u64 {
    let offset = usize::from(offset);
    (0..usize::from(len).min(64)).fold(0, |bits, i| {
        let bit = offset + i;
        let set = image.get(bit / 8).is_some_and(|b| b >> (bit % 8) & 1 != 0);
        bits | (u64::from(set) << i)
    })
}

/// Writes the low `len` bits of `bits` into `image` from bit `offset`, LSB first.
fn put_bits(image: &mut [u8], offset: u16, len: u8, bits: u64) {
    let offset = usize::from(offset);
    for i in 0..usize::from(len).min(64) {
        let bit = offset + i;
        if let Some(byte) = image.get_mut(bit / 8) {
            let set = u8::from(bits >> i & 1 != 0);
            *byte = (*byte & !(1 << (bit % 8))) | (set << (bit % 8));
        }
    }
}
