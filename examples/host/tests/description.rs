//! One description, three views: for every catalog device the dictionary, the SII image
//! (ETG.1000.6 §5.4, ETG.2010) and the ESI file (ETG.2000) are read back independently — the
//! image by the small SII reader below, the XML by `roxmltree` — and compared field by field.
//! Plus byte-exact checks of one SII image and the writer's buffer check.

use ecat_core::DeviceConfig;
use ecat_core::device::Identity;
use ecat_core::dictionary::{
    Access, At, DataType, EntryInfo, Limit, ObjectCode, ObjectDictionary, ObjectInfo,
};
use ecat_core::sii::{self, Names, SiiError};
use ecat_embassy::Application;
use ecat_emu::devices::{self, Sample};
use ecat_examples::catalog::{self, Visit};
use ecat_examples::description;
use roxmltree::{Document, Node};

// --- a small SII reader (ETG.2010), independent of the writer ---------------------------------

struct Sii<'a>(&'a [u8]);

/// One PDO of an SII PDO category: index, SM, name, entries (index, sub, name, type, bits).
#[derive(Debug, PartialEq)]
struct SiiPdo {
    index: u16,
    sm: u8,
    name: String,
    entries: Vec<(u16, u8, String, u8, u8)>,
}

impl<'a> Sii<'a> {
    fn word(&self, word: usize) -> u16 {
        u16::from_le_bytes([self.0[2 * word], self.0[2 * word + 1]])
    }

    fn dword(&self, word: usize) -> u32 {
        u32::from(self.word(word)) | u32::from(self.word(word + 1)) << 16
    }

    /// The categories from word 0x40 on: type and body, up to the end marker.
    fn categories(&self) -> Vec<(u16, &'a [u8])> {
        let mut at = 0x80;
        let mut out = Vec::new();
        loop {
            let kind = u16::from_le_bytes([self.0[at], self.0[at + 1]]);
            if kind == 0xFFFF {
                assert_eq!(at + 2, self.0.len(), "the end marker ends the image");
                return out;
            }
            let words = usize::from(u16::from_le_bytes([self.0[at + 2], self.0[at + 3]]));
            out.push((kind, &self.0[at + 4..at + 4 + 2 * words]));
            at += 4 + 2 * words;
        }
    }

    fn category(&self, kind: u16) -> Option<&'a [u8]> {
        self.categories()
            .into_iter()
            .find(|(k, _)| *k == kind)
            .map(|(_, body)| body)
    }

    /// String `index` (1-based) of the Strings category; "" for 0.
    fn string(&self, index: u8) -> String {
        let body = self.category(10).expect("Strings category");
        let mut at = 1;
        for n in 1..=body[0] {
            let len = usize::from(body[at]);
            if n == index {
                return String::from_utf8(body[at + 1..at + 1 + len].to_vec()).unwrap();
            }
            at += 1 + len;
        }
        String::new()
    }

    /// SM category entries: start, length, control, enable, type.
    fn sync_managers(&self) -> Vec<(u16, u16, u8, u8, u8)> {
        let body = self.category(41).expect("SyncManager category");
        body.chunks(8)
            .map(|c| {
                let word = |i: usize| u16::from_le_bytes([c[i], c[i + 1]]);
                (word(0), word(2), c[4], c[6], c[7])
            })
            .collect()
    }

    fn pdos(&self, kind: u16) -> Vec<SiiPdo> {
        let Some(body) = self.category(kind) else {
            return Vec::new();
        };
        let mut at = 0;
        let mut out = Vec::new();
        while at + 8 <= body.len() {
            let word = |i: usize| u16::from_le_bytes([body[i], body[i + 1]]);
            let (index, n, sm, name) = (word(at), body[at + 2], body[at + 3], body[at + 5]);
            at += 8;
            let mut entries = Vec::new();
            for _ in 0..n {
                let e = &body[at..at + 8];
                entries.push((
                    u16::from_le_bytes([e[0], e[1]]),
                    e[2],
                    self.string(e[3]),
                    e[4],
                    e[5],
                ));
                at += 8;
            }
            out.push(SiiPdo {
                index,
                sm,
                name: self.string(name),
                entries,
            });
        }
        out
    }
}

// --- ESI helpers --------------------------------------------------------------------------------

fn child<'a, 'i>(node: Node<'a, 'i>, name: &str) -> Node<'a, 'i> {
    node.children()
        .find(|c| c.has_tag_name(name))
        .unwrap_or_else(|| panic!("<{}> has no <{name}>", node.tag_name().name()))
}

fn children<'a, 'i>(node: Node<'a, 'i>, name: &str) -> Vec<Node<'a, 'i>> {
    node.children().filter(|c| c.has_tag_name(name)).collect()
}

fn text<'a>(node: Node<'a, '_>, name: &str) -> &'a str {
    child(node, name).text().unwrap_or("")
}

fn opt_text<'a>(node: Node<'a, '_>, name: &str) -> Option<&'a str> {
    node.children()
        .find(|c| c.has_tag_name(name))
        .map(|c| c.text().unwrap_or(""))
}

/// An ETG.2000 HexDecValue: `#x` hex or decimal.
fn number(s: &str) -> u64 {
    match s.strip_prefix("#x") {
        Some(hex) => u64::from_str_radix(hex, 16).unwrap(),
        None => s.parse().unwrap(),
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

// --- the dictionary's side ------------------------------------------------------------------

fn read<D: ObjectDictionary>(od: &D, index: u16, sub: u8) -> Vec<u8> {
    let object = D::object(index).unwrap();
    let mut buf = [0u8; 256];
    let n = (object.read)(od, At::start(sub), &mut buf)
        .unwrap()
        .copied();
    buf[..n].to_vec()
}

fn read_u32<D: ObjectDictionary>(od: &D, index: u16, sub: u8) -> u32 {
    let mut bytes = read(od, index, sub);
    bytes.resize(4, 0);
    u32::from_le_bytes(bytes.try_into().unwrap())
}

/// The default PDOs of the assignment object `assign`: (index, name, [(index, sub, bits)]).
type DictPdo = (u16, &'static str, Vec<(u16, u8, u8)>);

fn dictionary_pdos<D: ObjectDictionary>(od: &D, assign: u16) -> Vec<DictPdo> {
    if D::object(assign).is_none() {
        return Vec::new();
    }
    (1..=read(od, assign, 0)[0])
        .map(|n| {
            let pdo = read_u32(od, assign, n) as u16;
            let entries = (1..=read(od, pdo, 0)[0])
                .map(|s| {
                    let e = read_u32(od, pdo, s);
                    ((e >> 16) as u16, (e >> 8) as u8, e as u8)
                })
                .collect();
            (pdo, D::name(D::object(pdo).unwrap().info.name), entries)
        })
        .collect()
}

/// The ESI base type name of an entry (ETG.2000, ETG.1020 base types).
fn type_name(entry: &EntryInfo) -> String {
    match entry.data_type {
        DataType::Boolean => "BOOL".into(),
        DataType::Integer8 => "SINT".into(),
        DataType::Integer16 => "INT".into(),
        DataType::Integer32 => "DINT".into(),
        DataType::Integer64 => "LINT".into(),
        DataType::Unsigned8 => "USINT".into(),
        DataType::Unsigned16 => "UINT".into(),
        DataType::Unsigned32 => "UDINT".into(),
        DataType::Unsigned64 => "ULINT".into(),
        DataType::Real32 => "REAL".into(),
        DataType::Real64 => "LREAL".into(),
        DataType::VisibleString => format!("STRING({})", entry.bit_len / 8),
        DataType::OctetString => format!("OCTET_STRING({})", entry.bit_len / 8),
        other => panic!("no sample uses {other:?}"),
    }
}

/// The `Access` element of an entry: text and (ReadRestrictions, WriteRestrictions).
fn expected_access(access: Access) -> (&'static str, Option<String>, Option<String>) {
    let states = |bits: u16| {
        let names = [(1, "PreOP"), (2, "SafeOP"), (4, "OP")];
        let list: Vec<_> = names
            .iter()
            .filter(|(b, _)| bits & b != 0)
            .map(|(_, n)| *n)
            .collect();
        (bits != 0 && bits != 7).then(|| list.join("_"))
    };
    let (read, write) = (access.0 & 7, (access.0 >> 3) & 7);
    let text = match (read != 0, write != 0) {
        (true, true) => "rw",
        (false, true) => "wo",
        _ => "ro",
    };
    (text, states(read), states(write))
}

fn check_flags(flags: Node, access: Access, what: &str) {
    let node = child(flags, "Access");
    let (text, read, write) = expected_access(access);
    assert_eq!(node.text(), Some(text), "{what}: access");
    assert_eq!(
        node.attribute("ReadRestrictions"),
        read.as_deref(),
        "{what}"
    );
    assert_eq!(
        node.attribute("WriteRestrictions"),
        write.as_deref(),
        "{what}"
    );
    let mapping = match (access.rxpdo(), access.txpdo()) {
        (true, true) => Some("RT"),
        (true, false) => Some("R"),
        (false, true) => Some("T"),
        (false, false) => None,
    };
    assert_eq!(opt_text(flags, "PdoMapping"), mapping, "{what}: PdoMapping");
    assert_eq!(
        opt_text(flags, "Backup").is_some(),
        access.backup(),
        "{what}"
    );
    assert_eq!(
        opt_text(flags, "Setting").is_some(),
        access.settings(),
        "{what}"
    );
}

/// The declared values of `index:sub` as the ESI `Info` must carry them.
fn check_values<D: ObjectDictionary>(info: Option<Node>, index: u16, sub: u8) {
    let object = D::object(index).unwrap();
    for (limit, tag) in [
        (Limit::Min, "MinData"),
        (Limit::Max, "MaxData"),
        (Limit::Default, "DefaultData"),
    ] {
        let mut buf = [0u8; 256];
        let n = object.limit(sub, limit, &mut buf);
        let expected = (n > 0).then(|| hex(&buf[..n]));
        let actual = info.and_then(|i| opt_text(i, tag)).map(str::to_owned);
        assert_eq!(actual, expected, "{index:#06x}:{sub} {tag}");
    }
}

/// The complete-access bit offsets (ETG.1000.6 §5.6.2.1.2): SI0 one byte plus a pad byte, then
/// the entries, byte-sized ones byte-aligned; and the total bits.
fn complete_access_layout(info: &ObjectInfo) -> (Vec<usize>, usize) {
    let mut bit = 16usize;
    let mut offsets = vec![0];
    let subs: Vec<u8> = info.subindices().filter(|s| *s > 0).collect();
    for sub in subs {
        let len = usize::from(info.entry(sub).unwrap().bit_len);
        if len % 8 == 0 {
            bit = bit.div_ceil(8) * 8;
        }
        offsets.push(bit);
        bit += len;
    }
    (offsets, bit.div_ceil(8) * 8)
}

// --- the consistency check ---------------------------------------------------------------------

struct Consistent;

impl Visit for Consistent {
    type Output = ();
    fn visit<A, C, D>(self, sample: Sample<A, C, D>)
    where
        A: Application<D> + 'static,
        C: Application<D> + 'static,
        D: ObjectDictionary,
    {
        let files = description::of(&sample).unwrap();
        let doc = Document::parse(&files.esi).expect("the ESI file is well-formed XML");
        let sii = Sii(&files.sii);
        assert_eq!(
            files.sii, sample.device.eeprom,
            "the image the device runs with"
        );
        let od = &sample.device.od;
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "EtherCATInfo");
        let device = child(child(child(root, "Descriptions"), "Devices"), "Device");
        identity(&sample.identity, od, &sii, root, device);
        names(&sample.names, &sii, root, device);
        sync_managers(&sample.device.config, od, &sii, device);
        fmmus(&sii, device);
        pdos(od, &sii, device);
        coe(od, &sii, device);
        objects(od, child(child(device, "Profile"), "Dictionary"));
        eeprom(&files.sii, device);
    }
}

fn identity<D: ObjectDictionary>(id: &Identity, od: &D, sii: &Sii, root: Node, device: Node) {
    let words = [sii.dword(8), sii.dword(10), sii.dword(12), sii.dword(14)];
    assert_eq!(
        words,
        [id.vendor_id, id.product_code, id.revision, id.serial]
    );
    let dictionary: Vec<u32> = (1..=4).map(|s| read_u32(od, 0x1018, s)).collect();
    assert_eq!(dictionary, words);
    assert_eq!(
        number(text(child(root, "Vendor"), "Id")),
        u64::from(id.vendor_id)
    );
    let kind = child(device, "Type");
    assert_eq!(
        number(kind.attribute("ProductCode").unwrap()),
        u64::from(id.product_code)
    );
    assert_eq!(
        number(kind.attribute("RevisionNo").unwrap()),
        u64::from(id.revision)
    );
}

fn names(names: &Names, sii: &Sii, root: Node, device: Node) {
    let general = sii.category(30).expect("General category");
    assert_eq!(sii.string(general[0]), names.group);
    assert_eq!(sii.string(general[2]), names.order_code);
    assert_eq!(sii.string(general[3]), names.name);
    assert_eq!(text(device, "Type"), names.order_code);
    assert_eq!(text(device, "Name"), names.name);
    assert_eq!(text(device, "GroupType"), names.group);
    let group = child(child(child(root, "Descriptions"), "Groups"), "Group");
    assert_eq!(text(group, "Type"), names.group);
    assert_eq!(text(group, "Name"), names.group);
}

fn sync_managers<D: ObjectDictionary>(config: &DeviceConfig, od: &D, sii: &Sii, device: Node) {
    let m = config.mailbox;
    let words: Vec<u16> = (0x18..0x1C).map(|w| sii.word(w)).collect();
    assert_eq!(
        words,
        [
            m.receive.start,
            m.receive.length,
            m.send.start,
            m.send.length
        ]
    );
    let image_bytes = |assign| {
        let bits: u32 = dictionary_pdos(od, assign)
            .iter()
            .flat_map(|(_, _, entries)| entries.iter().map(|e| u32::from(e.2)))
            .sum();
        bits.div_ceil(8) as u16
    };
    let (outputs, inputs) = (image_bytes(0x1C12), image_bytes(0x1C13));
    let sms = sii.sync_managers();
    assert_eq!(sms.len(), 4);
    assert_eq!(sms[0], (m.receive.start, m.receive.length, 0x26, 1, 1));
    assert_eq!(sms[1], (m.send.start, m.send.length, 0x22, 1, 2));
    assert_eq!(
        (sms[2].1, sms[2].2, sms[2].3, sms[2].4),
        (outputs, 0x64, u8::from(outputs > 0), 3)
    );
    assert_eq!(
        (sms[3].1, sms[3].2, sms[3].3, sms[3].4),
        (inputs, 0x20, u8::from(inputs > 0), 4)
    );
    // 0x1C00, where the dictionary has it, gives each SM the type the SII gives it.
    if D::object(0x1C00).is_some() {
        let types: Vec<Vec<u8>> = (1..=4).map(|sub| read(od, 0x1C00, sub)).collect();
        let sii_types: Vec<Vec<u8>> = sms.iter().map(|sm| vec![sm.4]).collect();
        assert_eq!(types, sii_types, "0x1C00 = SII SM types");
    }
    // SM2 after the mailboxes, SM3 after three SM2 buffers of the largest output image an
    // assignment can make (every RxPDO mapping object declared), 8-byte aligned.
    let all_rx_bits: u32 = D::OBJECTS
        .iter()
        .map(|o| o.info.index)
        .filter(|i| (0x1600..=0x17FF).contains(i))
        .map(|index| {
            let n = read(od, index, 0)[0];
            (1..=n)
                .map(|sub| {
                    let entry = read(od, index, sub);
                    u32::from(entry[0])
                })
                .sum::<u32>()
        })
        .sum();
    let reserved = outputs.max(all_rx_bits.div_ceil(8) as u16);
    // After the bootstrap mailbox too, where it lies beyond (dio-update's).
    let boot_end = config.bootstrap_mailbox.map_or(0, |b| b.send.end());
    assert_eq!(
        u32::from(sms[2].0),
        m.send.end().max(boot_end).div_ceil(8) * 8
    );
    assert_eq!(sms[3].0, (sms[2].0 + 3 * reserved).div_ceil(8) * 8);
    let esi = children(device, "Sm");
    let kinds = ["MBoxOut", "MBoxIn", "Outputs", "Inputs"];
    assert_eq!(esi.len(), 4);
    for ((sm, node), kind) in sms.iter().zip(&esi).zip(kinds) {
        assert_eq!(node.text(), Some(kind));
        assert_eq!(
            number(node.attribute("StartAddress").unwrap()),
            u64::from(sm.0)
        );
        assert_eq!(
            number(node.attribute("DefaultSize").unwrap()),
            u64::from(sm.1)
        );
        assert_eq!(
            number(node.attribute("ControlByte").unwrap()),
            u64::from(sm.2)
        );
        assert_eq!(number(node.attribute("Enable").unwrap()), u64::from(sm.3));
    }
}

fn fmmus(sii: &Sii, device: Node) {
    let names = ["", "Outputs", "Inputs", "MBoxState"];
    let body = sii.category(40).expect("FMMU category");
    let from_sii: Vec<&str> = body
        .iter()
        .filter(|&&u| u != 0)
        .map(|&u| names[usize::from(u)])
        .collect();
    let sms = sii.sync_managers();
    let mut expected = Vec::new();
    if sms[2].1 > 0 {
        expected.push("Outputs");
    }
    if sms[3].1 > 0 {
        expected.push("Inputs");
    }
    expected.push("MBoxState");
    assert_eq!(from_sii, expected);
    let esi: Vec<&str> = children(device, "Fmmu")
        .iter()
        .map(|n| n.text().unwrap())
        .collect();
    assert_eq!(esi, expected);
}

fn pdos<D: ObjectDictionary>(od: &D, sii: &Sii, device: Node) {
    for (assign, category, tag, sm) in [(0x1C12, 51, "RxPdo", 2), (0x1C13, 50, "TxPdo", 3)] {
        let dictionary = dictionary_pdos(od, assign);
        let from_sii = sii.pdos(category);
        // The assigned PDOs carry their SyncManager; the others are alternatives a MainDevice
        // may assign instead: mapping objects of the dictionary that the default assignment
        // leaves out, excluding (with a single-PDO assignment) every other PDO.
        let (esi, alternatives): (Vec<Node>, Vec<Node>) = children(device, tag)
            .into_iter()
            .partition(|n| n.attribute("Sm").is_some());
        let all: Vec<u64> = children(device, tag)
            .iter()
            .map(|n| number(text(*n, "Index")))
            .collect();
        let single = D::object(assign).is_some_and(|a| a.info.max_sub <= 1);
        for alternative in &alternatives {
            let index = number(text(*alternative, "Index"));
            let object = D::object(u16::try_from(index).unwrap()).expect("declared");
            assert_eq!(text(*alternative, "Name"), D::name(object.info.name));
            assert!(dictionary.iter().all(|(i, _, _)| u64::from(*i) != index));
        }
        for pdo in children(device, tag) {
            let index = number(text(pdo, "Index"));
            let excluded: Vec<u64> = children(pdo, "Exclude")
                .iter()
                .map(|n| number(n.text().unwrap()))
                .collect();
            let others: Vec<u64> = all.iter().copied().filter(|&i| i != index).collect();
            assert_eq!(
                excluded,
                if single { others } else { Vec::new() },
                "{index:#x}"
            );
        }
        assert_eq!(from_sii.len(), dictionary.len(), "{tag}");
        assert_eq!(esi.len(), dictionary.len(), "{tag}");
        for (((index, name, entries), s), e) in dictionary.iter().zip(&from_sii).zip(&esi) {
            let fixed = !D::object(*index)
                .unwrap()
                .info
                .entry(0)
                .unwrap()
                .access
                .writable();
            assert_eq!((s.index, s.sm, s.name.as_str()), (*index, sm, *name));
            assert_eq!(number(text(*e, "Index")), u64::from(*index));
            assert_eq!(text(*e, "Name"), *name);
            assert_eq!(number(e.attribute("Sm").unwrap()), u64::from(sm));
            assert_eq!(
                e.attribute("Fixed"),
                fixed.then_some("true"),
                "{index:#06x}"
            );
            let esi_entries = children(*e, "Entry");
            assert_eq!(s.entries.len(), entries.len());
            assert_eq!(esi_entries.len(), entries.len());
            for ((&(i, sub, bits), se), ee) in entries.iter().zip(&s.entries).zip(&esi_entries) {
                let info = D::object(i).and_then(|o| o.info.entry(sub));
                let (name, code) =
                    info.map_or(("", 0), |e| (D::name(e.name), e.data_type.code() as u8));
                assert_eq!(*se, (i, sub, name.to_owned(), code, bits));
                assert_eq!(number(text(*ee, "Index")), u64::from(i));
                assert_eq!(number(text(*ee, "BitLen")), u64::from(bits));
                match info {
                    Some(info) => {
                        assert_eq!(number(text(*ee, "SubIndex")), u64::from(sub));
                        assert_eq!(text(*ee, "Name"), D::name(info.name));
                        assert_eq!(text(*ee, "DataType"), type_name(info));
                    }
                    None => assert_eq!(opt_text(*ee, "Name"), None, "a gap has no name"),
                }
            }
        }
    }
}

fn coe<D: ObjectDictionary>(od: &D, sii: &Sii, device: Node) {
    let general = sii.category(30).unwrap();
    let details = general[5];
    let writable =
        |index| D::object(index).is_some_and(|o| o.info.entry(0).unwrap().access.writable());
    let assign = writable(0x1C12) || writable(0x1C13);
    let config = [0x1C12, 0x1C13]
        .iter()
        .flat_map(|&a| dictionary_pdos(od, a))
        .any(|(pdo, _, _)| writable(pdo));
    let expected =
        0x01 | 0x02 | 0x20 | if assign { 0x04 } else { 0 } | if config { 0x08 } else { 0 };
    assert_eq!(details, expected);
    let node = child(child(device, "Mailbox"), "CoE");
    let flag = |bit: u8| if details & bit != 0 { "true" } else { "false" };
    assert_eq!(node.attribute("SdoInfo"), Some(flag(0x02)));
    assert_eq!(node.attribute("PdoAssign"), Some(flag(0x04)));
    assert_eq!(node.attribute("PdoConfig"), Some(flag(0x08)));
    assert_eq!(node.attribute("CompleteAccess"), Some(flag(0x20)));
}

fn objects<D: ObjectDictionary>(od: &D, dictionary: Node) {
    let types = children(child(dictionary, "DataTypes"), "DataType");
    let data_type = |name: &str| {
        let found: Vec<_> = types.iter().filter(|t| text(**t, "Name") == name).collect();
        assert_eq!(found.len(), 1, "one DataType {name}");
        *found[0]
    };
    let esi_objects = children(child(dictionary, "Objects"), "Object");
    assert_eq!(esi_objects.len(), D::OBJECTS.len());
    for (object, node) in D::OBJECTS.iter().zip(&esi_objects) {
        let info = &object.info;
        assert_eq!(text(*node, "Index"), format!("#x{:04X}", info.index));
        assert_eq!(text(*node, "Name"), D::name(info.name));
        for entry in info.entries {
            let base = data_type(&type_name(entry));
            assert_eq!(number(text(base, "BitSize")), u64::from(entry.bit_len));
        }
        if info.code == ObjectCode::Var {
            let entry = &info.entries[0];
            assert_eq!(text(*node, "Type"), type_name(entry));
            assert_eq!(number(text(*node, "BitSize")), u64::from(entry.bit_len));
            check_flags(child(*node, "Flags"), entry.access, D::name(info.name));
            let values = node.children().find(|c| c.has_tag_name("Info"));
            check_values::<D>(values, info.index, 0);
            continue;
        }
        let name = format!("DT{:04X}", info.index);
        assert_eq!(text(*node, "Type"), name);
        let dt = data_type(&name);
        let (offsets, bits) = complete_access_layout(info);
        assert_eq!(number(text(*node, "BitSize")), bits as u64);
        assert_eq!(number(text(dt, "BitSize")), bits as u64);
        let items = children(dt, "SubItem");
        let si0 = info.entry(0).unwrap();
        assert_eq!(number(text(items[0], "SubIdx")), 0);
        assert_eq!(text(items[0], "Name"), D::name(si0.name));
        assert_eq!(text(items[0], "Type"), "USINT");
        assert_eq!(number(text(items[0], "BitOffs")), 0);
        check_flags(child(items[0], "Flags"), si0.access, D::name(info.name));
        if info.code == ObjectCode::Array {
            let element = info.entry(1).unwrap();
            let size = u64::from(info.max_sub) * u64::from(element.bit_len);
            assert_eq!(items.len(), 2);
            let arr = data_type(&format!("{name}ARR"));
            assert_eq!(text(arr, "BaseType"), type_name(element));
            assert_eq!(number(text(arr, "BitSize")), size);
            let array_info = child(arr, "ArrayInfo");
            assert_eq!(number(text(array_info, "LBound")), 1);
            assert_eq!(
                number(text(array_info, "Elements")),
                u64::from(info.max_sub)
            );
            assert_eq!(text(items[1], "Type"), format!("{name}ARR"));
            assert_eq!(number(text(items[1], "BitSize")), size);
            assert_eq!(number(text(items[1], "BitOffs")), offsets[1] as u64);
            check_flags(child(items[1], "Flags"), element.access, D::name(info.name));
        } else {
            // A uniform RECORD (a PDO mapping) lists every subindex with its one description.
            let entries: Vec<_> = info
                .subindices()
                .filter_map(|s| Some((s, info.entry(s)?)))
                .collect();
            assert_eq!(items.len(), entries.len());
            for (((sub, entry), item), offset) in entries.iter().zip(&items).zip(&offsets) {
                assert_eq!(number(text(*item, "SubIdx")), u64::from(*sub));
                let name = match *sub {
                    _ if info.is_repeated(*sub) => format!("SubIndex {sub:03}"),
                    _ => D::name(entry.name).to_owned(),
                };
                assert_eq!(text(*item, "Name"), name);
                assert_eq!(text(*item, "Type"), type_name(entry));
                assert_eq!(number(text(*item, "BitSize")), u64::from(entry.bit_len));
                assert_eq!(number(text(*item, "BitOffs")), *offset as u64);
                check_flags(child(*item, "Flags"), entry.access, D::name(entry.name));
            }
        }
        // The object's Info: one SubItem per subindex; SI0's default is the count it reads.
        let sub_items = children(child(*node, "Info"), "SubItem");
        let subs: Vec<u8> = info.subindices().collect();
        assert_eq!(sub_items.len(), subs.len());
        for (sub, item) in subs.iter().zip(&sub_items) {
            // ETG.2000 `ObjectInfoType/SubItem`: `Name` then `Info`, both required.
            let elements: Vec<&str> = item
                .children()
                .filter(Node::is_element)
                .map(|c| c.tag_name().name())
                .collect();
            assert_eq!(elements, ["Name", "Info"], "{:#06x}:{sub}", info.index);
            let values = item.children().find(|c| c.has_tag_name("Info"));
            if *sub == 0 {
                let count = hex(&read(od, info.index, 0));
                assert_eq!(
                    opt_text(values.unwrap(), "DefaultData"),
                    Some(count.as_str())
                );
                assert_eq!(text(*item, "Name"), D::name(si0.name));
            } else {
                check_values::<D>(values, info.index, *sub);
                let expected = match info.is_repeated(*sub) {
                    true => format!("SubIndex {sub:03}"),
                    false => D::name(info.entry(*sub).unwrap().name).to_owned(),
                };
                assert_eq!(text(*item, "Name"), expected);
            }
        }
    }
}

fn eeprom(image: &[u8], device: Node) {
    let node = child(device, "Eeprom");
    let kbit = u64::from(u16::from_le_bytes([image[0x7C], image[0x7D]]));
    assert_eq!(
        number(text(node, "ByteSize")),
        (kbit + 1) * 1024 / 8,
        "word 0x3E"
    );
    assert_eq!(text(node, "ConfigData"), hex(&image[..14]));
}

#[test]
fn dictionary_sii_and_esi_agree_for_every_catalog_device() {
    for name in catalog::NAMES {
        catalog::visit(name, Consistent).unwrap();
    }
}

#[test]
fn files_by_name_are_the_files_of_the_sample() {
    let by_name = description::by_name("dio").unwrap().unwrap();
    assert_eq!(by_name, description::of(&devices::dio()).unwrap());
    assert!(description::by_name("dio2").is_none());
}

/// ESI details a MainDevice configures from: the profile number of 0x1000 and, for the drive and
/// the axis, the configurable PDOs.
#[test]
fn profile_and_pdo_flags_of_the_samples() {
    let xml = |name| description::by_name(name).unwrap().unwrap().esi;
    let axis = xml("cia402");
    assert!(
        axis.contains("<ProfileNo>402</ProfileNo>\n"),
        "0x1000 = 0x00020192"
    );
    assert!(axis.contains("<AddInfo>2</AddInfo>\n"));
    assert!(
        axis.contains("<RxPdo Sm=\"2\">\n"),
        "0x1600 is RW_PREOP: not fixed"
    );
    assert!(axis.contains(
        "<CoE SdoInfo=\"true\" PdoAssign=\"true\" PdoConfig=\"true\" CompleteAccess=\"true\" DiagHistory=\"true\"/>"
    ));
    let sensor = xml("sensor");
    assert!(
        sensor.contains("<ProfileNo>5001</ProfileNo>\n"),
        "0x1000 = 0x00001389"
    );
    assert!(sensor.contains("<TxPdo Sm=\"3\" Fixed=\"true\">\n"));
    assert!(!sensor.contains("<RxPdo"), "the sensor has no outputs");
    // Every sample has the communication area: the drive's 0x1000 is a CiA 402 servo drive's.
    assert!(
        xml("drive").contains("<ProfileNo>402</ProfileNo>\n"),
        "0x1000 = 0x00020192"
    );
}

// --- byte-exact SII -----------------------------------------------------------------------------

/// The sensor's image, byte by byte where the layout is fixed (ETG.2010 Table 2).
#[test]
fn sensor_image_byte_exact() {
    let image = devices::sensor().eeprom();
    // Configuration area of the ET1100 for a device without DC: PDI control 0x05 (SPI slave),
    // ESC configuration 0 (SYNC out and latch units off: no DC), PDI configuration 0x03 (SPI
    // mode 3, the driver's; IRQ push-pull active low, SEL active low), SYNC/LATCH 0, SYNC pulse
    // 100 × 10 ns = 1 µs (0 would be acknowledge mode), no extended PDI configuration, alias 0,
    // CRC-8 (poly 0x07, init 0xFF) of words 0..6 = 0x6D.
    assert_eq!(
        image[..16],
        [5, 0, 3, 0, 100, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x6D, 0]
    );
    // Identity: vendor 0xE0000001, product 0x2001, revision 1, serial 1.
    assert_eq!(
        image[0x10..0x20],
        [1, 0, 0, 0xE0, 1, 0x20, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]
    );
    // No bootstrap mailbox; standard mailbox 0x1000/128, 0x1080/128; CoE.
    assert_eq!(image[0x28..0x30], [0; 8]);
    assert_eq!(
        image[0x30..0x3A],
        [0, 0x10, 0x80, 0, 0x80, 0x10, 0x80, 0, 4, 0]
    );
    // Size 16 Kbit (15), version 1.
    assert_eq!(image[0x7C..0x80], [15, 0, 1, 0]);
    let sii = Sii(&image);
    let general = sii.category(30).unwrap();
    let mut expected = [0u8; 32];
    // group 2, order 1, name 3, CoE = SDO | SDO Info | complete access (fixed PDOs).
    expected[..6].copy_from_slice(&[2, 0, 1, 3, 0, 0x23]);
    expected[14] = 2; // group index (compatibility)
    expected[16] = 0x11; // ports 0 and 1: MII
    assert_eq!(general, expected);
    assert_eq!(
        sii.category(41).unwrap(),
        [
            0x00, 0x10, 0x80, 0, 0x26, 0, 1, 1, // SM0
            0x80, 0x10, 0x80, 0, 0x22, 0, 1, 2, // SM1
            0x00, 0x11, 0, 0, 0x64, 0, 0, 3, // SM2: no outputs, disabled
            0x00, 0x11, 6, 0, 0x20, 0, 1, 4, // SM3: 6 bytes
        ]
    );
    assert_eq!(
        sii.category(40).unwrap(),
        [2, 3],
        "FMMU inputs, mailbox state"
    );
    assert_eq!(image.len(), 0x136);
    assert_eq!(image[image.len() - 2..], [0xFF, 0xFF]);
}

#[test]
fn sii_write_refuses_a_too_small_buffer() {
    let sample = devices::sensor();
    let len = sample.eeprom().len();
    let write = |buf: &mut [u8]| {
        sii::write(
            &sample.names,
            &sample.identity,
            &sample.device.config,
            &sample.device.esc.chip,
            &sample.device.od,
            buf,
        )
    };
    assert_eq!(write(&mut vec![0; len]), Ok(len));
    assert_eq!(write(&mut vec![0; len - 1]), Err(SiiError::BufferTooSmall));
    assert_eq!(write(&mut [0; 16]), Err(SiiError::BufferTooSmall));
    assert_eq!(write(&mut []), Err(SiiError::BufferTooSmall));
}

/// SII words 0 and 1 (registers 0x0140/0x0141, 0x0150/0x0151): a DC SYNC0 device has the SYNC
/// out unit on (0x0141 bit 2) and drives SYNC0 as a push-pull, active-high output (0x0151 =
/// 0x06), which is what its firmware waits on; others leave the unit off and the pin a LATCH0
/// input. Both run the SPI slave (0x0140 = 0x05) in mode 3 (0x0150 = 0x03). The ESI's
/// ConfigData carries the same bytes.
#[test]
fn sync0_output_configuration_follows_dc_support() {
    for (name, expected) in [
        ("cia402", [0x05, 0x04, 0x03, 0x06]),
        ("sensor", [0x05, 0x00, 0x03, 0x00]),
    ] {
        let files = ecat_examples::description::by_name(name).unwrap().unwrap();
        assert_eq!(files.sii[..4], expected, "{name}");
        let config_data: String = files.sii[..14].iter().map(|b| format!("{b:02X}")).collect();
        assert!(
            files.esi.contains(&config_data),
            "{name}: ConfigData {config_data}"
        );
    }
}

/// The SII categories of an image: (type, body).
fn categories(image: &[u8]) -> Vec<(u16, &[u8])> {
    let mut at = 0x80;
    let mut found = Vec::new();
    while let Some(header) = image.get(at..at + 4) {
        let kind = u16::from_le_bytes([header[0], header[1]]);
        if kind == 0xFFFF {
            break;
        }
        let words = usize::from(u16::from_le_bytes([header[2], header[3]]));
        found.push((kind, &image[at + 4..at + 4 + 2 * words]));
        at += 4 + 2 * words;
    }
    found
}

/// A DC SYNC0 device's SII has the DC category (60) with one SYNC0 operation mode
/// (AssignActivate 0x0300, SYNC0 cycle factor 1), as its ESI's `Dc/OpMode`; others have none.
#[test]
fn the_dc_category_follows_dc_support() {
    let axis = ecat_examples::description::by_name("cia402")
        .unwrap()
        .unwrap();
    let dc: Vec<_> = categories(&axis.sii)
        .into_iter()
        .filter(|(k, _)| *k == 60)
        .collect();
    assert_eq!(dc.len(), 1);
    let body = dc[0].1;
    assert_eq!(body.len(), 24);
    assert_eq!(
        &body[12..18],
        &[0, 0, 0x00, 0x03, 1, 0],
        "SYNC1 factor, AssignActivate, SYNC0 factor"
    );
    assert!(
        axis.esi.contains("<AssignActivate>#x300</AssignActivate>"),
        "{}",
        axis.esi
    );
    let sensor = ecat_examples::description::by_name("sensor")
        .unwrap()
        .unwrap();
    assert!(categories(&sensor.sii).iter().all(|(k, _)| *k != 60));
}

/// On another chip only the configuration area (words 0..7) and the ESI's ConfigData differ:
/// the area is the chip's for the device's DC support, everything after it the same.
#[test]
fn on_each_chip_only_the_configuration_area_differs() {
    use ecat_core::chip::{Chip, ConfigArea};
    for name in catalog::NAMES {
        let own = description::by_name(name).unwrap().unwrap();
        let dc = own.sii[1] & 0x04 != 0;
        for chip in Chip::ALL {
            let files = description::on_chip(name, chip).unwrap().unwrap();
            let area = ConfigArea::new(&chip, dc).bytes();
            assert_eq!(files.sii[..16], area, "{name} on {}", chip.name);
            assert_eq!(files.sii[16..], own.sii[16..], "{name} on {}", chip.name);
            let config_data: String = area[..14].iter().map(|b| format!("{b:02x}")).collect();
            assert!(
                files
                    .esi
                    .contains(&format!("<ConfigData>{config_data}</ConfigData>"))
            );
        }
    }
}
