//! Fuzz target for the frame-level port of the emulated ESCs (stable toolchain, proptest):
//! arbitrary bytes as a frame and arbitrary well-formed datagram lists through a line of three
//! ESCs with process data mapped. The line never panics, never returns more bytes than it got,
//! never lowers a working counter, keeps every datagram's command, index, length and IRQ, moves
//! ADP only for the incrementing commands (ETG.1000.4 §5.4), and an ESC no datagram addresses
//! keeps its memory and leaves the data untouched.

use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::frame::{self, Datagram};
use ecat_emu::line::{FIRST_STATION, Line};
use proptest::prelude::*;

/// Each ESC's process data: 11 bytes each way, the whole image logical 0..66.
const PD: u16 = 11;
const IMAGE: u32 = 66;
/// First address after the process RAM of the default ESC.
const RAM_END: u16 = 0x3000;
/// The most a datagram's working counter grows on three ESCs: a read-write on each.
const MAX_COUNT: u16 = 3 * 3;

/// Three ESCs (the middle one with DC), addressed, process data mapped.
fn line() -> Line {
    let dc = EscConfig {
        dc_supported: true,
        ..EscConfig::default()
    };
    let line = Line::new(
        [EscConfig::default(), dc, EscConfig::default()]
            .into_iter()
            .map(Emulator::new)
            .collect(),
    );
    assert!(line.address());
    assert!(line.map_process_data(0x1000, 0x1100, PD));
    line
}

/// Every ESC's memory as its PDI reads it (registers and process RAM).
fn snapshot(line: &Line) -> Vec<Vec<u8>> {
    line.escs()
        .iter()
        .map(|emu| {
            let mut memory = vec![0; usize::from(RAM_END)];
            emu.with(|esc| esc.pdi_read(0, &mut memory));
            memory
        })
        .collect()
}

/// Whether `command` increments ADP at every ESC: AP*, B*, ARMW.
fn increments(command: u8) -> bool {
    matches!(command, 1..=3 | 7..=9 | 13)
}

/// Any datagram: mostly defined commands, sometimes reserved ones; working counters low enough
/// that nine increments cannot wrap.
fn datagram() -> impl Strategy<Value = Datagram> {
    (
        prop_oneof![4 => 0u8..=15, 1 => any::<u8>()],
        any::<u8>(),
        any::<[u8; 4]>(),
        prop::collection::vec(any::<u8>(), 0..48),
        any::<u16>(),
        0u16..0x8000,
    )
        .prop_map(|(command, index, address, data, irq, wkc)| Datagram {
            command,
            index,
            address,
            data,
            irq,
            wkc,
        })
}

/// A datagram no ESC of [`line`] answers: AP* beyond the line, FP* to no station, L* beyond the
/// image.
fn unaddressed() -> impl Strategy<Value = Datagram> {
    let data = || prop::collection::vec(any::<u8>(), 0..48);
    prop_oneof![
        (1u8..=3, 3u16..=0xFFFC, any::<u16>(), data())
            .prop_map(|(c, adp, ado, d)| Datagram::physical(c, adp, ado, &d)),
        (4u8..=6, any::<u16>(), any::<u16>(), data())
            .prop_filter("not a station", |(_, adp, _, _)| {
                !(FIRST_STATION..FIRST_STATION + 3).contains(adp)
            })
            .prop_map(|(c, adp, ado, d)| Datagram::physical(c, adp, ado, &d)),
        (10u8..=12, IMAGE..=u32::MAX, data())
            .prop_map(|(c, address, d)| Datagram::logical(c, address, &d)),
    ]
}

/// Frames of a MainDevice: header with EtherType 0x88A4 and arbitrary bytes after it, or
/// arbitrary bytes altogether.
fn raw_frame() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        prop::collection::vec(any::<u8>(), 0..160),
        prop::collection::vec(any::<u8>(), 0..160).prop_map(|tail| {
            let mut frame = frame::build([0x10; 6], &[]);
            frame.truncate(14);
            frame.extend(tail);
            frame
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic_nor_grow(frames in prop::collection::vec(raw_frame(), 1..6)) {
        let line = line();
        for mut bytes in frames {
            let len = bytes.len();
            if let Some(back) = line.process(&mut bytes) {
                prop_assert!(back <= len);
            }
            prop_assert_eq!(bytes.len(), len);
        }
    }

    #[test]
    fn well_formed_datagrams_keep_their_shape_and_counters_only_grow(
        frames in prop::collection::vec(prop::collection::vec(datagram(), 1..6), 1..5)
    ) {
        let line = line();
        for sent in frames {
            let mut bytes = frame::build([0x10; 6], &sent);
            let len = bytes.len();
            prop_assert_eq!(line.process(&mut bytes), Some(len));
            let back = frame::datagrams(&bytes).expect("the frame stays well-formed");
            prop_assert_eq!(back.len(), sent.len());
            for (s, b) in sent.iter().zip(&back) {
                prop_assert_eq!((b.command, b.index, b.irq), (s.command, s.index, s.irq));
                prop_assert_eq!(b.data.len(), s.data.len());
                prop_assert!(b.wkc >= s.wkc && b.wkc - s.wkc <= MAX_COUNT, "{:?} → {}", s, b.wkc);
                let adp = u16::from_le_bytes([s.address[0], s.address[1]]);
                let step = if increments(s.command) { 3 } else { 0 };
                let mut address = s.address;
                address[..2].copy_from_slice(&adp.wrapping_add(step).to_le_bytes());
                prop_assert_eq!(b.address, address);
            }
        }
    }

    #[test]
    fn unaddressed_escs_leave_data_and_memory_untouched(
        sent in prop::collection::vec(unaddressed(), 1..6)
    ) {
        let line = line();
        // The first snapshot acknowledges the events of the configuration (PDI reads of 0x0120,
        // the activate bytes); from then on the PDI reads nothing new.
        snapshot(&line);
        let before = snapshot(&line);
        let back = line.exchange(&sent).expect("the frame comes back");
        for (s, b) in sent.iter().zip(&back) {
            prop_assert_eq!(&b.data, &s.data);
            prop_assert_eq!(b.wkc, 0);
        }
        prop_assert_eq!(snapshot(&line), before);
    }
}
