//! File access over EtherCAT (FoE, ETG.1000.6 §5.9): a TFTP-like transfer of a named file
//! through the mailbox, the way firmware is updated in the field (SOEM's `ec_FOEwrite`, IgH's
//! `ethercat foe_write`, TwinCAT's "Firmware Update").
//!
//! [`Foe`] is the mailbox handler (type 4, [`crate::mailbox::Handler`]); the application's
//! [`Files`] accept or refuse a file name and password and stream the data in and out, a
//! segment at a time (nothing buffers the whole file). A firmware without FoE does not name
//! [`Foe`] and carries none of its code.
//!
//! A write: the MainDevice sends a write request (password, file name), the SubDevice
//! acknowledges packet 0; then data packets 1, 2, … each of the receive mailbox's size less 12
//! bytes (6 mailbox header, 6 FoE header), each acknowledged with its number; a shorter segment
//! (an empty one after an exact multiple) ends the file. A read mirrors it: the SubDevice sends
//! the data, the MainDevice acknowledges. Rules kept here:
//!
//! - a data packet repeating the last acknowledged number is acknowledged again and not written
//!   twice; a lost acknowledge is recovered by the mailbox's repeat (it writes the last message
//!   again), which needs nothing from FoE;
//! - any other number out of sequence ends the transfer with 0x8005 "packet number wrong";
//!   data without a write request, an acknowledge without a read, a request during a transfer,
//!   a busy or an unknown opcode end it with 0x8004 "illegal";
//! - an empty file name is 0x8001 "not found"; the name ends at the mailbox length or at a NUL;
//! - an error frame from the MainDevice ends the transfer without an answer;
//! - [`Files::allowed`] says in which states FoE is served (default: BOOT only); a request in
//!   another state gets 0x8008 "bootstrap only", or 0x8009 "not in bootstrap" in BOOT;
//! - the application may answer a segment with busy (done/entire): the MainDevice sends the
//!   same packet again later.

mod error;
mod packet;

pub use error::FoeError;
pub use packet::{OpCode, Packet};

use crate::AlState;
use crate::mailbox::{Env, Handler, MailboxError, MailboxType, Reply};
use packet::{write_busy, write_error, write_header};

/// What the application did with a segment of a written file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// The segment is stored.
    Written,
    /// The segment is not stored yet (e.g. a flash erase runs): the SubDevice answers busy with
    /// this progress, and the MainDevice sends the same packet again.
    Busy {
        /// The progress made.
        done: u16,
        /// The progress to make.
        entire: u16,
    },
}

/// The application's files: each method has a default, so a device implements only what it
/// serves (a firmware update implements `open_write`, `write` and `finish_write`).
pub trait Files {
    /// Whether FoE is served in `state` (PREOP, SAFEOP, OP or BOOT). Default: BOOT only.
    fn allowed(&self, state: AlState) -> bool {
        state == AlState::Boot
    }

    /// The MainDevice asks to write the file `name` with `password`: `Ok` to accept.
    /// Default: 0x8001 "not found".
    fn open_write(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        let _ = (name, password);
        Err(FoeError::NOT_FOUND)
    }

    /// The segment `data` of the accepted file, at `offset` (each segment is written once, in
    /// order). An error ends the transfer with that code.
    fn write(&mut self, offset: u32, data: &[u8]) -> Result<Progress, FoeError> {
        let _ = (offset, data);
        Err(FoeError::ILLEGAL)
    }

    /// The last segment is written: the file is `length` bytes long. An error (e.g. a bad
    /// image) is sent instead of the last acknowledge. Default: accepted.
    fn finish_write(&mut self, length: u32) -> Result<(), FoeError> {
        let _ = length;
        Ok(())
    }

    /// The MainDevice asks to read the file `name` with `password`: `Ok` to accept.
    /// Default: 0x8001 "not found".
    fn open_read(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        let _ = (name, password);
        Err(FoeError::NOT_FOUND)
    }

    /// Fills `out` with the file from `offset`: the length written; shorter than `out` at the
    /// end of the file.
    fn read(&mut self, offset: u32, out: &mut [u8]) -> Result<usize, FoeError> {
        let _ = (offset, out);
        Err(FoeError::ILLEGAL)
    }

    /// A transfer the application accepted ended without completing, for a reason it did not
    /// give itself (an error from the MainDevice, a wrong packet number, the mailbox stopped):
    /// what was written is incomplete.
    fn abort(&mut self) {}
}

/// Where a transfer stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Transfer {
    Idle,
    /// A write: the last packet acknowledged and the bytes written.
    Writing {
        packet: u32,
        offset: u32,
    },
    /// A write complete: its last packet, acknowledged again when repeated.
    Written {
        packet: u32,
    },
    /// A read: the last packet sent, the bytes sent and whether it was the last.
    Reading {
        packet: u32,
        offset: u32,
        last: bool,
    },
}

/// The FoE server: a mailbox [`Handler`] over the application's [`Files`].
#[derive(Debug)]
pub struct Foe<F> {
    files: F,
    transfer: Transfer,
}

impl<F: Files> Foe<F> {
    /// An FoE server over `files`, no transfer in progress.
    pub const fn new(files: F) -> Self {
        Self {
            files,
            transfer: Transfer::Idle,
        }
    }

    /// The application's files.
    pub fn files(&self) -> &F {
        &self.files
    }

    /// The application's files, for changing.
    pub fn files_mut(&mut self) -> &mut F {
        &mut self.files
    }

    /// Serves one frame; the length of the answer in `reply` (0: none).
    fn serve(&mut self, env: Env, frame: &Packet<&[u8]>, reply: &mut [u8]) -> usize {
        let opcode = frame.opcode();
        if opcode == OpCode::Error {
            self.abandon();
            return 0;
        }
        if !self.files.allowed(env.state) {
            let error = if env.state == AlState::Boot {
                FoeError::NOT_IN_BOOTSTRAP
            } else {
                FoeError::BOOTSTRAP_ONLY
            };
            return self.fail(reply, error);
        }
        match opcode {
            OpCode::Write => self.write_request(frame, reply),
            OpCode::Read => self.read_request(frame, reply),
            OpCode::Data => self.data(env, frame, reply),
            OpCode::Ack => self.ack(frame.value(), reply),
            _ => self.fail(reply, FoeError::ILLEGAL),
        }
    }

    fn in_progress(&self) -> bool {
        matches!(
            self.transfer,
            Transfer::Writing { .. } | Transfer::Reading { .. }
        )
    }

    fn write_request(&mut self, frame: &Packet<&[u8]>, reply: &mut [u8]) -> usize {
        match self.open(frame, F::open_write) {
            Ok(()) => {
                self.transfer = Transfer::Writing {
                    packet: 0,
                    offset: 0,
                };
                write_header(reply, OpCode::Ack, 0)
            }
            Err(error) => write_error(reply, error),
        }
    }

    /// What a read or write request must pass: no transfer in progress (0x8004, which ends the
    /// transfer), a file name (0x8001), and `open`, the files' consent to the name and password.
    fn open(
        &mut self,
        frame: &Packet<&[u8]>,
        open: impl FnOnce(&mut F, &[u8], u32) -> Result<(), FoeError>,
    ) -> Result<(), FoeError> {
        if self.in_progress() {
            self.abandon();
            return Err(FoeError::ILLEGAL);
        }
        self.transfer = Transfer::Idle;
        match file_name(frame.data()) {
            [] => Err(FoeError::NOT_FOUND),
            name => open(&mut self.files, name, frame.value()),
        }
    }

    fn data(&mut self, env: Env, frame: &Packet<&[u8]>, reply: &mut [u8]) -> usize {
        let number = frame.value();
        let (packet, offset) = match self.transfer {
            Transfer::Writing { packet, .. } | Transfer::Written { packet }
                if number == packet && packet != 0 =>
            {
                // A repeat of the last packet: acknowledged again, not written twice.
                return write_header(reply, OpCode::Ack, number);
            }
            Transfer::Writing { packet, offset } => (packet, offset),
            _ => return self.fail(reply, FoeError::ILLEGAL),
        };
        if number != packet.wrapping_add(1) {
            return self.fail(reply, FoeError::PACKET_NUMBER_WRONG);
        }
        let data = frame.data();
        let segment = env.max_request.saturating_sub(Packet::<&[u8]>::HEADER);
        match self.files.write(offset, data) {
            Ok(Progress::Written) => {}
            Ok(Progress::Busy { done, entire }) => return write_busy(reply, done, entire),
            Err(error) => {
                self.transfer = Transfer::Idle;
                return write_error(reply, error);
            }
        }
        let length = u32::try_from(data.len())
            .ok()
            .and_then(|len| offset.checked_add(len));
        let Some(offset) = length else {
            return self.fail(reply, FoeError::DISK_FULL);
        };
        if data.len() >= segment {
            self.transfer = Transfer::Writing {
                packet: number,
                offset,
            };
        } else if let Err(error) = self.files.finish_write(offset) {
            self.transfer = Transfer::Idle;
            return write_error(reply, error);
        } else {
            self.transfer = Transfer::Written { packet: number };
        }
        write_header(reply, OpCode::Ack, number)
    }

    fn read_request(&mut self, frame: &Packet<&[u8]>, reply: &mut [u8]) -> usize {
        match self.open(frame, F::open_read) {
            Ok(()) => self.send(0, 0, reply),
            Err(error) => write_error(reply, error),
        }
    }

    fn ack(&mut self, number: u32, reply: &mut [u8]) -> usize {
        let Transfer::Reading {
            packet,
            offset,
            last,
        } = self.transfer
        else {
            return self.fail(reply, FoeError::ILLEGAL);
        };
        if number != packet {
            return self.fail(reply, FoeError::PACKET_NUMBER_WRONG);
        }
        if last {
            self.transfer = Transfer::Idle;
            return 0;
        }
        self.send(packet, offset, reply)
    }

    /// The data packet after `packet`, from `offset` of the file being read.
    fn send(&mut self, packet: u32, offset: u32, reply: &mut [u8]) -> usize {
        let Some(mut frame) = Packet::new_checked(&mut *reply) else {
            return 0;
        };
        let out = frame.data_mut();
        let segment = out.len();
        let len = match self.files.read(offset, out) {
            Ok(len) => len.min(segment),
            Err(error) => {
                self.transfer = Transfer::Idle;
                return write_error(reply, error);
            }
        };
        let offset = u32::try_from(len)
            .ok()
            .and_then(|len| offset.checked_add(len));
        let Some(offset) = offset else {
            return self.fail(reply, FoeError::PROGRAM_ERROR);
        };
        let packet = packet.wrapping_add(1);
        frame.set_header(OpCode::Data, packet);
        self.transfer = Transfer::Reading {
            packet,
            offset,
            last: len < segment,
        };
        Packet::<&[u8]>::HEADER + len
    }

    /// Ends the transfer with `error`.
    fn fail(&mut self, reply: &mut [u8], error: FoeError) -> usize {
        self.abandon();
        write_error(reply, error)
    }

    /// Drops the transfer in progress; the application hears of it.
    fn abandon(&mut self) {
        if self.in_progress() {
            self.files.abort();
        }
        self.transfer = Transfer::Idle;
    }
}

/// The file name of a request: up to the first NUL, if any.
fn file_name(data: &[u8]) -> &[u8] {
    let end = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    data.get(..end).unwrap_or_default()
}

impl<F: Files> Handler for Foe<F> {
    const KIND: MailboxType = MailboxType::Foe;

    /// In every mailbox state: [`Files::allowed`] answers with FoE error codes.
    fn serves(&self, _: AlState) -> bool {
        true
    }

    fn request(&mut self, env: Env, payload: &[u8], reply: &mut [u8]) -> Reply {
        let Some(frame) = Packet::new_checked(payload) else {
            return Reply::Error(MailboxError::INVALID_SIZE);
        };
        match self.serve(env, &frame, reply) {
            0 => Reply::Silent,
            len => Reply::Send(len),
        }
    }

    fn reset(&mut self) {
        self.abandon();
    }
}
