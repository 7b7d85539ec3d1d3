//! The size of the buffer a segmented download (ETG.1000.6 §5.6.2.3) is gathered in: a value
//! that does not come whole with its initiate waits there segment by segment and is stored at
//! the last one, so that a refused value leaves the entry as it was. The buffer need not be
//! larger than the largest value the dictionary can store ([`largest_download`]), a
//! compile-time constant of the dictionary
//! ([`ObjectDictionary::Download`](crate::dictionary::ObjectDictionary::Download)), which
//! `ecat-embassy` sizes the SubDevice's [`SdoServer`](super::SdoServer) by.

use crate::dictionary::{DataType, Object, ObjectCode};

/// The most bytes a download stores into one of `objects` (DOMAINs aside: they stream to the
/// application): the longest entry with a write right (a string's capacity), or the
/// complete-access image of an object whose every entry from SI1 on has one. An image is
/// counted a byte per entry (a BOOL or BITn entry packs into fewer bits): a bound, not the
/// exact size, so that the layout's rules stay in one place
/// ([`complete_access`](super::complete_access)).
pub const fn largest_download<D>(objects: &[Object<D>]) -> usize {
    let mut largest = 0;
    let mut objects = objects;
    while let [object, rest @ ..] = objects {
        objects = rest;
        let info = &object.info;
        // The complete-access image: SI0 and its padding byte, then SI1..=max_sub, the last
        // description standing for the subindices above its own.
        let mut image = 2;
        let mut complete = !matches!(info.code, ObjectCode::Var) && info.entries.len() > 1;
        let mut entries = info.entries;
        while let [entry, rest @ ..] = entries {
            entries = rest;
            let bytes = entry.bit_len.div_ceil(8) as usize;
            let writable = entry.access.writable();
            if writable && !matches!(entry.data_type, DataType::Domain) {
                largest = max(largest, bytes);
            }
            if entry.sub > 0 {
                complete = complete && writable && !entry.data_type.is_variable_length();
                let covers = match rest.is_empty() {
                    true => (info.max_sub as usize + 1).saturating_sub(entry.sub as usize),
                    false => 1,
                };
                image += covers * bytes;
            }
        }
        if complete {
            largest = max(largest, image);
        }
    }
    largest
}

const fn max(a: usize, b: usize) -> usize {
    if a > b { a } else { b }
}
