//! How a Rust value travels in SDO transfers: its CoE data type, its bit length and its
//! little-endian encoding (ETG.1000.6 §5.6.2, CiA 301 §7.1).

use super::DataType;
use crate::abort::AbortCode;

/// A type that can be an entry of the object dictionary.
///
/// Numbers encode as little endian of their natural size; `bool` and [`Bits`] as one byte in SDO
/// transfers (and as 1 or N bits in PDOs and complete access); strings as their current bytes.
pub trait Value: Sized {
    /// The CoE data type.
    const DATA_TYPE: DataType;
    /// The bit length (the capacity for strings).
    const BIT_LEN: u16;

    /// The encoded size in bytes of the current value.
    fn size(&self) -> usize;

    /// Copies the encoded bytes from `offset` on into `out`; returns how many were copied.
    fn read_at(&self, offset: usize, out: &mut [u8]) -> usize;

    /// Decodes a value from exactly the bytes of an SDO download.
    fn decode(data: &[u8]) -> Result<Self, AbortCode>;

    /// The value as it sits in a process image: its low `BIT_LEN` bits, little endian. Only
    /// PDO-mappable types (numbers, BOOL, BITn) have one; others give 0.
    fn to_bits(&self) -> u64 {
        0
    }

    /// The value a process image holds in the low `BIT_LEN` bits of `bits`; `None` for types
    /// that cannot be mapped.
    fn from_bits(bits: u64) -> Option<Self> {
        let _ = bits;
        None
    }
}

/// Copies `bytes[offset..]` into `out` as far as both go.
#[inline]
pub(super) fn copy_from(bytes: &[u8], offset: usize, out: &mut [u8]) -> usize {
    // The whole value (an SDO upload): a copy of the value's own length, which a fixed-size
    // value turns into a plain store.
    if offset == 0
        && let Some(dst) = out.get_mut(..bytes.len())
    {
        return crate::bytes::copy(dst, bytes);
    }
    crate::bytes::copy(out, bytes.get(offset..).unwrap_or_default())
}

/// The exact-length check of a fixed-size value.
fn exact<const N: usize>(data: &[u8]) -> Result<[u8; N], AbortCode> {
    match data.len() {
        n if n > N => Err(AbortCode::LENGTH_TOO_HIGH),
        n if n < N => Err(AbortCode::LENGTH_TOO_LOW),
        _ => data.try_into().map_err(|_| AbortCode::LENGTH_MISMATCH),
    }
}

macro_rules! numbers {
    ($($ty:ty => $dt:ident as $unsigned:ty,)*) => {$(
        impl Value for $ty {
            const DATA_TYPE: DataType = DataType::$dt;
            const BIT_LEN: u16 = <$ty>::BITS as u16;
            fn size(&self) -> usize { core::mem::size_of::<$ty>() }
            #[inline]
            fn read_at(&self, offset: usize, out: &mut [u8]) -> usize { copy_from(&self.to_le_bytes(), offset, out) }
            fn decode(data: &[u8]) -> Result<Self, AbortCode> { exact(data).map(<$ty>::from_le_bytes) }
            #[allow(clippy::cast_sign_loss)]
            fn to_bits(&self) -> u64 { *self as $unsigned as u64 }
            #[allow(clippy::cast_possible_truncation)]
            fn from_bits(bits: u64) -> Option<Self> { Some(bits as $unsigned as $ty) }
        }
    )*};
}

numbers! {
    u8 => Unsigned8 as u8, u16 => Unsigned16 as u16, u32 => Unsigned32 as u32, u64 => Unsigned64 as u64,
    i8 => Integer8 as u8, i16 => Integer16 as u16, i32 => Integer32 as u32, i64 => Integer64 as u64,
}

macro_rules! reals {
    ($($ty:ty => $dt:ident, $bits:literal;)*) => {$(
        impl Value for $ty {
            const DATA_TYPE: DataType = DataType::$dt;
            const BIT_LEN: u16 = $bits;
            fn size(&self) -> usize { core::mem::size_of::<$ty>() }
            fn read_at(&self, offset: usize, out: &mut [u8]) -> usize { copy_from(&self.to_le_bytes(), offset, out) }
            fn decode(data: &[u8]) -> Result<Self, AbortCode> { exact(data).map(<$ty>::from_le_bytes) }
            fn to_bits(&self) -> u64 { u64::from(<$ty>::to_bits(*self)) }
            #[allow(clippy::cast_possible_truncation)]
            fn from_bits(bits: u64) -> Option<Self> { Some(<$ty>::from_bits(bits as _)) }
        }
    )*};
}

reals! { f32 => Real32, 32; f64 => Real64, 64; }

impl Value for bool {
    const DATA_TYPE: DataType = DataType::Boolean;
    const BIT_LEN: u16 = 1;
    fn size(&self) -> usize {
        1
    }
    fn read_at(&self, offset: usize, out: &mut [u8]) -> usize {
        copy_from(&[u8::from(*self)], offset, out)
    }
    fn decode(data: &[u8]) -> Result<Self, AbortCode> {
        match exact::<1>(data)? {
            [0] => Ok(false),
            [1] => Ok(true),
            _ => Err(AbortCode::VALUE_RANGE),
        }
    }
    fn to_bits(&self) -> u64 {
        u64::from(*self)
    }
    fn from_bits(bits: u64) -> Option<Self> {
        Some(bits & 1 == 1)
    }
}

/// A BITn value (1 ≤ N ≤ 8): the low N bits of a byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Bits<const N: u8>(u8);

impl<const N: u8> Bits<N> {
    const MASK: u8 = if N >= 8 { 0xFF } else { (1 << N) - 1 };
    const CHECK: () = assert!(N >= 1 && N <= 8, "BITn needs 1 <= n <= 8");

    /// The value `bits` truncated to N bits.
    pub const fn new(bits: u8) -> Self {
        let () = Self::CHECK;
        Self(bits & Self::MASK)
    }

    /// The value.
    pub const fn get(self) -> u8 {
        self.0
    }
}

impl<const N: u8> Value for Bits<N> {
    const DATA_TYPE: DataType = match DataType::bits(N) {
        Some(t) => t,
        None => DataType::Bit8,
    };
    const BIT_LEN: u16 = N as u16;
    fn size(&self) -> usize {
        1
    }
    fn read_at(&self, offset: usize, out: &mut [u8]) -> usize {
        copy_from(&[self.0], offset, out)
    }
    fn decode(data: &[u8]) -> Result<Self, AbortCode> {
        let [b] = exact::<1>(data)?;
        if b & !Self::MASK != 0 {
            Err(AbortCode::VALUE_RANGE)
        } else {
            Ok(Self(b))
        }
    }
    fn to_bits(&self) -> u64 {
        u64::from(self.0)
    }
    #[allow(clippy::cast_possible_truncation)]
    fn from_bits(bits: u64) -> Option<Self> {
        Some(Self(bits as u8 & Self::MASK))
    }
}

/// A byte string of at most `N` bytes with a current length: VISIBLE_STRING and OCTET_STRING.
///
/// A download shorter than `N` shortens it (the SI0-less string semantics of CiA 301); a longer
/// one is refused with 0x06070012.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Hash)]
pub struct ByteString<const N: usize, const VISIBLE: bool> {
    bytes: [u8; N],
    len: usize,
}

/// VISIBLE_STRING of at most `N` bytes.
pub type VisibleString<const N: usize> = ByteString<N, true>;
/// OCTET_STRING of at most `N` bytes.
pub type OctetString<const N: usize> = ByteString<N, false>;

impl<const N: usize, const VISIBLE: bool> ByteString<N, VISIBLE> {
    /// The string `s`, cut at `N` bytes. `const`, for defaults.
    pub const fn new(s: &[u8]) -> Self {
        let mut bytes = [0; N];
        let len = if s.len() < N { s.len() } else { N };
        bytes.split_at_mut(len).0.copy_from_slice(s.split_at(len).0);
        Self { bytes, len }
    }

    /// The buffer and the current length, for a declared value's encoding at compile time.
    pub(super) const fn parts(self) -> ([u8; N], usize) {
        (self.bytes, self.len)
    }

    /// The current bytes.
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or_default()
    }
}

impl<const N: usize, const VISIBLE: bool> Default for ByteString<N, VISIBLE> {
    fn default() -> Self {
        Self::new(&[])
    }
}

impl<const N: usize, const VISIBLE: bool> core::fmt::Debug for ByteString<N, VISIBLE> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match core::str::from_utf8(self.as_bytes()) {
            Ok(s) if VISIBLE => write!(f, "{s:?}"),
            _ => write!(f, "{:02x?}", self.as_bytes()),
        }
    }
}

impl<const N: usize, const VISIBLE: bool> Value for ByteString<N, VISIBLE> {
    const DATA_TYPE: DataType = if VISIBLE {
        DataType::VisibleString
    } else {
        DataType::OctetString
    };
    const BIT_LEN: u16 = (N * 8) as u16;
    fn size(&self) -> usize {
        self.len
    }
    fn read_at(&self, offset: usize, out: &mut [u8]) -> usize {
        copy_from(self.as_bytes(), offset, out)
    }
    fn decode(data: &[u8]) -> Result<Self, AbortCode> {
        if data.len() > N {
            Err(AbortCode::LENGTH_TOO_HIGH)
        } else {
            Ok(Self::new(data))
        }
    }
}

/// UNICODE_STRING of at most `N` UTF-16 code units, little endian on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Hash)]
pub struct UnicodeString<const N: usize> {
    units: [u16; N],
    len: usize,
}

impl<const N: usize> UnicodeString<N> {
    /// The string of `units`, cut at `N`.
    pub const fn new(units: &[u16]) -> Self {
        let mut out = [0; N];
        let len = if units.len() < N { units.len() } else { N };
        out.split_at_mut(len)
            .0
            .copy_from_slice(units.split_at(len).0);
        Self { units: out, len }
    }

    /// The units and the current length, for a declared value's encoding at compile time.
    pub(super) const fn parts(self) -> ([u16; N], usize) {
        (self.units, self.len)
    }

    /// The current code units.
    pub fn units(&self) -> &[u16] {
        self.units.get(..self.len).unwrap_or_default()
    }
}

impl<const N: usize> Default for UnicodeString<N> {
    fn default() -> Self {
        Self::new(&[])
    }
}

impl<const N: usize> Value for UnicodeString<N> {
    const DATA_TYPE: DataType = DataType::UnicodeString;
    const BIT_LEN: u16 = (N * 16) as u16;
    fn size(&self) -> usize {
        self.len * 2
    }
    fn read_at(&self, offset: usize, out: &mut [u8]) -> usize {
        let bytes = self
            .units()
            .iter()
            .flat_map(|unit| unit.to_le_bytes())
            .skip(offset);
        out.iter_mut()
            .zip(bytes)
            .map(|(slot, byte)| *slot = byte)
            .count()
    }
    fn decode(data: &[u8]) -> Result<Self, AbortCode> {
        if !data.len().is_multiple_of(2) {
            return Err(AbortCode::LENGTH_MISMATCH);
        }
        if data.len() / 2 > N {
            return Err(AbortCode::LENGTH_TOO_HIGH);
        }
        let mut s = Self::default();
        for (unit, pair) in s.units.iter_mut().zip(data.chunks_exact(2)) {
            if let [lo, hi] = *pair {
                *unit = u16::from_le_bytes([lo, hi]);
            }
        }
        s.len = data.len() / 2;
        Ok(s)
    }
}

/// A DOMAIN entry: no storage in the dictionary; its bytes stream through the application's
/// [`ObjectHooks`](super::ObjectHooks).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Hash, Default)]
pub struct Domain;

impl Value for Domain {
    const DATA_TYPE: DataType = DataType::Domain;
    const BIT_LEN: u16 = 0;
    fn size(&self) -> usize {
        0
    }
    fn read_at(&self, _offset: usize, _out: &mut [u8]) -> usize {
        0
    }
    fn decode(_data: &[u8]) -> Result<Self, AbortCode> {
        Ok(Self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_little_endian_and_exact_length() {
        let mut out = [0; 4];
        assert_eq!(0x1234_5678u32.read_at(0, &mut out), 4);
        assert_eq!(out, [0x78, 0x56, 0x34, 0x12]);
        assert_eq!(0x1234_5678u32.read_at(3, &mut out), 1);
        assert_eq!(u16::decode(&[1, 2]), Ok(0x0201));
        assert_eq!(u16::decode(&[1, 2, 3]), Err(AbortCode::LENGTH_TOO_HIGH));
        assert_eq!(u16::decode(&[1]), Err(AbortCode::LENGTH_TOO_LOW));
        assert_eq!(i8::decode(&[0xFF]), Ok(-1));
        assert_eq!(f32::decode(&1.5f32.to_le_bytes()), Ok(1.5));
    }

    #[test]
    fn bool_and_bits_reject_values_out_of_range() {
        assert_eq!(bool::decode(&[1]), Ok(true));
        assert_eq!(bool::decode(&[2]), Err(AbortCode::VALUE_RANGE));
        assert_eq!(Bits::<3>::decode(&[7]), Ok(Bits::new(7)));
        assert_eq!(Bits::<3>::decode(&[8]), Err(AbortCode::VALUE_RANGE));
        assert_eq!(<Bits<3> as Value>::DATA_TYPE, DataType::Bit3);
    }

    #[test]
    fn strings_keep_their_length_and_refuse_longer_values() {
        let s = VisibleString::<8>::decode(b"abc");
        assert_eq!(
            s.map(|s| (s.size(), s.as_bytes().to_vec())),
            Ok((3, b"abc".to_vec()))
        );
        assert_eq!(
            VisibleString::<2>::decode(b"abc"),
            Err(AbortCode::LENGTH_TOO_HIGH)
        );
        let u = UnicodeString::<4>::decode(&[0x41, 0, 0x42, 0]);
        let mut out = [0; 4];
        assert_eq!(u.map(|u| u.read_at(1, &mut out)), Ok(3));
        assert_eq!(out[..3], [0, 0x42, 0]);
        assert_eq!(
            UnicodeString::<4>::decode(&[1]),
            Err(AbortCode::LENGTH_MISMATCH)
        );
    }
}
