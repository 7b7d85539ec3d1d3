//! SDO Information (ETG.1000.6 §5.6.3), byte-exact: request bytes (after the CoE header) in,
//! response message bytes (CoE header included) out.

use ecat_core::coe::sdo_info::{InfoRequest, SdoInfo, ValueInfo};
use ecat_core::dictionary::{ObjectDictionary, VisibleString};

// --- a small dictionary with every kind of object and list flag ---------------------------

struct Identity {
    vendor_id: u32,
    product_code: u32,
}

struct Outputs {
    value: u16,
    other: i32,
}

struct Od {
    device_type: u32,
    name: VisibleString<8>,
    identity: Identity,
    gains: [i16; 4],
    setting: u8,
    inputs: u32,
    position: i32,
    outputs: Outputs,
}

ecat_core::dictionary! {
    minimal Od {
        0x1000 => var(device_type, RO, "Device type", default = 0x0002_0192);
        0x1008 => var(name, RO, "Manufacturer device name", default = VisibleString::new(b"ecat"));
        0x1018 => record(identity: Identity, "Identity object") {
            1 => vendor_id, RO, "Vendor ID", default = 0xE000_0001;
            3 => product_code, RO, "Product code";
        };
        0x2000 => array(gains, RW | TXPDO | BACKUP, "Gains", "Gain", default = 10, min = 0, max = 1000, unit = 0x00FD);
        0x2001 => var(setting, RW_PREOP | SETTINGS, "Réglage");
        0x6000 => var(inputs, RO | TXPDO, "Inputs");
        0x607A => var(position, RW | RXPDO | BACKUP, "Target position", default = 5, min = -1000, max = 1000, unit = 0x0001);
        0x7000 => record(outputs: Outputs, "Outputs") {
            1 => value, RW | RXPDO, "Value";
            2 => other, RW | RXPDO | BACKUP, "Other";
        };
    }
}

/// Mailbox data capacity (after the 6-byte mailbox header) of a 128-byte and a 1024-byte SM1.
const MBX_128: usize = 128 - 6;
const MBX_1024: usize = 1024 - 6;

/// The first response to `request` (the bytes after the CoE header) from `info` with `capacity`
/// bytes of room.
fn ask_with<D: ObjectDictionary>(info: &mut SdoInfo, request: &[u8], capacity: usize) -> Vec<u8> {
    let request = InfoRequest::parse(request).expect("a request with its fixed part");
    let mut out = vec![0xEE; capacity]; // not zero: padding must be written, not inherited
    let len = info.request::<D>(request, &mut out);
    out.truncate(len);
    out
}

/// The response of a fresh server to `request` in a 128-byte mailbox.
fn ask(request: &[u8]) -> Vec<u8> {
    ask_with::<Od>(&mut SdoInfo::new(), request, MBX_128)
}

/// The next fragment from `info`, `None` when it has none.
fn next<D: ObjectDictionary>(info: &mut SdoInfo, capacity: usize) -> Option<Vec<u8>> {
    let mut out = vec![0xEE; capacity];
    let len = info.next_fragment::<D>(&mut out)?;
    out.truncate(len);
    Some(out)
}

/// Every message of the response to `request`: the first, then fragments until none is pending.
fn transfer<D: ObjectDictionary>(request: &[u8], capacity: usize) -> Vec<Vec<u8>> {
    let mut info = SdoInfo::new();
    let mut messages = vec![ask_with::<D>(&mut info, request, capacity)];
    while info.is_pending() {
        assert!(messages.len() < 1000, "fragments never end");
        messages.push(next::<D>(&mut info, capacity).expect("pending, so a fragment follows"));
    }
    assert_eq!(next::<D>(&mut info, capacity), None);
    messages
}

/// CoE header (service 8) and SDO Info header of a message.
fn headers(opcode: u8, fragments_left: u16) -> Vec<u8> {
    let incomplete = if fragments_left > 0 { 0x80 } else { 0 };
    let [lo, hi] = fragments_left.to_le_bytes();
    vec![0x00, 0x80, opcode | incomplete, 0x00, lo, hi]
}

/// An unfragmented message: headers and `data`.
fn message(opcode: u8, data: &[&[u8]]) -> Vec<u8> {
    let mut m = headers(opcode, 0);
    m.extend(data.iter().copied().flatten());
    m
}

/// An SDO Info Error message.
fn info_error(abort: u32) -> Vec<u8> {
    message(0x07, &[&abort.to_le_bytes()])
}

const NO_OBJECT: u32 = 0x0602_0000;
const NO_SUBINDEX: u32 = 0x0609_0011;
const COMMAND_SPECIFIER: u32 = 0x0504_0001;
const UNSUPPORTED_ACCESS: u32 = 0x0601_0000;
const EXCEEDS_MAILBOX: u32 = 0x0601_0005;

// --- Get OD List ---------------------------------------------------------------------------

#[test]
fn od_list_type_0_gives_the_lengths_of_lists_1_to_5() {
    assert_eq!(
        ask(&[0x01, 0x00, 0x00, 0x00, 0x00, 0x00]),
        [
            0x00, 0x80, 0x02, 0x00, 0x00, 0x00, // CoE, OD list response, last fragment
            0x00, 0x00, // list type 0
            0x08, 0x00, 0x02, 0x00, 0x02, 0x00, 0x03, 0x00, 0x01,
            0x00, // 8 all, 2 Rx, 2 Tx, 3 backup, 1 settings
        ]
    );
}

#[test]
fn od_lists_of_a_device_without_a_dictionary_are_empty() {
    let list = |list_type: u8| {
        ask_with::<()>(
            &mut SdoInfo::new(),
            &[0x01, 0x00, 0x00, 0x00, list_type, 0x00],
            MBX_128,
        )
    };
    assert_eq!(list(0), message(0x02, &[&[0x00, 0x00], &[0x00; 10]]));
    for list_type in 1..=5 {
        assert_eq!(list(list_type), message(0x02, &[&[list_type, 0x00]]));
    }
    assert_eq!(list(6), info_error(UNSUPPORTED_ACCESS));
}

#[test]
fn od_list_types_1_to_5_list_the_objects_with_the_flag_in_any_entry() {
    let list = |list_type: u8| ask(&[0x01, 0x00, 0x00, 0x00, list_type, 0x00]);
    assert_eq!(
        list(1),
        message(
            0x02,
            &[
                &[0x01, 0x00],
                &[
                    0x00, 0x10, 0x08, 0x10, 0x18, 0x10, 0x00, 0x20, 0x01, 0x20, 0x00, 0x60, 0x7A,
                    0x60, 0x00, 0x70
                ]
            ]
        )
    );
    // 0x7000 is RxPDO-mappable through its entries, not SI0.
    assert_eq!(
        list(2),
        message(0x02, &[&[0x02, 0x00], &[0x7A, 0x60, 0x00, 0x70]])
    );
    // 0x2000 is TxPDO-mappable through its ARRAY element.
    assert_eq!(
        list(3),
        message(0x02, &[&[0x03, 0x00], &[0x00, 0x20, 0x00, 0x60]])
    );
    assert_eq!(
        list(4),
        message(
            0x02,
            &[&[0x04, 0x00], &[0x00, 0x20, 0x7A, 0x60, 0x00, 0x70]]
        )
    );
    assert_eq!(list(5), message(0x02, &[&[0x05, 0x00], &[0x01, 0x20]]));
}

#[test]
fn od_list_of_an_unknown_type_is_an_error() {
    assert_eq!(
        ask(&[0x01, 0x00, 0x00, 0x00, 0x06, 0x00]),
        [0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x06]
    );
    assert_eq!(
        ask(&[0x01, 0x00, 0x00, 0x00, 0xFF, 0xFF]),
        info_error(UNSUPPORTED_ACCESS)
    );
    assert_eq!(
        ask(&[0x01, 0x00, 0x00, 0x00, 0x01, 0x01]),
        info_error(UNSUPPORTED_ACCESS)
    );
}

/// Checks the fragments of an OD list: headers, countdown, bit 7, that every fragment but the
/// last is full, and returns the values (list type first).
fn reassemble(messages: &[Vec<u8>], capacity: usize) -> Vec<u16> {
    let count = messages.len();
    let mut values = Vec::new();
    for (k, m) in messages.iter().enumerate() {
        let left = (count - 1 - k) as u16;
        assert_eq!(m[..6], headers(0x02, left)[..], "fragment {k} of {count}");
        assert_eq!(m.len() % 2, 0, "whole 16-bit words only");
        if k + 1 < count {
            assert!(
                m.len() + 2 > capacity,
                "fragment {k} carries as much as fits"
            );
        }
        values.extend(m[6..].chunks(2).map(|w| u16::from_le_bytes([w[0], w[1]])));
    }
    values
}

#[test]
fn od_list_of_600_objects_in_a_128_byte_mailbox_takes_11_fragments() {
    let messages = transfer::<Big>(&[0x01, 0x00, 0x00, 0x00, 0x01, 0x00], MBX_128);
    assert_eq!(messages.len(), 11); // 1 + 600 words, 58 per fragment
    assert_eq!(
        messages[0][..12],
        [
            0x00, 0x80, 0x82, 0x00, 0x0A, 0x00, 0x01, 0x00, 0x00, 0x20, 0x01, 0x20
        ]
    );
    assert_eq!(
        messages[1][..8],
        [0x00, 0x80, 0x82, 0x00, 0x09, 0x00, 0x39, 0x20]
    );
    assert_eq!(messages[10].len(), 6 + 2 * 21);
    let values = reassemble(&messages, MBX_128);
    assert_eq!(values[0], 1, "the list type opens the first fragment only");
    assert_eq!(
        values[1..],
        (0..600).map(|i| 0x2000 + i).collect::<Vec<u16>>()[..]
    );
}

#[test]
fn od_list_of_600_objects_in_a_1024_byte_mailbox_takes_2_fragments() {
    let messages = transfer::<Big>(&[0x01, 0x00, 0x00, 0x00, 0x01, 0x00], MBX_1024);
    assert_eq!(messages.len(), 2);
    assert_eq!(messages[0].len(), MBX_1024); // list type + 505 indices
    assert_eq!(
        messages[0][..8],
        [0x00, 0x80, 0x82, 0x00, 0x01, 0x00, 0x01, 0x00]
    );
    assert_eq!(messages[1].len(), 6 + 2 * 95);
    assert_eq!(
        messages[1][..8],
        [0x00, 0x80, 0x02, 0x00, 0x00, 0x00, 0xF9, 0x21]
    );
    let values = reassemble(&messages, MBX_1024);
    assert_eq!(
        values[1..],
        (0..600).map(|i| 0x2000 + i).collect::<Vec<u16>>()[..]
    );
}

#[test]
fn a_filtered_od_list_is_fragmented_by_its_own_length() {
    let messages = transfer::<Big>(&[0x01, 0x00, 0x00, 0x00, 0x03, 0x00], MBX_128);
    assert_eq!(messages.len(), 4); // 1 + 200 words: 58, 58, 58, 27
    let values = reassemble(&messages, MBX_128);
    assert_eq!(values[0], 3);
    assert_eq!(
        values[1..],
        (0..600)
            .step_by(3)
            .map(|i| 0x2000 + i)
            .collect::<Vec<u16>>()[..]
    );

    let lengths = transfer::<Big>(&[0x01, 0x00, 0x00, 0x00, 0x00, 0x00], MBX_128);
    assert_eq!(
        lengths,
        [message(
            0x02,
            &[&[0x00, 0x00], &[0x58, 0x02, 0, 0, 0xC8, 0x00, 0, 0, 0, 0]]
        )]
    );
}

#[test]
fn od_list_fragments_never_split_a_word() {
    // 121 bytes of data: 115 after the headers, 57 words.
    let messages = transfer::<Big>(&[0x01, 0x00, 0x00, 0x00, 0x01, 0x00], 121);
    assert_eq!(messages.len(), 11); // 601 words, 57 per fragment
    assert!(messages[..10].iter().all(|m| m.len() == 6 + 114));
    let values = reassemble(&messages, 121);
    assert_eq!(
        values[1..],
        (0..600).map(|i| 0x2000 + i).collect::<Vec<u16>>()[..]
    );

    // The smallest message served: two words per fragment, even for list type 0.
    let lengths = transfer::<Od>(&[0x01, 0x00, 0x00, 0x00, 0x00, 0x00], 10);
    assert_eq!(
        lengths,
        [
            [headers(0x02, 2), vec![0x00, 0x00, 0x08, 0x00]].concat(),
            [headers(0x02, 1), vec![0x02, 0x00, 0x02, 0x00]].concat(),
            [headers(0x02, 0), vec![0x03, 0x00, 0x01, 0x00]].concat(),
        ]
    );
}

#[test]
fn a_new_request_abandons_the_fragmented_response() {
    let mut info = SdoInfo::new();
    let all = [0x01, 0x00, 0x00, 0x00, 0x01, 0x00];
    let first = ask_with::<Big>(&mut info, &all, MBX_128);
    assert!(next::<Big>(&mut info, MBX_128).is_some());
    assert!(info.is_pending());

    // The same request again starts over.
    assert_eq!(ask_with::<Big>(&mut info, &all, MBX_128), first);
    assert_eq!(next::<Big>(&mut info, MBX_128).unwrap()[6..8], [0x39, 0x20]);

    // Any other request ends it.
    assert_eq!(
        ask_with::<Big>(&mut info, &[0x03, 0x00, 0x00, 0x00, 0x00, 0x20], MBX_128),
        message(0x04, &[&[0x00, 0x20, 0x05, 0x00, 0x00, 0x07], b"Object"])
    );
    assert!(!info.is_pending());
    assert_eq!(next::<Big>(&mut info, MBX_128), None);

    // So does a refused one, and one too short to serve (the mailbox abandons it).
    ask_with::<Big>(&mut info, &all, MBX_128);
    assert_eq!(
        ask_with::<Big>(&mut info, &[0x02, 0x00, 0x00, 0x00], MBX_128),
        info_error(COMMAND_SPECIFIER)
    );
    assert!(!info.is_pending());
    ask_with::<Big>(&mut info, &all, MBX_128);
    info.abandon();
    assert!(!info.is_pending());
}

#[test]
fn a_buffer_too_small_for_a_fragment_abandons_the_response() {
    let mut info = SdoInfo::new();
    ask_with::<Big>(&mut info, &[0x01, 0x00, 0x00, 0x00, 0x01, 0x00], MBX_128);
    assert_eq!(next::<Big>(&mut info, 9), None);
    assert!(!info.is_pending());
    assert_eq!(next::<Big>(&mut info, MBX_128), None);
}

// --- Get Object Description ---------------------------------------------------------------

#[test]
fn object_description_of_a_var() {
    assert_eq!(
        ask(&[0x03, 0x00, 0x00, 0x00, 0x00, 0x10]),
        [
            0x00, 0x80, 0x04, 0x00, 0x00, 0x00, // CoE, object description response
            0x00, 0x10, 0x07, 0x00, 0x00, 0x07, // 0x1000, UNSIGNED32, max sub 0, VAR
            b'D', b'e', b'v', b'i', b'c', b'e', b' ', b't', b'y', b'p', b'e',
        ]
    );
}

#[test]
fn object_description_of_an_array_reports_the_element_type_and_count() {
    assert_eq!(
        ask(&[0x03, 0x00, 0x00, 0x00, 0x00, 0x20]),
        message(0x04, &[&[0x00, 0x20, 0x03, 0x00, 0x04, 0x08], b"Gains"])
    );
}

#[test]
fn object_description_of_a_record_reports_its_standard_type_and_the_highest_subindex() {
    // 0x1018: data type 0x0023 IDENTITY (SSC's DEFTYPE_IDENTITY), max sub 3, RECORD.
    assert_eq!(
        ask(&[0x03, 0x00, 0x00, 0x00, 0x18, 0x10]),
        message(
            0x04,
            &[&[0x18, 0x10, 0x23, 0x00, 0x03, 0x09], b"Identity object"]
        )
    );
    // An application's record has no type of its own: 0x0000.
    assert_eq!(
        ask(&[0x03, 0x00, 0x00, 0x00, 0x00, 0x70]),
        message(0x04, &[&[0x00, 0x70, 0x00, 0x00, 0x02, 0x09], b"Outputs"])
    );
}

#[test]
fn object_description_of_a_missing_object_is_an_error() {
    assert_eq!(
        ask(&[0x03, 0x00, 0x00, 0x00, 0x01, 0x10]),
        [0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x06]
    );
}

#[test]
fn a_long_name_is_cut_to_fit_at_a_character_boundary() {
    let mut info = SdoInfo::new();
    let mut object = |index: [u8; 2], capacity| {
        ask_with::<Od>(
            &mut info,
            &[0x03, 0x00, 0x00, 0x00, index[0], index[1]],
            capacity,
        )
    };
    assert_eq!(
        object([0x08, 0x10], 20),
        message(0x04, &[&[0x08, 0x10, 0x09, 0x00, 0x00, 0x07], b"Manufact"])
    );
    // "Réglage": 'é' is two bytes; 2 bytes of room hold "R" only, 3 hold "Ré".
    assert_eq!(
        object([0x01, 0x20], 14),
        message(0x04, &[&[0x01, 0x20, 0x05, 0x00, 0x00, 0x07], b"R"])
    );
    assert_eq!(
        object([0x01, 0x20], 15),
        message(
            0x04,
            &[&[0x01, 0x20, 0x05, 0x00, 0x00, 0x07], "Ré".as_bytes()]
        )
    );
    // No room for the fixed part: an error, and no room for an error: nothing.
    assert_eq!(object([0x00, 0x10], 11), info_error(EXCEEDS_MAILBOX));
    assert_eq!(
        object([0x00, 0x10], 12),
        message(0x04, &[&[0x00, 0x10, 0x07, 0x00, 0x00, 0x07]])
    );
    assert_eq!(object([0x00, 0x10], 9), []);
}

// --- Get Entry Description ----------------------------------------------------------------

/// Entry description of 0x607A:00 (all of unit, default, min, max declared) with `value_info`.
fn position(value_info: u8) -> Vec<u8> {
    ask(&[0x05, 0x00, 0x00, 0x00, 0x7A, 0x60, 0x00, value_info])
}

/// The fixed part of 0x607A:00's entry description with value info `vi`: INTEGER32, 32 bits,
/// access RW | RXPDO | BACKUP = 0x017F.
fn position_fixed(vi: u8) -> [u8; 10] {
    [0x7A, 0x60, 0x00, vi, 0x04, 0x00, 0x20, 0x00, 0x7F, 0x01]
}

const UNIT: [u8; 2] = [0x01, 0x00];
const DEFAULT: [u8; 4] = [0x05, 0x00, 0x00, 0x00];
const MIN: [u8; 4] = [0x18, 0xFC, 0xFF, 0xFF];
const MAX: [u8; 4] = [0xE8, 0x03, 0x00, 0x00];

#[test]
fn entry_description_with_value_info_0_has_no_optional_field() {
    assert_eq!(
        position(0x00),
        [
            0x00, 0x80, 0x06, 0x00, 0x00, 0x00, // CoE, entry description response
            0x7A, 0x60, 0x00, 0x00, // 0x607A:00, value info 0
            0x04, 0x00, 0x20, 0x00, 0x7F, 0x01, // INTEGER32, 32 bits, access 0x017F
            b'T', b'a', b'r', b'g', b'e', b't', b' ', b'p', b'o', b's', b'i', b't', b'i', b'o',
            b'n',
        ]
    );
}

#[test]
fn entry_description_carries_each_field_value_info_asks_for() {
    let name: &[u8] = b"Target position";
    assert_eq!(
        position(0x08),
        message(0x06, &[&position_fixed(0x08), &UNIT, name])
    );
    assert_eq!(
        position(0x10),
        message(0x06, &[&position_fixed(0x10), &DEFAULT, name])
    );
    assert_eq!(
        position(0x20),
        message(0x06, &[&position_fixed(0x20), &MIN, name])
    );
    assert_eq!(
        position(0x40),
        message(0x06, &[&position_fixed(0x40), &MAX, name])
    );
    assert_eq!(
        position(0x50),
        message(0x06, &[&position_fixed(0x50), &DEFAULT, &MAX, name])
    );
    assert_eq!(
        position(0x78),
        message(
            0x06,
            &[&position_fixed(0x78), &UNIT, &DEFAULT, &MIN, &MAX, name]
        )
    );
}

#[test]
fn entry_description_ignores_the_reserved_low_bits_of_value_info() {
    assert_eq!(position(0x7F), position(0x78));
    assert_eq!(position(0x07), position(0x00));
    assert_eq!(position(0x87)[9], 0x00, "bit 7 is not a field either");
}

#[test]
fn entry_description_clears_the_bits_of_undeclared_values() {
    // 0x6000: UNSIGNED32, RO | TXPDO, no default/min/max; the unit is always known (0).
    let fixed = |vi| [0x00, 0x60, 0x00, vi, 0x07, 0x00, 0x20, 0x00, 0x87, 0x00];
    let inputs = |vi| ask(&[0x05, 0x00, 0x00, 0x00, 0x00, 0x60, 0x00, vi]);
    assert_eq!(
        inputs(0x78),
        message(0x06, &[&fixed(0x08), &[0, 0], b"Inputs"])
    );
    assert_eq!(inputs(0x70), message(0x06, &[&fixed(0x00), b"Inputs"]));
    // 0x1018:01 declares a default only.
    assert_eq!(
        ask(&[0x05, 0x00, 0x00, 0x00, 0x18, 0x10, 0x01, 0x70]),
        message(
            0x06,
            &[
                &[0x18, 0x10, 0x01, 0x10, 0x07, 0x00, 0x20, 0x00, 0x07, 0x00],
                &[0x01, 0x00, 0x00, 0xE0],
                b"Vendor ID"
            ]
        )
    );
}

#[test]
fn entry_description_of_an_array_element_uses_the_element_description() {
    assert_eq!(
        ask(&[0x05, 0x00, 0x00, 0x00, 0x00, 0x20, 0x03, 0x78]),
        message(
            0x06,
            &[
                &[0x00, 0x20, 0x03, 0x78, 0x03, 0x00, 0x10, 0x00, 0xBF, 0x01], // INTEGER16, 16 bits, RW|TXPDO|BACKUP
                &[0xFD, 0x00],                                                 // unit
                &[0x0A, 0x00, 0x00, 0x00, 0xE8, 0x03], // default 10, min 0, max 1000
                b"Gain",
            ]
        )
    );
    // Its SI0: UNSIGNED8, read-only, no declared values.
    assert_eq!(
        ask(&[0x05, 0x00, 0x00, 0x00, 0x00, 0x20, 0x00, 0x78]),
        message(
            0x06,
            &[
                &[0x00, 0x20, 0x00, 0x08, 0x05, 0x00, 0x08, 0x00, 0x07, 0x00],
                &[0, 0],
                b"Number of entries"
            ]
        )
    );
}

#[test]
fn entry_description_of_a_record_si0() {
    assert_eq!(
        ask(&[0x05, 0x00, 0x00, 0x00, 0x00, 0x70, 0x00, 0x10]),
        message(
            0x06,
            &[
                &[0x00, 0x70, 0x00, 0x00, 0x05, 0x00, 0x08, 0x00, 0x07, 0x00],
                b"Highest sub-index supported"
            ]
        )
    );
}

#[test]
fn entry_description_of_a_missing_subindex_or_object_is_an_error() {
    let entry = |index: u16, sub: u8| {
        let [lo, hi] = index.to_le_bytes();
        ask(&[0x05, 0x00, 0x00, 0x00, lo, hi, sub, 0x00])
    };
    assert_eq!(
        entry(0x7000, 3),
        [0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x11, 0x00, 0x09, 0x06]
    );
    assert_eq!(
        entry(0x2000, 5),
        info_error(NO_SUBINDEX),
        "beyond the ARRAY"
    );
    assert_eq!(
        entry(0x1000, 1),
        info_error(NO_SUBINDEX),
        "a VAR has SI0 only"
    );
    assert_eq!(entry(0x1001, 0), info_error(NO_OBJECT));
}

/// A subindex a sparse RECORD does not declare below its highest one (0x1018:02 here; 0x1C32:0E
/// to :1F on a real device) is described as SSC describes it, not refused: SOEM's `ecx_readOE`
/// asks for every subindex 0..=max and records an SDO Info error for each refusal (22 per axis
/// before). Data type 0, bit length 0, access 0, value info 0 whatever was asked (no unit, no
/// value field), name `SubIndex NNN` (SSC 5.12 `OBJ_GetDesc` for an entry without a name).
#[test]
fn entry_description_of_a_gap_in_a_record_is_empty() {
    let gap = [
        0x00, 0x80, 0x06, 0x00, 0x00, 0x00, // CoE, entry description response
        0x18, 0x10, 0x02, 0x00, // 0x1018:02, value info 0
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // data type 0, bit length 0, access 0
        b'S', b'u', b'b', b'I', b'n', b'd', b'e', b'x', b' ', b'0', b'0', b'2',
    ];
    for value_info in [0x00, 0x07, 0x08, 0x78, 0xFF] {
        assert_eq!(
            ask(&[0x05, 0x00, 0x00, 0x00, 0x18, 0x10, 0x02, value_info]),
            gap,
            "value info {value_info:#04x}"
        );
    }
    // Three decimal digits, as SSC's "SubIndex 000" template.
    let sparse = |sub: u8| {
        ask_with::<Sparse>(
            &mut SdoInfo::new(),
            &[0x05, 0x00, 0x00, 0x00, 0x00, 0x30, sub, 0x00],
            MBX_128,
        )
    };
    let name = |sub: u8| sparse(sub)[16..].to_vec();
    assert_eq!(name(7), b"SubIndex 007");
    assert_eq!(name(0x1F), b"SubIndex 031");
    assert_eq!(name(0x64), b"SubIndex 100");
    assert_eq!(name(0xC7), b"SubIndex 199");
    assert_eq!(name(0xC8), b"Last", "declared");
    assert_eq!(sparse(0xC9), info_error(NO_SUBINDEX), "above the highest");
    // A name cut to the room, as any other: 16 bytes of headers and fixed part, then 4.
    let cut = ask_with::<Od>(
        &mut SdoInfo::new(),
        &[0x05, 0x00, 0x00, 0x00, 0x18, 0x10, 0x02, 0x00],
        20,
    );
    assert_eq!(cut, gap[..20]);
}

/// What SOEM's `ecx_readOE` does for an object: an entry description of every subindex
/// 0..=max (value info 7, as it sends), each answered with a description, never an error.
#[test]
fn every_subindex_up_to_the_highest_of_every_object_is_described() {
    fn each<D: ObjectDictionary>() {
        for object in D::OBJECTS {
            let [lo, hi] = object.info.index.to_le_bytes();
            for sub in 0..=object.info.max_sub {
                let request = [0x05, 0x00, 0x00, 0x00, lo, hi, sub, 0x07];
                let answer = ask_with::<D>(&mut SdoInfo::new(), &request, MBX_128);
                assert_eq!(answer[2], 0x06, "{:#06x}:{sub:#04x}", object.info.index);
                assert_eq!(answer[6..9], [lo, hi, sub]);
            }
        }
    }
    each::<Od>();
    each::<Sparse>();
}

struct Record {
    first: u8,
    last: u16,
}

struct Sparse {
    set: u8,
    record: Record,
}

ecat_core::dictionary! {
    minimal Sparse {
        0x2000 => var(set, RW, "Set");
        0x3000 => record(record: Record, "Sparse record") {
            1 => first, RO, "First";
            0xC8 => last, RO, "Last";
        };
    }
}

#[test]
fn a_string_default_fills_the_entry_bit_length() {
    // 0x1008: VISIBLE_STRING(8), default "ecat": 8 bytes, zero-padded.
    let fixed = |vi| [0x08, 0x10, 0x00, vi, 0x09, 0x00, 0x40, 0x00, 0x07, 0x00];
    let name: &[u8] = b"Manufacturer device name";
    assert_eq!(
        ask(&[0x05, 0x00, 0x00, 0x00, 0x08, 0x10, 0x00, 0x10]),
        message(0x06, &[&fixed(0x10), b"ecat\0\0\0\0", name])
    );
    // Room for the unit but not the default: the default is left out, its bit cleared, the name cut.
    let mut info = SdoInfo::new();
    assert_eq!(
        ask_with::<Od>(
            &mut info,
            &[0x05, 0x00, 0x00, 0x00, 0x08, 0x10, 0x00, 0x18],
            6 + 10 + 2 + 7
        ),
        message(0x06, &[&fixed(0x08), &[0, 0], b"Manufac"])
    );
    // No room for the fixed part.
    assert_eq!(
        ask_with::<Od>(
            &mut info,
            &[0x05, 0x00, 0x00, 0x00, 0x08, 0x10, 0x00, 0x00],
            15
        ),
        info_error(EXCEEDS_MAILBOX)
    );
}

// --- malformed requests -------------------------------------------------------------------

/// Shorter than the SDO Information header and the fixed part of the opcode: no request (the
/// mailbox answers with mailbox error 0x0008, `tests/tests/mailbox.rs`).
#[test]
fn a_request_without_its_header_or_fixed_part_does_not_parse() {
    for short in [
        &[][..],
        &[0x01],
        &[0x01, 0x00, 0x00],
        &[0x01, 0x00, 0x00, 0x00],
        &[0x01, 0x00, 0x00, 0x00, 0x01],
        &[0x03, 0x00, 0x00, 0x00, 0x00],
        &[0x05, 0x00, 0x00, 0x00, 0x7A, 0x60],
        &[0x05, 0x00, 0x00, 0x00, 0x7A, 0x60, 0x00],
    ] {
        assert_eq!(InfoRequest::parse(short), None, "{short:02x?}");
    }
}

#[test]
fn a_request_with_its_fixed_part_parses() {
    assert_eq!(
        InfoRequest::parse(&[0x01, 0x00, 0x00, 0x00, 0x01, 0x00]),
        Some(InfoRequest::OdList(1))
    );
    assert_eq!(
        InfoRequest::parse(&[0x03, 0x00, 0x00, 0x00, 0x00, 0x10]),
        Some(InfoRequest::ObjectDescription(0x1000))
    );
    assert_eq!(
        InfoRequest::parse(&[0x05, 0x00, 0x00, 0x00, 0x7A, 0x60, 0x00, 0x78]),
        Some(InfoRequest::EntryDescription {
            index: 0x607A,
            sub: 0,
            value_info: ValueInfo(0x78)
        })
    );
    assert_eq!(
        InfoRequest::parse(&[0x02, 0x00, 0x00, 0x00]),
        Some(InfoRequest::Unsupported),
        "other opcodes have no fixed part"
    );
}

#[test]
fn an_unknown_or_response_opcode_is_an_error() {
    for opcode in [0x00, 0x02, 0x04, 0x06, 0x07, 0x08, 0x7F, 0x82] {
        assert_eq!(
            ask(&[opcode, 0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00]),
            info_error(COMMAND_SPECIFIER),
            "opcode {opcode:#04x}"
        );
    }
}

#[test]
fn trailing_bytes_and_the_incomplete_bit_of_a_request_are_tolerated() {
    let plain = ask(&[0x03, 0x00, 0x00, 0x00, 0x00, 0x10]);
    assert_eq!(
        ask(&[0x03, 0x00, 0x00, 0x00, 0x00, 0x10, 0xAA, 0xBB]),
        plain
    );
    assert_eq!(ask(&[0x83, 0x00, 0x05, 0x00, 0x00, 0x10]), plain);
}

#[test]
fn a_buffer_too_small_for_an_error_gets_nothing() {
    let mut info = SdoInfo::new();
    let mut out = [0xEE; 9];
    assert_eq!(info.request::<Od>(InfoRequest::OdList(1), &mut out), 0);
    assert_eq!(info.request::<Od>(InfoRequest::Unsupported, &mut out), 0);
    assert_eq!(info.request::<Od>(InfoRequest::Unsupported, &mut []), 0);
    assert!(!info.is_pending());
    assert_eq!(info.next_fragment::<Od>(&mut out), None);
}

// --- a dictionary of 600 objects: 0x2000..=0x2257, every third TxPDO-mappable --------------

macro_rules! big_dictionary {
    ($($field:ident $index:literal $access:ident),* $(,)?) => {
        struct Big {
            $($field: u8,)*
        }

        ecat_core::dictionary! {
            minimal Big {
                $($index => var($field, $access, "Object");)*
            }
        }
    };
}

big_dictionary! {
    o000 0x2000 TXPDO, o001 0x2001 RO, o002 0x2002 RO, o003 0x2003 TXPDO, o004 0x2004 RO, o005 0x2005 RO,
    o006 0x2006 TXPDO, o007 0x2007 RO, o008 0x2008 RO, o009 0x2009 TXPDO, o010 0x200A RO, o011 0x200B RO,
    o012 0x200C TXPDO, o013 0x200D RO, o014 0x200E RO, o015 0x200F TXPDO, o016 0x2010 RO, o017 0x2011 RO,
    o018 0x2012 TXPDO, o019 0x2013 RO, o020 0x2014 RO, o021 0x2015 TXPDO, o022 0x2016 RO, o023 0x2017 RO,
    o024 0x2018 TXPDO, o025 0x2019 RO, o026 0x201A RO, o027 0x201B TXPDO, o028 0x201C RO, o029 0x201D RO,
    o030 0x201E TXPDO, o031 0x201F RO, o032 0x2020 RO, o033 0x2021 TXPDO, o034 0x2022 RO, o035 0x2023 RO,
    o036 0x2024 TXPDO, o037 0x2025 RO, o038 0x2026 RO, o039 0x2027 TXPDO, o040 0x2028 RO, o041 0x2029 RO,
    o042 0x202A TXPDO, o043 0x202B RO, o044 0x202C RO, o045 0x202D TXPDO, o046 0x202E RO, o047 0x202F RO,
    o048 0x2030 TXPDO, o049 0x2031 RO, o050 0x2032 RO, o051 0x2033 TXPDO, o052 0x2034 RO, o053 0x2035 RO,
    o054 0x2036 TXPDO, o055 0x2037 RO, o056 0x2038 RO, o057 0x2039 TXPDO, o058 0x203A RO, o059 0x203B RO,
    o060 0x203C TXPDO, o061 0x203D RO, o062 0x203E RO, o063 0x203F TXPDO, o064 0x2040 RO, o065 0x2041 RO,
    o066 0x2042 TXPDO, o067 0x2043 RO, o068 0x2044 RO, o069 0x2045 TXPDO, o070 0x2046 RO, o071 0x2047 RO,
    o072 0x2048 TXPDO, o073 0x2049 RO, o074 0x204A RO, o075 0x204B TXPDO, o076 0x204C RO, o077 0x204D RO,
    o078 0x204E TXPDO, o079 0x204F RO, o080 0x2050 RO, o081 0x2051 TXPDO, o082 0x2052 RO, o083 0x2053 RO,
    o084 0x2054 TXPDO, o085 0x2055 RO, o086 0x2056 RO, o087 0x2057 TXPDO, o088 0x2058 RO, o089 0x2059 RO,
    o090 0x205A TXPDO, o091 0x205B RO, o092 0x205C RO, o093 0x205D TXPDO, o094 0x205E RO, o095 0x205F RO,
    o096 0x2060 TXPDO, o097 0x2061 RO, o098 0x2062 RO, o099 0x2063 TXPDO, o100 0x2064 RO, o101 0x2065 RO,
    o102 0x2066 TXPDO, o103 0x2067 RO, o104 0x2068 RO, o105 0x2069 TXPDO, o106 0x206A RO, o107 0x206B RO,
    o108 0x206C TXPDO, o109 0x206D RO, o110 0x206E RO, o111 0x206F TXPDO, o112 0x2070 RO, o113 0x2071 RO,
    o114 0x2072 TXPDO, o115 0x2073 RO, o116 0x2074 RO, o117 0x2075 TXPDO, o118 0x2076 RO, o119 0x2077 RO,
    o120 0x2078 TXPDO, o121 0x2079 RO, o122 0x207A RO, o123 0x207B TXPDO, o124 0x207C RO, o125 0x207D RO,
    o126 0x207E TXPDO, o127 0x207F RO, o128 0x2080 RO, o129 0x2081 TXPDO, o130 0x2082 RO, o131 0x2083 RO,
    o132 0x2084 TXPDO, o133 0x2085 RO, o134 0x2086 RO, o135 0x2087 TXPDO, o136 0x2088 RO, o137 0x2089 RO,
    o138 0x208A TXPDO, o139 0x208B RO, o140 0x208C RO, o141 0x208D TXPDO, o142 0x208E RO, o143 0x208F RO,
    o144 0x2090 TXPDO, o145 0x2091 RO, o146 0x2092 RO, o147 0x2093 TXPDO, o148 0x2094 RO, o149 0x2095 RO,
    o150 0x2096 TXPDO, o151 0x2097 RO, o152 0x2098 RO, o153 0x2099 TXPDO, o154 0x209A RO, o155 0x209B RO,
    o156 0x209C TXPDO, o157 0x209D RO, o158 0x209E RO, o159 0x209F TXPDO, o160 0x20A0 RO, o161 0x20A1 RO,
    o162 0x20A2 TXPDO, o163 0x20A3 RO, o164 0x20A4 RO, o165 0x20A5 TXPDO, o166 0x20A6 RO, o167 0x20A7 RO,
    o168 0x20A8 TXPDO, o169 0x20A9 RO, o170 0x20AA RO, o171 0x20AB TXPDO, o172 0x20AC RO, o173 0x20AD RO,
    o174 0x20AE TXPDO, o175 0x20AF RO, o176 0x20B0 RO, o177 0x20B1 TXPDO, o178 0x20B2 RO, o179 0x20B3 RO,
    o180 0x20B4 TXPDO, o181 0x20B5 RO, o182 0x20B6 RO, o183 0x20B7 TXPDO, o184 0x20B8 RO, o185 0x20B9 RO,
    o186 0x20BA TXPDO, o187 0x20BB RO, o188 0x20BC RO, o189 0x20BD TXPDO, o190 0x20BE RO, o191 0x20BF RO,
    o192 0x20C0 TXPDO, o193 0x20C1 RO, o194 0x20C2 RO, o195 0x20C3 TXPDO, o196 0x20C4 RO, o197 0x20C5 RO,
    o198 0x20C6 TXPDO, o199 0x20C7 RO, o200 0x20C8 RO, o201 0x20C9 TXPDO, o202 0x20CA RO, o203 0x20CB RO,
    o204 0x20CC TXPDO, o205 0x20CD RO, o206 0x20CE RO, o207 0x20CF TXPDO, o208 0x20D0 RO, o209 0x20D1 RO,
    o210 0x20D2 TXPDO, o211 0x20D3 RO, o212 0x20D4 RO, o213 0x20D5 TXPDO, o214 0x20D6 RO, o215 0x20D7 RO,
    o216 0x20D8 TXPDO, o217 0x20D9 RO, o218 0x20DA RO, o219 0x20DB TXPDO, o220 0x20DC RO, o221 0x20DD RO,
    o222 0x20DE TXPDO, o223 0x20DF RO, o224 0x20E0 RO, o225 0x20E1 TXPDO, o226 0x20E2 RO, o227 0x20E3 RO,
    o228 0x20E4 TXPDO, o229 0x20E5 RO, o230 0x20E6 RO, o231 0x20E7 TXPDO, o232 0x20E8 RO, o233 0x20E9 RO,
    o234 0x20EA TXPDO, o235 0x20EB RO, o236 0x20EC RO, o237 0x20ED TXPDO, o238 0x20EE RO, o239 0x20EF RO,
    o240 0x20F0 TXPDO, o241 0x20F1 RO, o242 0x20F2 RO, o243 0x20F3 TXPDO, o244 0x20F4 RO, o245 0x20F5 RO,
    o246 0x20F6 TXPDO, o247 0x20F7 RO, o248 0x20F8 RO, o249 0x20F9 TXPDO, o250 0x20FA RO, o251 0x20FB RO,
    o252 0x20FC TXPDO, o253 0x20FD RO, o254 0x20FE RO, o255 0x20FF TXPDO, o256 0x2100 RO, o257 0x2101 RO,
    o258 0x2102 TXPDO, o259 0x2103 RO, o260 0x2104 RO, o261 0x2105 TXPDO, o262 0x2106 RO, o263 0x2107 RO,
    o264 0x2108 TXPDO, o265 0x2109 RO, o266 0x210A RO, o267 0x210B TXPDO, o268 0x210C RO, o269 0x210D RO,
    o270 0x210E TXPDO, o271 0x210F RO, o272 0x2110 RO, o273 0x2111 TXPDO, o274 0x2112 RO, o275 0x2113 RO,
    o276 0x2114 TXPDO, o277 0x2115 RO, o278 0x2116 RO, o279 0x2117 TXPDO, o280 0x2118 RO, o281 0x2119 RO,
    o282 0x211A TXPDO, o283 0x211B RO, o284 0x211C RO, o285 0x211D TXPDO, o286 0x211E RO, o287 0x211F RO,
    o288 0x2120 TXPDO, o289 0x2121 RO, o290 0x2122 RO, o291 0x2123 TXPDO, o292 0x2124 RO, o293 0x2125 RO,
    o294 0x2126 TXPDO, o295 0x2127 RO, o296 0x2128 RO, o297 0x2129 TXPDO, o298 0x212A RO, o299 0x212B RO,
    o300 0x212C TXPDO, o301 0x212D RO, o302 0x212E RO, o303 0x212F TXPDO, o304 0x2130 RO, o305 0x2131 RO,
    o306 0x2132 TXPDO, o307 0x2133 RO, o308 0x2134 RO, o309 0x2135 TXPDO, o310 0x2136 RO, o311 0x2137 RO,
    o312 0x2138 TXPDO, o313 0x2139 RO, o314 0x213A RO, o315 0x213B TXPDO, o316 0x213C RO, o317 0x213D RO,
    o318 0x213E TXPDO, o319 0x213F RO, o320 0x2140 RO, o321 0x2141 TXPDO, o322 0x2142 RO, o323 0x2143 RO,
    o324 0x2144 TXPDO, o325 0x2145 RO, o326 0x2146 RO, o327 0x2147 TXPDO, o328 0x2148 RO, o329 0x2149 RO,
    o330 0x214A TXPDO, o331 0x214B RO, o332 0x214C RO, o333 0x214D TXPDO, o334 0x214E RO, o335 0x214F RO,
    o336 0x2150 TXPDO, o337 0x2151 RO, o338 0x2152 RO, o339 0x2153 TXPDO, o340 0x2154 RO, o341 0x2155 RO,
    o342 0x2156 TXPDO, o343 0x2157 RO, o344 0x2158 RO, o345 0x2159 TXPDO, o346 0x215A RO, o347 0x215B RO,
    o348 0x215C TXPDO, o349 0x215D RO, o350 0x215E RO, o351 0x215F TXPDO, o352 0x2160 RO, o353 0x2161 RO,
    o354 0x2162 TXPDO, o355 0x2163 RO, o356 0x2164 RO, o357 0x2165 TXPDO, o358 0x2166 RO, o359 0x2167 RO,
    o360 0x2168 TXPDO, o361 0x2169 RO, o362 0x216A RO, o363 0x216B TXPDO, o364 0x216C RO, o365 0x216D RO,
    o366 0x216E TXPDO, o367 0x216F RO, o368 0x2170 RO, o369 0x2171 TXPDO, o370 0x2172 RO, o371 0x2173 RO,
    o372 0x2174 TXPDO, o373 0x2175 RO, o374 0x2176 RO, o375 0x2177 TXPDO, o376 0x2178 RO, o377 0x2179 RO,
    o378 0x217A TXPDO, o379 0x217B RO, o380 0x217C RO, o381 0x217D TXPDO, o382 0x217E RO, o383 0x217F RO,
    o384 0x2180 TXPDO, o385 0x2181 RO, o386 0x2182 RO, o387 0x2183 TXPDO, o388 0x2184 RO, o389 0x2185 RO,
    o390 0x2186 TXPDO, o391 0x2187 RO, o392 0x2188 RO, o393 0x2189 TXPDO, o394 0x218A RO, o395 0x218B RO,
    o396 0x218C TXPDO, o397 0x218D RO, o398 0x218E RO, o399 0x218F TXPDO, o400 0x2190 RO, o401 0x2191 RO,
    o402 0x2192 TXPDO, o403 0x2193 RO, o404 0x2194 RO, o405 0x2195 TXPDO, o406 0x2196 RO, o407 0x2197 RO,
    o408 0x2198 TXPDO, o409 0x2199 RO, o410 0x219A RO, o411 0x219B TXPDO, o412 0x219C RO, o413 0x219D RO,
    o414 0x219E TXPDO, o415 0x219F RO, o416 0x21A0 RO, o417 0x21A1 TXPDO, o418 0x21A2 RO, o419 0x21A3 RO,
    o420 0x21A4 TXPDO, o421 0x21A5 RO, o422 0x21A6 RO, o423 0x21A7 TXPDO, o424 0x21A8 RO, o425 0x21A9 RO,
    o426 0x21AA TXPDO, o427 0x21AB RO, o428 0x21AC RO, o429 0x21AD TXPDO, o430 0x21AE RO, o431 0x21AF RO,
    o432 0x21B0 TXPDO, o433 0x21B1 RO, o434 0x21B2 RO, o435 0x21B3 TXPDO, o436 0x21B4 RO, o437 0x21B5 RO,
    o438 0x21B6 TXPDO, o439 0x21B7 RO, o440 0x21B8 RO, o441 0x21B9 TXPDO, o442 0x21BA RO, o443 0x21BB RO,
    o444 0x21BC TXPDO, o445 0x21BD RO, o446 0x21BE RO, o447 0x21BF TXPDO, o448 0x21C0 RO, o449 0x21C1 RO,
    o450 0x21C2 TXPDO, o451 0x21C3 RO, o452 0x21C4 RO, o453 0x21C5 TXPDO, o454 0x21C6 RO, o455 0x21C7 RO,
    o456 0x21C8 TXPDO, o457 0x21C9 RO, o458 0x21CA RO, o459 0x21CB TXPDO, o460 0x21CC RO, o461 0x21CD RO,
    o462 0x21CE TXPDO, o463 0x21CF RO, o464 0x21D0 RO, o465 0x21D1 TXPDO, o466 0x21D2 RO, o467 0x21D3 RO,
    o468 0x21D4 TXPDO, o469 0x21D5 RO, o470 0x21D6 RO, o471 0x21D7 TXPDO, o472 0x21D8 RO, o473 0x21D9 RO,
    o474 0x21DA TXPDO, o475 0x21DB RO, o476 0x21DC RO, o477 0x21DD TXPDO, o478 0x21DE RO, o479 0x21DF RO,
    o480 0x21E0 TXPDO, o481 0x21E1 RO, o482 0x21E2 RO, o483 0x21E3 TXPDO, o484 0x21E4 RO, o485 0x21E5 RO,
    o486 0x21E6 TXPDO, o487 0x21E7 RO, o488 0x21E8 RO, o489 0x21E9 TXPDO, o490 0x21EA RO, o491 0x21EB RO,
    o492 0x21EC TXPDO, o493 0x21ED RO, o494 0x21EE RO, o495 0x21EF TXPDO, o496 0x21F0 RO, o497 0x21F1 RO,
    o498 0x21F2 TXPDO, o499 0x21F3 RO, o500 0x21F4 RO, o501 0x21F5 TXPDO, o502 0x21F6 RO, o503 0x21F7 RO,
    o504 0x21F8 TXPDO, o505 0x21F9 RO, o506 0x21FA RO, o507 0x21FB TXPDO, o508 0x21FC RO, o509 0x21FD RO,
    o510 0x21FE TXPDO, o511 0x21FF RO, o512 0x2200 RO, o513 0x2201 TXPDO, o514 0x2202 RO, o515 0x2203 RO,
    o516 0x2204 TXPDO, o517 0x2205 RO, o518 0x2206 RO, o519 0x2207 TXPDO, o520 0x2208 RO, o521 0x2209 RO,
    o522 0x220A TXPDO, o523 0x220B RO, o524 0x220C RO, o525 0x220D TXPDO, o526 0x220E RO, o527 0x220F RO,
    o528 0x2210 TXPDO, o529 0x2211 RO, o530 0x2212 RO, o531 0x2213 TXPDO, o532 0x2214 RO, o533 0x2215 RO,
    o534 0x2216 TXPDO, o535 0x2217 RO, o536 0x2218 RO, o537 0x2219 TXPDO, o538 0x221A RO, o539 0x221B RO,
    o540 0x221C TXPDO, o541 0x221D RO, o542 0x221E RO, o543 0x221F TXPDO, o544 0x2220 RO, o545 0x2221 RO,
    o546 0x2222 TXPDO, o547 0x2223 RO, o548 0x2224 RO, o549 0x2225 TXPDO, o550 0x2226 RO, o551 0x2227 RO,
    o552 0x2228 TXPDO, o553 0x2229 RO, o554 0x222A RO, o555 0x222B TXPDO, o556 0x222C RO, o557 0x222D RO,
    o558 0x222E TXPDO, o559 0x222F RO, o560 0x2230 RO, o561 0x2231 TXPDO, o562 0x2232 RO, o563 0x2233 RO,
    o564 0x2234 TXPDO, o565 0x2235 RO, o566 0x2236 RO, o567 0x2237 TXPDO, o568 0x2238 RO, o569 0x2239 RO,
    o570 0x223A TXPDO, o571 0x223B RO, o572 0x223C RO, o573 0x223D TXPDO, o574 0x223E RO, o575 0x223F RO,
    o576 0x2240 TXPDO, o577 0x2241 RO, o578 0x2242 RO, o579 0x2243 TXPDO, o580 0x2244 RO, o581 0x2245 RO,
    o582 0x2246 TXPDO, o583 0x2247 RO, o584 0x2248 RO, o585 0x2249 TXPDO, o586 0x224A RO, o587 0x224B RO,
    o588 0x224C TXPDO, o589 0x224D RO, o590 0x224E RO, o591 0x224F TXPDO, o592 0x2250 RO, o593 0x2251 RO,
    o594 0x2252 TXPDO, o595 0x2253 RO, o596 0x2254 RO, o597 0x2255 TXPDO, o598 0x2256 RO, o599 0x2257 RO,
}
