//! `line <slaves> <cycles>`: `cycles` process-data cycles of a MainDevice through a line of
//! `slaves` emulated ESCs at frame level, run under callgrind by `bench/callgrind.sh`.
//!
//! Each ESC is configured as in OP: station address, SM2 (outputs) and SM3 (inputs) of 11 bytes
//! in 3-buffer mode, FMMUs mapping them into one logical image (`Line::map_process_data`). A
//! cycle is what ethercrab sends: one LRW over the whole image and one FPRD of AL status (0x0130)
//! per slave, packed into frames of at most 1500 bytes of Ethernet payload (one frame up to 41
//! slaves; beyond, the LRW is split at slave boundaries).

use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::esc::datagram::{Command, Operation};
use ecat_emu::frame::{self, Datagram};
use ecat_emu::line::{FIRST_STATION, Line, MAIN_DEVICE_MAC};

/// Process data of each slave, each way.
const PD: u16 = 11;
/// Bytes of datagrams in one frame: a 1500-byte Ethernet payload less the EtherCAT header.
const FRAME_DATAGRAMS: usize = 1500 - frame::ECAT_HEADER;
/// A datagram's header and working counter.
const OVERHEAD: usize = frame::DATAGRAM_HEADER + frame::WKC;
/// AL status (ETG.1000.4 Table 34).
const AL_STATUS: u16 = 0x0130;

/// `slaves` ESCs in OP with their process data mapped.
fn op_line(slaves: u16) -> Line {
    let escs = (0..slaves).map(|_| Emulator::new(EscConfig::default()));
    let line = Line::new(escs.collect());
    assert!(line.address(), "every ESC addressed");
    assert!(
        line.map_process_data(0x1000, 0x1100, PD),
        "every ESC mapped"
    );
    for emu in line.escs() {
        emu.with(|esc| esc.pdi_write(AL_STATUS, &[0x08, 0]));
    }
    line
}

/// One cycle's datagrams: the LRW over the image in pieces of whole slaves that fit a frame (a
/// slave split between two pieces would count in both), then the FPRDs.
fn cycle(slaves: u16) -> Vec<Datagram> {
    let per_slave = 2 * usize::from(PD);
    let image = per_slave * usize::from(slaves);
    let piece = (FRAME_DATAGRAMS - OVERHEAD) / per_slave * per_slave;
    let lrw = Command::L(Operation::ReadWrite).code();
    let fprd = Command::Fp(Operation::Read).code();
    let mut datagrams: Vec<Datagram> = (0..image)
        .step_by(piece)
        .map(|start| {
            let len = (image - start).min(piece);
            Datagram::logical(lrw, start as u32, &vec![0; len])
        })
        .collect();
    datagrams.extend(
        (0..slaves).map(|n| Datagram::physical(fprd, FIRST_STATION + n, AL_STATUS, &[0; 2])),
    );
    datagrams
}

/// `datagrams` packed in order into as few frames as hold them.
fn frames(datagrams: Vec<Datagram>) -> Vec<Vec<u8>> {
    let mut frames: Vec<Vec<Datagram>> = vec![Vec::new()];
    for datagram in datagrams {
        let last = frames.last_mut().expect("one frame at least");
        let used: usize = last.iter().map(Datagram::size).sum();
        if used + datagram.size() > FRAME_DATAGRAMS {
            frames.push(vec![datagram]);
        } else {
            last.push(datagram);
        }
    }
    frames
        .iter()
        .map(|datagrams| frame::build(MAIN_DEVICE_MAC, datagrams))
        .collect()
}

/// Offset of the first datagram's data in a frame: the first output byte.
const FIRST_DATA: usize = frame::ETHERNET_HEADER + frame::ECAT_HEADER + frame::DATAGRAM_HEADER;

fn main() {
    let mut args = std::env::args().skip(1);
    let slaves: u16 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let cycles: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let line = op_line(slaves);
    let sent = frames(cycle(slaves));
    let mut buffers = sent.clone();
    for i in 0..cycles {
        for (buffer, frame) in buffers.iter_mut().zip(&sent) {
            buffer.copy_from_slice(frame);
            buffer[FIRST_DATA] = i as u8;
            let len = line.process(std::hint::black_box(buffer));
            assert_eq!(len, Some(frame.len()));
        }
    }
    // The last cycle was answered: 3 per slave on the LRW, 1 per FPRD.
    let wkc: u32 = buffers
        .iter()
        .flat_map(|frame| frame::datagrams(frame).expect("a well-formed answer"))
        .map(|datagram| u32::from(datagram.wkc))
        .sum();
    assert!(
        cycles == 0 || wkc == 4 * u32::from(slaves),
        "working counter {wkc}"
    );
    println!("{slaves} slaves: {} frame(s) per cycle", sent.len());
}
