//! A spec-correct CoE client for the test MainDevice (ETG.1000.6 §5.6.2): expedited, normal and
//! segmented SDO transfers both ways, complete access, aborts — built from bytes, so tests can
//! also send what a broken client would.

use ecat_core::coe::AbortCode;
use ecat_core::device::MailboxConfig;
use ecat_core::mailbox::{MailboxHeader, MailboxType, next_counter};

use crate::master::TestMaster;

/// What an SDO exchange ended with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SdoError {
    /// The SubDevice aborted with this code.
    Abort(AbortCode),
    /// The SubDevice answered with a mailbox error reply (detail code).
    Mailbox(u16),
    /// No answer, or one that makes no sense for the request.
    Protocol(String),
}

/// The SDO client of a test MainDevice, with its own mailbox counter.
pub struct SdoClient<'m> {
    master: &'m TestMaster,
    receive: (u16, u16),
    send: (u16, u16),
    counter: u8,
    /// Mailbox round trips so far (request written, answer read).
    pub round_trips: usize,
    /// The emergencies (their 8 bytes) that came in place of an answer, oldest first: like
    /// SOEM's `ec_mbxreceive`, the client keeps them and reads SM1 again.
    pub emergencies: Vec<[u8; 8]>,
}

impl<'m> SdoClient<'m> {
    /// A client for the SubDevice behind `master`, whose SM0 is `receive` (start, length) and SM1
    /// is `send`.
    pub fn new(master: &'m TestMaster, receive: (u16, u16), send: (u16, u16)) -> Self {
        Self {
            master,
            receive,
            send,
            counter: 0,
            round_trips: 0,
            emergencies: Vec::new(),
        }
    }

    /// A client for a SubDevice whose SM0/SM1 follow `mailbox`.
    pub fn for_mailbox(master: &'m TestMaster, mailbox: &MailboxConfig) -> Self {
        let (rx, tx) = (mailbox.receive, mailbox.send);
        Self::new(master, (rx.start, rx.length), (tx.start, tx.length))
    }

    /// The MainDevice the client talks through.
    pub fn master(&self) -> &'m TestMaster {
        self.master
    }

    /// Sends one mailbox message (header built here with the next counter) and returns the
    /// SubDevice's answer, the whole SM1 buffer.
    pub async fn exchange(&mut self, kind: MailboxType, payload: &[u8]) -> Option<Vec<u8>> {
        self.counter = next_counter(self.counter);
        let header = MailboxHeader::new(kind, payload.len() as u16, self.counter);
        self.exchange_raw(&header.to_bytes(), payload).await
    }

    /// Writes `header` and `payload` into SM0 (padded to its length, as MainDevices do), lets
    /// the SubDevice answer and reads SM1.
    pub async fn exchange_raw(&mut self, header: &[u8], payload: &[u8]) -> Option<Vec<u8>> {
        self.round_trips += 1;
        self.write_raw(header, payload).await;
        self.read().await
    }

    /// Writes a message into SM0 without waiting for an answer.
    pub async fn write_raw(&mut self, header: &[u8], payload: &[u8]) {
        let mut frame = vec![0; usize::from(self.receive.1)];
        let bytes: Vec<u8> = header.iter().chain(payload).copied().collect();
        let n = bytes.len().min(frame.len());
        frame[..n].copy_from_slice(&bytes[..n]);
        assert!(
            self.master.write(self.receive.0, &frame),
            "SM0 refused the request: still full"
        );
        self.master.settle().await;
    }

    /// Reads SM1 if the SubDevice filled it.
    pub async fn read(&mut self) -> Option<Vec<u8>> {
        self.master.settle().await;
        self.master.read(self.send.0, usize::from(self.send.1))
    }

    /// CoE SDO request `sdo` (after the CoE header); returns the SDO part of the answer.
    pub async fn sdo(&mut self, sdo: &[u8]) -> Result<Vec<u8>, SdoError> {
        let mut payload = vec![0x00, 0x20];
        payload.extend_from_slice(sdo);
        let mut answer = self.exchange(MailboxType::Coe, &payload).await;
        while let Some(emergency) = answer.as_deref().and_then(emergency_of) {
            self.emergencies.push(emergency);
            answer = self.read().await;
        }
        let answer = answer.ok_or_else(|| protocol("no answer"))?;
        let header = MailboxHeader::parse(&answer).ok_or_else(|| protocol("short answer"))?;
        let body = &answer[6..6 + usize::from(header.length).min(answer.len() - 6)];
        if header.kind == MailboxType::Error {
            return Err(SdoError::Mailbox(u16::from_le_bytes([body[2], body[3]])));
        }
        let sdo = body.get(2..).ok_or_else(|| protocol("no SDO"))?.to_vec();
        if sdo.first() == Some(&0x80) {
            return Err(SdoError::Abort(AbortCode(u32::from_le_bytes([
                sdo[4], sdo[5], sdo[6], sdo[7],
            ]))));
        }
        Ok(sdo)
    }

    /// Uploads `index:sub` (complete access from `sub` when `complete`), following segments.
    pub async fn upload(
        &mut self,
        index: u16,
        sub: u8,
        complete: bool,
    ) -> Result<Vec<u8>, SdoError> {
        let [i0, i1] = index.to_le_bytes();
        let command = if complete { 0x50 } else { 0x40 };
        let first = self.sdo(&[command, i0, i1, sub, 0, 0, 0, 0]).await?;
        if first[0] & 0xE0 != 0x40 {
            return Err(protocol("not an upload response"));
        }
        if first[0] & 0x02 != 0 {
            let size = 4 - usize::from((first[0] >> 2) & 0x03);
            return Ok(first[4..4 + size].to_vec());
        }
        let size = u32::from_le_bytes([first[4], first[5], first[6], first[7]]) as usize;
        let mut data = first[8..].to_vec();
        data.truncate(size);
        let mut toggle = false;
        while data.len() < size {
            let segment = self
                .sdo(&[0x60 | (u8::from(toggle) << 4), 0, 0, 0, 0, 0, 0, 0])
                .await?;
            if segment[0] & 0xE0 != 0x00 || (segment[0] & 0x10 != 0) != toggle {
                return Err(protocol("bad upload segment"));
            }
            let unused = usize::from((segment[0] >> 1) & 0x07);
            let mut part = &segment[1..];
            if part.len() == 7 {
                part = &part[..7 - unused];
            }
            data.extend_from_slice(&part[..part.len().min(size - data.len())]);
            if segment[0] & 0x01 != 0 {
                break;
            }
            toggle = !toggle;
        }
        Ok(data)
    }

    /// Downloads `data` to `index:sub`: expedited up to 4 bytes, else normal with as much as
    /// fits, then segments.
    pub async fn download(
        &mut self,
        index: u16,
        sub: u8,
        complete: bool,
        data: &[u8],
    ) -> Result<(), SdoError> {
        let [i0, i1] = index.to_le_bytes();
        let ca = if complete { 0x10 } else { 0 };
        if !data.is_empty() && data.len() <= 4 {
            let mut request = vec![0x23 | ca | (((4 - data.len()) as u8) << 2), i0, i1, sub];
            request.extend_from_slice(data);
            request.resize(8, 0);
            return self.expect(&request, 0x60 | ca).await;
        }
        let room = usize::from(self.receive.1) - 6 - 2 - 8;
        let first = data.len().min(room);
        let mut request = vec![0x21 | ca, i0, i1, sub];
        request.extend_from_slice(&(data.len() as u32).to_le_bytes());
        request.extend_from_slice(&data[..first]);
        self.expect(&request, 0x60 | ca).await?;
        let mut sent = first;
        let mut toggle = false;
        let room = usize::from(self.receive.1) - 6 - 2 - 1;
        while sent < data.len() {
            let n = (data.len() - sent).min(room);
            let last = sent + n == data.len();
            let unused = 7usize.saturating_sub(n) as u8;
            let mut segment = vec![(u8::from(toggle) << 4) | (unused << 1) | u8::from(last)];
            segment.extend_from_slice(&data[sent..sent + n]);
            segment.resize(segment.len().max(8), 0);
            self.expect(&segment, 0x20 | (u8::from(toggle) << 4))
                .await?;
            sent += n;
            toggle = !toggle;
        }
        Ok(())
    }

    async fn expect(&mut self, request: &[u8], command: u8) -> Result<(), SdoError> {
        let answer = self.sdo(request).await?;
        if answer[0] != command {
            return Err(protocol(&format!(
                "expected command {command:#04x}, got {:#04x}",
                answer[0]
            )));
        }
        Ok(())
    }
}

fn protocol(what: &str) -> SdoError {
    SdoError::Protocol(what.to_string())
}

/// The 8 bytes of a CoE emergency (service 1) in the SM1 buffer `message`.
pub fn emergency_of(message: &[u8]) -> Option<[u8; 8]> {
    let header = MailboxHeader::parse(message)?;
    let service = message.get(7)? >> 4;
    (header.kind == MailboxType::Coe && service == 1)
        .then(|| message.get(8..16)?.try_into().ok())
        .flatten()
}
