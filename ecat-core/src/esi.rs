//! The EtherCAT SubDevice Information file (ESI, ETG.2000 "EtherCAT Slave Information
//! Specification"): the XML description a configuration tool reads, generated from the same
//! description as the SII image ([`crate::sii`]) and the dictionary's metadata, so the file, the
//! EEPROM and the device cannot disagree.
//!
//! What [`write()`] produces (ETG.2000, root element `EtherCATInfo`):
//!
//! | element | from |
//! |---|---|
//! | `Vendor/Id`, `Name` | [`Identity::vendor_id`], [`Description::vendor`] |
//! | `Descriptions/Groups/Group` | [`Names::group`] |
//! | `Device/Type` (`ProductCode`, `RevisionNo`), `Name`, `GroupType` | [`Identity`], [`Names`] |
//! | `Device/Info/IdentificationReg134` | [`DeviceConfig::explicit_device_id`] (the SII General category's IdentALSts flag) |
//! | `Profile` (`ProfileNo`, `AddInfo`) | 0x1000 low / high word, when the dictionary has it |
//! | `Profile/Dictionary/DataTypes` | every base type used, a `DTxxxx` per RECORD and ARRAY (plus `DTxxxxARR`) |
//! | `Profile/Dictionary/Objects` | every object: type, bit size, declared default/min/max ([`Object::limit`]), flags |
//! | `Fmmu`, `Sm` | `sii::fmmus`, [`sii::sync_managers`] (the SII FMMU and SyncManager categories) |
//! | `RxPdo`, `TxPdo` | the default assignment and mapping (`sii::for_each_pdo`) |
//! | `Mailbox/CoE` | `sii::coe_details` (the SII General category's CoE details) |
//! | `Mailbox/FoE` | `sii::mailbox_protocols`: with a bootstrap mailbox (BOOT) |
//! | `Dc/OpMode` | when the dictionary's [`ObjectDictionary::SYNC_MODES`] support DC SYNC0 |
//! | `Eeprom` (`ByteSize`, `ConfigData`) | the SII image: the EEPROM size of word 0x3E, words 0..6 |
//!
//! Every text and attribute value is XML-escaped. The writer needs no heap and never panics: it
//! streams into any [`core::fmt::Write`].

use core::fmt::{self, Display, Write};

use crate::DeviceConfig;
use crate::al::AlStatusCode;
use crate::coe::sdo::complete_access;
use crate::device::Identity;
use crate::diagnosis::MAILBOX_ERROR_TEXT;
use crate::dictionary::{
    Access, At, DataType, EntryInfo, Limit, Limits, Object, ObjectCode, ObjectDictionary,
    ObjectInfo,
};
use crate::mailbox::MailboxError;
use crate::pdo::Direction;
use crate::sii::{self, ASSIGN_ACTIVATE_SYNC0, CoeDetails, Names};
use crate::sync_manager::SmKind;

/// What the ESI file describes besides the dictionary.
#[derive(Debug, Clone, Copy)]
pub struct Description<'a> {
    /// The vendor's name (ETG.2000 `Vendor/Name`).
    pub vendor: &'a str,
    /// Device name, order code and group, as in the SII strings.
    pub names: &'a Names<'a>,
    /// The identity (= 0x1018, SII words 0x08..0x0F).
    pub identity: &'a Identity,
    /// The device description the SII image is written from.
    pub config: &'a DeviceConfig,
}

/// Why no ESI file was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EsiError {
    /// The output refused the text.
    Write,
    /// A declared value of `index:sub` is longer than the writer's 256-byte buffer.
    ValueTooLong {
        /// The object.
        index: u16,
        /// The subindex.
        sub: u8,
    },
}

impl From<fmt::Error> for EsiError {
    fn from(_: fmt::Error) -> Self {
        Self::Write
    }
}

/// The largest declared value [`write()`] encodes.
const MAX_VALUE: usize = 256;
/// SII words 0..6: the configuration area the ESI `Eeprom/ConfigData` repeats (ETG.2000 `Device/Eeprom`).
const CONFIG_DATA_BYTES: usize = 14;

/// Writes the ESI file of the device into `out`. `sii` is the device's SII image as
/// [`sii::write`] wrote it from the same description.
pub fn write<D: ObjectDictionary>(
    out: &mut impl Write,
    device: &Description<'_>,
    od: &D,
    sii: &[u8],
) -> Result<(), EsiError> {
    let mut x = Xml { out, depth: 0 };
    x.line(format_args!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>"))?;
    x.open("EtherCATInfo", &[("Version", &"1.6")])?;
    x.open("Vendor", &[])?;
    x.leaf("Id", Hex32(device.identity.vendor_id))?;
    x.leaf("Name", device.vendor)?;
    x.close("Vendor")?;
    x.open("Descriptions", &[])?;
    x.open("Groups", &[])?;
    x.open("Group", &[])?;
    x.leaf("Type", device.names.group)?;
    x.leaf("Name", device.names.group)?;
    x.close("Group")?;
    x.close("Groups")?;
    x.open("Devices", &[])?;
    x.open("Device", &[("Physics", &"YY")])?;
    x.leaf_with(
        "Type",
        &[
            ("ProductCode", &Hex32(device.identity.product_code)),
            ("RevisionNo", &Hex32(device.identity.revision)),
        ],
        device.names.order_code,
    )?;
    x.leaf("Name", device.names.name)?;
    if device.config.explicit_device_id {
        // ETG.2000 `Device/Info/IdentificationReg134`: the explicit device ID in 0x0134, the SII
        // General category's IdentALSts flag.
        x.open("Info", &[])?;
        x.leaf("IdentificationReg134", "true")?;
        x.close("Info")?;
    }
    x.leaf("GroupType", device.names.group)?;
    profile(&mut x, od)?;
    for fmmu in sii::fmmus(device.config, od) {
        x.leaf("Fmmu", fmmu_name(fmmu))?;
    }
    sync_managers(&mut x, device.config, od)?;
    pdos(&mut x, od, Direction::Rx)?;
    pdos(&mut x, od, Direction::Tx)?;
    let protocols = sii::mailbox_protocols(device.config);
    mailbox(
        &mut x,
        sii::coe_details(od),
        protocols,
        has_diagnosis::<D>(),
    )?;
    if D::SYNC_MODES.dc() {
        dc(&mut x, D::SYNC_MODES)?;
    }
    eeprom(&mut x, sii)?;
    x.close("Device")?;
    x.close("Devices")?;
    x.close("Descriptions")?;
    x.close("EtherCATInfo")?;
    Ok(())
}

/// Indented elements; every text and attribute value goes through [`Escaped`].
struct Xml<'w, W> {
    out: &'w mut W,
    depth: usize,
}

type Attributes<'a> = [(&'a str, &'a dyn Display)];

impl<W: Write> Xml<'_, W> {
    fn indent(&mut self) -> fmt::Result {
        for _ in 0..self.depth {
            self.out.write_str("  ")?;
        }
        Ok(())
    }

    fn line(&mut self, args: fmt::Arguments<'_>) -> fmt::Result {
        self.indent()?;
        self.out.write_fmt(args)?;
        self.out.write_char('\n')
    }

    fn start(&mut self, tag: &str, attributes: &Attributes<'_>) -> fmt::Result {
        self.indent()?;
        write!(self.out, "<{tag}")?;
        for (name, value) in attributes {
            write!(self.out, " {name}=\"")?;
            write!(Escaped(&mut *self.out), "{value}")?;
            self.out.write_char('"')?;
        }
        Ok(())
    }

    fn open(&mut self, tag: &str, attributes: &Attributes<'_>) -> fmt::Result {
        self.start(tag, attributes)?;
        self.out.write_str(">\n")?;
        self.depth += 1;
        Ok(())
    }

    fn close(&mut self, tag: &str) -> fmt::Result {
        self.depth = self.depth.saturating_sub(1);
        self.line(format_args!("</{tag}>"))
    }

    fn empty(&mut self, tag: &str, attributes: &Attributes<'_>) -> fmt::Result {
        self.start(tag, attributes)?;
        self.out.write_str("/>\n")
    }

    fn leaf_with(
        &mut self,
        tag: &str,
        attributes: &Attributes<'_>,
        text: impl Display,
    ) -> fmt::Result {
        self.start(tag, attributes)?;
        self.out.write_char('>')?;
        write!(Escaped(&mut *self.out), "{text}")?;
        writeln!(self.out, "</{tag}>")
    }

    fn leaf(&mut self, tag: &str, text: impl Display) -> fmt::Result {
        self.leaf_with(tag, &[], text)
    }
}

/// Escapes `&`, `<`, `>`, `"` and `'` on the way to the inner writer (XML 1.0 §2.4).
struct Escaped<'w, W>(&'w mut W);

impl<W: Write> Write for Escaped<'_, W> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for c in s.chars() {
            match c {
                '&' => self.0.write_str("&amp;")?,
                '<' => self.0.write_str("&lt;")?,
                '>' => self.0.write_str("&gt;")?,
                '"' => self.0.write_str("&quot;")?,
                '\'' => self.0.write_str("&apos;")?,
                c => self.0.write_char(c)?,
            }
        }
        Ok(())
    }
}

/// `#x` and eight hex digits (ETG.2000 HexDecValue).
struct Hex32(u32);

impl Display for Hex32 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#x{:08X}", self.0)
    }
}

/// An index as `#x1018`.
struct Index(u16);

impl Display for Index {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#x{:04X}", self.0)
    }
}

/// Bytes as hex, in their order (ETG.2000 HexBinary; dictionary values are little-endian).
struct HexBytes<'a>(&'a [u8]);

impl Display for HexBytes<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.iter().try_for_each(|b| write!(f, "{b:02x}"))
    }
}

/// The ESI name of a base data type (ETG.2000 `DataType/Name`, the ETG.1020 base types); strings carry
/// their length in bytes.
struct TypeName {
    data_type: DataType,
    bit_len: u16,
}

impl Display for TypeName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let bytes = self.bit_len / 8;
        let name = match self.data_type {
            DataType::Boolean => "BOOL",
            DataType::Integer8 => "SINT",
            DataType::Integer16 => "INT",
            DataType::Integer32 => "DINT",
            DataType::Integer64 => "LINT",
            DataType::Unsigned8 => "USINT",
            DataType::Unsigned16 => "UINT",
            DataType::Unsigned32 => "UDINT",
            DataType::Unsigned64 => "ULINT",
            DataType::Real32 => "REAL",
            DataType::Real64 => "LREAL",
            DataType::Domain => "DOMAIN",
            DataType::VisibleString => return write!(f, "STRING({bytes})"),
            DataType::OctetString => return write!(f, "OCTET_STRING({bytes})"),
            DataType::UnicodeString => return write!(f, "UNICODE_STRING({})", bytes / 2),
            bits => return write!(f, "BIT{}", bits.code().saturating_sub(0x2F)),
        };
        f.write_str(name)
    }
}

fn type_name(entry: &EntryInfo) -> TypeName {
    TypeName {
        data_type: entry.data_type,
        bit_len: entry.bit_len,
    }
}

/// The name of the `DataType` a RECORD or ARRAY object has: `DT1018`; with `ARR` for an
/// array's element list (the ETG.2000 `DataType` naming convention).
struct ObjectType {
    index: u16,
    array: bool,
}

impl Display for ObjectType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "DT{:04X}", self.index)?;
        if self.array {
            f.write_str("ARR")?;
        }
        Ok(())
    }
}

/// `Profile`: profile number and additional info from 0x1000, then the dictionary.
fn profile<D: ObjectDictionary, W: Write>(x: &mut Xml<'_, W>, od: &D) -> Result<(), EsiError> {
    x.open("Profile", &[])?;
    if let Some(device_type) = D::object(0x1000).and_then(|o| o.read_u32(od, 0)) {
        x.leaf("ProfileNo", device_type & 0xFFFF)?;
        x.leaf("AddInfo", device_type >> 16)?;
    }
    x.open("Dictionary", &[])?;
    x.open("DataTypes", &[])?;
    base_types::<D, W>(x)?;
    for object in D::OBJECTS {
        object_types::<D, W>(x, &object.info)?;
    }
    x.close("DataTypes")?;
    x.open("Objects", &[])?;
    for object in D::OBJECTS {
        self::object(x, od, object)?;
    }
    x.close("Objects")?;
    x.close("Dictionary")?;
    if has_diagnosis::<D>() {
        diag_messages(x)?;
    }
    x.close("Profile")?;
    Ok(())
}

/// One `DataType` per distinct base type the entries use, in order of first use.
fn base_types<D: ObjectDictionary, W: Write>(x: &mut Xml<'_, W>) -> fmt::Result {
    let entries = || D::OBJECTS.iter().flat_map(|o| o.info.entries.iter());
    let key = |e: &EntryInfo| (e.data_type, e.bit_len);
    for (n, entry) in entries().enumerate() {
        if entries().take(n).any(|e| key(e) == key(entry)) {
            continue;
        }
        x.open("DataType", &[])?;
        x.leaf("Name", type_name(entry))?;
        x.leaf("BitSize", entry.bit_len)?;
        x.close("DataType")?;
    }
    Ok(())
}

/// The bit size of an ARRAY or RECORD: its complete-access image.
fn object_bits(info: &ObjectInfo) -> usize {
    complete_access::size(info, 0) * 8
}

/// `DTxxxx` of a RECORD (a SubItem per entry), or `DTxxxxARR` and `DTxxxx` of an ARRAY
/// (SubIndex 0 and the element list); nothing for a VAR. `BitOffs` are the complete-access
/// offsets.
fn object_types<D: ObjectDictionary, W: Write>(
    x: &mut Xml<'_, W>,
    info: &ObjectInfo,
) -> fmt::Result {
    let (index, array) = (info.index, ObjectCode::Array == info.code);
    let element = info.entry(1).filter(|_| array);
    let elements_bits = |e: &EntryInfo| usize::from(info.max_sub) * usize::from(e.bit_len);
    if info.code == ObjectCode::Var {
        return Ok(());
    }
    if let Some(element) = element {
        x.open("DataType", &[])?;
        x.leaf("Name", ObjectType { index, array: true })?;
        x.leaf("BaseType", type_name(element))?;
        x.leaf("BitSize", elements_bits(element))?;
        x.open("ArrayInfo", &[])?;
        x.leaf("LBound", 1)?;
        x.leaf("Elements", info.max_sub)?;
        x.close("ArrayInfo")?;
        x.close("DataType")?;
    }
    x.open("DataType", &[])?;
    x.leaf(
        "Name",
        ObjectType {
            index,
            array: false,
        },
    )?;
    x.leaf("BitSize", object_bits(info))?;
    for (sub, offset) in complete_access::bit_offsets(info) {
        let Some(entry) = info.entry(sub) else {
            continue;
        };
        x.open("SubItem", &[])?;
        match element.filter(|_| sub > 0) {
            Some(element) => {
                x.leaf("Name", "Elements")?;
                x.leaf("Type", ObjectType { index, array: true })?;
                x.leaf("BitSize", elements_bits(element))?;
            }
            // A PDO mapping's like entries are named by subindex, as SSC's ESI files name them
            // (and so are 0x10F3's messages).
            None if info.is_repeated(sub) => {
                x.leaf("SubIdx", sub)?;
                x.leaf("Name", format_args!("SubIndex {sub:03}"))?;
                x.leaf("Type", type_name(entry))?;
                x.leaf("BitSize", entry.bit_len)?;
            }
            None => {
                x.leaf("SubIdx", sub)?;
                x.leaf("Name", D::name(entry.name))?;
                x.leaf("Type", type_name(entry))?;
                x.leaf("BitSize", entry.bit_len)?;
            }
        }
        x.leaf("BitOffs", offset)?;
        flags(x, entry.access)?;
        x.close("SubItem")?;
        // One SubItem stands for all elements of an array.
        if element.is_some() && sub > 0 {
            break;
        }
    }
    x.close("DataType")
}

/// One `Object`: index, name, type, bit size, declared values, flags.
fn object<D: ObjectDictionary, W: Write>(
    x: &mut Xml<'_, W>,
    od: &D,
    object: &Object<D>,
) -> Result<(), EsiError> {
    let info = &object.info;
    x.open("Object", &[])?;
    x.leaf("Index", Index(info.index))?;
    x.leaf("Name", D::name(info.name))?;
    match (info.code, info.entries.first()) {
        (ObjectCode::Var, Some(entry)) => {
            x.leaf("Type", type_name(entry))?;
            x.leaf("BitSize", entry.bit_len)?;
            if has_values(object, 0) {
                x.open("Info", &[])?;
                values(x, object, 0)?;
                x.close("Info")?;
            }
            flags(x, entry.access)?;
        }
        _ => {
            x.leaf(
                "Type",
                ObjectType {
                    index: info.index,
                    array: false,
                },
            )?;
            x.leaf("BitSize", object_bits(info))?;
            x.open("Info", &[])?;
            for sub in info.subindices() {
                sub_item(x, od, object, sub)?;
            }
            x.close("Info")?;
        }
    }
    x.close("Object")?;
    Ok(())
}

/// An entry of an ARRAY or RECORD object's `Info`: its name (array elements and a PDO mapping's
/// like entries `SubIndex nnn`) and
/// declared values. SubIndex 0 has no declared default: its default is the count the dictionary
/// holds (the highest subindex, or a PDO object's default number of entries), so the dictionary
/// passed to [`write()`] holds its defaults, as it does for the SII image.
fn sub_item<D: ObjectDictionary, W: Write>(
    x: &mut Xml<'_, W>,
    od: &D,
    object: &Object<D>,
    sub: u8,
) -> Result<(), EsiError> {
    let info = &object.info;
    let Some(entry) = info.entry(sub) else {
        return Ok(());
    };
    x.open("SubItem", &[])?;
    if info.is_repeated(sub) {
        x.leaf("Name", format_args!("SubIndex {sub:03}"))?;
    } else {
        x.leaf("Name", D::name(entry.name))?;
    }
    let mut count = [0u8];
    let count = (sub == 0)
        .then(|| {
            (object.read)(od, At::start(0), &mut count)
                .ok()
                .map(|_| count)
        })
        .flatten();
    if count.is_some() || has_values(object, sub) {
        x.open("Info", &[])?;
        match count {
            Some(count) => x.leaf("DefaultData", HexBytes(&count))?,
            None => values(x, object, sub)?,
        }
        x.close("Info")?;
    } else {
        // ETG.2000 `ObjectInfoType/SubItem`: `Name` and `Info` are both required; `Info`'s
        // content is optional.
        x.empty("Info", &[])?;
    }
    x.close("SubItem")?;
    Ok(())
}

fn has_values<D>(object: &Object<D>, sub: u8) -> bool {
    let values = Limits::DEFAULT | Limits::MIN | Limits::MAX;
    object
        .info
        .entry(sub)
        .is_some_and(|e| e.limits.0 & values != 0)
}

/// `MinData`, `MaxData`, `DefaultData`: the declared values, little-endian hex.
fn values<D: ObjectDictionary, W: Write>(
    x: &mut Xml<'_, W>,
    object: &Object<D>,
    sub: u8,
) -> Result<(), EsiError> {
    let too_long = object
        .info
        .entry(sub)
        .is_some_and(|e| usize::from(e.bit_len).div_ceil(8) > MAX_VALUE);
    if too_long {
        return Err(EsiError::ValueTooLong {
            index: object.info.index,
            sub,
        });
    }
    for (limit, tag) in [
        (Limit::Min, "MinData"),
        (Limit::Max, "MaxData"),
        (Limit::Default, "DefaultData"),
    ] {
        let mut buf = [0u8; MAX_VALUE];
        let len = object.limit(sub, limit, &mut buf);
        if len > 0 {
            x.leaf(tag, HexBytes(buf.get(..len).unwrap_or_default()))?;
        }
    }
    Ok(())
}

/// `Flags`: access with its state restrictions, PDO mapping, backup, setting
/// (ETG.2000 `Object/Flags`, `SubItem/Flags`; ETG.1000.6 Table 49).
fn flags<W: Write>(x: &mut Xml<'_, W>, access: Access) -> fmt::Result {
    x.open("Flags", &[])?;
    let read = Restriction(access.0 & 0x7);
    let write = Restriction((access.0 >> 3) & 0x7);
    let text = match (read.any(), write.any()) {
        (true, true) => "rw",
        (false, true) => "wo",
        _ => "ro",
    };
    match (read.partial(), write.partial()) {
        (true, true) => x.leaf_with(
            "Access",
            &[("ReadRestrictions", &read), ("WriteRestrictions", &write)],
            text,
        )?,
        (true, false) => x.leaf_with("Access", &[("ReadRestrictions", &read)], text)?,
        (false, true) => x.leaf_with("Access", &[("WriteRestrictions", &write)], text)?,
        (false, false) => x.leaf("Access", text)?,
    }
    let mapping = match (access.rxpdo(), access.txpdo()) {
        (true, true) => Some("RT"),
        (true, false) => Some("R"),
        (false, true) => Some("T"),
        (false, false) => None,
    };
    if let Some(mapping) = mapping {
        x.leaf("PdoMapping", mapping)?;
    }
    if access.backup() {
        x.leaf("Backup", 1)?;
    }
    if access.settings() {
        x.leaf("Setting", 1)?;
    }
    x.close("Flags")
}

/// The states of a read or write triple (bit 0 PREOP, 1 SAFEOP, 2 OP) as an ESI restriction.
struct Restriction(u16);

impl Restriction {
    fn any(&self) -> bool {
        self.0 != 0
    }

    /// Some states but not all: the access needs the attribute.
    fn partial(&self) -> bool {
        self.0 != 0 && self.0 != 0x7
    }
}

impl Display for Restriction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for (bit, state) in [(1, "PreOP"), (2, "SafeOP"), (4, "OP")] {
            if self.0 & bit != 0 {
                if !first {
                    f.write_char('_')?;
                }
                f.write_str(state)?;
                first = false;
            }
        }
        Ok(())
    }
}

fn fmmu_name(fmmu: sii::Fmmu) -> &'static str {
    match fmmu {
        sii::Fmmu::Outputs => "Outputs",
        sii::Fmmu::Inputs => "Inputs",
        sii::Fmmu::MailboxState => "MBoxState",
    }
}

/// `Sm` elements, the values of the SII SyncManager category.
fn sync_managers<D: ObjectDictionary, W: Write>(
    x: &mut Xml<'_, W>,
    config: &DeviceConfig,
    od: &D,
) -> fmt::Result {
    for sm in sii::sync_managers(config, od) {
        let kind = match sm.kind {
            SmKind::MailboxOut => "MBoxOut",
            SmKind::MailboxIn => "MBoxIn",
            SmKind::Outputs => "Outputs",
            SmKind::Inputs => "Inputs",
        };
        x.leaf_with(
            "Sm",
            &[
                ("DefaultSize", &sm.length),
                ("StartAddress", &Index(sm.start)),
                ("ControlByte", &format_args!("#x{:02X}", sm.control)),
                ("Enable", &u8::from(sm.enable)),
            ],
            kind,
        )?;
    }
    Ok(())
}

/// `RxPdo`/`TxPdo` elements: first those of the default assignment (with their SyncManager),
/// then the mapping objects the dictionary declares besides (no SyncManager: a MainDevice may
/// assign them instead). `Fixed` when the mapping object is not writable; entries (a gap has
/// index 0 and only a bit length). When the assignment object holds a single PDO, every PDO of
/// the direction excludes the others (`Exclude`, ETG.2000), so a configuration tool offers them
/// as alternatives.
fn pdos<D: ObjectDictionary, W: Write>(
    x: &mut Xml<'_, W>,
    od: &D,
    direction: Direction,
) -> fmt::Result {
    let (tag, sm) = match direction {
        Direction::Rx => ("RxPdo", 2u8),
        Direction::Tx => ("TxPdo", 3),
    };
    let single = D::object(direction.assignment()).is_some_and(|a| a.info.max_sub <= 1);
    let mut all = [0u16; 64];
    let mut n = 0;
    let mut collect = |index: u16, _: &'static str, _: &[crate::pdo::MappingEntry]| {
        if let Some(slot) = all.get_mut(n) {
            *slot = index;
            n += 1;
        }
    };
    sii::for_each_pdo(od, direction, &mut collect);
    sii::for_each_alternative_pdo(od, direction, &mut collect);
    let all = all.get(..n).unwrap_or_default();
    let mut result = Ok(());
    let emit = |assigned: bool| {
        move |x: &mut Xml<'_, W>, index: u16, name: &str, entries: &[crate::pdo::MappingEntry]| {
            let fixed = !D::object(index)
                .and_then(|o| o.info.entry(0))
                .is_some_and(|e| e.access.writable());
            let mut attributes: [(&str, &dyn fmt::Display); 2] = [("Sm", &sm), ("Fixed", &"true")];
            let used = match (assigned, fixed) {
                (true, true) => &attributes[..],
                (true, false) => &attributes[..1],
                (false, true) => {
                    attributes.swap(0, 1);
                    &attributes[..1]
                }
                (false, false) => &attributes[..0],
            };
            x.open(tag, used)?;
            x.leaf("Index", Index(index))?;
            x.leaf("Name", name)?;
            if single {
                for &other in all.iter().filter(|&&other| other != index) {
                    x.leaf("Exclude", Index(other))?;
                }
            }
            for entry in entries {
                x.open("Entry", &[])?;
                x.leaf("Index", Index(entry.index()))?;
                let described = D::object(entry.index()).and_then(|o| o.info.entry(entry.sub()));
                if entry.index() != 0 {
                    x.leaf("SubIndex", entry.sub())?;
                }
                x.leaf("BitLen", entry.bit_len())?;
                if let Some(described) = described.filter(|_| entry.index() != 0) {
                    x.leaf("Name", D::name(described.name))?;
                    x.leaf("DataType", type_name(described))?;
                }
                x.close("Entry")?;
            }
            x.close(tag)
        }
    };
    let default = emit(true);
    sii::for_each_pdo(od, direction, |index, name, entries| {
        if result.is_ok() {
            result = default(x, index, name, entries);
        }
    });
    let alternative = emit(false);
    sii::for_each_alternative_pdo(od, direction, |index, name, entries| {
        if result.is_ok() {
            result = alternative(x, index, name, entries);
        }
    });
    result
}

/// `Mailbox/CoE` with the SII General category's CoE details (and `DiagHistory` for a
/// dictionary with 0x10F3), and `Mailbox/FoE` when the SII's mailbox protocols word has FoE
/// ([`sii::mailbox_protocols`]).
fn mailbox<W: Write>(
    x: &mut Xml<'_, W>,
    coe: CoeDetails,
    protocols: u16,
    diagnosis: bool,
) -> fmt::Result {
    let flag = |bit| if coe.has(bit) { "true" } else { "false" };
    x.open("Mailbox", &[])?;
    let attributes: [(&str, &dyn Display); 5] = [
        ("SdoInfo", &flag(CoeDetails::SDO_INFO)),
        ("PdoAssign", &flag(CoeDetails::PDO_ASSIGN)),
        ("PdoConfig", &flag(CoeDetails::PDO_CONFIG)),
        ("CompleteAccess", &flag(CoeDetails::COMPLETE_ACCESS)),
        ("DiagHistory", &"true"),
    ];
    let used = if diagnosis { 5 } else { 4 };
    x.empty("CoE", attributes.get(..used).unwrap_or(&attributes))?;
    if protocols & sii::PROTOCOL_FOE != 0 {
        x.empty("FoE", &[])?;
    }
    x.close("Mailbox")
}

/// Whether the dictionary has the diagnosis history 0x10F3.
fn has_diagnosis<D: ObjectDictionary>() -> bool {
    D::object(crate::diagnosis::DIAGNOSIS_HISTORY).is_some()
}

/// `Profile/DiagMessages` (ETG.2000 `DiagnosticsType`): the text of every text ID the stack logs
/// in the diagnosis history, the AL status codes ETG.1000.6 Table 11 names
/// ([`crate::diagnosis::Message::al_status_code`]) and the mailbox error replies of ETG.1000.4
/// Table 30 ([`crate::diagnosis::Message::mailbox_error`]), so a MainDevice shows them as text.
fn diag_messages<W: Write>(x: &mut Xml<'_, W>) -> fmt::Result {
    x.open("DiagMessages", &[])?;
    let codes = || 1..=u16::from(u8::MAX);
    let al = codes().filter_map(|code| Some((code, AlStatusCode(code).name()?)));
    let mailbox =
        codes().filter_map(|code| Some((MAILBOX_ERROR_TEXT + code, MailboxError(code).name()?)));
    for (id, text) in al.chain(mailbox) {
        x.open("DiagMessage", &[])?;
        x.leaf("TextId", Index(id))?;
        x.leaf("MessageText", text)?;
        x.close("DiagMessage")?;
    }
    x.close("DiagMessages")
}

/// `Dc`: an SM-synchronous operation mode (no DC activation) when supported, and the DC SYNC0
/// mode (`AssignActivate` #x0300, SYNC0 cycle = the bus cycle).
fn dc<W: Write>(x: &mut Xml<'_, W>, modes: crate::sync_mode::SupportedSyncModes) -> fmt::Result {
    x.open("Dc", &[])?;
    if modes.supports(crate::sync_mode::SyncMode::SmSynchronous) {
        x.open("OpMode", &[])?;
        x.leaf("Name", "SM")?;
        x.leaf("Desc", "SM-Synchron")?;
        x.leaf("AssignActivate", format_args!("#x{:X}", 0))?;
        x.close("OpMode")?;
    }
    x.open("OpMode", &[])?;
    x.leaf("Name", "DC")?;
    x.leaf("Desc", "DC-Synchron")?;
    x.leaf(
        "AssignActivate",
        format_args!("#x{ASSIGN_ACTIVATE_SYNC0:X}"),
    )?;
    x.leaf_with("CycleTimeSync0", &[("Factor", &1)], 0)?;
    x.leaf("ShiftTimeSync0", 0)?;
    x.close("OpMode")?;
    x.close("Dc")
}

/// `Eeprom`: the EEPROM's size in bytes (SII word 0x3E holds it in Kbit − 1; an image too short
/// to have the word gives its own length) and the configuration area (words 0..6).
fn eeprom<W: Write>(x: &mut Xml<'_, W>, sii: &[u8]) -> fmt::Result {
    x.open("Eeprom", &[])?;
    let size_word = sii
        .get(0x7C..)
        .and_then(|w| w.first_chunk())
        .map(|w| u16::from_le_bytes(*w));
    let bytes = size_word.map_or(sii.len(), |kbit| (usize::from(kbit) + 1) * 1024 / 8);
    x.leaf("ByteSize", bytes)?;
    let config = sii.get(..CONFIG_DATA_BYTES).unwrap_or(sii);
    x.leaf("ConfigData", HexBytes(config))?;
    x.close("Eeprom")
}
