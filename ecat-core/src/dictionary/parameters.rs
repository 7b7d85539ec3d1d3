//! Stored parameters: 0x1010 "store parameters" and 0x1011 "restore default parameters" (CiA 301
//! §7.5.2.13/14, ETG.1000.6 §5.6.7.1), and the backup record they store.
//!
//! A device declares storage with `communication(area, INFO, stored = field)` in
//! [`dictionary!`](crate::dictionary!), `field` a [`StoredParameters`]: the two objects then
//! appear in its communication area. Each is an ARRAY of one UNSIGNED32 ("all parameters"; no
//! groups):
//!
//! | entry | read | write |
//! |---|---|---|
//! | 0x1010:01 | 1: stores on command (bit 0), not autonomously (bit 1 = 0) | "save" (0x65766173): store every backup entry |
//! | 0x1011:01 | 1: restores defaults on command | "load" (0x64616F6C): defaults at the next reset |
//!
//! Any other value is refused with 0x08000020 "data cannot be stored" (CiA 301's code for a
//! wrong signature). A "load" takes effect at the next reset or power-up, as CiA 301 words it
//! (the values in RAM stay until then): it stores an empty record.
//!
//! The SDO write only records the [`Command`]; the firmware's storage
//! (`ecat_embassy::storage`) takes it right after the request is served and performs it before
//! the answer is sent, as SSC answers after storing.
//!
//! What is stored: every entry whose access has [`Access::BACKUP`] (ETG.2000 `Backup`, SSC's
//! `ACCESS_BACKUP`), walked once in index order and serialized by [`save`] into a compact record:
//! a format byte, then per entry index (UNSIGNED16 LE), subindex, length and the encoded value.
//! [`load`] writes each back through the entry's typed writer and its range check: an entry the
//! firmware no longer has, no longer backs up, or whose value it refuses (out of range after a
//! firmware update) is skipped and counted ([`Loaded::skipped`]), never applied.

use super::{
    Access, At, DataType, EntryInfo, Limits, ObjectCode, ObjectDictionary, ObjectInfo, Read,
};
use super::{read_value, write_value};
use crate::abort::AbortCode;

/// The signature that stores: "save" in ASCII, little-endian (CiA 301 §7.5.2.13).
pub const SAVE: u32 = 0x6576_6173;
/// The signature that restores the defaults: "load" (CiA 301 §7.5.2.14).
pub const LOAD: u32 = 0x6461_6F6C;
/// 0x1010:01 and 0x1011:01 read: bit 0, the device stores (restores) on command.
pub const ON_COMMAND: u32 = 1;
/// The first byte of a record: its format.
pub const FORMAT: u8 = 1;
/// Bytes a record spends per entry before the value: index, subindex, length.
pub const ENTRY_HEADER: usize = 4;

/// What a signature asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// "save" to 0x1010:01: store every backup entry.
    Save,
    /// "load" to 0x1011:01: the defaults at the next reset.
    RestoreDefaults,
}

/// The dictionary field of a device with storage: the command waiting for the firmware's
/// storage, and what the last load did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StoredParameters {
    /// The command written and not yet taken.
    pub request: Option<Command>,
    /// What the load at start-up did.
    pub loaded: Loaded,
}

impl StoredParameters {
    /// No command, nothing loaded.
    pub const fn new() -> Self {
        Self {
            request: None,
            loaded: Loaded {
                applied: 0,
                skipped: 0,
            },
        }
    }

    /// Takes the command written since the last call.
    pub fn take(&mut self) -> Option<Command> {
        self.request.take()
    }

    /// Reads 0x1010 or 0x1011: SI0 1, SI1 [`ON_COMMAND`].
    #[doc(hidden)]
    pub fn read(at: At, out: &mut [u8]) -> Result<Read, AbortCode> {
        let offset = at.offset();
        match at.sub() {
            0 => Ok(read_value(&1u8, offset, out)),
            1 => Ok(read_value(&ON_COMMAND, offset, out)),
            _ => Err(AbortCode::NO_SUBINDEX),
        }
    }

    /// Writes 0x1010:01 (`command` [`Command::Save`], signature [`SAVE`]) or 0x1011:01
    /// ([`Command::RestoreDefaults`], [`LOAD`]).
    #[doc(hidden)]
    pub fn write(&mut self, command: Command, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let expected = match command {
            Command::Save => SAVE,
            Command::RestoreDefaults => LOAD,
        };
        let mut signature = 0u32;
        match sub {
            0 => return Err(AbortCode::READ_ONLY),
            1 => write_value(&mut signature, data, None, None)?,
            _ => return Err(AbortCode::NO_SUBINDEX),
        }
        if signature != expected {
            return Err(AbortCode::CANNOT_STORE);
        }
        self.request = Some(command);
        Ok(())
    }
}

/// What [`load`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Loaded {
    /// Entries written back.
    pub applied: u16,
    /// Entries skipped: unknown, no longer backed up, refused by their writer, or cut short.
    pub skipped: u16,
}

/// SI0 and SI1 of 0x1010 or 0x1011: one UNSIGNED32, readable and writable in every state with
/// a mailbox.
const fn entries(element: &'static str) -> [EntryInfo<&'static str>; 2] {
    [
        EntryInfo::subindex_count("Highest sub-index supported"),
        EntryInfo {
            sub: 1,
            name: element,
            data_type: DataType::Unsigned32,
            bit_len: 32,
            access: Access::RW,
            limits: Limits(0),
        },
    ]
}

const STORE_ENTRIES: [EntryInfo<&'static str>; 2] = entries("Save all parameters");
const RESTORE_ENTRIES: [EntryInfo<&'static str>; 2] = entries("Restore all default parameters");

/// 0x1010, an ARRAY of one entry: all parameters.
pub const STORE: ObjectInfo<&'static str> = ObjectInfo {
    index: 0x1010,
    code: ObjectCode::Array,
    name: "Store parameters",
    max_sub: 1,
    entries: &STORE_ENTRIES,
};

/// 0x1011, an ARRAY of one entry: all parameters.
pub const RESTORE: ObjectInfo<&'static str> = ObjectInfo {
    index: 0x1011,
    code: ObjectCode::Array,
    name: "Restore default parameters",
    max_sub: 1,
    entries: &RESTORE_ENTRIES,
};

/// Why [`save`] made no record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveError {
    /// The record does not fit the buffer: [`record_size`] bytes are needed.
    TooSmall,
    /// A backup entry's value is longer than 255 bytes.
    TooLong,
}

/// Each backup entry of `D`: its object and subindex, in index order.
fn backup_entries<D: ObjectDictionary>() -> impl Iterator<Item = (&'static super::Object<D>, u8)> {
    D::OBJECTS.iter().flat_map(|object| {
        (0..=object.info.max_sub)
            .filter(move |&sub| object.info.entry(sub).is_some_and(|e| e.access.backup()))
            .map(move |sub| (object, sub))
    })
}

/// The size of the record of `D`'s backup entries with every value at its capacity (strings at
/// their declared length): a buffer this large always holds [`save`]'s record.
pub fn record_size<D: ObjectDictionary>() -> usize {
    backup_entries::<D>().fold(1, |size, (object, sub)| {
        let bits = object.info.entry(sub).map_or(0, |e| usize::from(e.bit_len));
        size + ENTRY_HEADER + bits.div_ceil(8)
    })
}

/// Serializes every backup entry of `od` into `out`; returns the record's length.
pub fn save<D: ObjectDictionary>(od: &D, out: &mut [u8]) -> Result<usize, SaveError> {
    let (first, mut rest) = out.split_first_mut().ok_or(SaveError::TooSmall)?;
    *first = FORMAT;
    let mut len = 1;
    for (object, sub) in backup_entries::<D>() {
        let (header, value) = rest
            .split_at_mut_checked(ENTRY_HEADER)
            .ok_or(SaveError::TooSmall)?;
        let read = (object.read)(od, At::start(sub), value).map_err(|_| SaveError::TooSmall)?;
        if read.copied() < read.size() {
            return Err(SaveError::TooSmall);
        }
        let size = u8::try_from(read.size()).map_err(|_| SaveError::TooLong)?;
        let [i0, i1] = object.info.index.to_le_bytes();
        header.copy_from_slice(&[i0, i1, sub, size]);
        let entry = ENTRY_HEADER + read.size();
        rest = rest.get_mut(entry..).ok_or(SaveError::TooSmall)?;
        len += entry;
    }
    Ok(len)
}

/// Writes the entries of `record` (made by [`save`], possibly by an older firmware) back into
/// `od`, each through its typed writer; counts what it applied and skipped. An empty record
/// (after "load") or one of another format applies nothing.
pub fn load<D: ObjectDictionary>(od: &mut D, record: &[u8]) -> Loaded {
    let mut loaded = Loaded::default();
    let Some((&FORMAT, mut rest)) = record.split_first() else {
        return loaded;
    };
    while let Some(([i0, i1, sub, size], after)) = rest.split_first_chunk::<ENTRY_HEADER>() {
        let Some((value, next)) = after.split_at_checked(usize::from(*size)) else {
            break;
        };
        rest = next;
        let index = u16::from_le_bytes([*i0, *i1]);
        let applied = D::object(index)
            .filter(|o| o.info.entry(*sub).is_some_and(|e| e.access.backup()))
            .is_some_and(|o| (o.write)(od, *sub, value).is_ok());
        if applied {
            loaded.applied = loaded.applied.saturating_add(1);
        } else {
            loaded.skipped = loaded.skipped.saturating_add(1);
        }
    }
    if !rest.is_empty() {
        // Cut short: the last entry is incomplete.
        loaded.skipped = loaded.skipped.saturating_add(1);
    }
    loaded
}

/// `const` check: none of `objects` (an application's own) is 0x1010 or 0x1011.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
pub const fn leaves_storage<D, S>(objects: &[super::Object<D, S>]) -> bool {
    let mut i = 0;
    while i < objects.len() {
        let index = objects[i].info.index;
        if index == STORE.index || index == RESTORE.index {
            return false;
        }
        i += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::Identity;
    use crate::dictionary::{Communication, DeviceInfo, VisibleString};
    use crate::pdo::PdoAssignment;

    const INFO: DeviceInfo = DeviceInfo {
        device_type: 0,
        name: "t",
        hardware_version: "1",
        software_version: "1",
        identity: Identity {
            vendor_id: 1,
            product_code: 2,
            revision: 3,
            serial: 4,
        },
    };

    struct Limits2 {
        min: i32,
        max: i32,
    }

    struct Od {
        area: Communication,
        params: StoredParameters,
        rx_assign: PdoAssignment<1>,
        tx_assign: PdoAssignment<1>,
        gain: u16,
        scratch: u16,
        gains: [i16; 3],
        limits: Limits2,
        name: VisibleString<8>,
    }

    crate::dictionary! {
        Od {
            communication(area, INFO, stored = params);
            0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "PDO");
            0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 PDO assignment", "PDO");
            0x2000 => var(gain, RW | BACKUP, "Gain", default = 7, max = 1000);
            0x2001 => var(scratch, RW, "Not backed up");
            0x2002 => array(gains, RW | BACKUP, "Gains", "Gain", min = -100, max = 100);
            0x2003 => record(limits: Limits2, "Limits") {
                1 => min, RW | BACKUP, "Min";
                2 => max, RW, "Max";
            };
            0x2004 => var(name, RW | BACKUP, "Name");
        }
    }

    fn write(od: &mut Od, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let object = Od::object(index).ok_or(AbortCode::NO_OBJECT)?;
        (object.write)(od, sub, data)
    }

    fn read(od: &Od, index: u16, sub: u8) -> ([u8; 4], usize) {
        let mut out = [0u8; 4];
        let object = Od::object(index).unwrap();
        let r = (object.read)(od, At::start(sub), &mut out).unwrap();
        (out, r.size())
    }

    #[test]
    fn the_area_has_0x1010_and_0x1011_reading_on_command() {
        let od = Od::default();
        assert_eq!(read(&od, 0x1010, 0), ([1, 0, 0, 0], 1));
        assert_eq!(read(&od, 0x1010, 1), ([1, 0, 0, 0], 4));
        assert_eq!(read(&od, 0x1011, 1), ([1, 0, 0, 0], 4));
        let indices = Od::OBJECTS.iter().map(|o| o.info.index);
        assert!(
            indices
                .take(7)
                .eq([0x1000, 0x1008, 0x1009, 0x100A, 0x1010, 0x1011, 0x1018])
        );
    }

    #[test]
    fn signatures_record_commands_and_others_abort_0x08000020() {
        let mut od = Od::default();
        assert_eq!(
            write(&mut od, 0x1010, 1, b"load"),
            Err(AbortCode::CANNOT_STORE)
        );
        assert_eq!(
            write(&mut od, 0x1011, 1, b"save"),
            Err(AbortCode::CANNOT_STORE)
        );
        assert_eq!(
            write(&mut od, 0x1010, 1, &[0, 0, 0, 0]),
            Err(AbortCode::CANNOT_STORE)
        );
        assert_eq!(od.params.take(), None);
        assert_eq!(write(&mut od, 0x1010, 1, b"save"), Ok(()));
        assert_eq!(od.params.take(), Some(Command::Save));
        assert_eq!(write(&mut od, 0x1011, 1, b"load"), Ok(()));
        assert_eq!(od.params.take(), Some(Command::RestoreDefaults));
        assert_eq!(od.params.take(), None);
        assert_eq!(
            write(&mut od, 0x1010, 2, b"save"),
            Err(AbortCode::NO_SUBINDEX)
        );
        assert_eq!(SAVE.to_le_bytes(), *b"save");
        assert_eq!(LOAD.to_le_bytes(), *b"load");
    }

    #[test]
    fn save_writes_exactly_the_backup_entries_and_load_restores_them() {
        let od = Od {
            gain: 300,
            scratch: 9,
            gains: [-5, 6, 7],
            limits: Limits2 { min: -42, max: 42 },
            name: VisibleString::new(b"abc"),
            ..Od::default()
        };
        let mut buf = [0u8; 64];
        let len = save(&od, &mut buf).unwrap();
        #[rustfmt::skip]
        let expected: &[u8] = &[
            FORMAT,
            0x00, 0x20, 0, 2, 0x2C, 0x01,
            0x02, 0x20, 1, 2, 0xFB, 0xFF,
            0x02, 0x20, 2, 2, 6, 0,
            0x02, 0x20, 3, 2, 7, 0,
            0x03, 0x20, 1, 4, 0xD6, 0xFF, 0xFF, 0xFF,
            0x04, 0x20, 0, 3, b'a', b'b', b'c',
        ];
        assert_eq!(&buf[..len], expected);
        assert!(record_size::<Od>() >= len);
        assert_eq!(save(&od, &mut buf[..len - 1]), Err(SaveError::TooSmall));

        let mut fresh = Od::default();
        assert_eq!(
            load(&mut fresh, &buf[..len]),
            Loaded {
                applied: 6,
                skipped: 0
            }
        );
        assert_eq!(
            (fresh.gain, fresh.gains, fresh.limits.min),
            (300, [-5, 6, 7], -42)
        );
        assert_eq!((fresh.scratch, fresh.limits.max), (0, 0));
        assert_eq!(fresh.name.as_bytes(), b"abc");
    }

    #[test]
    fn load_skips_and_counts_what_this_firmware_refuses() {
        let mut od = Od::default();
        #[rustfmt::skip]
        let record: &[u8] = &[
            FORMAT,
            0x00, 0x20, 0, 2, 0xE9, 0x03, // 1001 > max 1000
            0x01, 0x20, 0, 2, 1, 0,       // not backed up
            0x99, 0x20, 0, 1, 1,          // no such object
            0x02, 0x20, 9, 2, 1, 0,       // no such subindex
            0x02, 0x20, 1, 2, 50, 0,      // applied
            0x02, 0x20, 2, 4, 1,          // cut short
        ];
        assert_eq!(
            load(&mut od, record),
            Loaded {
                applied: 1,
                skipped: 5
            }
        );
        assert_eq!((od.gain, od.scratch, od.gains), (7, 0, [50, 0, 0]));
        assert_eq!(load(&mut od, &[]), Loaded::default());
        assert_eq!(
            load(&mut od, &[FORMAT + 1, 0, 0x20, 0, 2, 1, 0]),
            Loaded::default()
        );
    }
}
