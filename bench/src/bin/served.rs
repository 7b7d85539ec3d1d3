//! `served <slaves> <frames>`: what the virtual slave does for each cyclic frame of a MainDevice,
//! on virtual time, run under callgrind by `bench/callgrind.sh`: `slaves` digital I/O modules
//! (`ecat_emu::devices::dio`, the real runners) served by `harness::serve` and `Line::serve` as
//! `ecat-virtual-slave --device dio --count N` serves them, brought to OP, then `frames` frames
//! one millisecond apart, each one LRW over the whole process image (2 bytes of outputs and 2 of
//! inputs per SubDevice, as SOEM's `send_processdata` sends it). Counting the instructions of
//! two runs that differ only in `frames` gives the cost of one frame: the ESCs' share, the
//! runners' wake-ups and cycles, the line's settling.

use std::collections::VecDeque;

use ecat_core::device::MailboxConfig;
use ecat_emu::devices;
use ecat_emu::esc::datagram::{Command, Operation};
use ecat_emu::frame::{self, Datagram};
use ecat_emu::harness::{self, Spawn};
use ecat_emu::line::{Host, Line, MAIN_DEVICE_MAC};
use ecat_emu::master::TestMaster;
use embassy_time::Duration;

/// The sample devices' mailboxes (`ecat_emu::devices`).
const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
/// SM2 (outputs) and SM3 (inputs) of each SubDevice, after the mailboxes.
const OUTPUTS: u16 = 0x1100;
const INPUTS: u16 = 0x1180;
/// Process data of a `dio` each way.
const PD: u16 = 2;
/// The MainDevice's cycle.
const CYCLE: Duration = Duration::from_millis(1);

/// A host whose clock jumps to the next frame of its script (a frame every [`CYCLE`]) or to the
/// line's deadline, and ends after the last frame.
struct Scripted {
    clock: Duration,
    frames: VecDeque<(Duration, Vec<u8>)>,
    answers: Vec<Vec<u8>>,
}

impl Host for Scripted {
    fn elapsed(&self) -> Duration {
        self.clock
    }

    fn receive(&mut self) -> Option<(Duration, Vec<u8>)> {
        match self.frames.front() {
            Some(&(at, _)) if at <= self.clock => self.frames.pop_front(),
            _ => None,
        }
    }

    fn send(&mut self, frame: &[u8]) {
        self.answers.push(frame.to_vec());
    }

    async fn wait(&mut self, deadline: Duration) -> bool {
        let Some(&(next, _)) = self.frames.front() else {
            return false;
        };
        self.clock = deadline.min(next).max(self.clock);
        true
    }
}

/// Brings every SubDevice of `line` to OP as a MainDevice does: station addresses, mailboxes,
/// SM2/SM3 and FMMUs into one image ([`Line::map_process_data`]), PREOP, SAFEOP with outputs,
/// OP.
async fn to_op(line: &Line) {
    assert!(line.address(), "every ESC addressed");
    let masters: Vec<TestMaster> = line.escs().iter().cloned().map(TestMaster::new).collect();
    for master in &masters {
        master.configure_mailbox(&MAILBOX);
    }
    assert!(
        line.map_process_data(OUTPUTS, INPUTS, PD),
        "every ESC mapped"
    );
    for state in [0x02u16, 0x04, 0x08] {
        for master in &masters {
            if state == 0x08 {
                master.write(OUTPUTS, &[0; PD as usize]);
            }
            assert_eq!(master.request(state).await, (state, 0), "to {state:#x}");
        }
    }
}

/// One LRW over the image of `slaves` SubDevices, tagged with `index`.
fn lrw(slaves: usize, index: u8) -> Vec<u8> {
    let mut datagram = Datagram::logical(
        Command::L(Operation::ReadWrite).code(),
        0,
        &vec![0; 2 * usize::from(PD) * slaves],
    );
    datagram.index = index;
    frame::build(MAIN_DEVICE_MAC, &[datagram])
}

fn main() {
    let mut args = std::env::args().skip(1);
    let slaves: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let frames: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let devices: Vec<Box<dyn Spawn>> = (0..slaves)
        .map(|_| Box::new(devices::dio().device) as Box<dyn Spawn>)
        .collect();
    harness::serve(devices, move |escs| async move {
        let line = Line::new(escs);
        to_op(&line).await;
        let frames: VecDeque<(Duration, Vec<u8>)> = (1..=frames)
            .map(|n| (CYCLE * n as u32, lrw(slaves, n as u8)))
            .collect();
        let sent = frames.len();
        let mut host = Scripted {
            clock: Duration::from_ticks(0),
            frames,
            answers: Vec::new(),
        };
        line.serve(&mut host).await;
        assert_eq!(host.answers.len(), sent, "every frame answered");
        // Each SubDevice in OP counts its read (inputs) once and its write (outputs) twice.
        let wkc = host
            .answers
            .iter()
            .map(|answer| frame::datagrams(answer).expect("a well-formed answer")[0].wkc);
        assert!(
            wkc.clone().all(|wkc| usize::from(wkc) == 3 * slaves),
            "working counters"
        );
        for master in line.escs().iter().cloned().map(TestMaster::new) {
            assert_eq!(master.al_status(), 0x08, "still in OP");
        }
        println!(
            "{slaves} slaves: {sent} frames, working counter {} each",
            3 * slaves
        );
    });
}
