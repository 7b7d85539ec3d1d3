//! The tables a dictionary keeps at run time, made at compile time from what
//! [`dictionary!`](crate::dictionary!) declares: every name once, one after the other, in one
//! text ([`ObjectDictionary::NAMES`](super::ObjectDictionary::NAMES)) — a name that a longer
//! one holds ("Cycle time" in "Cycle time too small counter") not even once: it points into the
//! longer —, descriptions that refer
//! to it by [`Name`] (4 bytes where a `&'static str` takes 8), and the entry descriptions of
//! all objects in one array whose slices the objects share (like entries, as 0x1C32's and
//! 0x1C33's, once). The declaration's own tables (a [`Declaration`] per object, names as
//! text) are read by `const` evaluation only and never reach the program.
//!
//! Names are listed in one order everywhere here: each object's, then its entries'.

use super::{Access, At, DataType, EntryInfo, Limits, Name, Object, ObjectInfo, Read};
use crate::abort::AbortCode;

/// An object as [`dictionary!`](crate::dictionary!) declares it: names as text.
pub type Declaration<D> = Object<D, &'static str>;

/// The number of names of `objects`: each object's and each entry's.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn name_count<D>(objects: &[Declaration<D>]) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < objects.len() {
        n += 1 + objects[i].info.entries.len();
        i += 1;
    }
    n
}

/// Every name of `objects` in order ([`name_count`] of them).
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn names<D, const COUNT: usize>(objects: &[Declaration<D>]) -> [&'static str; COUNT] {
    let mut out = [""; COUNT];
    let (mut i, mut k) = (0, 0);
    while i < objects.len() {
        let info = &objects[i].info;
        out[k] = info.name;
        k += 1;
        let mut j = 0;
        while j < info.entries.len() {
            out[k] = info.entries[j].name;
            k += 1;
            j += 1;
        }
        i += 1;
    }
    assert!(k == COUNT);
    out
}

/// Whether two names have the same text.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The first name of `names` with the text of name `k`: `k` when it is new.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
const fn first(names: &[&str], k: usize) -> usize {
    let mut j = 0;
    while !same(names[j], names[k]) {
        j += 1;
    }
    j
}

/// Where the text `inner` first lies in the text `outer`, if it does.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
const fn find(outer: &str, inner: &str) -> Option<usize> {
    let (outer, inner) = (outer.as_bytes(), inner.as_bytes());
    let mut at = 0;
    while at + inner.len() <= outer.len() {
        let mut b = 0;
        while b < inner.len() && outer[at + b] == inner[b] {
            b += 1;
        }
        if b == inner.len() {
            return Some(at);
        }
        at += 1;
    }
    None
}

/// Whether the table keeps the text of name `k`: its first use, unless a longer name holds
/// it ("Output" in "Outputs"), which then names it too.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
const fn kept(names: &[&str], k: usize) -> bool {
    if first(names, k) != k {
        return false;
    }
    let mut m = 0;
    while m < names.len() {
        if names[m].len() > names[k].len() && find(names[m], names[k]).is_some() {
            return false;
        }
        m += 1;
    }
    true
}

/// The length of the table of `names`: every text once, none that another holds.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
pub const fn table_len(names: &[&str]) -> usize {
    let (mut k, mut len) = (0, 0);
    while k < names.len() {
        if kept(names, k) {
            len += names[k].len();
        }
        k += 1;
    }
    len
}

/// The table of `names` ([`table_len`] bytes): every text once, in order of first use, but
/// none that another name holds.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn table<const LEN: usize>(names: &[&str]) -> [u8; LEN] {
    let mut out = [0; LEN];
    let (mut k, mut at) = (0, 0);
    while k < names.len() {
        if kept(names, k) {
            let text = names[k].as_bytes();
            let mut b = 0;
            while b < text.len() {
                out[at] = text[b];
                at += 1;
                b += 1;
            }
        }
        k += 1;
    }
    out
}

/// Where each of `names` lies in its [`table`]: a kept name where it was put, any other in
/// the first kept name that holds its text.
#[allow(clippy::indexing_slicing, clippy::cast_possible_truncation)] // checked; compile time
pub const fn refs<const COUNT: usize>(names: &[&str]) -> [Name; COUNT] {
    let mut out = [Name::EMPTY; COUNT];
    let mut keep = [false; COUNT];
    let (mut k, mut at) = (0, 0);
    while k < names.len() {
        keep[k] = kept(names, k);
        let len = names[k].len();
        assert!(
            len <= 255 && at + len <= 0xFFFF,
            "a name has at most 255 bytes, all names of a dictionary at most 65 535"
        );
        if keep[k] {
            out[k] = Name::new(at as u16, len as u8);
            at += len;
        }
        k += 1;
    }
    k = 0;
    while k < names.len() {
        if !keep[k] {
            let mut j = 0;
            loop {
                if keep[j]
                    && let Some(within) = find(names[j], names[k])
                {
                    let (start, _) = out[j].parts();
                    out[k] = Name::new(start + within as u16, names[k].len() as u8);
                    break;
                }
                j += 1;
            }
        }
        k += 1;
    }
    out
}

/// The table as text: the names' texts one after the other (UTF-8, as each of them).
pub const fn text(table: &'static [u8]) -> &'static str {
    let text = core::str::from_utf8(table);
    assert!(text.is_ok(), "names are text");
    match text {
        Ok(text) => text,
        Err(_) => "",
    }
}

/// Whether two entry descriptions say the same.
const fn same_entry(a: &EntryInfo<&str>, b: &EntryInfo<&str>) -> bool {
    a.sub == b.sub
        && same(a.name, b.name)
        && a.data_type as u16 == b.data_type as u16
        && a.bit_len == b.bit_len
        && a.access.0 == b.access.0
        && a.limits.0 == b.limits.0
}

/// The first object of `objects` whose entries say what object `i`'s say: `i` when they are
/// new.
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
const fn first_like<D>(objects: &[Declaration<D>], i: usize) -> usize {
    let entries = objects[i].info.entries;
    let mut o = 0;
    'objects: while o < i {
        let other = objects[o].info.entries;
        if other.len() == entries.len() {
            let mut j = 0;
            while j < entries.len() {
                if !same_entry(&entries[j], &other[j]) {
                    o += 1;
                    continue 'objects;
                }
                j += 1;
            }
            return o;
        }
        o += 1;
    }
    i
}

/// The number of entry descriptions of `objects`, each object's once unless an earlier object
/// has the same.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
pub const fn entries_len<D>(objects: &[Declaration<D>]) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < objects.len() {
        if first_like(objects, i) == i {
            n += objects[i].info.entries.len();
        }
        i += 1;
    }
    n
}

/// The entry descriptions of `objects` ([`entries_len`] of them), the names `at` in their
/// [`table`] ([`refs`] of [`names`]).
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn entries<D, const LEN: usize>(
    objects: &[Declaration<D>],
    at: &[Name],
) -> [EntryInfo; LEN] {
    let mut out = [EntryInfo {
        sub: 0,
        name: Name::EMPTY,
        data_type: DataType::Unsigned8,
        bit_len: 0,
        access: Access(0),
        limits: Limits(0),
    }; LEN];
    let (mut i, mut k, mut n) = (0, 0, 0);
    while i < objects.len() {
        let entries = objects[i].info.entries;
        k += 1; // the object's name
        let new = first_like(objects, i) == i;
        let mut j = 0;
        while j < entries.len() {
            if new {
                let e = &entries[j];
                out[n] = EntryInfo {
                    sub: e.sub,
                    name: at[k],
                    data_type: e.data_type,
                    bit_len: e.bit_len,
                    access: e.access,
                    limits: e.limits,
                };
                n += 1;
            }
            k += 1;
            j += 1;
        }
        i += 1;
    }
    assert!(n == LEN);
    out
}

/// A stand-in the table of objects starts from (every one replaced).
fn no_read<D>(_: &D, _: At, _: &mut [u8]) -> Result<Read, AbortCode> {
    Err(AbortCode::NO_OBJECT)
}

/// The objects of the dictionary (`N`: all of `objects`): the names `at` in their [`table`],
/// the entries slices of [`entries`] (`all`).
#[allow(clippy::indexing_slicing)] // bounded by the loop conditions; evaluated at compile time
pub const fn objects<D, const N: usize>(
    objects: &[Declaration<D>],
    at: &[Name],
    all: &'static [EntryInfo],
) -> [Object<D>; N] {
    let mut out = [Object {
        info: ObjectInfo {
            index: 0,
            code: super::ObjectCode::Var,
            name: Name::EMPTY,
            max_sub: 0,
            entries: &[],
        },
        read: no_read::<D>,
        write: super::communication::read_only::<D>,
    }; N];
    let mut starts = [0; N];
    let (mut i, mut k, mut next) = (0, 0, 0);
    while i < N {
        let object = &objects[i];
        let count = object.info.entries.len();
        let like = first_like(objects, i);
        let start = if like == i {
            next += count;
            next - count
        } else {
            starts[like]
        };
        starts[i] = start;
        out[i] = Object {
            info: ObjectInfo {
                index: object.info.index,
                code: object.info.code,
                name: at[k],
                max_sub: object.info.max_sub,
                entries: all.split_at(start).1.split_at(count).0,
            },
            read: object.read,
            write: object.write,
        };
        k += 1 + count;
        i += 1;
    }
    assert!(next == all.len() && objects.len() == N);
    out
}
