//! FoE (ETG.1000.6 §5.9) through the SubDevice, byte by byte: the frames a MainDevice writes into
//! SM0 and the answers the SubDevice writes into SM1, in BOOT with the bootstrap mailbox (64
//! bytes: FoE segments of 64 − 12 = 52 bytes) and in PREOP with the standard one (128 bytes).

mod common;

use common::{DEVICE, MAILBOX, Op, Regs, configure_all};
use ecat_core::device::MailboxConfig;
use ecat_core::foe::{Files, Foe, FoeError, Progress};
use ecat_core::{AlEvent, AlState, DeviceConfig, Instant, SubDevice, Transition};

const T0: Instant = Instant::from_micros(0);
const BOOT_MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1800, 64);
/// The data of a full segment in BOOT.
const SEGMENT: usize = 64 - 12;
const PASSWORD: u32 = 0x1234_5678;

static BOOT_DEVICE: DeviceConfig = {
    let mut config = DEVICE;
    config.bootstrap_mailbox = Some(BOOT_MAILBOX);
    config
};

/// What the files were asked, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Call {
    OpenWrite(Vec<u8>, u32),
    Write(u32, usize),
    Finish(u32),
    OpenRead(Vec<u8>),
    Abort,
}

/// One writable file `app.bin` and one readable `log.txt`, password [`PASSWORD`].
#[derive(Default)]
struct TestFiles {
    calls: Vec<Call>,
    written: Vec<u8>,
    log: Vec<u8>,
    /// States besides BOOT where FoE is served; BOOT refused when set.
    not_in_boot: bool,
    preop: bool,
    /// Answer the next segment with busy.
    busy_once: bool,
    /// Refuse the data beyond this many bytes with disk full.
    capacity: Option<usize>,
}

impl Files for TestFiles {
    fn allowed(&self, state: AlState) -> bool {
        match state {
            AlState::Boot => !self.not_in_boot,
            _ => self.preop,
        }
    }

    fn open_write(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        self.calls.push(Call::OpenWrite(name.to_vec(), password));
        match (name, password) {
            (b"app.bin", PASSWORD) => Ok(()),
            (b"app.bin", _) => Err(FoeError::NO_RIGHTS),
            _ => Err(FoeError::NOT_FOUND),
        }
    }

    fn write(&mut self, offset: u32, data: &[u8]) -> Result<Progress, FoeError> {
        if std::mem::take(&mut self.busy_once) {
            return Ok(Progress::Busy {
                done: 3,
                entire: 10,
            });
        }
        if self
            .capacity
            .is_some_and(|c| offset as usize + data.len() > c)
        {
            return Err(FoeError::DISK_FULL);
        }
        self.calls.push(Call::Write(offset, data.len()));
        assert_eq!(offset as usize, self.written.len(), "in order, once");
        self.written.extend_from_slice(data);
        Ok(Progress::Written)
    }

    fn finish_write(&mut self, length: u32) -> Result<(), FoeError> {
        self.calls.push(Call::Finish(length));
        Ok(())
    }

    fn open_read(&mut self, name: &[u8], _: u32) -> Result<(), FoeError> {
        self.calls.push(Call::OpenRead(name.to_vec()));
        match name {
            b"log.txt" => Ok(()),
            _ => Err(FoeError::NOT_FOUND),
        }
    }

    fn read(&mut self, offset: u32, out: &mut [u8]) -> Result<usize, FoeError> {
        let rest = self.log.get(offset as usize..).unwrap_or_default();
        let n = rest.len().min(out.len());
        out[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }

    fn abort(&mut self) {
        self.calls.push(Call::Abort);
    }
}

/// A SubDevice, the registers standing in for its ESC, and the FoE handler.
struct Bench {
    regs: Regs,
    sub: SubDevice<'static>,
    handlers: (Foe<TestFiles>,),
    counter: u8,
    mailbox: MailboxConfig,
}

impl Bench {
    /// A device with a bootstrap mailbox, in `state` (BOOT or PREOP).
    fn new(state: AlState, files: TestFiles) -> Self {
        let mut regs = Regs::new();
        let mut sub = SubDevice::new::<()>(&BOOT_DEVICE);
        regs.drive(&mut sub, T0);
        let (mailbox, control) = match state {
            AlState::Boot => (BOOT_MAILBOX, 3),
            _ => (MAILBOX, 2),
        };
        configure_all(&mut regs);
        regs.sm(0, mailbox.receive.start, mailbox.receive.length, 0x26, true);
        regs.sm(1, mailbox.send.start, mailbox.send.length, 0x22, true);
        regs.al_control(control);
        sub.handle_al_event(AlEvent(regs.event));
        regs.drive(&mut sub, T0);
        sub.complete_transition(
            Transition {
                from: AlState::Init,
                to: state,
            },
            Ok(()),
        );
        regs.drive(&mut sub, T0);
        assert_eq!(sub.state(), state);
        Self {
            regs,
            sub,
            handlers: (Foe::new(files),),
            counter: 0,
            mailbox,
        }
    }

    fn files(&self) -> &TestFiles {
        self.handlers.0.files()
    }

    /// Handles `event` and serves the mailbox until it has nothing more; the accesses.
    fn serve(&mut self, event: AlEvent) -> Vec<Op> {
        self.sub.handle_al_event(event);
        let mut log = self.regs.drive(&mut self.sub, T0);
        while self
            .sub
            .service_mailbox_with(T0, &mut (), &mut (), &mut self.handlers)
        {
            log.extend(self.regs.drive(&mut self.sub, T0));
        }
        log
    }

    /// The MainDevice writes a message of mailbox type `kind` into SM0, the SubDevice serves it,
    /// the MainDevice reads SM1. The answer (mailbox header included), `None` when SM1 was not
    /// written.
    fn exchange(&mut self, kind: u8, payload: &[u8]) -> Option<Vec<u8>> {
        self.counter = self.counter % 7 + 1;
        let mut message = (payload.len() as u16).to_le_bytes().to_vec();
        message.extend([0, 0, 0, kind | (self.counter << 4)]);
        message.extend(payload);
        self.regs.put(self.mailbox.receive.start, &message);
        let log = self.serve(AlEvent::sync_manager(0));
        let send = self.mailbox.send.start;
        let answer = log.iter().find_map(|op| match op {
            Op::Write(a, data) if *a == send => Some(data.clone()),
            _ => None,
        });
        self.serve(AlEvent::sync_manager(1));
        answer
    }

    /// An FoE exchange: the FoE part of the answer, its mailbox header checked.
    fn foe(&mut self, payload: &[u8]) -> Option<Vec<u8>> {
        let answer = self.exchange(4, payload)?;
        assert_eq!(answer[..4], [(answer.len() - 6) as u8, 0, 0, 0]);
        assert_eq!(answer[5] & 0x0F, 4, "FoE answers FoE");
        Some(answer[6..].to_vec())
    }
}

fn frame(opcode: u8, value: u32, data: &[u8]) -> Vec<u8> {
    let mut f = vec![opcode, 0];
    f.extend(value.to_le_bytes());
    f.extend(data);
    f
}

fn write_request(name: &[u8], password: u32) -> Vec<u8> {
    frame(2, password, name)
}

fn data(packet: u32, bytes: &[u8]) -> Vec<u8> {
    frame(3, packet, bytes)
}

fn ack(packet: u32) -> Vec<u8> {
    frame(4, packet, &[])
}

fn error(code: u32) -> Vec<u8> {
    frame(5, code, &[])
}

/// A file of `len` bytes, each its offset's low byte.
fn file(len: usize) -> Vec<u8> {
    (0..len).map(|i| i as u8).collect()
}

#[test]
fn a_three_segment_write_with_a_repeated_packet() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    let image = file(2 * SEGMENT + 10);
    assert_eq!(
        b.exchange(4, &write_request(b"app.bin", PASSWORD)),
        Some(vec![6, 0, 0, 0, 0, 0x14, 4, 0, 0, 0, 0, 0]),
        "ACK 0 in a whole mailbox message, counter 1"
    );
    assert_eq!(b.foe(&data(1, &image[..SEGMENT])), Some(ack(1)));
    // The MainDevice sends packet 1 again (its ACK looked lost): acknowledged, not written.
    assert_eq!(b.foe(&data(1, &image[..SEGMENT])), Some(ack(1)));
    assert_eq!(b.foe(&data(2, &image[SEGMENT..2 * SEGMENT])), Some(ack(2)));
    assert_eq!(b.foe(&data(3, &image[2 * SEGMENT..])), Some(ack(3)));
    // The last packet repeated after the end: acknowledged again, nothing more.
    assert_eq!(b.foe(&data(3, &image[2 * SEGMENT..])), Some(ack(3)));
    assert_eq!(b.files().written, image);
    assert_eq!(
        b.files().calls,
        [
            Call::OpenWrite(b"app.bin".to_vec(), PASSWORD),
            Call::Write(0, SEGMENT),
            Call::Write(SEGMENT as u32, SEGMENT),
            Call::Write(2 * SEGMENT as u32, 10),
            Call::Finish(2 * SEGMENT as u32 + 10),
        ]
    );
}

#[test]
fn an_exact_multiple_ends_with_an_empty_segment() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    let image = file(2 * SEGMENT);
    assert_eq!(b.foe(&write_request(b"app.bin", PASSWORD)), Some(ack(0)));
    assert_eq!(b.foe(&data(1, &image[..SEGMENT])), Some(ack(1)));
    assert_eq!(b.foe(&data(2, &image[SEGMENT..])), Some(ack(2)));
    assert!(!b.files().calls.contains(&Call::Finish(2 * SEGMENT as u32)));
    assert_eq!(b.foe(&data(3, &[])), Some(ack(3)));
    assert_eq!(
        b.files().calls.last(),
        Some(&Call::Finish(2 * SEGMENT as u32))
    );
    assert_eq!(b.files().written, image);
}

#[test]
fn a_lost_ack_is_recovered_by_the_mailbox_repeat() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    let image = file(SEGMENT + 1);
    b.foe(&write_request(b"app.bin", PASSWORD));
    assert_eq!(b.foe(&data(1, &image[..SEGMENT])), Some(ack(1)));
    // The frame carrying ACK 1 is lost: the MainDevice toggles SM1's repeat request (0x080E
    // bit 1); the SubDevice writes the same message, counter included, then toggles the
    // acknowledge (0x080F bit 1).
    let send = usize::from(BOOT_MAILBOX.send.start);
    let last = b.regs.mem[send..send + 12].to_vec();
    assert_eq!(last, [6, 0, 0, 0, 0, 0x24, 4, 0, 1, 0, 0, 0]);
    b.regs.mem[send..send + 12].fill(0);
    b.regs.put(0x080E, &[0x03]);
    b.regs.event |= AlEvent::SM_CHANGE.bits();
    let log = b.serve(AlEvent(b.regs.event));
    assert!(log.contains(&Op::Write(BOOT_MAILBOX.send.start, last.clone())));
    assert!(log.contains(&Op::Write(0x080F, vec![0x02])));
    b.serve(AlEvent::sync_manager(1)); // the MainDevice reads it this time
    assert_eq!(b.foe(&data(2, &image[SEGMENT..])), Some(ack(2)));
    assert_eq!(b.files().written, image, "packet 1 written once");
}

#[test]
fn busy_then_the_same_packet_again() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    b.foe(&write_request(b"app.bin", PASSWORD));
    b.handlers.0.files_mut().busy_once = true;
    assert_eq!(
        b.foe(&data(1, &[0xAA; 5])),
        Some(vec![6, 0, 3, 0, 10, 0]),
        "BUSY done 3 of 10"
    );
    assert_eq!(b.foe(&data(1, &[0xAA; 5])), Some(ack(1)));
    assert_eq!(b.files().written, [0xAA; 5]);
}

#[test]
fn refused_requests_get_the_files_code() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    assert_eq!(
        b.foe(&write_request(b"app.bin", 0)),
        Some(vec![5, 0, 0x0A, 0x80, 0, 0]),
        "wrong password: no rights"
    );
    assert_eq!(
        b.foe(&write_request(b"boot.bin", PASSWORD)),
        Some(error(0x8001))
    );
    assert_eq!(
        b.foe(&write_request(b"", PASSWORD)),
        Some(error(0x8001)),
        "an empty name is not found, the files not asked"
    );
    // A name ends at a NUL.
    assert_eq!(b.foe(&write_request(b"app.bin\0x", PASSWORD)), Some(ack(0)));
    assert_eq!(
        b.files().calls,
        [
            Call::OpenWrite(b"app.bin".to_vec(), 0),
            Call::OpenWrite(b"boot.bin".to_vec(), PASSWORD),
            Call::OpenWrite(b"app.bin".to_vec(), PASSWORD),
        ]
    );
    // A segment the files refuse ends the transfer with their code, nothing written.
    b.handlers.0.files_mut().capacity = Some(4);
    assert_eq!(b.foe(&data(1, &[1; 5])), Some(error(0x8003)));
    assert_eq!(b.foe(&data(1, &[1; 5])), Some(error(0x8004)), "ended");
    assert!(b.files().written.is_empty());
}

#[test]
fn a_read_sends_segments_until_a_short_one() {
    let files = TestFiles {
        log: file(SEGMENT + 8),
        ..TestFiles::default()
    };
    let mut b = Bench::new(AlState::Boot, files);
    let log = file(SEGMENT + 8);
    assert_eq!(
        b.foe(&frame(1, 0, b"log.txt")),
        Some(data(1, &log[..SEGMENT]))
    );
    assert_eq!(b.foe(&ack(1)), Some(data(2, &log[SEGMENT..])));
    assert_eq!(b.foe(&ack(2)), None, "the last ACK is not answered");
    assert_eq!(
        b.foe(&frame(1, 0, b"none")),
        Some(error(0x8001)),
        "a new read after the end"
    );
}

#[test]
fn out_of_sequence_frames_end_the_transfer() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    assert_eq!(
        b.foe(&data(1, &[1])),
        Some(error(0x8004)),
        "DATA without WRQ"
    );
    assert_eq!(b.foe(&ack(0)), Some(error(0x8004)), "ACK without RRQ");
    b.foe(&write_request(b"app.bin", PASSWORD));
    assert_eq!(b.foe(&data(2, &[1])), Some(error(0x8005)), "packet 2 first");
    b.foe(&write_request(b"app.bin", PASSWORD));
    assert_eq!(
        b.foe(&write_request(b"app.bin", PASSWORD)),
        Some(error(0x8004)),
        "a second WRQ during a transfer"
    );
    b.foe(&write_request(b"app.bin", PASSWORD));
    assert_eq!(b.foe(&frame(6, 0, &[])), Some(error(0x8004)), "BUSY");
    b.foe(&write_request(b"app.bin", PASSWORD));
    assert_eq!(b.foe(&frame(9, 0, &[])), Some(error(0x8004)), "opcode 9");
    b.foe(&write_request(b"app.bin", PASSWORD));
    assert_eq!(b.foe(&error(0x8000)), None, "an ERR is not answered");
    assert_eq!(
        b.foe(&data(1, &[1])),
        Some(error(0x8004)),
        "ended by the ERR"
    );
    let aborts = b
        .files()
        .calls
        .iter()
        .filter(|c| **c == Call::Abort)
        .count();
    assert_eq!(aborts, 5);
    assert!(b.files().written.is_empty());
    // A frame shorter than the FoE header: mailbox error 0x0008.
    let answer = b.exchange(4, &[3, 0, 1]).unwrap();
    assert_eq!((answer[5] & 0x0F, &answer[6..]), (0, &[1, 0, 8, 0][..]));
}

#[test]
fn boot_serves_foe_only() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    // An SDO upload of 0x1000:00 in BOOT: mailbox error 0x0002.
    let upload = [0x00, 0x20, 0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];
    let answer = b.exchange(3, &upload).unwrap();
    assert_eq!(answer[6..], [1, 0, 2, 0]);
    assert_eq!(answer[5] & 0x0F, 0, "a mailbox error reply");
    // Without an FoE handler FoE is not supported either.
    b.counter = b.counter % 7 + 1;
    let mut message = vec![6 + 7, 0, 0, 0, 0, 4 | (b.counter << 4)];
    message.extend(write_request(b"app.bin", PASSWORD));
    b.regs.put(BOOT_MAILBOX.receive.start, &message);
    b.sub.handle_al_event(AlEvent::sync_manager(0));
    b.regs.drive(&mut b.sub, T0);
    while b.sub.service_mailbox(T0, &mut (), &mut ()) {
        b.regs.drive(&mut b.sub, T0);
    }
    let send = usize::from(BOOT_MAILBOX.send.start);
    assert_eq!(b.regs.mem[send + 5] & 0x0F, 0);
    assert_eq!(b.regs.mem[send + 6..send + 10], [1, 0, 2, 0]);
    assert!(b.files().calls.is_empty());
}

#[test]
fn a_state_the_files_refuse_gets_bootstrap_only_or_not_in_bootstrap() {
    let mut preop = Bench::new(AlState::PreOp, TestFiles::default());
    assert_eq!(
        preop.foe(&write_request(b"app.bin", PASSWORD)),
        Some(error(0x8008))
    );
    let files = TestFiles {
        not_in_boot: true,
        ..TestFiles::default()
    };
    let mut boot = Bench::new(AlState::Boot, files);
    assert_eq!(
        boot.foe(&write_request(b"app.bin", PASSWORD)),
        Some(error(0x8009))
    );
    assert!(preop.files().calls.is_empty() && boot.files().calls.is_empty());
    // A device that allows FoE in PREOP serves it there, with the standard mailbox's segments.
    let files = TestFiles {
        preop: true,
        ..TestFiles::default()
    };
    let mut preop = Bench::new(AlState::PreOp, files);
    assert_eq!(
        preop.foe(&write_request(b"app.bin", PASSWORD)),
        Some(ack(0))
    );
    let image = file(128 - 12 + 1);
    assert_eq!(preop.foe(&data(1, &image[..116])), Some(ack(1)));
    assert_eq!(preop.foe(&data(2, &image[116..])), Some(ack(2)));
    assert_eq!(preop.files().calls.last(), Some(&Call::Finish(117)));
}

#[test]
fn leaving_boot_aborts_the_transfer() {
    let mut b = Bench::new(AlState::Boot, TestFiles::default());
    b.foe(&write_request(b"app.bin", PASSWORD));
    b.regs.al_control(1);
    b.serve(AlEvent(b.regs.event));
    assert_eq!(b.sub.state(), AlState::Init);
    b.regs.al_control(3);
    b.serve(AlEvent(b.regs.event));
    let to_boot = Transition {
        from: AlState::Init,
        to: AlState::Boot,
    };
    b.sub.complete_transition(to_boot, Ok(()));
    b.regs.drive(&mut b.sub, T0);
    // The first service of the new mailbox resets the handlers: the files hear of the abort
    // before the new request.
    assert_eq!(b.foe(&write_request(b"app.bin", PASSWORD)), Some(ack(0)));
    assert_eq!(
        b.files().calls,
        [
            Call::OpenWrite(b"app.bin".to_vec(), PASSWORD),
            Call::Abort,
            Call::OpenWrite(b"app.bin".to_vec(), PASSWORD),
        ]
    );
}
