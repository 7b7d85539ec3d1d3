//! Byte copies without a panic path.
//!
//! `<[u8]>::copy_from_slice` panics when the lengths differ; where the compiler cannot prove
//! them equal it keeps the panic call and its source location (a path string in the firmware,
//! whose size then depends on the checkout path). [`copy`] copies as far as both slices go.

/// Copies `src` into the start of `dst` as far as both go; returns the number of bytes copied.
#[inline]
pub(crate) fn copy(dst: &mut [u8], src: &[u8]) -> usize {
    let n = dst.len().min(src.len());
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
    n
}
