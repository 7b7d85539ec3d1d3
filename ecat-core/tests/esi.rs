//! The ESI writer (ETG.2000), exact text: escaping, access flags with state restrictions,
//! declared values as little-endian hex, complete-access bit offsets of records, BITn type names,
//! the Dc and Eeprom elements, and its errors. The agreement of whole files with the SII image and
//! the dictionary is `examples/host/tests/description.rs`.

use ecat_core::DeviceConfig;
use ecat_core::device::{Identity, MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::{Bits, ObjectDictionary, VisibleString};
use ecat_core::esi::{self, Description, EsiError};
use ecat_core::sii::Names;
use ecat_core::sync_mode::SupportedSyncModes;
use proptest::prelude::*;

struct Flags {
    a: bool,
    b: Bits<3>,
    c: u16,
}

/// The probe's dictionary; `SYNC` tells the declarations apart ([`Od`], [`OdDc`],
/// [`OdDcOnly`]), each with its own sync modes.
struct Od<const SYNC: u16 = 0> {
    device_type: u32,
    gain: i16,
    preop: u32,
    preop_safeop: u32,
    command: u8,
    saved: u16,
    status: u16,
    flags: Flags,
}

macro_rules! od {
    ($name:ident $(, $sync:expr)?) => {
ecat_core::dictionary! {
    minimal $name {
        $(sync($sync);)?
        0x1000 => var(device_type, RO, "Device type", default = 0x0003_0191);
        0x2000 => var(gain, RW, "Gain <&>", default = 5, min = -100, max = 1000);
        0x2001 => var(preop, RW_PREOP, "PREOP parameter");
        0x2002 => var(preop_safeop, RW_PREOP_SAFEOP, "PREOP/SAFEOP parameter");
        0x2003 => var(command, WO, "Command");
        0x2004 => var(saved, RW | BACKUP | SETTINGS, "Saved");
        0x6000 => var(status, RO | TXPDO, "Status");
        0x6001 => record(flags: Flags, "Flags") {
            1 => a, RO | TXPDO, "A";
            2 => b, RO | TXPDO, "B";
            3 => c, RW | RXPDO, "C", default = 0x1234;
        };
    }
}
    };
}

od!(Od);
/// [`Od`] with DC SYNC0 beside SM-synchronous.
type OdDc = Od<6>;
od!(
    OdDc,
    SupportedSyncModes(SupportedSyncModes::SM | SupportedSyncModes::SYNC0)
);
/// [`Od`] with DC SYNC0 only.
type OdDcOnly = Od<4>;
od!(OdDcOnly, SupportedSyncModes(SupportedSyncModes::SYNC0));

impl Default for Flags {
    fn default() -> Self {
        Self {
            a: false,
            b: Bits::default(),
            c: 0x1234,
        }
    }
}

const NAMES: Names<'static> = Names {
    name: "Probe \"A\" & 'B'",
    order_code: "P<1>",
    group: "Test & measurement",
};

const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 0x0000_0ABC,
    revision: 0x0002_0001,
    serial: 7,
};

fn config() -> DeviceConfig {
    DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes {
            outputs: 0,
            inputs: 2,
        },
    )
}

/// A stand-in SII image: 14 bytes of configuration area and more.
const SII: [u8; 20] = [
    0x05, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C, 0xAA, 0x00,
    0xFF, 0xFF, 0xFF, 0xFF,
];

fn esi<D: ObjectDictionary + Default>() -> String {
    esi_of::<D>(&config())
}

fn esi_of<D: ObjectDictionary + Default>(config: &DeviceConfig) -> String {
    let description = Description {
        vendor: "ACME <test>",
        names: &NAMES,
        identity: &IDENTITY,
        config,
    };
    let mut out = String::new();
    esi::write(&mut out, &description, &D::default(), &SII).unwrap();
    out
}

fn sm_only() -> String {
    esi::<Od>()
}

/// `fragment` occurs once, as whole lines.
fn has(xml: &str, fragment: &str) {
    assert_eq!(
        xml.matches(fragment).count(),
        1,
        "{fragment}\n--- in ---\n{xml}"
    );
}

#[test]
fn header_vendor_group_and_device_are_escaped() {
    let xml = sm_only();
    assert!(xml.starts_with(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<EtherCATInfo Version=\"1.6\">\n  <Vendor>\n    <Id>#xE0000001</Id>\n    <Name>ACME &lt;test&gt;</Name>\n  </Vendor>\n"
    ));
    has(
        &xml,
        "      <Group>\n        <Type>Test &amp; measurement</Type>\n        <Name>Test &amp; measurement</Name>\n      </Group>\n",
    );
    has(
        &xml,
        "        <Type ProductCode=\"#x00000ABC\" RevisionNo=\"#x00020001\">P&lt;1&gt;</Type>\n        <Name>Probe &quot;A&quot; &amp; &apos;B&apos;</Name>\n        <GroupType>Test &amp; measurement</GroupType>\n",
    );
    assert!(xml.ends_with("    </Devices>\n  </Descriptions>\n</EtherCATInfo>\n"));
}

#[test]
fn profile_number_and_additional_info_from_0x1000() {
    let xml = sm_only();
    has(
        &xml,
        "<Profile>\n          <ProfileNo>401</ProfileNo>\n          <AddInfo>3</AddInfo>\n          <Dictionary>\n",
    );
}

#[test]
fn declared_values_are_little_endian_hex_min_max_default() {
    has(
        &sm_only(),
        "<Index>#x2000</Index>
                <Name>Gain &lt;&amp;&gt;</Name>
                <Type>INT</Type>
                <BitSize>16</BitSize>
                <Info>
                  <MinData>9cff</MinData>
                  <MaxData>e803</MaxData>
                  <DefaultData>0500</DefaultData>
                </Info>
                <Flags>
                  <Access>rw</Access>
                </Flags>
",
    );
}

#[test]
fn access_with_state_restrictions_mapping_backup_and_setting() {
    let xml = sm_only();
    let flags = |index: &str, body: &str| {
        let object = xml.split("<Object>").find(|o| o.contains(index)).unwrap();
        let flags = object.split("<Flags>\n").nth(1).unwrap();
        let flags = flags.split("</Flags>").next().unwrap();
        let lines: Vec<&str> = flags
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        assert_eq!(lines.join("\n"), body, "{index}");
    };
    flags("#x1000", "<Access>ro</Access>");
    flags("#x2001", "<Access WriteRestrictions=\"PreOP\">rw</Access>");
    flags(
        "#x2002",
        "<Access WriteRestrictions=\"PreOP_SafeOP\">rw</Access>",
    );
    flags("#x2003", "<Access>wo</Access>");
    flags(
        "#x2004",
        "<Access>rw</Access>\n<Backup>1</Backup>\n<Setting>1</Setting>",
    );
    flags("#x6000", "<Access>ro</Access>\n<PdoMapping>T</PdoMapping>");
}

#[test]
fn record_type_with_complete_access_bit_offsets() {
    let xml = sm_only();
    let sub_item = |sub: u8, name: &str, ty: &str, bits: u16, offs: u16, flags: &str| {
        format!(
            "                <SubItem>
                  <SubIdx>{sub}</SubIdx>
                  <Name>{name}</Name>
                  <Type>{ty}</Type>
                  <BitSize>{bits}</BitSize>
                  <BitOffs>{offs}</BitOffs>
                  <Flags>
{flags}                  </Flags>
                </SubItem>
"
        )
    };
    let ro = "                    <Access>ro</Access>\n";
    let ro_t =
        "                    <Access>ro</Access>\n                    <PdoMapping>T</PdoMapping>\n";
    let rw_r =
        "                    <Access>rw</Access>\n                    <PdoMapping>R</PdoMapping>\n";
    // SI0 one byte and a pad byte; BOOL and BIT3 packed from bit 16; the UINT byte-aligned at 24.
    let expected = format!(
        "              <DataType>\n                <Name>DT6001</Name>\n                <BitSize>40</BitSize>\n{}{}{}{}              </DataType>\n",
        sub_item(0, "Highest sub-index supported", "USINT", 8, 0, ro),
        sub_item(1, "A", "BOOL", 1, 16, ro_t),
        sub_item(2, "B", "BIT3", 3, 17, ro_t),
        sub_item(3, "C", "UINT", 16, 24, rw_r),
    );
    has(&xml, &expected);
    // The object's Info: ETG.2000 (`ObjectInfoType/SubItem`) requires `Info` in every SubItem,
    // empty where nothing is declared (A, B).
    has(
        &xml,
        "<Index>#x6001</Index>
                <Name>Flags</Name>
                <Type>DT6001</Type>
                <BitSize>40</BitSize>
                <Info>
                  <SubItem>
                    <Name>Highest sub-index supported</Name>
                    <Info>
                      <DefaultData>03</DefaultData>
                    </Info>
                  </SubItem>
                  <SubItem>
                    <Name>A</Name>
                    <Info/>
                  </SubItem>
                  <SubItem>
                    <Name>B</Name>
                    <Info/>
                  </SubItem>
                  <SubItem>
                    <Name>C</Name>
                    <Info>
                      <DefaultData>3412</DefaultData>
                    </Info>
                  </SubItem>
                </Info>
              </Object>
",
    );
}

#[test]
fn base_types_once_each_in_order_of_first_use() {
    let xml = sm_only();
    let names: Vec<&str> = xml
        .split("<DataType>\n")
        .skip(1)
        .map(|t| {
            t.split("<Name>")
                .nth(1)
                .unwrap()
                .split("</Name>")
                .next()
                .unwrap()
        })
        .collect();
    assert_eq!(
        names,
        ["UDINT", "INT", "USINT", "UINT", "BOOL", "BIT3", "DT6001"]
    );
    has(
        &xml,
        "<Name>BIT3</Name>\n                <BitSize>3</BitSize>\n",
    );
}

#[test]
fn dc_op_modes_only_with_sync0_support() {
    assert!(!sm_only().contains("<Dc>"));
    let dc = "        <Dc>
          <OpMode>
            <Name>SM</Name>
            <Desc>SM-Synchron</Desc>
            <AssignActivate>#x0</AssignActivate>
          </OpMode>
          <OpMode>
            <Name>DC</Name>
            <Desc>DC-Synchron</Desc>
            <AssignActivate>#x300</AssignActivate>
            <CycleTimeSync0 Factor=\"1\">0</CycleTimeSync0>
            <ShiftTimeSync0>0</ShiftTimeSync0>
          </OpMode>
        </Dc>
";
    has(&esi::<OdDc>(), dc);
    let dc_only = esi::<OdDcOnly>();
    assert!(!dc_only.contains("<Name>SM</Name>"));
    has(&dc_only, "<Name>DC</Name>");
}

#[test]
fn mailbox_sync_managers_and_eeprom() {
    let xml = sm_only();
    has(
        &xml,
        "        <Fmmu>Inputs</Fmmu>
        <Fmmu>MBoxState</Fmmu>
        <Sm DefaultSize=\"128\" StartAddress=\"#x1000\" ControlByte=\"#x26\" Enable=\"1\">MBoxOut</Sm>
        <Sm DefaultSize=\"128\" StartAddress=\"#x1080\" ControlByte=\"#x22\" Enable=\"1\">MBoxIn</Sm>
        <Sm DefaultSize=\"0\" StartAddress=\"#x1100\" ControlByte=\"#x64\" Enable=\"0\">Outputs</Sm>
        <Sm DefaultSize=\"2\" StartAddress=\"#x1100\" ControlByte=\"#x20\" Enable=\"1\">Inputs</Sm>
        <Mailbox>
          <CoE SdoInfo=\"true\" PdoAssign=\"false\" PdoConfig=\"false\" CompleteAccess=\"true\"/>
        </Mailbox>
        <Eeprom>
          <ByteSize>20</ByteSize>
          <ConfigData>05000102030405060708090a0b0c</ConfigData>
        </Eeprom>
",
    );
    assert!(!xml.contains("<Fmmu>Outputs</Fmmu>"));
}

struct TooLong {
    text: VisibleString<300>,
}

ecat_core::dictionary! {
    minimal TooLong {
        0x1008 => var(text, RO, "Name", default = VisibleString::new(b"x"));
    }
}

#[test]
fn a_value_longer_than_the_buffer_is_an_error() {
    let config = config();
    let description = Description {
        vendor: "v",
        names: &NAMES,
        identity: &IDENTITY,
        config: &config,
    };
    let mut out = String::new();
    let od = TooLong {
        text: VisibleString::new(b"x"),
    };
    assert_eq!(
        esi::write(&mut out, &description, &od, &SII),
        Err(EsiError::ValueTooLong {
            index: 0x1008,
            sub: 0
        })
    );
}

/// Accepts `room` bytes, then refuses.
struct Limited {
    text: String,
    room: usize,
}

impl core::fmt::Write for Limited {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        if self.text.len() + s.len() > self.room {
            return Err(core::fmt::Error);
        }
        self.text.push_str(s);
        Ok(())
    }
}

proptest! {
    /// A writer that runs out anywhere gives `EsiError::Write` and a prefix of the file; with
    /// room for all of it, the whole file.
    #[test]
    fn a_refusing_writer_is_an_error_never_a_panic(share in 0.0f64..1.1) {
        let full = sm_only();
        let room = (full.len() as f64 * share) as usize;
        let config = config();
        let description = Description {
            vendor: "ACME <test>",
            names: &NAMES,
            identity: &IDENTITY,
            config: &config,
        };
        let mut out = Limited { text: String::new(), room };
        let result = esi::write(&mut out, &description, &<Od>::default(), &SII);
        prop_assert!(full.starts_with(&out.text));
        if room >= full.len() {
            prop_assert_eq!(result, Ok(()));
            prop_assert_eq!(out.text, full);
        } else {
            prop_assert_eq!(result, Err(EsiError::Write));
        }
    }
}

/// A device with an explicit device ID says so in `Device/Info/IdentificationReg134` (ETG.2000,
/// between `Name` and `GroupType`), as its SII General category's IdentALSts flag does; others
/// have no `Info`.
#[test]
fn explicit_device_id_is_advertised_in_device_info() {
    assert!(!sm_only().contains("<IdentificationReg134>"));
    let mut config = config();
    config.explicit_device_id = true;
    let description = Description {
        vendor: "v",
        names: &NAMES,
        identity: &IDENTITY,
        config: &config,
    };
    let mut xml = String::new();
    esi::write(&mut xml, &description, &<Od>::default(), &SII).unwrap();
    has(
        &xml,
        "        <Name>Probe &quot;A&quot; &amp; &apos;B&apos;</Name>
        <Info>
          <IdentificationReg134>true</IdentificationReg134>
        </Info>
        <GroupType>Test &amp; measurement</GroupType>
",
    );
}

/// A device with a bootstrap mailbox serves FoE in BOOT and says so in `Mailbox/FoE` (after
/// `CoE`, ETG.2000), as the SII's mailbox protocols word does (bit 3); others have no `FoE`.
#[test]
fn a_device_with_boot_advertises_foe() {
    assert!(!sm_only().contains("<FoE"));
    let mut config = config();
    config.bootstrap_mailbox = Some(MailboxConfig::contiguous(0x1800, 256));
    has(
        &esi_of::<Od>(&config),
        "        <Mailbox>
          <CoE SdoInfo=\"true\" PdoAssign=\"false\" PdoConfig=\"false\" CompleteAccess=\"true\"/>
          <FoE/>
        </Mailbox>
",
    );
}

struct Diagnosed {
    history: ecat_core::diagnosis::DiagnosisHistory<2>,
}

ecat_core::dictionary! {
    minimal Diagnosed {
        0x10F3 => diagnosis(history);
    }
}

/// A dictionary with the diagnosis history 0x10F3 (ETG.1020 §13): `CoE DiagHistory="true"`,
/// the messages' like entries named by subindex, and `Profile/DiagMessages` after the
/// dictionary with the text of each AL status code the stack logs.
#[test]
fn a_diagnosis_history_is_advertised_with_its_text_ids() {
    let config = config();
    let description = Description {
        vendor: "v",
        names: &NAMES,
        identity: &IDENTITY,
        config: &config,
    };
    let mut xml = String::new();
    let od = Diagnosed {
        history: Default::default(),
    };
    esi::write(&mut xml, &description, &od, &SII).unwrap();
    has(&xml, "DiagHistory=\"true\"/>");
    has(
        &xml,
        "
                <SubItem>
                  <SubIdx>7</SubIdx>
                  <Name>SubIndex 007</Name>
                  <Type>OCTET_STRING(28)</Type>
                  <BitSize>224</BitSize>
                  <BitOffs>288</BitOffs>
                  <Flags>
                    <Access>ro</Access>
                  </Flags>
                </SubItem>
              </DataType>",
    );
    has(
        &xml,
        "
          </Dictionary>
          <DiagMessages>
            <DiagMessage>
              <TextId>#x0001</TextId>
              <MessageText>unspecified error</MessageText>
            </DiagMessage>",
    );
    has(
        &xml,
        "
            <DiagMessage>
              <TextId>#x001A</TextId>
              <MessageText>synchronization error</MessageText>
            </DiagMessage>",
    );
    // The mailbox error replies the stack logs: text ID 0x0100 + the code (ETG.1000.4 Table 30).
    has(
        &xml,
        "
            <DiagMessage>
              <TextId>#x0102</TextId>
              <MessageText>mailbox error: mailbox protocol not supported</MessageText>
            </DiagMessage>",
    );
    assert!(xml.contains("<TextId>#x0108</TextId>"));
    assert!(!xml.contains("<TextId>#x0109</TextId>"));
    // Without 0x10F3: neither.
    assert!(!sm_only().contains("Diag"));
}
