//! The FoE server driven by arbitrary bytes: the fuzz target of the FoE parser
//! ([`ecat_core::foe::Packet`]) and server ([`ecat_core::foe::Foe`]), as the mailbox hands them
//! frames (at most the receive mailbox's payload) in any state, with mailbox restarts between.
//!
//! [`foe`] reads the bytes as steps: a step byte (bits 0..1 the state: PREOP, SAFEOP, OP, BOOT;
//! bit 7 a mailbox restart first), a mailbox size byte (the receive and send mailbox's payload,
//! 6..=255 bytes), a length byte, then that many frame bytes. Whatever the bytes, it asserts that
//! - the server does not panic;
//! - every answer fits the reply buffer and is an FoE acknowledge, data, busy or error frame
//!   whose error code is one of ETG.1000.6's (0x8000..=0x800B); a mailbox error answers only a
//!   frame shorter than the FoE header;
//! - a written file is written in order, each byte once, and never more than was sent.
//!
//! Two drivers run it: `fuzz/fuzz_targets/foe.rs` (`cargo fuzz run foe`) and the stable test
//! `tests/tests/fuzz_foe.rs` (random inputs on every `cargo test`).

use ecat_core::foe::{Files, Foe, FoeError, OpCode, Packet, Progress};
use ecat_core::mailbox::{Env, Handler, MailboxError, Reply};
use ecat_core::{AlState, Instant};

/// Files that accept `a` for writing (password 0) and reading, serve FoE in every state but
/// SAFEOP, and answer every fifth segment with busy.
#[derive(Debug, Default)]
struct FuzzFiles {
    written: usize,
    writes: u32,
}

impl Files for FuzzFiles {
    fn allowed(&self, state: AlState) -> bool {
        state != AlState::SafeOp
    }

    fn open_write(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        match (name, password) {
            (b"a", 0) => {
                self.written = 0;
                Ok(())
            }
            (b"a", _) => Err(FoeError::NO_RIGHTS),
            _ => Err(FoeError::NOT_FOUND),
        }
    }

    fn write(&mut self, offset: u32, data: &[u8]) -> Result<Progress, FoeError> {
        self.writes += 1;
        if self.writes.is_multiple_of(5) {
            return Ok(Progress::Busy { done: 1, entire: 2 });
        }
        assert_eq!(offset as usize, self.written, "in order, each byte once");
        self.written += data.len();
        Ok(Progress::Written)
    }

    fn open_read(&mut self, name: &[u8], _: u32) -> Result<(), FoeError> {
        match name {
            b"a" => Ok(()),
            _ => Err(FoeError::NOT_FOUND),
        }
    }

    fn read(&mut self, offset: u32, out: &mut [u8]) -> Result<usize, FoeError> {
        // A file of 300 bytes.
        let n = 300usize.saturating_sub(offset as usize).min(out.len());
        out[..n].fill(0x5A);
        Ok(n)
    }
}

/// Runs the FoE server over `data` (see the module documentation).
pub fn foe(data: &[u8]) {
    let mut server = Foe::new(FuzzFiles::default());
    let mut sent = 0usize;
    let mut reply = [0u8; 255];
    let mut rest = data;
    while let [step, size, len, tail @ ..] = rest {
        let size = usize::from(*size).max(6);
        let len = usize::from(*len).min(tail.len()).min(size);
        let (frame, next) = tail.split_at(len);
        rest = next;
        if step & 0x80 != 0 {
            server.reset();
        }
        let state =
            [AlState::PreOp, AlState::SafeOp, AlState::Op, AlState::Boot][usize::from(step & 3)];
        let env = Env {
            state,
            now: Instant::from_micros(0),
            max_request: size,
        };
        if let Some(packet) = Packet::new_checked(frame) {
            let _ = (
                packet.opcode(),
                packet.value(),
                packet.busy(),
                packet.data(),
            );
            if packet.opcode() == OpCode::Data {
                sent += packet.data().len();
            }
        }
        let out = &mut reply[..size];
        match server.request(env, frame, out) {
            Reply::Silent => {}
            Reply::Error(error) => {
                assert_eq!(error, MailboxError::INVALID_SIZE);
                assert!(frame.len() < Packet::<&[u8]>::HEADER);
            }
            Reply::Send(n) => check_answer(&out[..n.min(size)], n, size),
        }
        assert!(server.files().written <= sent, "never more than was sent");
    }
}

fn check_answer(answer: &[u8], n: usize, size: usize) {
    assert!(n <= size, "the answer fits the reply buffer");
    let packet = Packet::new_checked(answer).expect("an FoE header");
    match packet.opcode() {
        OpCode::Ack | OpCode::Busy => assert_eq!(n, 6),
        OpCode::Data => {}
        OpCode::Error => {
            assert_eq!(n, 6);
            assert!((0x8000..=0x800B).contains(&packet.value()));
        }
        other => panic!("the server sent {other:?}"),
    }
}
