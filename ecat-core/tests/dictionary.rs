//! The dictionary a `dictionary!` declaration produces: metadata from the field types, typed
//! access with range checks, declared limits, lookup.

use ecat_core::coe::AbortCode;
use ecat_core::dictionary::{
    Access, At, Bits, DataType, Limit, ObjectCode, ObjectDictionary, Read, VisibleString,
};

struct Identity {
    vendor_id: u32,
    product_code: u32,
}

struct Od {
    device_type: u32,
    name: VisibleString<8>,
    identity: Identity,
    flags: [bool; 3],
    mode: i8,
    level: Bits<3>,
    position: i32,
}

ecat_core::dictionary! {
    minimal Od {
        0x1000 => var(device_type, RO, "Device type", default = 0x0002_0192);
        0x1008 => var(name, RW, "Manufacturer device name", default = VisibleString::new(b"ecat"));
        0x1018 => record(identity: Identity, "Identity object") {
            1 => vendor_id, RO, "Vendor ID", default = 0xE000_0001;
            3 => product_code, RO, "Product code";
        };
        0x2000 => array(flags, RW | TXPDO, "Flags", "Flag", default = true);
        0x6060 => var(mode, RW | RXPDO, "Modes of operation", default = 8, min = -1, max = 10, unit = 0x0000);
        0x6061 => var(level, RW_PREOP, "Level");
        0x607A => var(position, RW | RXPDO | BACKUP, "Target position", min = -1000, max = 1000, unit = 0x0001);
    }
}

fn read(od: &Od, index: u16, sub: u8) -> Result<Vec<u8>, AbortCode> {
    let object = Od::object(index).ok_or(AbortCode::NO_OBJECT)?;
    let mut out = [0; 16];
    let read = (object.read)(od, At::start(sub), &mut out)?;
    let (copied, size) = (read.copied(), read.size());
    assert_eq!(copied, size);
    Ok(out[..copied].to_vec())
}

fn write(od: &mut Od, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
    let object = Od::object(index).ok_or(AbortCode::NO_OBJECT)?;
    (object.write)(od, sub, data)
}

#[test]
fn metadata_comes_from_the_field_types() {
    let o = Od::object(0x6060).unwrap();
    assert_eq!(
        (o.info.code, o.info.max_sub, Od::name(o.info.name)),
        (ObjectCode::Var, 0, "Modes of operation")
    );
    let e = o.info.entry(0).unwrap();
    assert_eq!(
        (e.data_type, e.bit_len, e.access),
        (DataType::Integer8, 8, Access(0x3F | 0x40))
    );
    assert!(o.info.entry(1).is_none());

    let level = Od::object(0x6061).unwrap().info.entry(0).unwrap();
    assert_eq!(
        (level.data_type, level.bit_len, level.access),
        (DataType::Bit3, 3, Access::RW_PREOP)
    );

    let name = Od::object(0x1008).unwrap().info.entry(0).unwrap();
    assert_eq!(
        (name.data_type, name.bit_len),
        (DataType::VisibleString, 64)
    );

    let array = Od::object(0x2000).unwrap().info;
    assert_eq!(
        (array.code, array.max_sub, array.data_type()),
        (ObjectCode::Array, 3, 0x0001)
    );
    assert_eq!(Od::name(array.entry(3).unwrap().name), "Flag");
    assert!(array.entry(4).is_none());
    assert_eq!(array.subindices().collect::<Vec<_>>(), [0, 1, 2, 3]);

    let record = Od::object(0x1018).unwrap().info;
    assert_eq!((record.code, record.max_sub), (ObjectCode::Record, 3));
    assert_eq!(record.subindices().collect::<Vec<_>>(), [0, 1, 3]);
    assert!(
        record.entry(2).is_none(),
        "a gap in a record does not exist"
    );
    assert_eq!(record.entry(0).unwrap().data_type, DataType::Unsigned8);

    let object = Od::object(0x607A).unwrap();
    let position = object.info.entry(0).unwrap();
    // The declared unit: flagged in the entry, its value from the object's `limit`.
    let mut unit = [0u8; 2];
    let unit_len = object.limit(0, Limit::Unit, &mut unit);
    assert!(position.limits.has(Limit::Unit));
    assert_eq!(
        (unit_len, unit, position.access.backup()),
        (2, [0x01, 0x00], true)
    );
    assert!(Od::object(0x1001).is_none());
}

#[test]
fn defaults_initialise_the_fields() {
    let od = Od::default();
    assert_eq!(od.device_type, 0x0002_0192);
    assert_eq!(od.name.as_bytes(), b"ecat");
    assert_eq!(
        (od.identity.vendor_id, od.identity.product_code),
        (0xE000_0001, 0)
    );
    assert_eq!(od.flags, [true; 3]);
    assert_eq!((od.mode, od.position), (8, 0));
}

#[test]
fn reads_encode_little_endian_and_si0() {
    let od = Od::default();
    assert_eq!(read(&od, 0x1000, 0), Ok(vec![0x92, 0x01, 0x02, 0x00]));
    assert_eq!(read(&od, 0x1008, 0), Ok(b"ecat".to_vec()));
    assert_eq!(
        read(&od, 0x1018, 0),
        Ok(vec![3]),
        "record SI0 = highest subindex"
    );
    assert_eq!(read(&od, 0x1018, 1), Ok(vec![0x01, 0, 0, 0xE0]));
    assert_eq!(read(&od, 0x1018, 2), Err(AbortCode::NO_SUBINDEX));
    assert_eq!(
        read(&od, 0x2000, 0),
        Ok(vec![3]),
        "array SI0 = number of elements"
    );
    assert_eq!(read(&od, 0x2000, 3), Ok(vec![1]));
    assert_eq!(read(&od, 0x2000, 4), Err(AbortCode::NO_SUBINDEX));
    assert_eq!(read(&od, 0x6060, 1), Err(AbortCode::NO_SUBINDEX));
}

#[test]
fn reads_stream_from_an_offset() {
    let od = Od::default();
    let object = Od::object(0x1008).unwrap();
    let mut out = [0; 3];
    assert_eq!(
        (object.read)(&od, At::new(0, 2), &mut out),
        Ok(Read::new(2, 4))
    );
    assert_eq!(&out[..2], b"at");
}

#[test]
fn writes_decode_check_the_range_and_store() {
    let mut od = Od::default();
    assert_eq!(write(&mut od, 0x607A, 0, &1000i32.to_le_bytes()), Ok(()));
    assert_eq!(od.position, 1000);
    assert_eq!(
        write(&mut od, 0x607A, 0, &1001i32.to_le_bytes()),
        Err(AbortCode::VALUE_TOO_HIGH)
    );
    assert_eq!(
        write(&mut od, 0x607A, 0, &(-1001i32).to_le_bytes()),
        Err(AbortCode::VALUE_TOO_LOW)
    );
    assert_eq!(od.position, 1000, "a refused value is not stored");
    assert_eq!(
        write(&mut od, 0x607A, 0, &[1, 2]),
        Err(AbortCode::LENGTH_TOO_LOW)
    );
    assert_eq!(write(&mut od, 0x6060, 0, &[0xFF]), Ok(()));
    assert_eq!(od.mode, -1);
    assert_eq!(
        write(&mut od, 0x6061, 0, &[8]),
        Err(AbortCode::VALUE_RANGE),
        "BIT3 holds 0..=7"
    );
    assert_eq!(
        write(&mut od, 0x1008, 0, b"toolongname"),
        Err(AbortCode::LENGTH_TOO_HIGH)
    );
    assert_eq!(write(&mut od, 0x1008, 0, b"ab"), Ok(()));
    assert_eq!(od.name.as_bytes(), b"ab");
    assert_eq!(write(&mut od, 0x2000, 2, &[0]), Ok(()));
    assert_eq!(od.flags, [true, false, true]);
    assert_eq!(write(&mut od, 0x2000, 0, &[2]), Err(AbortCode::READ_ONLY));
    assert_eq!(write(&mut od, 0x1018, 0, &[1]), Err(AbortCode::READ_ONLY));
    // A read-only VAR or ARRAY is never written (neither writable nor BACKUP): its write is
    // the shared refusal, with no decoding behind it.
    assert_eq!(
        write(&mut od, 0x1000, 0, &[0; 4]),
        Err(AbortCode::READ_ONLY)
    );
    assert_eq!(
        write(&mut od, 0x1000, 0, &[0; 9]),
        Err(AbortCode::READ_ONLY)
    );
    assert_eq!(od.device_type, 0x0002_0192);
}

#[test]
fn declared_limits_encode_in_the_entry_type() {
    let limit = |index: u16, sub: u8, which: Limit| {
        let mut out = [0; 8];
        let n = Od::object(index).unwrap().limit(sub, which, &mut out);
        out[..n].to_vec()
    };
    assert_eq!(limit(0x6060, 0, Limit::Default), [8]);
    assert_eq!(limit(0x6060, 0, Limit::Min), [0xFF]);
    assert_eq!(limit(0x6060, 0, Limit::Max), [10]);
    assert_eq!(limit(0x607A, 0, Limit::Min), (-1000i32).to_le_bytes());
    assert_eq!(
        limit(0x607A, 0, Limit::Default),
        Vec::<u8>::new(),
        "no default declared"
    );
    assert_eq!(limit(0x1018, 1, Limit::Default), [0x01, 0, 0, 0xE0]);
    assert_eq!(limit(0x2000, 2, Limit::Default), [1]);
    let info = Od::object(0x6060).unwrap().info.entry(0).unwrap().limits;
    assert!(info.has(Limit::Default) && info.has(Limit::Min) && info.has(Limit::Max));
    let info = Od::object(0x607A).unwrap().info.entry(0).unwrap().limits;
    assert!(!info.has(Limit::Default) && info.has(Limit::Min));
}

mod communication_item {
    use ecat_core::device::Identity;
    use ecat_core::dictionary::{
        Access, At, Communication, DeviceInfo, Limit, ObjectCode, ObjectDictionary,
    };
    use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};

    const INFO: DeviceInfo = DeviceInfo {
        device_type: 0x0001_1389,
        name: "ecat test",
        hardware_version: "B",
        software_version: "0.1.0",
        identity: Identity {
            vendor_id: 0xE000_0001,
            product_code: 0x0000_0402,
            revision: 7,
            serial: 0x1234_5678,
        },
    };

    struct Od {
        area: Communication,
        error_register: u8,
        rx: PdoMapping<1>,
        rx_assign: PdoAssignment<1>,
        tx_assign: PdoAssignment<1>,
        value: u8,
    }

    // The application's objects around the area's: 0x1001 between 0x1000 and 0x1008, the PDO
    // configuration between 0x1018 and 0x1C00 and between 0x1C00 and 0x1C32.
    ecat_core::dictionary! {
        Od {
            communication(area, INFO);
            0x1001 => var(error_register, RO, "Error register");
            0x1600 => pdo(rx, RO, "RxPDO", "Mapped object", default = PdoMapping::mapping(&[MappingEntry::new(0x7000, 0, 8)]));
            0x1C12 => pdo(rx_assign, RO, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
            0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[]));
            0x7000 => var(value, RW | RXPDO, "Value");
        }
    }

    fn read(od: &Od, index: u16, sub: u8) -> Vec<u8> {
        let object = Od::object(index).expect("present");
        let mut out = [0u8; 64];
        let read = (object.read)(od, At::start(sub), &mut out).unwrap();
        assert_eq!(read.copied(), read.size());
        out[..read.size()].to_vec()
    }

    fn default(index: u16, sub: u8) -> Vec<u8> {
        let object = Od::object(index).expect("present");
        let mut out = [0u8; 64];
        let n = object.limit(sub, Limit::Default, &mut out);
        out[..n].to_vec()
    }

    #[test]
    fn the_area_is_merged_in_index_order_with_the_application_objects() {
        let indices: Vec<u16> = Od::OBJECTS.iter().map(|o| o.info.index).collect();
        assert_eq!(
            indices,
            [
                0x1000, 0x1001, 0x1008, 0x1009, 0x100A, 0x1018, 0x1600, 0x1C00, 0x1C12, 0x1C13,
                0x1C32, 0x1C33, 0x7000
            ]
        );
    }

    /// The names are one table, each text once; a description keeps 3 bytes of it, and
    /// objects with the same entries (0x1C32/0x1C33, the assignments) share one slice of them.
    #[test]
    fn names_are_one_table_and_like_entries_one_slice() {
        for text in [
            "Highest sub-index supported",
            "Number of entries",
            "Assigned PDO",
        ] {
            assert_eq!(Od::NAMES.matches(text).count(), 1, "{text}");
        }
        let names: Vec<&str> = Od::OBJECTS
            .iter()
            .flat_map(|o| {
                let entries = o.info.entries.iter().map(|e| Od::name(e.name));
                core::iter::once(Od::name(o.info.name)).chain(entries)
            })
            .collect();
        // Every distinct name once, but none that a longer name holds ("Cycle time" in "Cycle
        // time too small counter"): the table is the other names' texts together.
        let mut distinct = names.clone();
        distinct.sort_unstable();
        distinct.dedup();
        let held = |n: &str| distinct.iter().any(|m| m.len() > n.len() && m.contains(n));
        let (inside, kept): (Vec<&str>, Vec<&str>) = distinct.iter().partition(|n| held(n));
        assert_eq!(inside, ["Cycle time", "Shift time", "Synchronization type"]);
        assert_eq!(Od::NAMES.len(), kept.iter().map(|n| n.len()).sum::<usize>());
        assert_eq!(names[..3], ["Device type", "Device type", "Error register"]);
        assert_eq!(Od::name(ecat_core::dictionary::Name::EMPTY), "");
        let entries = |index| Od::object(index).unwrap().info.entries;
        assert!(core::ptr::eq(entries(0x1C32), entries(0x1C33)));
        assert!(core::ptr::eq(entries(0x1C12), entries(0x1C13)));
        assert!(!core::ptr::eq(entries(0x1C12), entries(0x1600)));
        assert_eq!(size_of::<ecat_core::dictionary::Name>(), 3);
        assert_eq!(size_of::<ecat_core::dictionary::EntryInfo>(), 10);
    }

    #[test]
    fn constants_come_from_the_device_info_read_only_with_their_defaults() {
        let od = Od::default();
        for (index, name, code, value) in [
            (0x1000, "Device type", 0x0007, &[0x89, 0x13, 0x01, 0x00][..]),
            (0x1008, "Manufacturer device name", 0x0009, b"ecat test"),
            (0x1009, "Manufacturer hardware version", 0x0009, b"B"),
            (0x100A, "Manufacturer software version", 0x0009, b"0.1.0"),
        ] {
            let info = &Od::object(index).unwrap().info;
            assert_eq!(
                (info.code, Od::name(info.name), info.max_sub),
                (ObjectCode::Var, name, 0)
            );
            let entry = info.entry(0).unwrap();
            assert_eq!(
                (entry.data_type.code(), entry.bit_len, entry.access),
                (code, value.len() as u16 * 8, Access::RO),
                "{index:#06x}"
            );
            assert_eq!(read(&od, index, 0), value, "{index:#06x}");
            assert_eq!(default(index, 0), value, "{index:#06x} declares its value");
        }
        // 0x1C00: mailbox out, mailbox in, outputs, inputs.
        let info = &Od::object(0x1C00).unwrap().info;
        assert_eq!((info.code, info.max_sub), (ObjectCode::Array, 4));
        let types: Vec<Vec<u8>> = (0..=4).map(|s| read(&od, 0x1C00, s)).collect();
        assert_eq!(types, [[4], [1], [2], [3], [4]]);
        assert_eq!(default(0x1C00, 3), [3]);
    }

    #[test]
    fn identity_is_the_standard_record_initialised_from_the_constant() {
        let object = Od::object(0x1018).expect("0x1018");
        assert_eq!(object.info.code, ObjectCode::Record);
        assert_eq!(Od::name(object.info.name), "Identity object");
        assert_eq!(object.info.max_sub, 4);
        let names: Vec<_> = (1..=4)
            .map(|s| Od::name(object.info.entry(s).unwrap().name))
            .collect();
        assert_eq!(
            names,
            [
                "Vendor ID",
                "Product code",
                "Revision number",
                "Serial number"
            ]
        );
        assert!((1..=4).all(|s| object.info.entry(s).unwrap().access == Access::RO));
        let mut od = Od::default();
        assert_eq!(od.area.identity, INFO.identity);
        assert_eq!(read(&od, 0x1018, 0), [4]);
        assert_eq!(read(&od, 0x1018, 3), [7, 0, 0, 0]);
        assert_eq!(default(0x1018, 4), [0x78, 0x56, 0x34, 0x12], "the constant");
        // The application sets the serial number at start-up; the default stays the constant.
        od.area.identity.serial = 42;
        assert_eq!(read(&od, 0x1018, 4), [42, 0, 0, 0]);
        assert_eq!(default(0x1018, 4), [0x78, 0x56, 0x34, 0x12]);
        assert_eq!(
            (object.write)(&mut od, 4, &[1, 0, 0, 0]),
            Err(ecat_core::coe::AbortCode::READ_ONLY)
        );
    }

    #[test]
    fn sync_parameters_are_ssc_records_with_the_defaults_of_each_direction() {
        let od = Od::default();
        assert_eq!(
            (
                od.area
                    .outputs
                    .get(ecat_core::sync_parameters::SyncParameters::SYNC_TYPE),
                od.area
                    .inputs
                    .get(ecat_core::sync_parameters::SyncParameters::SYNC_TYPE)
            ),
            (1, 0x22)
        );
        for (index, name, si1) in [
            (0x1C32, "SM output parameter", Access::RW_PREOP),
            (0x1C33, "SM input parameter", Access::RW_PREOP),
        ] {
            let object = Od::object(index).expect("declared");
            assert_eq!(object.info.code, ObjectCode::Record);
            assert_eq!(Od::name(object.info.name), name);
            let subs: Vec<u8> = object.info.subindices().collect();
            // SSC's record: SI 1..0x0D and 0x20, SI0 = 0x20 (ETG.1000.6 Table 74).
            assert_eq!(
                subs,
                [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0x0A, 0x0B, 0x0C, 0x0D, 0x20]
            );
            assert_eq!(object.info.max_sub, 0x20);
            let described: Vec<_> = subs
                .iter()
                .map(|&s| {
                    let e = object.info.entry(s).unwrap();
                    (s, e.data_type.code(), e.bit_len, e.access.0)
                })
                .collect();
            assert_eq!(
                described,
                [
                    (0, 0x0005, 8, 0x0007),
                    (1, 0x0006, 16, si1.0),
                    (2, 0x0007, 32, 0x000F),
                    (3, 0x0007, 32, 0x0007),
                    (4, 0x0006, 16, 0x0007),
                    (5, 0x0007, 32, 0x0007),
                    (6, 0x0007, 32, 0x0007),
                    (7, 0x0007, 32, 0x0007),
                    (8, 0x0006, 16, 0x003F),
                    (9, 0x0007, 32, 0x0007),
                    (0x0A, 0x0007, 32, 0x0007),
                    (0x0B, 0x0006, 16, 0x0007),
                    (0x0C, 0x0006, 16, 0x0007),
                    (0x0D, 0x0006, 16, 0x0007),
                    (0x20, 0x0001, 1, 0x0007),
                ]
            );
            assert_eq!(object.info.entry(0x0E), None, "the gap 0x0E..0x1F");
            assert_eq!(object.info.entry(0x1F), None);
            let mut od = Od::default();
            let mut out = [0xAA; 4];
            assert_eq!(
                (object.read)(&od, At::start(0), &mut out).unwrap().copied(),
                1
            );
            assert_eq!(out[0], 0x20, "SI0");
            // SI8 (get cycle time) takes a command word and keeps it; 0 by default.
            assert_eq!(
                (object.read)(&od, At::start(8), &mut out).unwrap().size(),
                2
            );
            assert_eq!(out[..2], [0, 0]);
            (object.write)(&mut od, 8, &[0x01, 0x00]).unwrap();
            (object.read)(&od, At::start(8), &mut out).unwrap();
            assert_eq!(out[..2], [0x01, 0x00]);
            assert_eq!(
                (object.write)(&mut od, 0x0E, &[0, 0]),
                Err(ecat_core::coe::AbortCode::NO_SUBINDEX)
            );
            let mut out = [0u8; 2];
            assert_eq!(
                object.limit(1, Limit::Default, &mut out),
                2,
                "SI1 declares its default"
            );
        }
    }
}

#[test]
fn a_read_keeps_both_halves_up_to_the_largest_entry() {
    let read = Read::new(3, 8191);
    assert_eq!((read.copied(), read.size()), (3, 8191));
    let full = Read::new(0xFFFF, 0xFFFF);
    assert_eq!((full.copied(), full.size()), (0xFFFF, 0xFFFF));
    assert_eq!((Read::new(0, 0).copied(), Read::new(0, 0).size()), (0, 0));
}
