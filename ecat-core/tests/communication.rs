//! The communication area as MainDevices see it (ETG.1000.6 §5.6.7.4, SSC's object
//! descriptions): object codes and data types in SDO Information and in the ESI file.

use ecat_core::DeviceConfig;
use ecat_core::coe::sdo_info::{InfoRequest, SdoInfo};
use ecat_core::device::{Identity, MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::{Communication, DeviceInfo, ObjectDictionary};
use ecat_core::esi::{self, Description};
use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
use ecat_core::sii::Names;

struct Od {
    area: Communication,
    rx: PdoMapping<2>,
    tx: PdoMapping<1>,
    rx_assign: PdoAssignment<1>,
    tx_assign: PdoAssignment<1>,
    outputs: [u8; 2],
    inputs: u16,
}

const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 0x0000_0C0E,
    revision: 1,
    serial: 1,
};

const INFO: DeviceInfo = DeviceInfo {
    device_type: 5001,
    name: "Probe",
    hardware_version: "1",
    software_version: "0.1.0",
    identity: IDENTITY,
};

const RX: [MappingEntry; 2] = [
    MappingEntry::new(0x7000, 1, 8),
    MappingEntry::new(0x7000, 2, 8),
];
const TX: [MappingEntry; 1] = [MappingEntry::new(0x6000, 0, 16)];

ecat_core::dictionary! {
    Od {
        communication(area, INFO);
        0x1600 => pdo(rx, RW_PREOP, "RxPDO", "Mapped object", default = PdoMapping::mapping(&RX));
        0x1A00 => pdo(tx, RO, "TxPDO", "Mapped object", default = PdoMapping::mapping(&TX));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x6000 => var(inputs, RO | TXPDO, "Inputs");
        0x7000 => array(outputs, RW | RXPDO, "Outputs", "Output");
    }
}

/// The fixed part of the object description of `index` (after the CoE and SDO Information
/// headers): index, data type, max subindex, object code.
fn description(index: u16) -> [u8; 6] {
    let [i0, i1] = index.to_le_bytes();
    let request = [0x03, 0x00, 0x00, 0x00, i0, i1];
    let mut out = [0u8; 122];
    let len = SdoInfo::new().request::<Od>(InfoRequest::parse(&request).unwrap(), &mut out);
    assert!(len >= 12, "{index:#06x}: {:02X?}", &out[..len]);
    assert_eq!(out[2], 0x04, "{index:#06x}: an object description response");
    out[6..12].try_into().unwrap()
}

/// SSC's codes and types: PDO mappings RECORD of 0x0021, 0x1018 RECORD of 0x0023, 0x1C32/0x1C33
/// RECORD of 0x0029, 0x1C12/0x1C13 ARRAY of UNSIGNED16, 0x1C00 ARRAY of UNSIGNED8.
#[test]
fn standard_objects_have_ssc_object_codes_and_data_types() {
    let cases = [
        (0x1018, [0x18, 0x10, 0x23, 0x00, 0x04, 0x09]),
        (0x1600, [0x00, 0x16, 0x21, 0x00, 0x02, 0x09]),
        (0x1A00, [0x00, 0x1A, 0x21, 0x00, 0x01, 0x09]),
        (0x1C00, [0x00, 0x1C, 0x05, 0x00, 0x04, 0x08]),
        (0x1C12, [0x12, 0x1C, 0x06, 0x00, 0x01, 0x08]),
        (0x1C13, [0x13, 0x1C, 0x06, 0x00, 0x01, 0x08]),
        (0x1C32, [0x32, 0x1C, 0x29, 0x00, 0x20, 0x09]),
        (0x1C33, [0x33, 0x1C, 0x29, 0x00, 0x20, 0x09]),
    ];
    for (index, expected) in cases {
        assert_eq!(description(index), expected, "{index:#06x}");
    }
}

/// A PDO mapping RECORD describes each of its entries as UNSIGNED32 with the object's access,
/// and has every subindex up to its capacity.
#[test]
fn a_pdo_mapping_record_has_like_entries_up_to_its_capacity() {
    let info = &Od::object(0x1600).unwrap().info;
    assert_eq!(info.subindices().collect::<Vec<_>>(), [0, 1, 2]);
    for sub in 1..=2 {
        let entry = info.entry(sub).unwrap();
        assert_eq!(
            (entry.data_type.code(), entry.bit_len, entry.access.0),
            (0x0007, 32, 0x000F)
        );
    }
    assert_eq!(info.entry(3), None);
}

/// In the ESI file a PDO mapping is a RECORD type with one SubItem per entry (SSC's DT1600),
/// an assignment an ARRAY of UINT.
#[test]
fn esi_describes_mappings_as_records_and_assignments_as_arrays() {
    let config = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes {
            outputs: 2,
            inputs: 2,
        },
    );
    let names = Names {
        name: "Probe",
        order_code: "P-1",
        group: "Tests",
    };
    let description = Description {
        vendor: "ACME",
        names: &names,
        identity: &IDENTITY,
        config: &config,
    };
    let mut xml = String::new();
    esi::write(&mut xml, &description, &Od::default(), &[0; 16]).unwrap();
    assert!(!xml.contains("DT1600ARR"), "{xml}");
    for sub in 0..=2 {
        let ty = if sub == 0 { "USINT" } else { "UDINT" };
        let item = format!("<SubIdx>{sub}</SubIdx>\n");
        let start = xml.find("<Name>DT1600</Name>").unwrap();
        let dt = &xml[start..start + xml[start..].find("</DataType>").unwrap()];
        assert!(dt.contains(&item), "SubIndex {sub} in {dt}");
        if sub > 0 {
            // Named by subindex, as SSC's ESI files name a mapping's entries.
            let compact: String = dt.split_whitespace().collect();
            let named = format!("<SubIdx>{sub}</SubIdx><Name>SubIndex{sub:03}</Name>");
            assert!(compact.contains(&named), "{named} in {dt}");
        }
        assert!(dt.contains(&format!("<Type>{ty}</Type>")), "{dt}");
    }
    assert!(xml.contains("<Name>DT1C12ARR</Name>\n"), "{xml}");
    assert!(xml.contains("<BaseType>UINT</BaseType>"), "{xml}");
}
