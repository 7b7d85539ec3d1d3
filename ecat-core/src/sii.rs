//! The SII EEPROM image (ETG.1000.6 §5.4, Tables 2–4; ETG.2010 categories), generated from the
//! same description the SubDevice checks the MainDevice against ([`DeviceConfig`]), its identity
//! ([`Identity`], which the dictionary's 0x1018 also holds) and the dictionary's default PDO
//! assignment and mapping. What the MainDevice reads and what the device does cannot disagree.
//!
//! Layout written by [`write()`]:
//!
//! | words | contents |
//! |---|---|
//! | 0x00..0x07 | the ESC configuration area of the chip ([`ConfigArea::new`]: PDI control, ESC configuration, PDI configuration, SYNC/LATCH configuration, SYNC pulse length, …), CRC-8 of words 0..6 in word 7 |
//! | 0x08..0x0F | identity: vendor ID, product code, revision, serial number |
//! | 0x14..0x17 | bootstrap mailbox (receive offset/size, send offset/size), zero without BOOT |
//! | 0x18..0x1B | standard mailbox |
//! | 0x1C | mailbox protocols (`mailbox_protocols`): CoE, and FoE with BOOT (then also the General category's FoE details) |
//! | 0x3E, 0x3F | EEPROM size (16 Kbit → 15), version 1 |
//! | 0x40.. | categories: Strings (10), General (30), FMMU (40), SyncManager (41), TxPDO (50), RxPDO (51), DC (60, DC SYNC0 devices), end 0xFFFF |
//!
//! Process-data SyncManagers: SM2 (outputs) starts after the last mailbox byte, SM3 (inputs)
//! after SM2's three buffers, both 8-byte aligned; their default lengths are the images the
//! default PDO assignment describes. Every reserved bit is 0: some MainDevices reject unknown bits.
//!
//! The parts of the description the ESI file ([`crate::esi`]) repeats are computed here once and
//! shared: [`sync_managers`], `fmmus`, `coe_details`, `for_each_pdo`.

use crate::chip::{Chip, ConfigArea};
use crate::device::{DeviceConfig, Identity, MailboxConfig};
use crate::dictionary::ObjectDictionary;
use crate::pdo::layout::Layout as PdoLayout;
use crate::pdo::{Direction, MappingEntry};
use crate::sync_manager::SmKind;

/// The names the SII strings carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Names<'a> {
    /// The device's name (General NameIdx; ethercrab's `name()`).
    pub name: &'a str,
    /// The order code (General OrderIdx).
    pub order_code: &'a str,
    /// The device group (General GroupIdx).
    pub group: &'a str,
}

/// Why no image was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiiError {
    /// The buffer is too small for the image.
    BufferTooSmall,
    /// More than 255 strings, or a string longer than 255 bytes.
    TooManyStrings,
}

/// Mailbox protocol CoE (word 0x1C, bit 2).
const PROTOCOL_COE: u16 = 0x0004;
/// Mailbox protocol FoE (word 0x1C, bit 3).
pub(crate) const PROTOCOL_FOE: u16 = 0x0008;
/// SyncManager control bytes: mailbox out/in, 3-buffer out with watchdog, 3-buffer in.
const SM_CONTROL: [u8; 4] = [0x26, 0x22, 0x64, 0x20];
/// Category types (ETG.2010 Table 3).
const CAT_STRINGS: u16 = 10;
const CAT_GENERAL: u16 = 30;
const CAT_FMMU: u16 = 40;
const CAT_SYNC_MANAGER: u16 = 41;
const CAT_TXPDO: u16 = 50;
const CAT_RXPDO: u16 = 51;
const CAT_DC: u16 = 60;
const CAT_END: u16 = 0xFFFF;
/// DC AssignActivate (register 0x0980/0x0981 as the MainDevice should write them): cyclic
/// operation with SYNC0.
pub(crate) const ASSIGN_ACTIVATE_SYNC0: u16 = 0x0300;
/// Word 0x3E: EEPROM size in Kbit − 1 (16 Kbit).
const SIZE_KBIT_MINUS_ONE: u16 = 15;
/// Largest image: 16 Kbit.
pub const MAX_SIZE: usize = 2048;

/// The mailbox protocols word (0x1C; ETG.2010 Table 2, bit 2 CoE, bit 3 FoE): CoE always, FoE
/// when the device supports BOOT, whose only protocol FoE is (ETG.1000.6 §6.4.1). A device with
/// a bootstrap mailbox serves FoE ([`crate::foe::Foe`] among its mailbox handlers).
pub(crate) const fn mailbox_protocols(config: &DeviceConfig) -> u16 {
    if config.bootstrap_mailbox.is_some() {
        PROTOCOL_COE | PROTOCOL_FOE
    } else {
        PROTOCOL_COE
    }
}

/// Writes the SII image of the device on `chip` into `out`; returns its length in bytes.
pub fn write<D: ObjectDictionary>(
    names: &Names<'_>,
    identity: &Identity,
    config: &DeviceConfig,
    chip: &Chip,
    od: &D,
    out: &mut [u8],
) -> Result<usize, SiiError> {
    let mut w = Writer {
        out,
        at: 0,
        overflow: false,
    };
    w.bytes(&ConfigArea::new(chip, D::SYNC_MODES.dc()).bytes());
    for value in [
        identity.vendor_id,
        identity.product_code,
        identity.revision,
        identity.serial,
    ] {
        w.u32(value);
    }
    w.words(&[0; 4]);
    w.mailbox(config.bootstrap_mailbox.as_ref());
    w.mailbox(Some(&config.mailbox));
    w.u16(mailbox_protocols(config));
    w.fill_to(0x3E * 2);
    w.words(&[SIZE_KBIT_MINUS_ONE, 1]);
    let strings = Strings::new(names, od)?;
    w.category(CAT_STRINGS, |w| strings.write(w, od));
    let foe = u8::from(mailbox_protocols(config) & PROTOCOL_FOE != 0);
    w.category(CAT_GENERAL, |w| {
        general(w, coe_details(od), foe, general_flags(config))
    });
    w.category(CAT_FMMU, |w| {
        for fmmu in fmmus(config, od) {
            w.u8(fmmu as u8);
        }
    });
    w.category(CAT_SYNC_MANAGER, |w| {
        for sm in sync_managers(config, od) {
            w.u16(sm.start);
            w.u16(sm.length);
            w.bytes(&[sm.control, 0, u8::from(sm.enable), sm.kind as u8]);
        }
    });
    for (category, direction) in [(CAT_TXPDO, Direction::Tx), (CAT_RXPDO, Direction::Rx)] {
        if count_pdos(od, direction) > 0 {
            w.category(category, |w| pdos(w, od, direction));
        }
    }
    if D::SYNC_MODES.dc() {
        w.category(CAT_DC, dc_sync0);
    }
    w.u16(CAT_END);
    if w.overflow {
        return Err(SiiError::BufferTooSmall);
    }
    Ok(w.at)
}

/// The DC category (ETG.2010, category 60) with one operation mode, "SYNC0": SYNC0 cycle time
/// and shifts 0 (the MainDevice chooses them), SYNC1 cycle factor 0, AssignActivate
/// [`ASSIGN_ACTIVATE_SYNC0`], SYNC0 cycle factor 1, no name or description string, 4 reserved
/// bytes.
fn dc_sync0(w: &mut Writer<'_>) {
    w.u32(0);
    w.u32(0);
    w.u32(0);
    w.u16(0);
    w.u16(ASSIGN_ACTIVATE_SYNC0);
    w.u16(1);
    w.bytes(&[0; 6]);
}

/// Writes little-endian words into the buffer, remembering whether it ran out.
struct Writer<'a> {
    out: &'a mut [u8],
    at: usize,
    overflow: bool,
}

impl Writer<'_> {
    fn bytes(&mut self, bytes: &[u8]) {
        match self.out.get_mut(self.at..self.at + bytes.len()) {
            Some(dst) => dst.copy_from_slice(bytes),
            None => self.overflow = true,
        }
        self.at += bytes.len();
    }

    fn u8(&mut self, value: u8) {
        self.bytes(&[value]);
    }

    fn u16(&mut self, value: u16) {
        self.bytes(&value.to_le_bytes());
    }

    fn u32(&mut self, value: u32) {
        self.bytes(&value.to_le_bytes());
    }

    fn words(&mut self, words: &[u16]) {
        for &word in words {
            self.u16(word);
        }
    }

    /// Zeros up to byte `end`.
    fn fill_to(&mut self, end: usize) {
        while self.at < end {
            self.u8(0);
        }
    }

    /// Receive offset/size, send offset/size; zeros without a mailbox.
    fn mailbox(&mut self, mailbox: Option<&MailboxConfig>) {
        let words = mailbox.map_or([0; 4], |m| {
            [
                m.receive.start,
                m.receive.length,
                m.send.start,
                m.send.length,
            ]
        });
        self.words(&words);
    }

    /// A category: type, size in words, `body` padded to whole words.
    fn category(&mut self, kind: u16, body: impl FnOnce(&mut Self)) {
        self.u16(kind);
        let size_at = self.at;
        self.u16(0);
        let start = self.at;
        body(self);
        if !(self.at - start).is_multiple_of(2) {
            self.u8(0);
        }
        let words = u16::try_from((self.at - start) / 2).unwrap_or(u16::MAX);
        if let Some(size) = self.out.get_mut(size_at..size_at + 2) {
            size.copy_from_slice(&words.to_le_bytes());
        }
    }
}

/// String indices of the General category (1-based; the PDO and entry names follow from
/// [`FIRST_PDO_STRING`] on). The order code comes first, as in Beckhoff's own devices' SII:
/// SOEM takes string 1 for a SubDevice's name whatever General says (`ecx_config_init`), so it
/// shows the order code, as it does for an EL1008, rather than the group every device of a
/// vendor shares (what SSC's tooling puts first).
const ORDER: u8 = 1;
const GROUP: u8 = 2;
const NAME: u8 = 3;
const FIRST_PDO_STRING: usize = 4;

/// The Strings category: the three names, then for the TxPDOs and then the RxPDOs each PDO's name
/// followed by the names of its mapped entries (gaps have none), in the order [`pdos`] numbers
/// them.
struct Strings<'a> {
    names: Names<'a>,
    count: u8,
}

impl<'a> Strings<'a> {
    fn new<D: ObjectDictionary>(names: &Names<'a>, od: &D) -> Result<Self, SiiError> {
        let mut count = FIRST_PDO_STRING - 1;
        for direction in [Direction::Tx, Direction::Rx] {
            pdo_strings(od, direction, |_| count += 1);
        }
        let long = [names.name, names.order_code, names.group]
            .iter()
            .any(|s| s.len() > 255);
        match u8::try_from(count) {
            Ok(count) if !long => Ok(Self {
                names: *names,
                count,
            }),
            _ => Err(SiiError::TooManyStrings),
        }
    }

    fn write<D: ObjectDictionary>(&self, w: &mut Writer<'_>, od: &D) {
        w.u8(self.count);
        for s in [self.names.order_code, self.names.group, self.names.name] {
            string(w, s);
        }
        for direction in [Direction::Tx, Direction::Rx] {
            pdo_strings(od, direction, |s| string(w, s));
        }
    }
}

/// Calls `f` with the PDO and entry names of `direction`, in string-table order.
fn pdo_strings<D: ObjectDictionary>(od: &D, direction: Direction, mut f: impl FnMut(&'static str)) {
    for_each_pdo(od, direction, |_, name, entries| {
        f(name);
        for entry in entries.iter().filter(|e| e.index() != 0) {
            f(entry_name(od, *entry));
        }
    });
}

/// One string: length byte and bytes (cut at 255).
fn string(w: &mut Writer<'_>, s: &str) {
    let bytes = s.as_bytes().get(..s.len().min(255)).unwrap_or_default();
    w.u8(u8::try_from(bytes.len()).unwrap_or(u8::MAX));
    w.bytes(bytes);
}

/// General category flags (ETG.2010 Table 6, byte 0x0B) bit 3 "IdentALSts": the device shows
/// an explicit device ID in the AL status code (0x0134) when the MainDevice sets AL control bit 5
/// (ETG.1000.6 Table 9). Within bits 0..4, the flags ethercrab parses.
pub const FLAG_IDENT_AL_STATUS: u8 = 1 << 3;

/// The General category's flags: [`FLAG_IDENT_AL_STATUS`] for a device with an explicit device
/// ID ([`DeviceConfig::explicit_device_id`]).
pub(crate) fn general_flags(config: &DeviceConfig) -> u8 {
    if config.explicit_device_id {
        FLAG_IDENT_AL_STATUS
    } else {
        0
    }
}

/// The General category (ETG.2010 Table 6), 32 bytes; `foe` is its "FoE Details" byte (bit 0:
/// FoE supported).
fn general(w: &mut Writer<'_>, coe: CoeDetails, foe: u8, flags: u8) {
    w.bytes(&[GROUP, 0, ORDER, NAME, 0, coe.0, foe, 0, 0, 0, 0, flags]);
    w.u16(0); // current on E-bus
    w.bytes(&[GROUP, 0]); // group index (compatibility), reserved
    w.u16(0x0011); // physical ports 0 and 1: MII
    w.u16(0); // physical memory address of the identification
    w.bytes(&[0; 12]); // reserved: 0x14..0x1F
}

/// The CoE details byte of the General category (ETG.2010 Table 6, "CoE Details"); the ESI
/// `Mailbox/CoE` attributes carry the same flags (ETG.2000 `Device/Mailbox/CoE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct CoeDetails(pub(crate) u8);

impl CoeDetails {
    /// Bit 0: SDO supported.
    pub(crate) const SDO: u8 = 0x01;
    /// Bit 1: SDO Information.
    pub(crate) const SDO_INFO: u8 = 0x02;
    /// Bit 2: PDO assignment writable.
    pub(crate) const PDO_ASSIGN: u8 = 0x04;
    /// Bit 3: PDO mapping writable.
    pub(crate) const PDO_CONFIG: u8 = 0x08;
    /// Bit 5: SDO complete access.
    pub(crate) const COMPLETE_ACCESS: u8 = 0x20;

    /// Whether every bit of `flag` is set.
    pub(crate) const fn has(self, flag: u8) -> bool {
        self.0 & flag == flag
    }
}

/// The CoE details the dictionary supports: SDO, SDO Information and complete access always;
/// PDO assignment / configuration when 0x1C12/0x1C13 / their mapping objects are writable.
pub(crate) fn coe_details<D: ObjectDictionary>(od: &D) -> CoeDetails {
    let mut details = CoeDetails::SDO | CoeDetails::SDO_INFO | CoeDetails::COMPLETE_ACCESS;
    let writable = |index: u16| {
        D::object(index)
            .and_then(|o| o.info.entry(0))
            .is_some_and(|e| e.access.writable())
    };
    for direction in [Direction::Rx, Direction::Tx] {
        if writable(direction.assignment()) {
            details |= CoeDetails::PDO_ASSIGN;
        }
        for_each_pdo(od, direction, |pdo, _, _| {
            if writable(pdo) {
                details |= CoeDetails::PDO_CONFIG;
            }
        });
    }
    CoeDetails(details)
}

/// An FMMU's usage (ETG.2010 Table 9; the ESI `Fmmu` element, ETG.2000 `Device/Fmmu`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Fmmu {
    /// Maps the outputs (SM2).
    Outputs = 0x01,
    /// Maps the inputs (SM3).
    Inputs = 0x02,
    /// Maps the SyncManager status (the mailbox-full bit of SM1).
    MailboxState = 0x03,
}

/// The FMMUs the device needs: outputs and inputs for the images that exist, then the mailbox
/// status.
pub(crate) fn fmmus<D: ObjectDictionary>(
    config: &DeviceConfig,
    od: &D,
) -> impl Iterator<Item = Fmmu> {
    let image = ProcessImage::of(config, od);
    let outputs = Some(Fmmu::Outputs).filter(|_| image.outputs > 0);
    let inputs = Some(Fmmu::Inputs).filter(|_| image.inputs > 0);
    [outputs, inputs, Some(Fmmu::MailboxState)]
        .into_iter()
        .flatten()
}

/// One SyncManager's default configuration: an SII SyncManager category entry (ETG.2010
/// Table 10) and an ESI `Sm` element (ETG.2000 `Device/Sm`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SyncManager {
    /// Physical start address.
    pub start: u16,
    /// Default length in bytes.
    pub length: u16,
    /// Control register byte (0x0804).
    pub control: u8,
    /// Enabled by default (0x0806 bit 0).
    pub enable: bool,
    /// What it is for.
    pub kind: SmKind,
}

/// SM0..SM3 of the device. Mailboxes from the [`DeviceConfig`]; SM2 (outputs) after the last
/// mailbox byte, SM3 (inputs) after SM2's three buffers, both 8-byte aligned, with the lengths of
/// the default images; a process-data SM without data is disabled.
pub fn sync_managers<D: ObjectDictionary>(config: &DeviceConfig, od: &D) -> [SyncManager; 4] {
    let image = ProcessImage::of(config, od);
    let mailboxes = [Some(&config.mailbox), config.bootstrap_mailbox.as_ref()];
    let mailbox_end = mailboxes
        .into_iter()
        .flatten()
        .flat_map(|m| [m.receive.end(), m.send.end()])
        .max()
        .unwrap_or(0);
    let align = |a: u32| u16::try_from(a.div_ceil(8) * 8).unwrap_or(u16::MAX);
    let outputs_start = align(mailbox_end);
    // SM3 starts after SM2's three buffers at the largest output image an assignment can make
    // (every RxPDO mapping object the dictionary declares, assigned or an alternative), so that
    // assigning another PDO set in PREOP cannot make SM2 overlap SM3.
    let mut bits = 0u32;
    let mut add = |_: u16, _: &'static str, entries: &[MappingEntry]| {
        bits += entries.iter().map(|e| u32::from(e.bit_len())).sum::<u32>();
    };
    for_each_pdo(od, Direction::Rx, &mut add);
    for_each_alternative_pdo(od, Direction::Rx, &mut add);
    let reserved = u32::from(image.outputs).max(bits.div_ceil(8));
    let inputs_start = align(u32::from(outputs_start) + 3 * reserved);
    let [mbx_out, mbx_in, outputs, inputs] = SM_CONTROL;
    let sm = |start, length, control, enable, kind| SyncManager {
        start,
        length,
        control,
        enable,
        kind,
    };
    let (receive, send) = (config.mailbox.receive, config.mailbox.send);
    [
        sm(
            receive.start,
            receive.length,
            mbx_out,
            true,
            SmKind::MailboxOut,
        ),
        sm(send.start, send.length, mbx_in, true, SmKind::MailboxIn),
        sm(
            outputs_start,
            image.outputs,
            outputs,
            image.outputs > 0,
            SmKind::Outputs,
        ),
        sm(
            inputs_start,
            image.inputs,
            inputs,
            image.inputs > 0,
            SmKind::Inputs,
        ),
    ]
}

/// The default images.
struct ProcessImage {
    outputs: u16,
    inputs: u16,
}

impl ProcessImage {
    /// Sizes from the default PDO assignment, computed as the SubDevice computes them at
    /// PREOP→SAFEOP ([`PdoLayout::of`]), or the fixed sizes of a device without one (or with an
    /// unusable default mapping).
    fn of<D: ObjectDictionary>(config: &DeviceConfig, od: &D) -> Self {
        let bytes = |direction, fixed| {
            PdoLayout::of(od, direction)
                .ok()
                .flatten()
                .map_or(fixed, |layout| layout.bytes())
        };
        Self {
            outputs: bytes(Direction::Rx, config.process_data.outputs),
            inputs: bytes(Direction::Tx, config.process_data.inputs),
        }
    }
}

/// The number of PDOs the assignment of `direction` lists.
fn count_pdos<D: ObjectDictionary>(od: &D, direction: Direction) -> usize {
    let mut n = 0;
    for_each_pdo(od, direction, |_, _, _| n += 1);
    n
}

/// Calls `f(pdo index, pdo name, entries)` for every PDO the default assignment of `direction`
/// lists (ETG.1000.6 §5.6.7.4; the SII PDO categories and the ESI `RxPdo`/`TxPdo` elements).
pub(crate) fn for_each_pdo<D: ObjectDictionary>(
    od: &D,
    direction: Direction,
    mut f: impl FnMut(u16, &'static str, &[MappingEntry]),
) {
    let Some(assignment) = D::object(direction.assignment()) else {
        return;
    };
    for n in 1..=assignment.count(od) {
        let Some(index) = assignment.read_u16(od, n) else {
            continue;
        };
        let Some(mapping) = D::object(index).filter(|_| direction.is_mapping(index)) else {
            continue;
        };
        let mut entries = [MappingEntry(0); 64];
        let mut len = 0;
        for sub in 1..=mapping.count(od) {
            if let (Some(slot), Some(entry)) = (entries.get_mut(len), mapping.read_u32(od, sub)) {
                *slot = MappingEntry(entry);
                len += 1;
            }
        }
        f(
            index,
            D::name(mapping.info.name),
            entries.get(..len).unwrap_or_default(),
        );
    }
}

/// Calls `f(pdo index, pdo name, entries)` for every PDO mapping object of `direction` the
/// dictionary declares but the default assignment does not list: the alternatives a MainDevice
/// may assign instead (the ESI lists them without a SyncManager, ETG.2000 `RxPdo`/`TxPdo`).
pub(crate) fn for_each_alternative_pdo<D: ObjectDictionary>(
    od: &D,
    direction: Direction,
    mut f: impl FnMut(u16, &'static str, &[MappingEntry]),
) {
    let mut assigned = [0u16; 64];
    let mut n = 0;
    for_each_pdo(od, direction, |index, _, _| {
        if let Some(slot) = assigned.get_mut(n) {
            *slot = index;
            n += 1;
        }
    });
    for mapping in D::OBJECTS {
        let index = mapping.info.index;
        if !direction.is_mapping(index) || assigned.get(..n).unwrap_or_default().contains(&index) {
            continue;
        }
        let mut entries = [MappingEntry(0); 64];
        let mut len = 0;
        for sub in 1..=mapping.count(od) {
            if let (Some(slot), Some(entry)) = (entries.get_mut(len), mapping.read_u32(od, sub)) {
                *slot = MappingEntry(entry);
                len += 1;
            }
        }
        f(
            index,
            D::name(mapping.info.name),
            entries.get(..len).unwrap_or_default(),
        );
    }
}

/// A PDO category (ETG.2010 Table 14): per PDO index, entry count, SyncManager, DC sync 0, name
/// string, flags 0; per entry index, subindex, name string, data type, bit length, flags 0.
fn pdos<D: ObjectDictionary>(w: &mut Writer<'_>, od: &D, direction: Direction) {
    let mut next = FIRST_PDO_STRING;
    if direction == Direction::Rx {
        pdo_strings(od, Direction::Tx, |_| next += 1);
    }
    let mut index_of = |present: bool| {
        let index = if present {
            u8::try_from(next).unwrap_or(0)
        } else {
            0
        };
        next += usize::from(present);
        index
    };
    let sm = match direction {
        Direction::Rx => 2,
        Direction::Tx => 3,
    };
    for_each_pdo(od, direction, |index, _, entries| {
        w.u16(index);
        let n = u8::try_from(entries.len()).unwrap_or(u8::MAX);
        w.bytes(&[n, sm, 0, index_of(true)]);
        w.u16(0);
        for entry in entries {
            w.u16(entry.index());
            w.bytes(&[entry.sub(), index_of(entry.index() != 0)]);
            w.bytes(&[entry_type(od, *entry), entry.bit_len()]);
            w.u16(0);
        }
    });
}

/// The data type of a mapped entry (the low byte of its code, as the SII stores it); 0 for a
/// gap.
fn entry_type<D: ObjectDictionary>(_od: &D, entry: MappingEntry) -> u8 {
    D::object(entry.index())
        .and_then(|o| o.info.entry(entry.sub()))
        .map_or(0, |e| e.data_type.code().to_le_bytes()[0])
}

/// The name of a mapped entry: its entry description's name.
fn entry_name<D: ObjectDictionary>(_od: &D, entry: MappingEntry) -> &'static str {
    D::object(entry.index())
        .and_then(|o| o.info.entry(entry.sub()))
        .map_or("", |e| D::name(e.name))
}
