//! PDO mapping and assignment: the configuration write rules, the image layout, and bit-exact
//! pack/unpack against a reference model (ETG.1000.6 §5.6.7, conformance.md "CoE SDO").

use ecat_core::coe::AbortCode;
use ecat_core::coe::sdo::Writes;
use ecat_core::coe::sdo::{Context, SdoServer};
use ecat_core::device::{DeviceConfig, MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::{Bits, Length, ObjectDictionary};
use ecat_core::pdo::image::{pack, unpack};
use ecat_core::pdo::layout::Layout;
use ecat_core::pdo::{Direction, MappingEntry, PdoAssignment, PdoMapping};
use ecat_core::{AlState, AlStatusCode, Instant};
use proptest::prelude::*;

#[derive(Default)]
struct Pair {
    low: u8,
    hidden: u32,
    high: i16,
}

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
    words: [u16; 3],
    pair: Pair,
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
    minimal Od {
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
        0x2006 => array(words, RW | TXPDO | RXPDO, "Words", "Word");
        0x2007 => record(pair: Pair, "Pair") {
            1 => low, RW | TXPDO | RXPDO, "Low";
            2 => hidden, RW, "Not mappable";
            3 => high, RW | TXPDO | RXPDO, "High";
        };
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
    assert_eq!(
        write(&mut od, 0x1C12, 0, &[2]),
        Err(AbortCode::VALUE_RANGE),
        "SI0 would count SI2, never written (0x0000 is no RxPDO)"
    );
    assert_eq!(od.rx_assign.count, 0);
    assert_eq!(write(&mut od, 0x1C12, 0, &[1]), Ok(()));
    assert_eq!(od.rx_assign.valid().collect::<Vec<_>>(), [0x1600]);
}

#[test]
fn cia402_like_layout_is_11_bytes_each_way() {
    let od = Od::default();
    let rx = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    assert_eq!((rx.bytes(), tx.bytes()), (11, 11));
    let offsets: Vec<Option<u16>> = [0x6040, 0x607A, 0x60FF, 0x6060, 0x6041]
        .iter()
        .map(|&index| rx.offset(index, 0))
        .collect();
    assert_eq!(offsets, [Some(0), Some(16), Some(48), Some(80), None]);
    assert_eq!(tx.offset(0x6061, 0), Some(80));
    assert!(!rx.has_gaps() && rx.repeats().is_empty());
}

/// The outputs' layout the process-data side keeps has no room for repeats and the same image
/// as `Layout::of`: offsets, size, gaps; an unusable mapping is refused the same way.
#[test]
fn rx_layout_is_the_outputs_layout_without_repeat_room() {
    use ecat_core::pdo::layout::{Repeat, RxLayout};
    let od = Od::default();
    let full = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    let rx = RxLayout::outputs(&od).unwrap().unwrap();
    assert_eq!(rx.offsets(), full.offsets());
    assert_eq!((rx.bits(), rx.bytes(), rx.has_gaps()), (88, 11, false));
    assert!(rx.repeats().is_empty());
    assert!(
        core::mem::size_of::<RxLayout<Od>>() + 8 * core::mem::size_of::<Repeat>()
            <= core::mem::size_of::<Layout<Od>>()
    );
    let big = Big {
        rx_assign: PdoAssignment::assignment(&[0x1600, 0x1601]),
        ..Big::default()
    };
    assert!(matches!(
        RxLayout::outputs(&big),
        Err(AlStatusCode::INVALID_OUTPUT_MAPPING)
    ));
}

/// The layout's offsets are indexed by entry number: every RxPDO- or TxPDO-mappable entry in
/// index order, a RECORD's by subindex, an ARRAY's element by element; others have none.
#[test]
fn mappable_entries_are_numbered_in_dictionary_order() {
    use ecat_core::pdo::layout::mappable_entries;
    let number = ecat_core::pdo::layout::number::<Od>;
    assert_eq!(number(0x2000, 0), Some(0));
    assert_eq!(number(0x2002, 0), Some(2));
    assert_eq!(number(0x2003, 0), None, "not mappable");
    assert_eq!(number(0x2004, 0), Some(3));
    assert_eq!(number(0x2005, 0), Some(4));
    assert_eq!(
        [1, 2, 3].map(|sub| number(0x2006, sub)),
        [Some(5), Some(6), Some(7)]
    );
    assert_eq!(number(0x2006, 0), None, "SI0 is the count");
    assert_eq!(number(0x2006, 4), None, "beyond the array");
    assert_eq!(
        [1, 2, 3].map(|sub| number(0x2007, sub)),
        [Some(8), None, Some(9)]
    );
    assert_eq!(number(0x6040, 0), Some(10));
    assert_eq!(number(0x60FF, 0), Some(17));
    assert_eq!(number(0x1600, 1), None, "a mapping object");
    assert_eq!(number(0x6040, 1), None);
    assert_eq!(mappable_entries(Od::OBJECTS), 18);
    assert_eq!(
        <<Od as ObjectDictionary>::Mappable as Length>::array(0u16).len(),
        18
    );
}

/// The lookup (binary search + each object's first number) gives every subindex of every object
/// the number a plain count gives it: the mappable entries before it in index and subindex order,
/// an ARRAY's element standing for each of its subindices.
#[test]
fn the_entry_number_is_the_count_of_mappable_entries_before_it() {
    use ecat_core::dictionary::ObjectCode;
    use ecat_core::pdo::layout::number;
    fn agree<D: ObjectDictionary>() {
        let mut count = 0;
        for object in D::OBJECTS {
            let info = &object.info;
            for sub in 0..=u8::MAX {
                let mappable = info
                    .entry(sub)
                    .filter(|_| sub > 0 || info.code == ObjectCode::Var)
                    .is_some_and(|e| e.access.rxpdo() || e.access.txpdo());
                let expected = mappable.then_some(count);
                assert_eq!(
                    number::<D>(info.index, sub),
                    expected,
                    "{:#06x}:{sub}",
                    info.index
                );
                count += usize::from(mappable);
            }
        }
        assert_eq!(number::<D>(0x0FFF, 0), None, "no such object");
        assert_eq!(D::MAPPABLE.len(), count, "one key per mappable entry");
    }
    agree::<Od>();
    agree::<Big>();
}

/// An ARRAY's elements and a RECORD's entries travel at their own offsets.
#[test]
fn array_elements_and_record_entries_are_mapped_one_by_one() {
    let entries = [
        MappingEntry::new(0x2006, 3, 16),
        MappingEntry::new(0x2007, 3, 16),
        MappingEntry::new(0x2006, 1, 16),
        MappingEntry::new(0x2007, 1, 8),
    ];
    let mut od = Od {
        words: [0x1111, 0x2222, 0x3333],
        pair: Pair {
            low: 0x44,
            hidden: 0xDEAD_BEEF,
            high: -2,
        },
        tx1: PdoMapping::mapping(&entries),
        rx1: PdoMapping::mapping(&entries),
        ..Od::default()
    };
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    let mut image = [0xAA; 7];
    pack(&tx, &od, &mut image);
    assert_eq!(image, [0x33, 0x33, 0xFE, 0xFF, 0x11, 0x11, 0x44]);

    let rx = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    unpack(&rx, &[0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07], &mut od);
    assert_eq!(od.words, [0x0605, 0x2222, 0x0201]);
    assert_eq!(
        (od.pair.low, od.pair.hidden, od.pair.high),
        (0x07, 0xDEAD_BEEF, 0x0403)
    );
}

/// A TxPDO entry mapped twice is in the image twice; an RxPDO entry mapped twice takes its value
/// from the last place.
#[test]
fn an_entry_mapped_twice() {
    let entries = [
        MappingEntry::new(0x2004, 0, 16),
        MappingEntry::new(0x2001, 0, 3),
        MappingEntry::new(0x2004, 0, 16),
        MappingEntry::new(0x2001, 0, 3),
    ];
    let mut od = Od {
        word: 0xBEEF,
        level: Bits::new(0b101),
        tx1: PdoMapping::mapping(&entries),
        rx1: PdoMapping::mapping(&entries),
        ..Od::default()
    };
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    assert_eq!((tx.bits(), tx.repeats().len()), (38, 2));
    let mut image = [0xFF; 5];
    pack(&tx, &od, &mut image);
    // bits 0..16 word, 16..19 level, 19..35 word, 35..38 level, 38..40 padding.
    let expected = 0xBEEFu64 | 0b101 << 16 | 0xBEEF << 19 | 0b101 << 35;
    assert_eq!(image, expected.to_le_bytes()[..5]);
    // An image too short for the repeats: the entries it holds, no part of a repeat.
    let mut short = [0xFF; 3];
    pack(&tx, &od, &mut short);
    assert_eq!(short, [0xEF, 0xBE, 0b101]);

    let rx = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    let image = (0x1234u64 | 0b001 << 16 | 0x5678 << 19 | 0b110 << 35).to_le_bytes();
    unpack(&rx, &image[..5], &mut od);
    assert_eq!((od.word, od.level.get()), (0x5678, 0b110));
}

/// More TxPDO entries mapped again than a layout keeps ([`MAX_REPEATS`]) is 0x0024.
#[test]
fn too_many_repeated_tx_entries_are_0x0024() {
    use ecat_core::pdo::layout::MAX_REPEATS;
    assert_eq!(MAX_REPEATS, 8);
    let byte = MappingEntry::new(0x2002, 0, 8);
    let word = MappingEntry::new(0x2004, 0, 16);
    // The same TxPDO assigned twice: every entry of the second is a repeat.
    let mut od = Od {
        tx1: PdoMapping::mapping(&[byte, byte, byte, byte, word]),
        tx_assign: PdoAssignment::assignment(&[0x1A00, 0x1A00]),
        ..Od::default()
    };
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    assert_eq!(tx.repeats().len(), 8);
    od.tx1 = PdoMapping::mapping(&[byte; 5]);
    assert!(matches!(
        Layout::of(&od, Direction::Tx),
        Err(AlStatusCode::INVALID_INPUT_MAPPING)
    ));
}

/// A layout's room for repeats is what the TxPDO configuration can hold: one PDO (0x1C13 of
/// capacity 1) of three entries holds two, all of which a layout keeps.
#[test]
fn repeat_room_is_what_the_tx_configuration_holds() {
    struct Small {
        value: u16,
        tx: PdoMapping<3>,
        tx_assign: PdoAssignment<1>,
    }
    const ONE: [MappingEntry; 1] = [MappingEntry::new(0x6000, 0, 16)];
    ecat_core::dictionary! {
        minimal Small {
            0x1A00 => pdo(tx, RO, "TxPDO", "Mapped object", default = PdoMapping::mapping(&ONE));
            0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
            0x6000 => var(value, RO | TXPDO, "Value");
        }
    }
    let room = <<Small as ObjectDictionary>::Repeatable as Length>::array(0u8);
    assert_eq!(room.as_ref().len(), 2);
    assert_eq!(
        <<Od as ObjectDictionary>::Repeatable as Length>::array(0u8)
            .as_ref()
            .len(),
        8
    );
    let entry = MappingEntry::new(0x6000, 0, 16);
    let od = Small {
        tx: PdoMapping::mapping(&[entry; 3]),
        ..Small::default()
    };
    let tx = Layout::of(&od, Direction::Tx).unwrap().unwrap();
    assert_eq!(tx.bytes(), 6);
    assert_eq!(tx.repeats().len(), 2);
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

/// The entries a property case may map, both ways: (index, subindex, bit length).
const ENTRIES: [(u16, u8, u8); 8] = [
    (0x2000, 0, 1),
    (0x2001, 0, 3),
    (0x2002, 0, 8),
    (0x2004, 0, 16),
    (0x2005, 0, 32),
    (0x2006, 2, 16),
    (0x2007, 1, 8),
    (0x2007, 3, 16),
];

fn set(od: &mut Od, (index, sub): (u16, u8), v: u64) {
    match (index, sub) {
        (0x2000, _) => od.flag = v & 1 == 1,
        (0x2001, _) => od.level = Bits::new(v as u8),
        (0x2002, _) => od.small = v as u8,
        (0x2004, _) => od.word = v as u16,
        (0x2005, _) => od.long = v as i32,
        (0x2006, _) => od.words[1] = v as u16,
        (_, 1) => od.pair.low = v as u8,
        _ => od.pair.high = v as i16,
    }
}

fn get(od: &Od, (index, sub): (u16, u8)) -> u64 {
    match (index, sub) {
        (0x2000, _) => u64::from(od.flag),
        (0x2001, _) => u64::from(od.level.get()),
        (0x2002, _) => u64::from(od.small),
        (0x2004, _) => u64::from(od.word),
        (0x2005, _) => u64::from(od.long as u32),
        (0x2006, _) => u64::from(od.words[1]),
        (_, 1) => u64::from(od.pair.low),
        _ => u64::from(od.pair.high as u16),
    }
}

proptest! {
    /// Random mappings of BOOL, BIT3, bytes, words and gaps at any bit offset: the packed image
    /// holds every value at its bit offset, LSB first, gaps zero; unpacking it restores the values.
    #[test]
    fn pack_unpack_match_the_reference_model(
        picks in proptest::collection::vec((0..=ENTRIES.len(), 1u8..17, any::<u64>()), 1..8),
    ) {
        let mut od = Od::default();
        let mut entries = Vec::new();
        let mut model: Vec<((u16, u8), u8, u64)> = Vec::new();
        for (pick, gap, value) in picks {
            if pick == ENTRIES.len() {
                entries.push(MappingEntry::new(0, 0, gap));
                model.push(((0, 0), gap, 0));
            } else {
                let (index, sub, bits) = ENTRIES[pick];
                if model.iter().any(|(at, _, _)| *at == (index, sub)) { continue; }
                let v = value & ((1u64 << bits) - 1);
                set(&mut od, (index, sub), v);
                entries.push(MappingEntry::new(index, sub, bits));
                model.push(((index, sub), bits, v));
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
        for (entry, _, v) in model.iter().filter(|(at, _, _)| at.0 != 0) {
            prop_assert_eq!(get(&fresh, *entry), *v, "{:x?}", entry);
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
            for (index, sub, bits) in ENTRIES {
                if let Some(at) = layout.offset(index, sub) {
                    prop_assert!(u32::from(at) + u32::from(bits) <= layout.bits());
                }
            }
            prop_assert!(layout.bits() <= u32::from(layout.bytes()) * 8);
            let mut image = vec![0xA5; image_len];
            pack(&layout, &od, &mut image);
            unpack(&layout, &image, &mut od);
        }
    }
}

/// A dictionary whose mappings can describe more than 65 535 bits.
struct Big {
    rx1: PdoMapping<255>,
    rx2: PdoMapping<255>,
    rx_assign: PdoAssignment<2>,
}

ecat_core::dictionary! {
    minimal Big {
        0x1600 => pdo(rx1, RW_PREOP, "RxPDO 1", "Entry", default = PdoMapping::mapping(&[MappingEntry::new(0, 0, 255); 255]));
        0x1601 => pdo(rx2, RW_PREOP, "RxPDO 2", "Entry", default = PdoMapping::mapping(&[MappingEntry::new(0, 0, 255); 255]));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "PDO", default = PdoAssignment::assignment(&[0x1600]));
    }
}

/// Offsets are 16-bit: an image over 65 535 bits is an unusable mapping (0x0025).
#[test]
fn an_image_over_65535_bits_is_0x0025() {
    let mut od = Big::default();
    let one = Layout::of(&od, Direction::Rx).unwrap().unwrap();
    assert_eq!(
        (one.bits(), one.bytes(), one.has_gaps()),
        (65_025, 8129, true)
    );
    od.rx_assign = PdoAssignment::assignment(&[0x1600, 0x1601]);
    assert!(matches!(
        Layout::of(&od, Direction::Rx),
        Err(AlStatusCode::INVALID_OUTPUT_MAPPING)
    ));
}

/// One SDO request to `server` in `state`; the answer (CoE header on).
fn serve(server: &mut SdoServer<64>, od: &mut Od, state: AlState, request: &[u8]) -> Vec<u8> {
    serve_on(None, server, od, state, request)
}

/// One SDO request to `server` in `state` of a SubDevice described by `device`.
fn serve_on<D: ObjectDictionary>(
    device: Option<&DeviceConfig>,
    server: &mut SdoServer<64>,
    od: &mut D,
    state: AlState,
    request: &[u8],
) -> Vec<u8> {
    let mut cx = Context {
        od,
        hooks: &mut (),
        state,
        now: Instant::from_micros(0),
        writes: &mut Writes::default(),
        device,
    };
    let mut out = [0u8; 58];
    let n = server.request(&mut cx, request, &mut out);
    out[..n].to_vec()
}

/// The download response for `index:sub`.
fn downloaded(index: u16, sub: u8) -> Vec<u8> {
    let [i0, i1] = index.to_le_bytes();
    vec![0x00, 0x30, 0x60, i0, i1, sub, 0, 0, 0, 0]
}

/// The abort 0x06040042 "the number and length of the objects to be mapped would exceed the
/// PDO length" for `index:sub`.
fn too_long(index: u16, sub: u8) -> Vec<u8> {
    let [i0, i1] = index.to_le_bytes();
    vec![0x00, 0x20, 0x80, i0, i1, sub, 0x42, 0x00, 0x04, 0x06]
}

/// An SI0 that makes the image of its direction longer than 65 535 bits (the image's bit
/// offsets are 16-bit) is refused at the SDO write with 0x06040042 (ETG.1000.6 Table 41,
/// conformance.md "CoE SDO"), where it was accepted and refused only at PREOP→SAFEOP (0x0025):
/// assigning a second PDO of 65 025 bits, or growing an assigned mapping past the limit.
#[test]
fn an_si0_making_the_image_longer_than_65535_bits_is_0x06040042() {
    let mut od = Big::default();
    let mut server = SdoServer::<64>::new();
    let mut sdo =
        |od: &mut Big, request: &[u8]| serve_on(None, &mut server, od, AlState::PreOp, request);
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x12, 0x1C, 0x00, 0, 0, 0, 0]),
        downloaded(0x1C12, 0)
    );
    let second = [0x2B, 0x12, 0x1C, 0x02, 0x01, 0x16, 0, 0];
    assert_eq!(sdo(&mut od, &second), downloaded(0x1C12, 2));
    let both = [0x2F, 0x12, 0x1C, 0x00, 2, 0, 0, 0];
    assert_eq!(sdo(&mut od, &both), too_long(0x1C12, 0));
    assert_eq!(od.rx_assign.count, 0, "refused before it is stored");
    let one = [0x2F, 0x12, 0x1C, 0x00, 1, 0, 0, 0];
    assert_eq!(sdo(&mut od, &one), downloaded(0x1C12, 0));
    // Both assigned, the second emptied: 65 025 bits. Each entry of it adds a 255-bit gap:
    // 65 280, 65 535 (the limit itself), then 65 790.
    od.rx_assign = PdoAssignment::assignment(&[0x1600, 0x1601]);
    od.rx2.count = 0;
    for (n, answer) in [(1, downloaded(0x1601, 0)), (2, downloaded(0x1601, 0))] {
        od.rx2.count = 0;
        assert_eq!(
            sdo(&mut od, &[0x2F, 0x01, 0x16, 0x00, n, 0, 0, 0]),
            answer,
            "{n}"
        );
    }
    od.rx2.count = 0;
    let three = [0x2F, 0x01, 0x16, 0x00, 3, 0, 0, 0];
    assert_eq!(sdo(&mut od, &three), too_long(0x1601, 0));
    // Not assigned, a mapping makes no image: any count is taken.
    od.rx_assign = PdoAssignment::assignment(&[0x1600]);
    assert_eq!(sdo(&mut od, &three), downloaded(0x1601, 0));
}

/// A device whose process RAM after the mailboxes holds 40 bytes takes images of up to 13
/// bytes (three buffers, 39 bytes): growing the RxPDO from 11 to 15 bytes is refused with
/// 0x06040042, by a single access and by a complete access (which stores nothing then); the
/// other direction is not counted.
#[test]
fn an_si0_making_the_image_longer_than_the_process_ram_takes_is_0x06040042() {
    let mut device = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes::default(),
    );
    device.process_ram_end = 0x1100 + 40;
    assert_eq!(ecat_core::pdo::process_ram(&device), 40);
    let mut od = Od::default();
    let mut server = SdoServer::<64>::new();
    let mut sdo = |od: &mut Od, request: &[u8]| {
        serve_on(Some(&device), &mut server, od, AlState::PreOp, request)
    };
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x16, 0x00, 0, 0, 0, 0]),
        downloaded(0x1600, 0)
    );
    // 0x1600:05 = 0x2005:00, 32 bits: 88 + 32 bits = 15 bytes.
    let fifth = [0x23, 0x00, 0x16, 0x05, 0x20, 0x00, 0x05, 0x20];
    assert_eq!(sdo(&mut od, &fifth), downloaded(0x1600, 5));
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x16, 0x00, 5, 0, 0, 0]),
        too_long(0x1600, 0)
    );
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x16, 0x00, 4, 0, 0, 0]),
        downloaded(0x1600, 0)
    );
    // 0x2006:01 (16 bits) instead: 13 bytes, the most three buffers of 40 bytes hold.
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x16, 0x00, 0, 0, 0, 0]),
        downloaded(0x1600, 0)
    );
    let word = [0x23, 0x00, 0x16, 0x05, 0x10, 0x01, 0x06, 0x20];
    assert_eq!(sdo(&mut od, &word), downloaded(0x1600, 5));
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x16, 0x00, 5, 0, 0, 0]),
        downloaded(0x1600, 0)
    );
    // A complete access with the 32-bit entry: refused, the mapping as it was.
    let mut request = vec![0x31, 0x00, 0x16, 0x00, 22, 0, 0, 0, 5, 0];
    for entry in RX.iter().chain([MappingEntry::new(0x2005, 0, 32)].iter()) {
        request.extend_from_slice(&entry.0.to_le_bytes());
    }
    assert_eq!(sdo(&mut od, &request), too_long(0x1600, 0));
    assert_eq!(od.rx1.count, 5);
    assert_eq!(od.rx1.items[4], 0x2006_0110);
    // The TxPDO grows on its own account: 11 + 4 bytes of inputs are refused, 11 + 2 taken,
    // whatever the outputs take.
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x1A, 0x00, 0, 0, 0, 0]),
        downloaded(0x1A00, 0)
    );
    let long = [0x23, 0x00, 0x1A, 0x05, 0x20, 0x00, 0x05, 0x20];
    assert_eq!(sdo(&mut od, &long), downloaded(0x1A00, 5));
    assert_eq!(
        sdo(&mut od, &[0x2F, 0x00, 0x1A, 0x00, 5, 0, 0, 0]),
        too_long(0x1A00, 0)
    );
}

/// A segmented download started in PREOP into entries the RxPDO configuration maps is refused
/// with 0x06010006 at its last segment when the SubDevice reached SAFEOP meanwhile: the check
/// is made again before the value is stored, and the value stays as it was.
#[test]
fn a_segmented_download_into_mapped_entries_is_checked_again_at_its_last_segment() {
    let mut od = Od {
        rx1: PdoMapping::mapping(&[MappingEntry::new(0x2006, 2, 16)]),
        ..Od::default()
    };
    let mut server = SdoServer::<64>::new();
    let mut serve = |od: &mut Od, state, request: &[u8]| serve(&mut server, od, state, request);
    // Complete access to 0x2006 from SI0: SI0 and its pad byte, three words = 8 bytes, of
    // which the initiate carries 4.
    let initiate = [0x31, 0x06, 0x20, 0x00, 8, 0, 0, 0, 3, 0, 0x11, 0x11];
    let accepted = serve(&mut od, AlState::PreOp, &initiate);
    assert_eq!(accepted, [0x00, 0x30, 0x70, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    // The last segment: 4 data bytes of 7 (3 unused), toggle 0.
    let last = [0x07, 0x22, 0x22, 0x33, 0x33, 0, 0, 0];
    let refused = serve(&mut od, AlState::SafeOp, &last);
    assert_eq!(
        refused,
        [0x00, 0x20, 0x80, 0x06, 0x20, 0x00, 0x06, 0x00, 0x01, 0x06]
    );
    assert_eq!(od.words, [0, 0, 0], "nothing stored");
    // In PREOP the same transfer completes.
    assert_eq!(
        serve(&mut od, AlState::PreOp, &initiate),
        [0x00, 0x30, 0x70, 0x06, 0x20, 0x00, 0, 0, 0, 0]
    );
    assert_eq!(
        serve(&mut od, AlState::PreOp, &last),
        [0x00, 0x30, 0x20, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(od.words, [0x1111, 0x2222, 0x3333]);
}

/// The same for the access rights: a segmented download started in PREOP into an entry writable
/// in PREOP only (a complete access to 0x1C12) is refused with 0x08000022 at its last segment in
/// SAFEOP, and the assignment stays as it was.
#[test]
fn a_segmented_download_is_checked_for_the_state_it_ends_in() {
    let mut od = Od::default();
    let mut server = SdoServer::<64>::new();
    let mut serve = |od: &mut Od, state, request: &[u8]| serve(&mut server, od, state, request);
    // SI0 = 2 and its pad, 0x1600, then 0x1601 in the segment.
    let initiate = [0x31, 0x12, 0x1C, 0x00, 6, 0, 0, 0, 2, 0, 0x00, 0x16];
    let last = [0x0B, 0x01, 0x16, 0, 0, 0, 0, 0];
    assert_eq!(
        serve(&mut od, AlState::PreOp, &initiate),
        [0x00, 0x30, 0x70, 0x12, 0x1C, 0x00, 0, 0, 0, 0]
    );
    assert_eq!(
        serve(&mut od, AlState::SafeOp, &last),
        [0x00, 0x20, 0x80, 0x12, 0x1C, 0x00, 0x22, 0x00, 0x00, 0x08]
    );
    assert_eq!((od.rx_assign.count, od.rx_assign.items), (1, [0x1600, 0]));
}

/// A complete-access upload of an ARRAY carries SI0 and the entries SI0 counts: the object's
/// current size, not every slot of its capacity (SSC 5.12 sizes an ARRAY's complete access by
/// SI0's value, `objdef.c` `OBJ_GetObjectLength`). 0x1600 (capacity 8) with two entries: 2 + 8
/// bytes, where every slot gave 2 + 32.
#[test]
fn a_complete_access_upload_of_a_mapping_carries_the_entries_si0_counts() {
    let mut od = Od {
        rx1: PdoMapping::mapping(&RX[..2]),
        ..Od::default()
    };
    let mut server = SdoServer::<64>::new();
    assert_eq!(
        serve(
            &mut server,
            &mut od,
            AlState::PreOp,
            &[0x50, 0x00, 0x16, 0x00, 0, 0, 0, 0]
        ),
        [
            0x00, 0x30, 0x51, 0x00, 0x16, 0x00, 10, 0, 0,
            0, // normal, complete access, 10 bytes
            2, 0, // SI0 and its pad byte
            0x10, 0x00, 0x40, 0x60, 0x20, 0x00, 0x7A, 0x60, // 0x6040:00 16, 0x607A:00 32
        ]
    );
    // From SI1: the two entries only.
    assert_eq!(
        serve(
            &mut server,
            &mut od,
            AlState::PreOp,
            &[0x50, 0x00, 0x16, 0x01, 0, 0, 0, 0]
        ),
        [
            0x00, 0x30, 0x51, 0x00, 0x16, 0x01, 8, 0, 0, 0, //
            0x10, 0x00, 0x40, 0x60, 0x20, 0x00, 0x7A, 0x60,
        ]
    );
    // Emptied (SI0 = 0): SI0 and its pad from SI0, nothing from SI1.
    od.rx1.count = 0;
    assert_eq!(
        serve(
            &mut server,
            &mut od,
            AlState::PreOp,
            &[0x50, 0x00, 0x16, 0x00, 0, 0, 0, 0]
        ),
        [0x00, 0x30, 0x5B, 0x00, 0x16, 0x00, 0, 0, 0, 0],
        "expedited, 2 bytes"
    );
    assert_eq!(
        serve(
            &mut server,
            &mut od,
            AlState::PreOp,
            &[0x50, 0x00, 0x16, 0x01, 0, 0, 0, 0]
        ),
        [0x00, 0x30, 0x51, 0x00, 0x16, 0x01, 0, 0, 0, 0],
        "normal, 0 bytes"
    );
}

/// The same for an assignment: 0x1C12 (capacity 2) assigning one PDO is SI0, its pad and one
/// index, 4 bytes: an expedited answer, where every slot gave a normal one of 6 bytes.
#[test]
fn a_complete_access_upload_of_an_assignment_carries_the_pdos_si0_counts() {
    let mut od = Od::default();
    let mut server = SdoServer::<64>::new();
    assert_eq!(
        serve(
            &mut server,
            &mut od,
            AlState::PreOp,
            &[0x50, 0x12, 0x1C, 0x00, 0, 0, 0, 0]
        ),
        [0x00, 0x30, 0x53, 0x12, 0x1C, 0x00, 1, 0, 0x00, 0x16]
    );
    od.rx_assign = PdoAssignment::assignment(&[0x1600, 0x1600]);
    assert_eq!(
        serve(
            &mut server,
            &mut od,
            AlState::PreOp,
            &[0x50, 0x12, 0x1C, 0x00, 0, 0, 0, 0]
        ),
        [
            0x00, 0x30, 0x51, 0x12, 0x1C, 0x00, 6, 0, 0, 0, 2, 0, 0x00, 0x16, 0x00, 0x16
        ],
        "full: every slot"
    );
}

/// The PDO configuration indices and their directions (ETG.1000.6 §5.6.7): mappings
/// 0x1600..=0x17FF (RxPDO) and 0x1A00..=0x1BFF (TxPDO), assignments 0x1C12/0x1C13.
#[test]
fn configuration_indices_name_their_direction() {
    use Direction::{Rx, Tx};
    let mapping = [
        (0x15FF, None),
        (0x1600, Some(Rx)),
        (0x17FF, Some(Rx)),
        (0x1800, None),
        (0x19FF, None),
        (0x1A00, Some(Tx)),
        (0x1BFF, Some(Tx)),
        (0x1C00, None),
        (0x3600, None),
    ];
    for (index, direction) in mapping {
        assert_eq!(Direction::of_mapping(index), direction, "{index:#06x}");
        assert_eq!(Rx.is_mapping(index), direction == Some(Rx), "{index:#06x}");
        assert_eq!(Tx.is_mapping(index), direction == Some(Tx), "{index:#06x}");
        assert_eq!(
            Direction::of_configuration(index),
            direction,
            "{index:#06x}"
        );
    }
    for (index, direction) in [
        (0x1C11, None),
        (0x1C12, Some(Rx)),
        (0x1C13, Some(Tx)),
        (0x1C14, None),
    ] {
        assert_eq!(Direction::of_assignment(index), direction, "{index:#06x}");
        assert_eq!(
            Direction::of_configuration(index),
            direction,
            "{index:#06x}"
        );
    }
    assert!(ecat_core::pdo::configures_process_data(0x1C32));
    assert!(!ecat_core::pdo::configures_process_data(0x1C00));
}
