//! The declared values of a dictionary's entries — default, minimum, maximum and unit, which
//! SDO Information's entry description (ETG.1000.6 §5.6.3.6, value info 0x08..0x40) and the
//! ESI file report — as one table of bytes encoded at compile time
//! ([`ObjectDictionary::LIMITS`](super::ObjectDictionary::LIMITS)), read by one function
//! ([`Object::limit`](super::Object::limit)) instead of code per object.
//!
//! The table is a run of records `index (u16 LE), subindex, Limit, length, bytes…` (a length of
//! 255 bytes or more as 0xFF and a u16 LE), in the order
//! of declaration; an ARRAY's elements share one record, of SI1 with the [`Limit`] marked
//! `EVERY_ELEMENT`. `dictionary!` builds it from
//! [`Declared`] values, each encoded by [`Encode`] with the encoding of the field's type (the
//! same little-endian bytes its `Value` reads).

use super::Limit;
use super::value::{Bits, ByteString, Domain, UnicodeString};

/// One declared value of an entry, before packing: where it belongs and its bytes.
#[derive(Debug, Clone, Copy)]
pub struct Declared {
    index: u16,
    sub: u8,
    /// The [`Limit`], with `EVERY_ELEMENT`.
    which: u8,
    bytes: &'static [u8],
}

impl Declared {
    /// `bytes` as the `which` of `index:sub`.
    pub const fn new(index: u16, sub: u8, which: Limit, bytes: &'static [u8]) -> Self {
        Self {
            index,
            sub,
            which: which as u8,
            bytes,
        }
    }

    /// `bytes` as the value of the constant entry `index:sub` that declares no default (0x1C00's
    /// SI0, the number of SyncManagers): a record of kind [`VALUE`], which
    /// [`communication::read_declared`](super::communication::read_declared) reads and no
    /// [`Limit`] finds (SDO Information and the ESI report no default for it).
    pub const fn value(index: u16, sub: u8, bytes: &'static [u8]) -> Self {
        Self {
            index,
            sub,
            which: VALUE,
            bytes,
        }
    }

    /// The same value for every element of an ARRAY (SI1 and up).
    pub const fn every_element(self) -> Self {
        Self {
            sub: 1,
            which: self.which | EVERY_ELEMENT,
            ..self
        }
    }
}

/// The mark on a record's [`Limit`] that makes it every element's, SI1 and up (an ARRAY's
/// declared values; 0x1C00 declares each SyncManager's type on its own).
const EVERY_ELEMENT: u8 = 0x80;

/// The kind of a constant's value that is no declared [`Limit`] ([`Declared::value`]): a bit
/// beside theirs.
pub(super) const VALUE: u8 = 0x10;
const _: () = assert!(
    VALUE
        & (Limit::Default as u8
            | Limit::Min as u8
            | Limit::Max as u8
            | Limit::Unit as u8
            | EVERY_ELEMENT)
        == 0
);

/// The bytes of a record's head: index, subindex, kind and length.
const HEAD: usize = 5;

/// The length byte of a value of [`LONG`] bytes or more: its length follows in two bytes
/// (a string's default; an entry is at most 8 191 bytes).
const LONG: u8 = 0xFF;

/// The head of a record of a value of `len` bytes.
const fn head_len(len: usize) -> usize {
    if len < LONG as usize { HEAD } else { HEAD + 2 }
}

/// The size of the packed table of `groups` (each the declared values of one object).
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn packed_len(groups: &[&[Declared]]) -> usize {
    let mut len = 0;
    let mut i = 0;
    while i < groups.len() {
        let mut j = 0;
        while j < groups[i].len() {
            len += head_len(groups[i][j].bytes.len()) + groups[i][j].bytes.len();
            j += 1;
        }
        i += 1;
    }
    len
}

/// The packed table of `groups`, `N` = [`packed_len`]: [`ObjectDictionary::LIMITS`](super::ObjectDictionary::LIMITS).
#[allow(clippy::indexing_slicing, clippy::cast_possible_truncation)] // compile time; a value's length is a u16 (asserted)
pub const fn pack<const N: usize>(groups: &[&[Declared]]) -> [u8; N] {
    let mut out = [0; N];
    let mut at = 0;
    let mut i = 0;
    while i < groups.len() {
        let mut j = 0;
        while j < groups[i].len() {
            let d = groups[i][j];
            let len = d.bytes.len();
            assert!(
                len <= u16::MAX as usize,
                "a declared value is at most 65 535 bytes"
            );
            let [i0, i1] = d.index.to_le_bytes();
            out[at] = i0;
            out[at + 1] = i1;
            out[at + 2] = d.sub;
            out[at + 3] = d.which;
            if len < LONG as usize {
                out[at + 4] = len as u8;
            } else {
                let [l0, l1] = (len as u16).to_le_bytes();
                out[at + 4] = LONG;
                out[at + 5] = l0;
                out[at + 6] = l1;
            }
            at += head_len(len);
            let mut k = 0;
            while k < d.bytes.len() {
                out[at] = d.bytes[k];
                at += 1;
                k += 1;
            }
            j += 1;
        }
        i += 1;
    }
    out
}

/// The bytes of the default of VAR `index` in the packed `table`, at compile time: what a
/// constant VAR of the communication area reads (0x1000 and the texts, whose default is their
/// value), so that its bytes are in flash once. A slice of `table` itself.
#[allow(clippy::panic)] // evaluated in a `const` block: a missing record fails the build
pub const fn default_of(table: &'static [u8], index: u16) -> &'static [u8] {
    match record(table, index, 0, Limit::Default as u8) {
        [] => panic!("a constant object declares its value as its default"),
        bytes => bytes,
    }
}

/// Copies the `which` of `index:sub` from the packed `table` into `out` (as far as it goes);
/// 0 when the table declares none.
pub(super) fn find(table: &[u8], index: u16, sub: u8, which: Limit, out: &mut [u8]) -> usize {
    crate::bytes::copy(out, record(table, index, sub, which as u8))
}

/// The bytes of the first record of `index:sub` in the packed `table` whose kind is one of the
/// bits of `which` (a [`Limit`], or with [`VALUE`] a constant's value), none when it declares
/// none (a DOMAIN's declared value has none either): the one reader of the records, at compile
/// time ([`default_of`]) and at run time ([`find`], `communication::read_declared`).
pub(super) const fn record(table: &[u8], index: u16, sub: u8, which: u8) -> &[u8] {
    let mut rest = table;
    while let [r0, r1, s, w, len, tail @ ..] = rest {
        let (len, tail) = match (*len, tail) {
            (LONG, [l0, l1, tail @ ..]) => (u16::from_le_bytes([*l0, *l1]), tail),
            _ => (*len as u16, tail),
        };
        let Some((bytes, next)) = tail.split_at_checked(len as usize) else {
            break;
        };
        let subs = *s == sub || (*w & EVERY_ELEMENT != 0 && sub != 0);
        if u16::from_le_bytes([*r0, *r1]) == index && *w & which != 0 && subs {
            return bytes;
        }
        rest = next;
    }
    &[]
}

/// The encoded bytes of a declared value: `K` units of `W` bytes, the first `len` bytes valid.
#[derive(Debug, Clone, Copy)]
pub struct Bytes<const K: usize, const W: usize> {
    units: [[u8; W]; K],
    len: usize,
}

impl<const K: usize, const W: usize> Bytes<K, W> {
    /// The valid bytes.
    pub const fn as_slice(&'static self) -> &'static [u8] {
        self.units.as_flattened().split_at(self.len).0
    }
}

/// A declared value of type `T`, to be encoded at compile time: [`of`]`(field, value)`,
/// then `encode()` of its type (an inherent `const fn` per type: a trait's methods cannot run
/// at compile time).
#[derive(Debug, Clone, Copy)]
pub struct Encode<T>(T);

/// `value`, of the type of the field `get` reaches.
pub const fn of<S, T>(_: fn(&S) -> &T, value: T) -> Encode<T> {
    Encode(value)
}

/// `value`, of the element type of the ARRAY field `get` reaches.
pub const fn element<S, T, const N: usize>(_: fn(&S) -> &[T; N], value: T) -> Encode<T> {
    Encode(value)
}

/// A unit (UNSIGNED16).
pub const fn unit(unit: u16) -> Encode<u16> {
    Encode(unit)
}

/// The little-endian bytes of numbers, one `encode` per type.
macro_rules! numbers {
    ($($ty:ty => $n:literal, |$v:ident| $bytes:expr;)*) => {$(
        impl Encode<$ty> {
            /// The encoded value.
            pub const fn encode(self) -> Bytes<1, $n> {
                let $v = self.0;
                Bytes { units: [$bytes], len: $n }
            }
        }
    )*};
}

numbers! {
    u8 => 1, |v| v.to_le_bytes(); u16 => 2, |v| v.to_le_bytes();
    u32 => 4, |v| v.to_le_bytes(); u64 => 8, |v| v.to_le_bytes();
    i8 => 1, |v| v.to_le_bytes(); i16 => 2, |v| v.to_le_bytes();
    i32 => 4, |v| v.to_le_bytes(); i64 => 8, |v| v.to_le_bytes();
    f32 => 4, |v| v.to_bits().to_le_bytes(); f64 => 8, |v| v.to_bits().to_le_bytes();
    bool => 1, |v| [v as u8];
}

impl<const N: u8> Encode<Bits<N>> {
    /// The encoded value: one byte.
    pub const fn encode(self) -> Bytes<1, 1> {
        Bytes {
            units: [[self.0.get()]],
            len: 1,
        }
    }
}

impl Encode<Domain> {
    /// The encoded value: none (a DOMAIN's bytes stream through the hooks).
    pub const fn encode(self) -> Bytes<0, 1> {
        Bytes { units: [], len: 0 }
    }
}

impl<const N: usize, const VISIBLE: bool> Encode<ByteString<N, VISIBLE>> {
    /// The encoded value: the current bytes.
    #[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
    pub const fn encode(self) -> Bytes<N, 1> {
        let (bytes, len) = self.0.parts();
        let mut units = [[0; 1]; N];
        let mut i = 0;
        while i < N {
            units[i] = [bytes[i]];
            i += 1;
        }
        Bytes { units, len }
    }
}

impl<const N: usize> Encode<UnicodeString<N>> {
    /// The encoded value: the current code units, little endian.
    #[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
    pub const fn encode(self) -> Bytes<N, 2> {
        let (units, len) = self.0.parts();
        let mut out = [[0; 2]; N];
        let mut i = 0;
        while i < N {
            out[i] = units[i].to_le_bytes();
            i += 1;
        }
        Bytes {
            units: out,
            len: len * 2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::VisibleString;

    struct Od {
        speed: i32,
        text: VisibleString<8>,
        label: UnicodeString<4>,
        gains: [u16; 3],
    }

    const TABLE: [u8; 38] = {
        const GROUPS: &[&[Declared]] = &[
            &[
                Declared::new(
                    0x2000,
                    0,
                    Limit::Min,
                    Bytes::as_slice(&of(|d: &Od| &d.speed, -2).encode()),
                ),
                Declared::new(
                    0x2000,
                    0,
                    Limit::Unit,
                    Bytes::as_slice(&unit(0x0017).encode()),
                ),
            ],
            &[],
            &[
                Declared::new(
                    0x2001,
                    0,
                    Limit::Default,
                    Bytes::as_slice(&of(|d: &Od| &d.text, VisibleString::new(b"abc")).encode()),
                ),
                Declared::new(
                    0x2002,
                    0,
                    Limit::Default,
                    Bytes::as_slice(&of(|d: &Od| &d.label, UnicodeString::new(&[0x263A])).encode()),
                ),
                Declared::new(
                    0x2003,
                    1,
                    Limit::Max,
                    Bytes::as_slice(&element(|d: &Od| &d.gains, 500).encode()),
                )
                .every_element(),
            ],
        ];
        assert!(packed_len(GROUPS) == 38);
        pack(GROUPS)
    };

    fn get(index: u16, sub: u8, which: Limit, room: usize) -> ([u8; 8], usize) {
        let mut out = [0; 8];
        let n = find(&TABLE, index, sub, which, &mut out[..room]);
        (out, n)
    }

    fn bytes(got: &([u8; 8], usize)) -> &[u8] {
        &got.0[..got.1]
    }

    #[test]
    fn values_are_their_types_encoding_by_index_subindex_and_kind() {
        assert_eq!(
            bytes(&get(0x2000, 0, Limit::Min, 8)),
            [0xFE, 0xFF, 0xFF, 0xFF]
        );
        assert_eq!(bytes(&get(0x2000, 0, Limit::Unit, 8)), [0x17, 0]);
        assert_eq!(bytes(&get(0x2001, 0, Limit::Default, 8)), b"abc");
        assert_eq!(bytes(&get(0x2002, 0, Limit::Default, 8)), [0x3A, 0x26]);
        assert_eq!(bytes(&get(0x2003, 1, Limit::Max, 8)), [0xF4, 0x01]);
        // An ARRAY's value is every element's, not SI0's.
        assert_eq!(bytes(&get(0x2003, 3, Limit::Max, 8)), [0xF4, 0x01]);
        assert_eq!(bytes(&get(0x2003, 0, Limit::Max, 8)), [0u8; 0]);
        // Not declared: nothing.
        assert_eq!(bytes(&get(0x2000, 0, Limit::Max, 8)), [0u8; 0]);
        assert_eq!(bytes(&get(0x2000, 1, Limit::Min, 8)), [0u8; 0]);
        assert_eq!(bytes(&get(0x2004, 0, Limit::Min, 8)), [0u8; 0]);
        // As far as `out` goes.
        assert_eq!(bytes(&get(0x2000, 0, Limit::Min, 3)), [0xFE, 0xFF, 0xFF]);
    }

    #[test]
    fn a_value_of_255_bytes_or_more_has_a_long_length() {
        struct Long {
            text: VisibleString<300>,
            after: u8,
        }
        const TEXT: VisibleString<300> = VisibleString::new(&[b'x'; 300]);
        const GROUPS: &[&[Declared]] = &[&[
            Declared::new(
                0x2000,
                0,
                Limit::Default,
                Bytes::as_slice(&of(|d: &Long| &d.text, TEXT).encode()),
            ),
            Declared::new(
                0x2001,
                0,
                Limit::Default,
                Bytes::as_slice(&of(|d: &Long| &d.after, 7).encode()),
            ),
        ]];
        const LONG_TABLE: [u8; 7 + 300 + 6] = pack(GROUPS);
        assert_eq!(packed_len(GROUPS), 313);
        assert_eq!(LONG_TABLE[4..7], [0xFF, 0x2C, 0x01]);
        let mut out = [0; 400];
        assert_eq!(find(&LONG_TABLE, 0x2000, 0, Limit::Default, &mut out), 300);
        assert!(out[..300].iter().all(|&b| b == b'x'));
        assert_eq!(find(&LONG_TABLE, 0x2001, 0, Limit::Default, &mut out), 1);
        assert_eq!(out[0], 7);
        // A long length cut short ends the walk.
        assert_eq!(
            find(&LONG_TABLE[..6], 0x2000, 0, Limit::Default, &mut out),
            0
        );
    }

    #[test]
    fn a_truncated_table_ends_the_walk() {
        let mut out = [0; 8];
        assert_eq!(find(&TABLE[..8], 0x2000, 0, Limit::Min, &mut out), 0);
        assert_eq!(find(&TABLE[..9], 0x2000, 0, Limit::Min, &mut out), 4);
        assert_eq!(find(&TABLE[..9], 0x2000, 0, Limit::Unit, &mut out), 0);
    }
}
