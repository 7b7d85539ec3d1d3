//! `foe <case> <n>`: FoE through the core (issue #16 point 4).
//!
//! - `segment-128 <n>`, `segment-1024 <n>`: a write request, then `n` data segments of a file,
//!   each a mailbox round trip (128- or 1024-byte mailboxes: 116 or 1 012 bytes of data a
//!   segment). Run under callgrind by `bench/callgrind.sh`: the difference between n = 1001 and
//!   n = 1 divided by 1000 is one segment's cost, the SubDevice's side counted alone
//!   (`Bench::serve`).
//! - `throughput`: writes a 256 KiB image with each mailbox size and prints the round trips,
//!   the bytes a round trip moves, and the protocol's minimum (one round trip for the request,
//!   one per segment, the empty segment after an exact multiple included).
//!
//! The device serves FoE in PREOP (the bench's state); the application's `Files` take every
//! segment as written and count the bytes, so the figures are the stack's, not a flash's.

use ecat_bench::{Bench, FOE, Od, device};
use ecat_core::AlState;
use ecat_core::foe::{Files, Foe, FoeError, Progress};

/// Takes every file, keeps nothing but its length.
#[derive(Default)]
struct Counter {
    bytes: u32,
    finished: Option<u32>,
}

impl Files for Counter {
    fn allowed(&self, _: AlState) -> bool {
        true
    }
    fn open_write(&mut self, _: &[u8], _: u32) -> Result<(), FoeError> {
        self.bytes = 0;
        self.finished = None;
        Ok(())
    }
    fn write(&mut self, _: u32, data: &[u8]) -> Result<Progress, FoeError> {
        self.bytes += data.len() as u32;
        Ok(Progress::Written)
    }
    fn finish_write(&mut self, length: u32) -> Result<(), FoeError> {
        self.finished = Some(length);
        Ok(())
    }
}

/// FoE opcodes (ETG.1000.6 Table 92).
const WRITE: u8 = 2;
const DATA: u8 = 3;
const ACK: u8 = 4;

/// An FoE frame: opcode, reserved byte, the 32-bit value (password or packet number), data.
fn frame(opcode: u8, value: u32, data: &[u8]) -> Vec<u8> {
    let mut frame = vec![opcode, 0];
    frame.extend_from_slice(&value.to_le_bytes());
    frame.extend_from_slice(data);
    frame
}

/// Writes `len` bytes (more when `len` is `None`: `n` full segments) through one transfer;
/// returns the round trips.
fn write<const MBX: usize>(len: Option<usize>, segments: usize) -> usize {
    let config = device(MBX as u16);
    let mut bench = Bench::<MBX>::new(&config);
    let mut od = Od::default();
    let mut foe = (Foe::new(Counter::default()),);
    let segment = MBX - 12;
    let data = vec![0x5A; segment];
    let answer = bench.exchange_with(&mut od, &mut (), &mut foe, FOE, &frame(WRITE, 0, b"image"));
    assert_eq!(answer[..6], [ACK, 0, 0, 0, 0, 0]);
    let mut trips = 1;
    let mut sent = 0;
    let mut packet = 0u32;
    loop {
        let k = len.map_or(segment, |len| (len - sent).min(segment));
        packet += 1;
        let answer = bench.exchange_with(
            &mut od,
            &mut (),
            &mut foe,
            FOE,
            &frame(DATA, packet, &data[..k]),
        );
        assert_eq!(answer[0], ACK, "packet {packet}");
        trips += 1;
        sent += k;
        let done = match len {
            Some(_) => k < segment,
            None => packet as usize == segments,
        };
        if done {
            break;
        }
    }
    if let Some(len) = len {
        assert_eq!(foe.0.files().finished, Some(len as u32));
    }
    trips
}

fn main() {
    let mut args = std::env::args().skip(1);
    let case = args.next().expect("case");
    let n: usize = args.next().map_or(1, |n| n.parse().expect("n"));
    match case.as_str() {
        "segment-128" => {
            write::<128>(None, n);
        }
        "segment-1024" => {
            write::<1024>(None, n);
        }
        "throughput" => {
            let image = 256 * 1024;
            println!(
                "| mailbox | data per segment | round trips for 256 KiB | protocol minimum | bytes per round trip |"
            );
            println!("|---|---|---|---|---|");
            for (mbx, trips) in [
                (128, write::<128>(Some(image), 0)),
                (1024, write::<1024>(Some(image), 0)),
            ] {
                let segment = mbx - 12;
                let minimum = 1 + image / segment + 1;
                println!(
                    "| {mbx} | {segment} | {trips} | {minimum} | {:.1} |",
                    image as f64 / trips as f64
                );
            }
        }
        other => panic!("unknown case {other}"),
    }
}
