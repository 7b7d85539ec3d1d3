//! A SubDevice session driven by arbitrary bytes: the fuzz target of every input path of the
//! core — AL control, the SyncManager, watchdog and DC registers, mailbox frames (CoE: SDO in
//! every form, SDO Information; other protocols), SM1 reads and repeat requests, the
//! application's answers to transitions, time, emergencies and the process-data cycle (copy
//! plan, pack/unpack, cycle monitor).
//!
//! [`session`] reads the bytes as a list of steps (the private `Step`), performs each against a plain
//! register file standing in for the ESC, and lets the core perform every access it asks for
//! after each step, as the runners do. Whatever the bytes, it asserts that
//! - the core does not panic (the target's reason to exist: ecat-core is panic-free);
//! - each round of accesses is bounded, and so is the mailbox service;
//! - every access lies inside the ESC's 64 KiB address space;
//! - AL status shows a valid state, with the error indication exactly when 0x0134 holds a code;
//! - every message written to SM1 is a well-formed mailbox message of a type the SubDevice speaks
//!   (error reply or CoE) and fits SM1.
//!
//! Two drivers run it: the coverage-guided libFuzzer target `fuzz/fuzz_targets/session.rs`
//! (`cargo fuzz run session`, bounded in CI) and the stable test `tests/tests/fuzz_session.rs`
//! (random inputs and the committed corpus, on every `cargo test`).

use ecat_core::coe::Emergency;
use ecat_core::device::{Identity, MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::{
    Bits, Communication, DeviceInfo, Domain, OctetString, UnicodeString, VisibleString,
};
use ecat_core::mailbox::MailboxHeader;
use ecat_core::mailbox::MailboxType;
use ecat_core::pdo::image::{pack, unpack};
use ecat_core::pdo::layout::Layout as PdoLayout;
use ecat_core::pdo::{Direction, MappingEntry, PdoAssignment, PdoMapping};
use ecat_core::sync_mode::SupportedSyncModes;
use ecat_core::sync_parameters::{CycleMonitor, CycleReport};
use ecat_core::{
    AlEvent, AlState, AlStatusCode, DeviceConfig, Duration, Instant, RegisterAccess, SubDevice,
    register,
};

/// A record with entries of several kinds.
#[derive(Debug, Default)]
pub struct Record {
    /// 0x2002:01.
    pub small: u8,
    /// 0x2002:02.
    pub bits: Bits<3>,
    /// 0x2002:05.
    pub flag: bool,
    /// 0x2002:06.
    pub wide: i64,
}

/// The fuzzed device's dictionary: every object kind and data type class the stack serves —
/// identity, PDO mapping and assignment, sync parameters, strings (visible, octet, unicode), a
/// DOMAIN, a record with gaps, an array with limits, a write-only entry, REAL32 and the
/// CiA402-like process data.
#[derive(Debug)]
pub struct FuzzOd {
    /// The communication area.
    pub area: Communication,
    /// 0x10F3: the diagnosis history the session's errors fill and its SDO writes acknowledge.
    pub history: ecat_core::diagnosis::DiagnosisHistory<3>,
    /// 0x1600.
    pub rx1: PdoMapping<8>,
    /// 0x1601.
    pub rx2: PdoMapping<4>,
    /// 0x1A00.
    pub tx1: PdoMapping<8>,
    /// 0x1C12.
    pub rx_assign: PdoAssignment<2>,
    /// 0x1C13.
    pub tx_assign: PdoAssignment<2>,
    /// 0x2000.
    pub text: VisibleString<300>,
    /// 0x2001.
    pub blob: Domain,
    /// 0x2002.
    pub record: Record,
    /// 0x2003.
    pub array: [u16; 6],
    /// 0x2004.
    pub secret: i16,
    /// 0x2005.
    pub octets: OctetString<8>,
    /// 0x2006.
    pub gain: f32,
    /// 0x2007.
    pub label: UnicodeString<8>,
    /// 0x6040.
    pub controlword: u16,
    /// 0x6041.
    pub statusword: u16,
    /// 0x6060.
    pub mode: i8,
    /// 0x6064.
    pub position: i32,
    /// 0x607A.
    pub target_position: i32,
}

/// The identity of the fuzzed device.
pub const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 0x0000_F022,
    revision: 1,
    serial: 1,
};

/// The communication area of the fuzzed device.
pub const INFO: DeviceInfo = DeviceInfo {
    device_type: 0x0002_0192,
    name: "fuzz",
    hardware_version: "1",
    software_version: "1",
    identity: IDENTITY,
};

const RX: [MappingEntry; 3] = [
    MappingEntry::new(0x6040, 0, 16),
    MappingEntry::new(0x607A, 0, 32),
    MappingEntry::new(0x6060, 0, 8),
];

const TX: [MappingEntry; 3] = [
    MappingEntry::new(0x6041, 0, 16),
    MappingEntry::new(0x6064, 0, 32),
    MappingEntry::new(0x2002, 5, 1),
];

ecat_core::dictionary! {
    FuzzOd {
        sync(SupportedSyncModes(
            SupportedSyncModes::FREE_RUN | SupportedSyncModes::SM | SupportedSyncModes::SYNC0,
        ));
        communication(area, INFO);
        0x10F3 => diagnosis(history);
        0x1600 => pdo(rx1, RW_PREOP, "RxPDO 1", "Entry", default = PdoMapping::mapping(&RX));
        0x1601 => pdo(rx2, RW_PREOP, "RxPDO 2", "Entry");
        0x1A00 => pdo(tx1, RW_PREOP, "TxPDO 1", "Entry", default = PdoMapping::mapping(&TX));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 PDO assignment", "PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x2000 => var(text, RW, "Text");
        0x2001 => var(blob, RW, "Blob");
        0x2002 => record(record: Record, "Record") {
            1 => small, RW, "Small", max = 200;
            2 => bits, RW_PREOP | RXPDO, "Bits";
            5 => flag, RW | TXPDO | RXPDO, "Flag";
            6 => wide, RW, "Wide", min = -5, max = 5;
        };
        0x2003 => array(array, RW | RXPDO | TXPDO, "Array", "Element", default = 3, min = 1, max = 9);
        0x2004 => var(secret, WO, "Secret");
        0x2005 => var(octets, RW, "Octets");
        0x2006 => var(gain, RW, "Gain", default = 1.5);
        0x2007 => var(label, RW, "Label");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword");
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6064 => var(position, RO | TXPDO, "Position actual value");
        0x607A => var(target_position, RW | RXPDO, "Target position", min = -1_000_000, max = 1_000_000);
    }
}

/// Mailboxes: 128 bytes at 0x1000/0x1080; a bootstrap mailbox at 0x1800/0x1880.
const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);

/// The fuzzed device: BOOT supported, free-run, SM-synchronous and DC SYNC0, 11 bytes each way
/// when no assignment says otherwise, a short transition timeout.
pub const DEVICE: DeviceConfig = {
    let mut device = DeviceConfig::new(
        MAILBOX,
        ProcessDataSizes {
            outputs: 11,
            inputs: 11,
        },
    );
    device.bootstrap_mailbox = Some(MailboxConfig::contiguous(0x1800, 128));
    device.transition_timeout = Duration::from_millis(50);
    device
};

/// The most accesses one round may take, and the most messages one mailbox service may build.
const ROUND_LIMIT: usize = 64;

/// One step of a session, decoded from the bytes.
#[derive(Debug)]
enum Step<'a> {
    /// The MainDevice writes AL control.
    AlControl(u16),
    /// The MainDevice writes SyncManager `n` (start, length, control, activate).
    SyncManager(u8, [u8; 8]),
    /// The MainDevice configures SM0..SM3 as the device describes them.
    ConfigureAll,
    /// The MainDevice writes a raw message into SM0.
    Mailbox(&'a [u8]),
    /// The MainDevice writes an SDO request into SM0 (counter, command, index, subindex, data).
    Sdo(u8, u8, u16, u8, &'a [u8]),
    /// The MainDevice reads SM1.
    ReadSm1,
    /// The MainDevice toggles SM1's repeat request.
    Repeat,
    /// Time passes (milliseconds).
    Wait(u16),
    /// The application answers the pending transition: `None` accepts, a code refuses (even
    /// 0x0000, which an application should not give).
    Answer(Option<u16>),
    /// The application raises an emergency.
    Emergency(u16),
    /// The MainDevice writes the DC activation and SYNC0 cycle (µs).
    Dc(u8, u32),
    /// The MainDevice writes the process-data watchdog time; the watchdog expires if `expired`.
    Watchdog(u16, bool),
    /// A process-data cycle with these output bytes.
    Cycle(&'a [u8]),
    /// The MainDevice writes an SDO Information request into SM0 (counter, opcode, then the
    /// index or list type, subindex and value-info byte as the opcode reads them).
    SdoInfo(u8, u8, u16, u8, u8),
    /// The MainDevice configures SM0/SM1 as the bootstrap mailbox.
    ConfigureBoot,
}

/// The bytes, read front to back; a read past the end gives zeros.
struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    fn u8(&mut self) -> u8 {
        let (first, rest) = self.0.split_first().map_or((0, &[][..]), |(f, r)| (*f, r));
        self.0 = rest;
        first
    }

    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    fn take(&mut self, n: usize) -> &'a [u8] {
        let (head, rest) = self.0.split_at(n.min(self.0.len()));
        self.0 = rest;
        head
    }

    fn step(&mut self) -> Step<'a> {
        match self.u8() % 15 {
            0 => Step::AlControl(self.u16() & 0x003F),
            1 => Step::SyncManager(self.u8() % 9, core::array::from_fn(|_| self.u8())),
            2 => Step::ConfigureAll,
            3 => {
                let n = usize::from(self.u8());
                Step::Mailbox(self.take(n))
            }
            4 => {
                let (counter, command) = (self.u8(), self.u8());
                let index = INDICES[usize::from(self.u8()) % INDICES.len()];
                let sub = self.u8() % 8;
                let n = usize::from(self.u8() % 120);
                Step::Sdo(counter, command, index, sub, self.take(n))
            }
            5 => Step::ReadSm1,
            6 => Step::Repeat,
            7 => Step::Wait(self.u16()),
            8 => Step::Answer(match self.u8() % 0x42 {
                0 => None,
                0x41 => Some(0),
                code => Some(u16::from(code)),
            }),
            9 => Step::Emergency(self.u16()),
            10 => Step::Dc(self.u8(), u32::from(self.u16()) * 10),
            11 => Step::Watchdog(self.u16(), self.u8() & 1 != 0),
            12 => Step::Cycle(self.take(CYCLE_BYTES)),
            13 => {
                let (counter, opcode) = (self.u8(), self.u8() % 9);
                let index = match self.u8() {
                    pick @ 0..=127 => INDICES[usize::from(pick) % INDICES.len()],
                    list_type => u16::from(list_type % 8),
                };
                Step::SdoInfo(counter, opcode, index, self.u8() % 8, self.u8())
            }
            _ => Step::ConfigureBoot,
        }
    }
}

/// The registers of an enabled SyncManager at `start` of `length` bytes with `control`.
fn sm(start: u16, length: u16, control: u8) -> [u8; 8] {
    let [s0, s1] = start.to_le_bytes();
    let [l0, l1] = length.to_le_bytes();
    [s0, s1, l0, l1, control, 0, 1, 0]
}

/// The output bytes a cycle step takes.
const CYCLE_BYTES: usize = 24;

/// The indices an SDO step aims at: every object, and one that does not exist.
const INDICES: [u16; 24] = [
    0x1008, 0x1018, 0x1600, 0x1601, 0x1A00, 0x1C12, 0x1C13, 0x1C32, 0x1C33, 0x2000, 0x2001, 0x2002,
    0x2003, 0x2004, 0x2005, 0x2006, 0x2007, 0x6040, 0x6041, 0x6060, 0x6064, 0x607A, 0x5555, 0x10F3,
];

/// The ESC as plain memory, the SubDevice, its dictionary and the time.
struct Session<'c> {
    sub: SubDevice<'c>,
    od: FuzzOd,
    mem: Vec<u8>,
    event: u32,
    now: Instant,
    monitor: CycleMonitor,
}

/// Runs the steps `data` describes and returns the state it ends in; panics if the core breaks
/// one of the rules in the module documentation.
pub fn session(data: &[u8]) -> AlState {
    let mut s = Session {
        sub: SubDevice::new::<FuzzOd>(&DEVICE),
        od: FuzzOd::default(),
        mem: vec![0; 0x1_0000],
        event: 0,
        now: Instant::from_micros(0),
        monitor: CycleMonitor::default(),
    };
    s.put(register::WATCHDOG_TIME_PROCESS_DATA, &1000u16.to_le_bytes());
    s.settle();
    let mut bytes = Bytes(data);
    for _ in 0..256 {
        if bytes.0.is_empty() {
            break;
        }
        let step = bytes.step();
        s.perform(step);
        s.settle();
        s.check();
    }
    s.sub.state()
}

/// Step encodings for [`seeds`].
mod seed {
    pub const AL_CONTROL: u8 = 0;
    pub const CONFIGURE_ALL: u8 = 2;
    pub const SDO: u8 = 4;
    pub const READ_SM1: u8 = 5;
    pub const ANSWER_OK: [u8; 2] = [8, 0];
    pub const CYCLE: u8 = 12;
    pub const SDO_INFO: u8 = 13;
    pub const CONFIGURE_BOOT: u8 = 14;
}

/// Starting points for the fuzzer (committed as `fuzz/corpus/session/seed-*`): a session that
/// reaches OP and exchanges process data, one that reaches PREOP and makes SDO requests of
/// every kind on the way (expedited upload and download, complete access, a segmented upload,
/// an abort, SDO Information lists and descriptions), and one that reaches BOOT.
pub fn seeds() -> Vec<Vec<u8>> {
    use seed::{
        AL_CONTROL, ANSWER_OK, CONFIGURE_ALL, CONFIGURE_BOOT, CYCLE, READ_SM1, SDO, SDO_INFO,
    };
    let control = |state: u8| [AL_CONTROL, state, 0];
    let index = |i: u16| INDICES.iter().position(|&x| x == i).unwrap_or(0) as u8;
    let sdo = |counter: u8, command: u8, object: u16, sub: u8, data: &[u8]| {
        let mut step = vec![SDO, counter, command, index(object), sub, data.len() as u8];
        step.extend_from_slice(data);
        step.push(READ_SM1);
        step
    };
    let mut op = vec![CONFIGURE_ALL];
    op.extend(control(2));
    op.extend(ANSWER_OK);
    op.extend(control(4));
    op.extend(ANSWER_OK);
    let cycle = |outputs: [u8; 7]| {
        let mut step = [0u8; 1 + CYCLE_BYTES];
        step[0] = CYCLE;
        step[1..8].copy_from_slice(&outputs);
        step
    };
    op.extend(cycle([0x0F, 0, 1, 0, 0, 0, 8]));
    op.extend(control(8));
    op.extend(ANSWER_OK);
    op.extend(cycle([0x1F, 0, 2, 0, 0, 0, 8]));
    let mut preop = vec![CONFIGURE_ALL];
    preop.extend(control(2));
    preop.extend(ANSWER_OK);
    preop.extend(sdo(1, 0x40, 0x1018, 1, &[0; 4]));
    preop.extend(sdo(2, 0x2B, 0x6040, 0, &[6, 0, 0, 0]));
    preop.extend(sdo(3, 0x50, 0x1C12, 0, &[0; 4]));
    preop.extend(sdo(4, 0x40, 0x2000, 0, &[0; 4]));
    preop.extend(sdo(5, 0x60, 0x2000, 0, &[0; 7]));
    preop.extend(sdo(6, 0x80, 0x2000, 0, &[0, 0, 4, 5]));
    // Get OD list of list type 1 (all objects), then the object and entry descriptions of
    // 0x2002 (the index picked by its position in INDICES, below 128).
    preop.extend([SDO_INFO, 7, 0x01, 0x81, 0, 0, READ_SM1]);
    preop.extend([SDO_INFO, 1, 0x03, index(0x2002), 0, 0, READ_SM1]);
    preop.extend([SDO_INFO, 2, 0x05, index(0x2002), 6, 0x78, READ_SM1]);
    let mut boot = vec![CONFIGURE_BOOT];
    boot.extend(control(3));
    boot.extend(ANSWER_OK);
    boot.extend(sdo(1, 0x40, 0x1018, 1, &[0; 4]));
    vec![op, preop, boot]
}

impl Session<'_> {
    fn put(&mut self, address: u16, data: &[u8]) {
        let a = usize::from(address);
        let end = (a + data.len()).min(self.mem.len());
        let n = end - a;
        self.mem[a..end].copy_from_slice(&data[..n]);
    }

    fn perform(&mut self, step: Step<'_>) {
        match step {
            Step::AlControl(value) => {
                self.put(register::AL_CONTROL, &value.to_le_bytes());
                self.event |= AlEvent::AL_CONTROL.bits();
            }
            Step::SyncManager(n, bytes) => {
                self.put(register::sync_manager(n), &bytes);
                self.event |= AlEvent::SM_CHANGE.bits();
            }
            Step::ConfigureAll => self.configure_all(),
            Step::Mailbox(message) => self.write_sm0(message),
            Step::Sdo(counter, command, index, sub, data) => {
                let [i0, i1] = index.to_le_bytes();
                let mut payload = vec![0x00, 0x20, command, i0, i1, sub];
                payload.extend_from_slice(data);
                self.write_coe(counter, &payload);
            }
            Step::SdoInfo(counter, opcode, index, sub, value_info) => {
                let [i0, i1] = index.to_le_bytes();
                let payload = [0x00, 0x80, opcode, 0, 0, 0, i0, i1, sub, value_info];
                self.write_coe(counter, &payload);
            }
            Step::ConfigureBoot => {
                self.configure_mailbox(DEVICE.bootstrap_mailbox.unwrap_or(MAILBOX));
            }
            Step::ReadSm1 => self.event |= AlEvent::sync_manager(1).bits(),
            Step::Repeat => {
                let activate = register::sync_manager(1) + 6;
                let value = self.mem[usize::from(activate)] ^ 0x02;
                self.put(activate, &[value]);
                self.event |= AlEvent::SM_CHANGE.bits();
            }
            Step::Wait(ms) => {
                self.now = self
                    .now
                    .saturating_add(Duration::from_millis(u64::from(ms)));
                if self.sub.poll_timeout().is_some_and(|t| t <= self.now) {
                    self.sub.handle_timeout(self.now);
                }
            }
            Step::Answer(code) => {
                let result = code.map_or(Ok(()), |code| Err(AlStatusCode(code)));
                if let Some(t) = self.sub.pending_transition() {
                    self.sub.complete_transition(t, result);
                }
            }
            Step::Emergency(code) => {
                self.sub.emergency(Emergency {
                    code,
                    register: 1,
                    data: [0; 5],
                });
            }
            Step::Dc(activation, cycle) => {
                self.put(register::DC_ACTIVATION, &[activation]);
                self.put(register::DC_SYNC0_CYCLE_TIME, &cycle.to_le_bytes());
                self.event |= AlEvent::AL_CONTROL.bits();
            }
            Step::Watchdog(time, expired) => {
                self.put(register::WATCHDOG_TIME_PROCESS_DATA, &time.to_le_bytes());
                self.put(
                    register::WATCHDOG_STATUS_PROCESS_DATA,
                    &[u8::from(!expired), 0],
                );
                if expired {
                    self.event |= AlEvent::WATCHDOG_PROCESS_DATA.bits();
                }
            }
            Step::Cycle(outputs) => self.cycle(outputs),
        }
    }

    /// A CoE message with `payload` (CoE header on) and the mailbox counter `counter` into SM0.
    fn write_coe(&mut self, counter: u8, payload: &[u8]) {
        let header = MailboxHeader::new(MailboxType::Coe, payload.len() as u16, counter % 8);
        let mut message = header.to_bytes().to_vec();
        message.extend_from_slice(payload);
        self.write_sm0(&message);
    }

    /// SM0..SM3 as the device describes them: the default PDOs' 7 bytes out and 7 bytes in at
    /// 0x1100/0x1200.
    fn configure_all(&mut self) {
        self.configure_mailbox(MAILBOX);
        self.put(register::sync_manager(2), &sm(0x1100, 7, 0x64));
        self.put(register::sync_manager(3), &sm(0x1200, 7, 0x20));
    }

    /// SM0 and SM1 as `mailbox` describes them.
    fn configure_mailbox(&mut self, mailbox: MailboxConfig) {
        let (rx, tx) = (mailbox.receive, mailbox.send);
        self.put(register::sync_manager(0), &sm(rx.start, rx.length, 0x26));
        self.put(register::sync_manager(1), &sm(tx.start, tx.length, 0x22));
        self.event |= AlEvent::SM_CHANGE.bits();
    }

    /// The MainDevice writes `message` at SM0's start (the bootstrap mailbox's in BOOT) and the
    /// ESC raises the SM0 event.
    fn write_sm0(&mut self, message: &[u8]) {
        let message = message.get(..128).unwrap_or(message);
        self.put(self.mailbox().receive.start, message);
        self.event |= AlEvent::sync_manager(0).bits();
    }

    /// One process-data cycle as the process-data runner makes it, in SAFEOP and OP: the
    /// outputs unpacked (OP), the cycle monitor, the inputs packed.
    fn cycle(&mut self, outputs: &[u8]) {
        let Some(layout) = self.sub.process_data() else {
            return;
        };
        if let Some(area) = layout.outputs {
            self.put(area.start, outputs);
            self.sub.outputs_received();
        }
        self.monitor.cycle(
            &mut self.od,
            CycleReport {
                now: self.now,
                nominal: layout.period(),
                expects_outputs: layout.sync0() && layout.outputs_active,
                new_outputs: layout.outputs.is_some(),
            },
        );
        let mut image = [0u8; 64];
        if let Ok(Some(rx)) = PdoLayout::of(&self.od, Direction::Rx)
            && layout.outputs_active
        {
            unpack(&rx, outputs, &mut self.od);
        }
        if let Ok(Some(tx)) = PdoLayout::of(&self.od, Direction::Tx) {
            let n = usize::from(tx.bytes()).min(image.len());
            pack(&tx, &self.od, &mut image[..n]);
        }
    }

    /// What the runners do after every step: the AL event to the core, every access it asks
    /// for, the mailbox served, the process-data configuration refreshed, the events answered.
    fn settle(&mut self) {
        let event = AlEvent(core::mem::take(&mut self.event));
        self.sub.handle_al_event(event);
        self.drive();
        let mut served = 0;
        while self.sub.service_mailbox(self.now, &mut self.od, &mut ()) {
            served += 1;
            assert!(served < ROUND_LIMIT, "unbounded mailbox service");
            self.drive();
        }
        self.sub.refresh_process_data(&mut self.od);
        self.drive();
        while self.sub.poll_event().is_some() {}
    }

    /// Performs every access the core asks for, checking each.
    fn drive(&mut self) {
        let mut n = 0;
        loop {
            let send = self.mailbox().send;
            let Some(access) = self.sub.poll_access() else {
                return;
            };
            n += 1;
            assert!(n < ROUND_LIMIT, "unbounded register accesses");
            let event = AlEvent(self.event);
            let clears = access.clears();
            match access {
                RegisterAccess::Read { address, buf, .. } => {
                    buf.copy_from_slice(span(&mut self.mem, address, buf.len()))
                }
                RegisterAccess::Write { address, data, .. } => {
                    span(&mut self.mem, address, data.len()).copy_from_slice(data)
                }
                RegisterAccess::Send {
                    address,
                    data,
                    last,
                    ..
                } => {
                    assert_eq!(address, send.start, "a message goes to SM1");
                    check_message(data, send.length);
                    span(&mut self.mem, address, data.len()).copy_from_slice(data);
                    let end = usize::from(send.start) + usize::from(send.length) - 1;
                    let expected = (data.len() < usize::from(send.length)).then_some(end);
                    assert_eq!(
                        last.map(usize::from),
                        expected,
                        "SM1's last byte, only after a short message"
                    );
                    if let Some(last) = last {
                        span(&mut self.mem, last, 1)[0] = 0;
                    }
                }
            }
            self.event &= !clears.bits();
            self.sub.access_done(self.now, event);
        }
    }

    /// The mailbox of the current state: the bootstrap mailbox in BOOT.
    fn mailbox(&self) -> MailboxConfig {
        match (self.sub.state(), DEVICE.bootstrap_mailbox) {
            (AlState::Boot, Some(boot)) => boot,
            _ => MAILBOX,
        }
    }

    /// AL status and code agree with the core and with each other.
    /// What the ESC's registers present once the core settled: AL status (0x0130) and code
    /// (0x0134) as the core holds them, a valid state, the error indication exactly when the
    /// code is not 0x0000 (unless 0x0134 shows the device ID).
    fn check(&self) {
        let word = |address: u16| {
            let a = usize::from(address);
            u16::from_le_bytes([self.mem[a], self.mem[a + 1]])
        };
        let (status, code) = (word(register::AL_STATUS), word(register::AL_STATUS_CODE));
        assert_eq!(status, self.sub.al_status().bits(), "AL status presented");
        assert_eq!(
            code,
            self.sub.al_status_code().0,
            "AL status code presented"
        );
        assert!(
            matches!(status & 0x0F, 1 | 2 | 3 | 4 | 8),
            "state {status:#06x}"
        );
        let (error, id_loaded) = (status & 0x10 != 0, status & 0x20 != 0);
        if !id_loaded {
            assert_eq!(
                error,
                code != 0,
                "error indication without a code or a code without it: {status:#06x} {code:#06x}"
            );
        }
    }
}

/// `len` bytes of the register file `mem` at `address`; an access must stay inside 64 KiB.
fn span(mem: &mut [u8], address: u16, len: usize) -> &mut [u8] {
    let (a, end) = (usize::from(address), usize::from(address) + len);
    assert!(end <= mem.len(), "access past 0xFFFF: {address:#06x}+{len}");
    &mut mem[a..end]
}

/// A message the SubDevice writes into SM1: a mailbox header whose length fits SM1, of type 0
/// (error reply) or 3 (CoE).
fn check_message(data: &[u8], sm1: u16) {
    let header = MailboxHeader::parse(data).expect("a message starts with its header");
    let length = usize::from(header.length);
    assert!(
        length + MailboxHeader::SIZE <= usize::from(sm1),
        "message longer than SM1: {length}"
    );
    assert!(
        length <= data.len() - MailboxHeader::SIZE,
        "header says more than was written"
    );
    assert!(
        matches!(header.kind.code(), 0 | 3),
        "the SubDevice speaks CoE and error replies only: {:?}",
        header.kind
    );
}
