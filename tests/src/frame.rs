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
        let header: [u8; DATAGRAM_HEADER] = frame
            .get(at..at + DATAGRAM_HEADER)
            .and_then(|h| h.try_into().ok())
            .filter(|_| at + DATAGRAM_HEADER <= end)
            .ok_or(Malformed { at })?;
        let length_field = u16::from_le_bytes([header[6], header[7]]);
        let len = usize::from(length_field & LENGTH_MASK);
        let data_at = at + DATAGRAM_HEADER;
        let wkc_at = data_at + len;
        if wkc_at + WKC > end {
            return Err(Malformed { at });
        }
        let mut address = [header[2], header[3], header[4], header[5]];
        let (head, rest) = frame.split_at_mut(data_at);
        let (data, tail) = rest.split_at_mut(len);
        let counted = esc.datagram(header[0], &mut address, data);
        head[at + 2..at + 6].copy_from_slice(&address);
        let wkc = u16::from_le_bytes([tail[0], tail[1]]).wrapping_add(counted);
        tail[..WKC].copy_from_slice(&wkc.to_le_bytes());
        at = wkc_at + WKC;
        if length_field & MORE_FOLLOWS == 0 {
            return Ok(());
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
