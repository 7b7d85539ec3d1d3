//! PDO mapping and assignment: the configuration write rules, the image layout, and bit-exact
//! pack/unpack against a reference model (ETG.1000.6 §5.6.7, conformance.md "CoE SDO").

use ecat_core::AlStatusCode;
use ecat_core::coe::AbortCode;
use ecat_core::dictionary::{Bits, ObjectDictionary};
use ecat_core::pdo::image::{pack, unpack};
use ecat_core::pdo::layout::Layout;
use ecat_core::pdo::{Direction, MappingEntry, PdoAssignment, PdoMapping};
use proptest::prelude::*;

struct Od {
    controlword: u16,
    target_position: i32,
    target_velocity: i32,
    mode: i8,
    statusword: u16,
    position: i32,
    velocity: i32,
    mode_display: i8,
    flag: bool,
    level: Bits<3>,
    small: u8,
    name: u32,
    word: u16,
    long: i32,
    rx1: PdoMapping<8>,
    tx1: PdoMapping<8>,
    rx_assign: PdoAssignment<2>,
    tx_assign: PdoAssignment<2>,
}

const RX: [MappingEntry; 4] = [
    MappingEntry::new(0x6040, 0, 16),
    MappingEntry::new(0x607A, 0, 32),
    MappingEntry::new(0x60FF, 0, 32),
    MappingEntry::new(0x6060, 0, 8),
];
const TX: [MappingEntry; 4] = [
    MappingEntry::new(0x6041, 0, 16),
    MappingEntry::new(0x6064, 0, 32),
    MappingEntry::new(0x606C, 0, 32),
    MappingEntry::new(0x6061, 0, 8),
];

ecat_core::dictionary! {
    Od {
        0x1600 => pdo(rx1, RW_PREOP, "RxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&RX));
        0x1A00 => pdo(tx1, RW_PREOP, "TxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&TX));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x2000 => var(flag, RW | TXPDO | RXPDO, "Flag");
        0x2001 => var(level, RW | TXPDO | RXPDO, "Level");
        0x2002 => var(small, RW | TXPDO | RXPDO, "Small");
        0x2003 => var(name, RW, "Not mappable");
        0x2004 => var(word, RW | TXPDO | RXPDO, "Word");
        0x2005 => var(long, RW | TXPDO | RXPDO, "Long");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword");
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
        0x6064 => var(position, RO | TXPDO, "Position actual value");
        0x606C => var(velocity, RO | TXPDO, "Velocity actual value");
        0x607A => var(target_position, RW | RXPDO, "Target position");
        0x60FF => var(target_velocity, RW | RXPDO, "Target velocity");
    }
}

fn write(od: &mut Od, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
    (Od::object(index).unwrap().write)(od, sub, data)
}

#[test]
fn configuration_write_rules() {
    let mut od = Od::default();
    let entry = |e: MappingEntry| e.0.to_le_bytes();
    assert_eq!(
        write(&mut od, 0x1600, 1, &entry(RX[0])),
        Err(AbortCode::SI0_NOT_ZERO),
        "SI0 must be 0 first"
    );
    assert_eq!(
        write(&mut od, 0x1600, 0, &[9]),
        Err(AbortCode::VALUE_TOO_HIGH),
        "capacity 8"
    );
    assert_eq!(write(&mut od, 0x1600, 0, &[0]), Ok(()));
    assert_eq!(
        write(&mut od, 0x1600, 1, &entry(MappingEntry::new(0x2003, 0, 32))),
        Err(AbortCode::NOT_MAPPABLE),
        "not mappable"
    );
    assert_eq!(
        write(&mut od, 0x1600, 1, &entry(MappingEntry::new(0x6041, 0, 16))),
        Err(AbortCode::NOT_MAPPABLE),
        "a TxPDO entry in an RxPDO"
    );
    assert_eq!(
        write(&mut od, 0x1600, 1, &entry(MappingEntry::new(0x6040, 0, 8))),
        Err(AbortCode::NOT_MAPPABLE),
        "wrong bit length"
    );
    assert_eq!(
        write(&mut od, 0x1600, 1, &entry(MappingEntry::new(0x7000, 0, 8))),
        Err(AbortCode::NOT_MAPPABLE),
        "no such object"
    );
    assert_eq!(
        write(&mut od, 0x1600, 9, &entry(RX[0])),
        Err(AbortCode::NO_SUBINDEX)
    );
    assert_eq!(
        write(&mut od, 0x1600, 1, &entry(MappingEntry::new(0, 0, 5))),
        Ok(()),
        "a 5-bit gap"
    );
    assert_eq!(
        write(&mut od, 0x1600, 2, &entry(MappingEntry::new(0x2001, 0, 3))),
        Ok(())
    );
    assert_eq!(write(&mut od, 0x1600, 0, &[2]), Ok(()));
    assert_eq!(
        od.rx1.mapped().collect::<Vec<_>>(),
        [MappingEntry::new(0, 0, 5), MappingEntry::new(0x2001, 0, 3)]
    );

    assert_eq!(
        write(&mut od, 0x1C12, 1, &0x1600u16.to_le_bytes()),
        Err(AbortCode::SI0_NOT_ZERO)
    );
    assert_eq!(write(&mut od, 0x1C12, 0, &[0]), Ok(()));
    assert_eq!(
        write(&mut od, 0x1C12, 1, &0x1A00u16.to_le_bytes()),
        Err(AbortCode::VALUE_RANGE),
        "TxPDO into SM2"
    );
    assert_eq!(
        write(&mut od, 0x1C12, 1, &0x1601u16.to_le_bytes()),
        Err(AbortCode::VALUE_RANGE),
        "no such PDO"
    );
    assert_eq!(write(&mut od, 0x1C12, 1, &0x1600u16.to_le_bytes()), Ok(()));
    assert_eq!(
        write(&mut od, 0x1C12, 0, &[3]),
        Err(AbortCode::VALUE_TOO_HIGH)
    );
    assert_eq!(
        write(&mut od, 0x1C12, 0, &[1, 0]),
        Err(AbortCode::LENGTH_TOO_HIGH)
    );
}

#[test]
fn cia402_like_layout_is_11_bytes_each_way() {
    let od = Od::default();
    let rx = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    assert_eq!((rx.bytes(), tx.bytes()), (11, 11));
    let offsets: Vec<(u16, u8)> = rx
        .slots()
        .iter()
        .map(|s| (s.bit_offset, s.bit_len))
        .collect();
    assert_eq!(offsets, [(0, 16), (16, 32), (48, 32), (80, 8)]);
}

#[test]
fn an_unusable_mapping_is_0x0025_or_0x0024() {
    let mut od = Od {
        rx_assign: PdoAssignment::assignment(&[0x1601]),
        ..Od::default()
    };
    assert!(matches!(
        Layout::of(&od, Direction::Rx),
        Err(AlStatusCode::INVALID_OUTPUT_MAPPING)
    ));
    od.tx1 = PdoMapping::mapping(&[MappingEntry::new(0x6040, 0, 16)]);
    assert!(
        matches!(
            Layout::of(&od, Direction::Tx),
            Err(AlStatusCode::INVALID_INPUT_MAPPING)
        ),
        "an RxPDO entry in a TxPDO"
    );
}

#[test]
fn pack_and_unpack_the_cia402_image() {
    let mut od = Od {
        statusword: 0x0237,
        position: -5,
        velocity: 0x0102_0304,
        mode_display: 8,
        ..Od::default()
    };
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    let mut image = [0xAA; 11];
    pack(&tx, &od, &mut image);
    assert_eq!(
        image,
        [
            0x37, 0x02, 0xFB, 0xFF, 0xFF, 0xFF, 0x04, 0x03, 0x02, 0x01, 0x08
        ]
    );
    let rx = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    unpack(
        &rx,
        &[0x0F, 0x00, 0x10, 0x27, 0, 0, 0xF0, 0xD8, 0xFF, 0xFF, 0x09],
        &mut od,
    );
    assert_eq!(
        (
            od.controlword,
            od.target_position,
            od.target_velocity,
            od.mode
        ),
        (0x000F, 10_000, -10_000, 9)
    );
}

/// The entries a property case may map, both ways: (index, bit length).
const ENTRIES: [(u16, u8); 5] = [
    (0x2000, 1),
    (0x2001, 3),
    (0x2002, 8),
    (0x2004, 16),
    (0x2005, 32),
];

fn set(od: &mut Od, index: u16, v: u64) {
    match index {
        0x2000 => od.flag = v & 1 == 1,
        0x2001 => od.level = Bits::new(v as u8),
        0x2002 => od.small = v as u8,
        0x2004 => od.word = v as u16,
        _ => od.long = v as i32,
    }
}

fn get(od: &Od, index: u16) -> u64 {
    match index {
        0x2000 => u64::from(od.flag),
        0x2001 => u64::from(od.level.get()),
        0x2002 => u64::from(od.small),
        0x2004 => u64::from(od.word),
        _ => u64::from(od.long as u32),
    }
}

proptest! {
    /// Random mappings of BOOL, BIT3, bytes, words and gaps at any bit offset: the packed image
    /// holds every value at its bit offset, LSB first, gaps zero; unpacking it restores the values.
    #[test]
    fn pack_unpack_match_the_reference_model(
        picks in proptest::collection::vec((0usize..6, 1u8..17, any::<u64>()), 1..8),
    ) {
        let mut od = Od::default();
        let mut entries = Vec::new();
        let mut model: Vec<(u16, u8, u64)> = Vec::new();
        for (pick, gap, value) in picks {
            if pick == 5 {
                entries.push(MappingEntry::new(0, 0, gap));
                model.push((0, gap, 0));
            } else {
                let (index, bits) = ENTRIES[pick];
                if model.iter().any(|(i, _, _)| *i == index) { continue; }
                let v = value & ((1u64 << bits) - 1);
                set(&mut od, index, v);
                entries.push(MappingEntry::new(index, 0, bits));
                model.push((index, bits, v));
            }
        }
        // Map everything as both a TxPDO and an RxPDO (the entries used are mappable both ways).
        od.tx1 = PdoMapping::mapping(&entries);
        od.rx1 = od.tx1;
        let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
        let total: u32 = model.iter().map(|(_, b, _)| u32::from(*b)).sum();
        prop_assert_eq!(usize::from(tx.bytes()), total.div_ceil(8) as usize);

        let mut image = vec![0xFF; usize::from(tx.bytes())];
        pack(&tx, &od, &mut image);
        let mut expected = vec![0u8; image.len()];
        let mut bit = 0usize;
        for (_, bits, v) in &model {
            for i in 0..usize::from(*bits) {
                if v >> i & 1 == 1 { expected[(bit + i) / 8] |= 1 << ((bit + i) % 8); }
            }
            bit += usize::from(*bits);
        }
        prop_assert_eq!(&image, &expected);

        let mut fresh = Od { rx1: od.rx1, ..Od::default() };
        let rx = Layout::of(&fresh, Direction::Rx).unwrap().unwrap();
        unpack(&rx, &image, &mut fresh);
        for (index, _, v) in model.iter().filter(|(i, _, _)| *i != 0) {
            prop_assert_eq!(get(&fresh, *index), *v, "{:#06x}", index);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2_000, ..ProptestConfig::default() })]

    /// Fuzz target for the PDO configuration parser: arbitrary SDO writes (any bytes, any
    /// subindex, including raw mapping entries naming missing, unmappable or oversized objects)
    /// into the mapping and assignment objects, then the layout of both directions and a
    /// pack/unpack into images of any length. Nothing panics; a usable layout fits its image.
    #[test]
    fn any_pdo_configuration_is_refused_or_fits(
        writes in proptest::collection::vec(
            (
                prop_oneof![Just(0x1600u16), Just(0x1A00), Just(0x1C12), Just(0x1C13)],
                0u8..12,
                proptest::collection::vec(any::<u8>(), 0..6),
            ),
            0..24,
        ),
        image_len in 0usize..40,
    ) {
        let mut od = Od::default();
        for (index, sub, data) in &writes {
            let _ = write(&mut od, *index, *sub, data);
        }
        for direction in [Direction::Rx, Direction::Tx] {
            let Ok(Some(layout)) = Layout::of(&od, direction) else { continue };
            let end = layout.slots().iter().map(|s| u32::from(s.bit_offset) + u32::from(s.bit_len)).max();
            prop_assert!(end.unwrap_or(0) <= u32::from(layout.bytes()) * 8);
            let mut image = vec![0xA5; image_len];
            pack(&layout, &od, &mut image);
            unpack(&layout, &image, &mut od);
        }
    }
}
