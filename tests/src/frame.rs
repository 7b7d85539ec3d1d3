//! EtherCAT frames (ETG.1000.4 §5.3): an Ethernet II frame with EtherType 0x88A4 whose payload is
//! a 2-byte EtherCAT header (bits 0..10 length of the datagrams, bit 11 reserved, bits 12..15
//! type, 1 = datagrams) and the datagrams, each a 10-byte header (command, index, 4-byte
//! address, bits 0..10 data length + bit 14 circulated + bit 15 more datagrams follow, 2-byte
//! IRQ), the data and a 2-byte working counter.
//!
//! What a frame that is not a well-formed EtherCAT frame does on a line of emulated ESCs
//! ([`Frame::parse`]): shorter than the two headers → dropped (a runt); another EtherType or
//! EtherCAT type → forwarded untouched (ESCs pass foreign frames on); a datagram that claims more
//! bytes than the frame holds, or more datagrams announced than fit → the datagrams before it are
//! processed and the frame is dropped (on the wire its checksum would be wrong, so the MainDevice
//! never gets it back).
//!
//! [`build`] and [`datagrams`] are the MainDevice's side: frames for test scripts and benchmarks.

use crate::esc::Esc;

/// The EtherType of EtherCAT frames.
pub const ETHERTYPE: u16 = 0x88A4;
/// The Ethernet II header: destination, source, EtherType.
pub const ETHERNET_HEADER: usize = 14;
/// The EtherCAT header.
pub const ECAT_HEADER: usize = 2;
/// The datagram header.
pub const DATAGRAM_HEADER: usize = 10;
/// The working counter after the data.
pub const WKC: usize = 2;
/// EtherCAT header type 1: datagrams.
const TYPE_DATAGRAMS: u16 = 1;
/// Datagram length field: bit 15, another datagram follows.
const MORE_FOLLOWS: u16 = 1 << 15;
/// Datagram length field: bits 0..10, the data length.
const LENGTH_MASK: u16 = 0x07FF;

/// What a line does with a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// EtherCAT datagrams from this offset to that end.
    Datagrams(usize, usize),
    /// Not EtherCAT datagrams: passed on untouched.
    Foreign,
    /// Too short to be an Ethernet frame: lost.
    Runt,
}

impl Frame {
    /// How `frame` is handled.
    pub fn parse(frame: &[u8]) -> Frame {
        let word = |at: usize| frame.get(at..at + 2).map(|b| [b[0], b[1]]);
        let (Some(ethertype), Some(header)) = (word(12), word(ETHERNET_HEADER)) else {
            return Frame::Runt;
        };
        let header = u16::from_le_bytes(header);
        if u16::from_be_bytes(ethertype) != ETHERTYPE || header >> 12 != TYPE_DATAGRAMS {
            return Frame::Foreign;
        }
        let start = ETHERNET_HEADER + ECAT_HEADER;
        let end = start + usize::from(header & LENGTH_MASK);
        Frame::Datagrams(start, end.min(frame.len()).max(start))
    }
}

/// Why datagram processing stopped early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Malformed {
    /// Offset of the datagram header that did not fit.
    pub at: usize,
}

/// Passes the datagrams `frame[start..end]` through `esc`: each datagram in order, its working
/// counter incremented by what the ESC counted. Stops at the first datagram that does not fit.
pub fn pass(esc: &mut Esc, frame: &mut [u8], start: usize, end: usize) -> Result<(), Malformed> {
    let mut at = start;
    loop {
        let (header, len) = datagram_header(frame, at, end)?;
        let data_at = at + DATAGRAM_HEADER;
        let wkc_at = data_at + len;
        let mut address = [header[2], header[3], header[4], header[5]];
        let (head, rest) = frame.split_at_mut(data_at);
        let (data, tail) = rest.split_at_mut(len);
        let counted = esc.datagram(header[0], &mut address, data);
        head[at + 2..at + 6].copy_from_slice(&address);
        let wkc = u16::from_le_bytes([tail[0], tail[1]]).wrapping_add(counted);
        tail[..WKC].copy_from_slice(&wkc.to_le_bytes());
        at = wkc_at + WKC;
        if !more_follows(&header) {
            return Ok(());
        }
    }
}

/// The header of the datagram at `at` and its data length, if the datagram (header, data and
/// working counter) ends by `end`.
fn datagram_header(
    frame: &[u8],
    at: usize,
    end: usize,
) -> Result<([u8; DATAGRAM_HEADER], usize), Malformed> {
    let header: [u8; DATAGRAM_HEADER] = frame
        .get(at..at + DATAGRAM_HEADER)
        .and_then(|h| h.try_into().ok())
        .ok_or(Malformed { at })?;
    let len = usize::from(u16::from_le_bytes([header[6], header[7]]) & LENGTH_MASK);
    if at + DATAGRAM_HEADER + len + WKC > end {
        return Err(Malformed { at });
    }
    Ok((header, len))
}

/// Whether the length field of `header` announces another datagram.
fn more_follows(header: &[u8; DATAGRAM_HEADER]) -> bool {
    u16::from_le_bytes([header[6], header[7]]) & MORE_FOLLOWS != 0
}

/// One datagram as a MainDevice builds it (ETG.1000.4 §5.4, Table 14), for test scripts and
/// benchmarks that speak frames to a [`crate::line::Line`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Datagram {
    /// Command code (ETG.1000.4 Table 13).
    pub command: u8,
    /// Index: the MainDevice's tag, passed back untouched.
    pub index: u8,
    /// Address: ADP and ADO (little-endian u16 each), or a logical address (u32).
    pub address: [u8; 4],
    /// The data.
    pub data: Vec<u8>,
    /// The IRQ field.
    pub irq: u16,
    /// The working counter.
    pub wkc: u16,
}

impl Datagram {
    /// A physical-address datagram (AP*, FP*, B*, ARMW, FRMW, NOP): `adp`, `ado`, `data`.
    pub fn physical(command: u8, adp: u16, ado: u16, data: &[u8]) -> Self {
        let [a, b] = adp.to_le_bytes();
        let [c, d] = ado.to_le_bytes();
        Self::new(command, [a, b, c, d], data)
    }

    /// A logical-address datagram (LRD, LWR, LRW) at `address`.
    pub fn logical(command: u8, address: u32, data: &[u8]) -> Self {
        Self::new(command, address.to_le_bytes(), data)
    }

    fn new(command: u8, address: [u8; 4], data: &[u8]) -> Self {
        Self {
            command,
            index: 0,
            address,
            data: data.to_vec(),
            irq: 0,
            wkc: 0,
        }
    }

    /// The bytes the datagram takes in a frame: header, data, working counter.
    pub fn size(&self) -> usize {
        DATAGRAM_HEADER + self.data.len() + WKC
    }

    /// Appends the datagram to `frame`; `more` sets the "more datagrams follow" bit. The data
    /// length is cut to the 11 bits of the field.
    fn encode(&self, more: bool, frame: &mut Vec<u8>) {
        let len = u16::try_from(self.data.len()).unwrap_or(u16::MAX) & LENGTH_MASK;
        let length_field = len | if more { MORE_FOLLOWS } else { 0 };
        frame.extend([self.command, self.index]);
        frame.extend(self.address);
        frame.extend(length_field.to_le_bytes());
        frame.extend(self.irq.to_le_bytes());
        frame.extend(&self.data);
        frame.extend(self.wkc.to_le_bytes());
    }
}

/// The broadcast destination MainDevices send to.
pub const BROADCAST: [u8; 6] = [0xFF; 6];

/// An EtherCAT frame from `source` (to [`BROADCAST`]) carrying `datagrams`, without padding.
pub fn build(source: [u8; 6], datagrams: &[Datagram]) -> Vec<u8> {
    let mut frame = Vec::new();
    frame.extend(BROADCAST);
    frame.extend(source);
    frame.extend(ETHERTYPE.to_be_bytes());
    let length: usize = datagrams.iter().map(Datagram::size).sum();
    let length = u16::try_from(length).unwrap_or(u16::MAX) & LENGTH_MASK;
    frame.extend((length | TYPE_DATAGRAMS << 12).to_le_bytes());
    for (n, datagram) in datagrams.iter().enumerate() {
        datagram.encode(n + 1 < datagrams.len(), &mut frame);
    }
    frame
}

/// The datagrams of an EtherCAT frame, `None` if it is not a well-formed one.
pub fn datagrams(frame: &[u8]) -> Option<Vec<Datagram>> {
    let Frame::Datagrams(mut at, end) = Frame::parse(frame) else {
        return None;
    };
    let mut datagrams = Vec::new();
    loop {
        let (header, len) = datagram_header(frame, at, end).ok()?;
        let data_at = at + DATAGRAM_HEADER;
        let wkc = frame.get(data_at + len..data_at + len + WKC)?;
        datagrams.push(Datagram {
            command: header[0],
            index: header[1],
            address: [header[2], header[3], header[4], header[5]],
            data: frame.get(data_at..data_at + len)?.to_vec(),
            irq: u16::from_le_bytes([header[8], header[9]]),
            wkc: u16::from_le_bytes([wkc[0], wkc[1]]),
        });
        at = data_at + len + WKC;
        if !more_follows(&header) {
            return Some(datagrams);
        }
    }
}

/// Marks `frame` as processed by an ESC: the locally-administered bit of the source MAC
/// (ETG.1000.4 §5.2: the first ESC of a line sets it, so a MainDevice tells its own frame on
/// the way out from the answer).
pub fn mark_processed(frame: &mut [u8]) {
    if let Some(source) = frame.get_mut(6) {
        *source |= 0x02;
    }
}
