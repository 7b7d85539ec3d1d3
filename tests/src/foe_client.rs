//! An FoE client for the test MainDevice (ETG.1000.6 §5.9): file writes and reads segment by
//! segment, busy answered by sending the packet again, built from bytes so that tests can also
//! send what a broken client would ([`FoeClient::frame`]) and recover a lost answer through the
//! mailbox repeat ([`FoeClient::repeat`]).

use ecat_core::device::MailboxConfig;
use ecat_core::mailbox::{MailboxHeader, MailboxType};

use crate::coe_client::SdoClient;
use crate::master::TestMaster;

/// An FoE frame as the SubDevice answered it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    /// The opcode (1 read, 2 write, 3 data, 4 acknowledge, 5 error, 6 busy).
    pub opcode: u8,
    /// The 32-bit field: password, packet number, error code, or busy's done/entire.
    pub value: u32,
    /// The data after the FoE header.
    pub data: Vec<u8>,
}

/// FoE opcodes (ETG.1000.6 §5.9).
pub mod opcode {
    /// Read request.
    pub const READ: u8 = 1;
    /// Write request.
    pub const WRITE: u8 = 2;
    /// Data.
    pub const DATA: u8 = 3;
    /// Acknowledge.
    pub const ACK: u8 = 4;
    /// Error.
    pub const ERROR: u8 = 5;
    /// Busy.
    pub const BUSY: u8 = 6;
}

/// What an FoE transfer ended with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FoeFailure {
    /// The SubDevice sent an FoE error frame with this code.
    Error(u32),
    /// The SubDevice answered with a mailbox error reply (detail code).
    Mailbox(u16),
    /// No answer, or one that makes no sense for the request.
    Protocol(String),
}

/// The FoE client of a test MainDevice: the mailbox side (counters, SM0 and SM1) is an
/// [`SdoClient`]'s.
pub struct FoeClient<'m> {
    mailbox: SdoClient<'m>,
    /// The SM1 activate register (its repeat request, bit 1).
    sm1_activate: u16,
    /// The data of a full segment: the receive mailbox's size less 12 bytes.
    pub segment: usize,
    /// Busy answers seen so far.
    pub busy: usize,
}

impl<'m> FoeClient<'m> {
    /// A client for a SubDevice whose SM0/SM1 follow `mailbox` (in BOOT: its bootstrap mailbox).
    pub fn for_mailbox(master: &'m TestMaster, mailbox: &MailboxConfig) -> Self {
        Self {
            mailbox: SdoClient::for_mailbox(master, mailbox),
            sm1_activate: ecat_core::register::sync_manager(1) + 6,
            segment: usize::from(mailbox.receive.length) - 12,
            busy: 0,
        }
    }

    /// Mailbox round trips so far.
    pub fn round_trips(&self) -> usize {
        self.mailbox.round_trips
    }

    /// Sends one FoE frame and returns the SubDevice's answer (`Ok(None)`: none).
    pub async fn frame(
        &mut self,
        opcode: u8,
        value: u32,
        data: &[u8],
    ) -> Result<Option<Frame>, FoeFailure> {
        let mut payload = vec![opcode, 0];
        payload.extend_from_slice(&value.to_le_bytes());
        payload.extend_from_slice(data);
        let answer = self.mailbox.exchange(MailboxType::Foe, &payload).await;
        answer.map(|answer| parse(&answer)).transpose()
    }

    /// The MainDevice lost the last answer: toggles SM1's repeat request and returns what the
    /// SubDevice wrote again.
    pub async fn repeat(&mut self) -> Result<Frame, FoeFailure> {
        let master = self.master();
        let activate = master
            .read(self.sm1_activate, 1)
            .ok_or_else(|| protocol("SM1 unreadable"))?[0];
        master.write(self.sm1_activate, &[activate ^ 0x02]);
        let answer = self
            .mailbox
            .read()
            .await
            .ok_or_else(|| protocol("no repeat"))?;
        parse(&answer)
    }

    /// Writes the file `name` with `password`: the write request, then the data in segments
    /// (an empty last one after an exact multiple), each sent again while answered busy.
    pub async fn write(
        &mut self,
        name: &str,
        password: u32,
        file: &[u8],
    ) -> Result<(), FoeFailure> {
        self.expect_ack(opcode::WRITE, password, name.as_bytes(), 0)
            .await?;
        let mut packets: Vec<&[u8]> = file.chunks(self.segment).collect();
        if file.len().is_multiple_of(self.segment) {
            packets.push(&[]);
        }
        for (n, segment) in packets.into_iter().enumerate() {
            self.expect_ack(opcode::DATA, n as u32 + 1, segment, n as u32 + 1)
                .await?;
        }
        Ok(())
    }

    /// Sends a request or data packet `number` and expects its acknowledge, sending it again
    /// while the SubDevice answers busy.
    async fn expect_ack(
        &mut self,
        opcode: u8,
        value: u32,
        data: &[u8],
        number: u32,
    ) -> Result<(), FoeFailure> {
        loop {
            let answer = self.frame(opcode, value, data).await?;
            let answer = answer.ok_or_else(|| protocol("no answer"))?;
            match answer.opcode {
                opcode::ACK if answer.value == number => return Ok(()),
                opcode::BUSY => self.busy += 1,
                _ => return Err(unexpected(&answer)),
            }
        }
    }

    /// Reads the file `name` with `password`: data packets until a short one, each
    /// acknowledged.
    pub async fn read(&mut self, name: &str, password: u32) -> Result<Vec<u8>, FoeFailure> {
        let mut file = Vec::new();
        let mut answer = self.frame(opcode::READ, password, name.as_bytes()).await?;
        for number in 1.. {
            let frame = answer.ok_or_else(|| protocol("no data"))?;
            if frame.opcode != opcode::DATA || frame.value != number {
                return Err(unexpected(&frame));
            }
            file.extend_from_slice(&frame.data);
            let last = frame.data.len() < self.segment;
            answer = self.frame(opcode::ACK, number, &[]).await?;
            if last {
                break;
            }
        }
        match answer {
            None => Ok(file),
            Some(frame) => Err(unexpected(&frame)),
        }
    }

    fn master(&self) -> &'m TestMaster {
        self.mailbox.master()
    }
}

/// The FoE frame in the SM1 buffer `answer`; a mailbox error reply or another protocol's message
/// is a failure.
fn parse(answer: &[u8]) -> Result<Frame, FoeFailure> {
    let header = MailboxHeader::parse(answer).ok_or_else(|| protocol("short answer"))?;
    let end = (MailboxHeader::SIZE + usize::from(header.length)).min(answer.len());
    let body = &answer[MailboxHeader::SIZE..end];
    if header.kind == MailboxType::Error {
        return Err(FoeFailure::Mailbox(u16::from_le_bytes([body[2], body[3]])));
    }
    if header.kind != MailboxType::Foe || body.len() < 6 {
        return Err(protocol("not an FoE frame"));
    }
    Ok(Frame {
        opcode: body[0],
        value: u32::from_le_bytes([body[2], body[3], body[4], body[5]]),
        data: body[6..].to_vec(),
    })
}

/// An FoE error frame as its code, anything else as a protocol failure.
fn unexpected(frame: &Frame) -> FoeFailure {
    match frame.opcode {
        opcode::ERROR => FoeFailure::Error(frame.value),
        _ => protocol(&format!("unexpected {frame:?}")),
    }
}

fn protocol(what: &str) -> FoeFailure {
    FoeFailure::Protocol(what.to_string())
}
