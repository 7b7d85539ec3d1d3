//! A line in two segments, as the virtual slave chains instances with `--out`: the first
//! segment's last ESC has a link on port 1 ([`Line::open_ended`]), so a frame it processed leaves
//! there for the next segment, which processes it and loops it back at its own last ESC; the
//! frame then passes the first segment unprocessed and leaves through its first ESC's port 0. To
//! the MainDevice the two segments are one line: positions (ADP increments), broadcast working
//! counters and logical addressing come out as through one line of all the ESCs.

use std::collections::VecDeque;

use ecat_core::register;
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::frame::{self, Datagram};
use ecat_emu::harness;
use ecat_emu::line::{Host, Line, Served};
use embassy_time::Duration;

const APRD: u8 = 1;
const APWR: u8 = 2;
const FPRD: u8 = 4;
const FPWR: u8 = 5;
const BRD: u8 = 7;
const LRW: u8 = 12;

/// The MainDevice's source MAC: locally-administered bit clear.
const SOURCE: [u8; 6] = [0x10, 0x20, 0x30, 0x40, 0x50, 0x60];
/// Process RAM no SyncManager guards.
const RAM: u16 = 0x1800;

fn escs(n: usize) -> Vec<Emulator> {
    (0..n)
        .map(|_| Emulator::new(EscConfig::default()))
        .collect()
}

/// Two ESCs, then one: the first segment open-ended.
fn segments() -> (Line, Line) {
    (Line::open_ended(escs(2)), Line::new(escs(1)))
}

/// `datagrams` through the two segments as the virtual slaves pass a frame: through the first,
/// out of its port 1 into the second, back unchanged through the first.
fn through_segments(first: &Line, second: &Line, datagrams: &[Datagram]) -> Vec<u8> {
    let mut frame = frame::build(SOURCE, datagrams);
    let len = frame.len();
    assert_eq!(first.process(&mut frame), Some(len));
    assert_eq!(second.process(&mut frame), Some(len));
    frame
}

fn through_line(line: &Line, datagrams: &[Datagram]) -> Vec<u8> {
    let mut frame = frame::build(SOURCE, datagrams);
    let len = frame.len();
    assert_eq!(line.process(&mut frame), Some(len));
    frame
}

/// A byte-aligned FMMU entity: `length` logical bytes at `logical` onto `physical`, `kind`
/// 1 read, 2 write (ETG.1000.4 Table 56).
fn fmmu(logical: u32, length: u16, physical: u16, kind: u8) -> Vec<u8> {
    let mut entity = Vec::new();
    entity.extend(logical.to_le_bytes());
    entity.extend(length.to_le_bytes());
    entity.extend([0, 7]);
    entity.extend(physical.to_le_bytes());
    entity.extend([0, kind, 1, 0, 0, 0]);
    entity
}

/// What a MainDevice does on a line of three: station addresses by position, a position read
/// of the third, a broadcast read, RAM filled per station, a read and a write FMMU per ESC, an
/// LRW over all three. The same frames through the two segments and through one line of three
/// ESCs come back byte for byte the same, with the numbers of one line of three.
#[test]
fn a_frame_through_two_segments_is_a_frame_through_one_line_of_all_their_escs() {
    let (first, second) = segments();
    let whole = Line::new(escs(3));
    let mut frames: Vec<Vec<Datagram>> = vec![
        (0..3u16)
            .map(|n| {
                Datagram::physical(
                    APWR,
                    0u16.wrapping_sub(n),
                    0x0010,
                    &(0x1000 + n).to_le_bytes(),
                )
            })
            .collect(),
        vec![Datagram::physical(APRD, 0xFFFE, 0x0010, &[0, 0])],
        vec![Datagram::physical(BRD, 0, 0x0010, &[0, 0])],
    ];
    for n in 0..3u16 {
        frames.push(vec![
            Datagram::physical(FPWR, 0x1000 + n, RAM, &[0x10 * (n as u8 + 1), 0]),
            Datagram::physical(
                FPWR,
                0x1000 + n,
                0x0600,
                &[
                    fmmu(u32::from(2 * n), 1, RAM, 1),
                    fmmu(u32::from(2 * n + 1), 1, RAM + 1, 2),
                ]
                .concat(),
            ),
        ]);
    }
    frames.push(vec![Datagram::logical(
        LRW,
        0,
        &[0, 0xA1, 0, 0xA2, 0, 0xA3],
    )]);
    frames.push(vec![Datagram::physical(FPRD, 0x1002, RAM, &[0, 0])]);
    let mut back = Vec::new();
    for datagrams in &frames {
        let split = through_segments(&first, &second, datagrams);
        assert_eq!(split, through_line(&whole, datagrams), "{datagrams:?}");
        back.push(frame::datagrams(&split).expect("a well-formed frame"));
    }
    let wkcs = |n: usize| back[n].iter().map(|d| d.wkc).collect::<Vec<_>>();
    assert_eq!(
        wkcs(0),
        [1, 1, 1],
        "each APWR reaches one ESC, the third in segment two"
    );
    assert_eq!(
        (
            back[1][0].address,
            back[1][0].data.as_slice(),
            back[1][0].wkc
        ),
        ([0x01, 0x00, 0x10, 0x00], &[0x02, 0x10][..], 1),
        "APRD at position 2 (ADP −2): the third ESC (0x1002) saw 0; every ESC incremented it"
    );
    assert_eq!(
        (
            back[2][0].address,
            back[2][0].data.as_slice(),
            back[2][0].wkc
        ),
        ([0x03, 0x00, 0x10, 0x00], &[0x03, 0x10][..], 3),
        "BRD: ADP +3, the stations ORed, counted by all three"
    );
    assert_eq!(
        (back[6][0].data.as_slice(), back[6][0].wkc),
        (&[0x10, 0xA1, 0x20, 0xA2, 0x30, 0xA3][..], 9),
        "LRW: each ESC's RAM read into its read byte, its write byte taken; 3 × (1 + 2)"
    );
    assert_eq!(
        (back[7][0].data.as_slice(), back[7][0].wkc),
        (&[0x30, 0xA3][..], 1),
        "the LRW wrote the third ESC's RAM in segment two"
    );
    assert_eq!(
        frame::build(SOURCE, &[])[6] | 0x02,
        through_segments(&first, &second, &frames[2])[6],
        "the source MAC marked processed"
    );
}

/// ESC datasheet, DL status 0x0110: the last ESC of a segment followed by another has a link and
/// communication on port 1 and its loop open; the last ESC of the line has no link on port 1
/// and its loop closed. Ports 2 and 3 closed, port 0 linked and open everywhere.
#[test]
fn dl_status_shows_port_1_open_with_link_at_the_end_of_a_segment_and_closed_at_the_end() {
    let (first, second) = segments();
    let status = |emu: &Emulator| {
        let mut buf = [0; 2];
        emu.with(|esc| esc.pdi_read(register::DL_STATUS, &mut buf));
        u16::from_le_bytes(buf)
    };
    // Bits 0, 1 PDI; 4, 5 link on ports 0, 1; 9, 11 communication on ports 0, 1; 12, 14 loops
    // of ports 2, 3 closed.
    assert_eq!(status(&first.escs()[0]), 0x5A33);
    assert_eq!(
        status(&first.escs()[1]),
        0x5A33,
        "open-ended: port 1 linked, loop open"
    );
    // Bit 10: the loop of port 1 closed; no link (bit 5) or communication (bit 11) there.
    assert_eq!(status(&second.escs()[0]), 0x5613, "the end of the line");
}

/// A host on virtual time: requests arrive on port 0, frames come back from the next segment,
/// and the host records what the line sent where.
#[derive(Default)]
struct Segment {
    requests: VecDeque<Vec<u8>>,
    coming_back: VecDeque<Vec<u8>>,
    sent: Vec<Vec<u8>>,
    passed_on: Vec<Vec<u8>>,
    clock: Duration,
}

impl Host for Segment {
    fn elapsed(&self) -> Duration {
        self.clock
    }

    fn receive(&mut self) -> Option<(Duration, Vec<u8>)> {
        let clock = self.clock;
        self.requests.pop_front().map(|frame| (clock, frame))
    }

    fn send(&mut self, frame: &[u8]) {
        self.sent.push(frame.to_vec());
    }

    async fn wait(&mut self, _deadline: Duration) -> bool {
        false
    }

    fn returned(&mut self) -> Option<Vec<u8>> {
        self.coming_back.pop_front()
    }

    fn pass_on(&mut self, frame: &[u8]) {
        self.passed_on.push(frame.to_vec());
    }
}

/// Served on a host, an open-ended segment sends every request it processed to the next
/// segment (none to the MainDevice) and every frame that came back to the MainDevice,
/// unchanged; a line whose end is closed loops back itself and is never asked for returns.
#[test]
fn a_served_segment_passes_requests_on_and_sends_what_comes_back_to_the_maindevice() {
    let _clock = harness::exclusive();
    let (first, _) = segments();
    let request = frame::build(SOURCE, &[Datagram::physical(BRD, 0, 0x0010, &[0, 0])]);
    let back = {
        let mut frame = request.clone();
        frame[6] |= 0x02;
        let wkc = frame.len() - 2;
        frame[wkc] = 7;
        frame
    };
    let mut host = Segment {
        requests: VecDeque::from([request.clone(), request.clone()]),
        coming_back: VecDeque::from([back.clone()]),
        ..Segment::default()
    };
    let served = embassy_futures::block_on(first.serve(&mut host));
    let mut processed = request.clone();
    assert_eq!(first.process(&mut processed), Some(request.len()));
    assert_eq!(host.passed_on, [processed.clone(), processed]);
    assert_eq!(
        host.sent,
        core::slice::from_ref(&back),
        "what came back, unchanged"
    );
    assert_eq!(
        served,
        Served {
            frames: 1,
            lost: 0,
            wakeups: 0
        }
    );

    let closed = Line::new(escs(2));
    let mut host = Segment {
        requests: VecDeque::from([request.clone()]),
        coming_back: VecDeque::from([back]),
        ..Segment::default()
    };
    let served = embassy_futures::block_on(closed.serve(&mut host));
    assert_eq!(host.passed_on.len(), 0);
    assert_eq!(host.sent.len(), 1, "looped back at the last ESC");
    assert_eq!(host.coming_back.len(), 1, "no return path asked for");
    assert_eq!(served.frames, 1);
}
