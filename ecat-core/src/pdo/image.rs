//! Bit-exact copies between the process image and the dictionary (ETG.1000.6 §5.6.7): entries
//! sit at their bit offsets, little endian, least significant bit first.

use super::layout::Layout;
use crate::dictionary::ObjectDictionary;

/// Copies the image's entries into the dictionary (outputs: MainDevice → application). Entries
/// whose value the dictionary refuses (e.g. a BOOL that is neither 0 nor 1 cannot occur; an
/// enumeration out of range can) keep their previous value.
pub fn unpack<D: ObjectDictionary>(layout: &Layout<D>, image: &[u8], od: &mut D) {
    for slot in layout.slots() {
        let Some(object) = slot.object else { continue };
        let mut value = [0u8; 8];
        let n = usize::from(slot.bit_len).div_ceil(8);
        get_bits(
            image,
            usize::from(slot.bit_offset),
            usize::from(slot.bit_len),
            &mut value,
        );
        let _ = (object.write)(od, slot.sub, value.get(..n).unwrap_or_default());
    }
}

/// Copies the dictionary's entries into the image (inputs: application → MainDevice). Gaps are
/// zero.
pub fn pack<D: ObjectDictionary>(layout: &Layout<D>, od: &D, image: &mut [u8]) {
    image.fill(0);
    for slot in layout.slots() {
        let Some(object) = slot.object else { continue };
        let mut value = [0u8; 8];
        if (object.read)(od, slot.sub, 0, &mut value).is_ok() {
            put_bits(
                &value,
                usize::from(slot.bit_offset),
                usize::from(slot.bit_len),
                image,
            );
        }
    }
}

/// Reads `len` bits from `image` at bit `offset` into `out`, LSB first.
fn get_bits(image: &[u8], offset: usize, len: usize, out: &mut [u8]) {
    if offset.is_multiple_of(8) && len.is_multiple_of(8) {
        let (start, n) = (offset / 8, len / 8);
        if let (Some(src), Some(dst)) = (image.get(start..start + n), out.get_mut(..n)) {
            dst.copy_from_slice(src);
        }
        return;
    }
    for i in 0..len {
        let bit = offset + i;
        let set = image.get(bit / 8).is_some_and(|b| b >> (bit % 8) & 1 != 0);
        if let Some(byte) = out.get_mut(i / 8) {
            *byte |= u8::from(set) << (i % 8);
        }
    }
}

/// Writes the low `len` bits of `value` into `image` at bit `offset`, LSB first.
fn put_bits(value: &[u8], offset: usize, len: usize, image: &mut [u8]) {
    if offset.is_multiple_of(8) && len.is_multiple_of(8) {
        let (start, n) = (offset / 8, len / 8);
        if let (Some(dst), Some(src)) = (image.get_mut(start..start + n), value.get(..n)) {
            dst.copy_from_slice(src);
        }
        return;
    }
    for i in 0..len {
        let set = value.get(i / 8).is_some_and(|b| b >> (i % 8) & 1 != 0);
        let bit = offset + i;
        if let Some(byte) = image.get_mut(bit / 8) {
            *byte = (*byte & !(1 << (bit % 8))) | (u8::from(set) << (bit % 8));
        }
    }
}
