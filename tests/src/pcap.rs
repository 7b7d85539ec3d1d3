//! A capture file of Ethernet frames in the classic libpcap format, which Wireshark and tshark open
//! and dissect as EtherCAT (EtherType 0x88A4).
//!
//! Format: a 24-byte global header (magic 0xA1B23C4D for nanosecond timestamps, version 2.4,
//! snapshot length, link type 1 = Ethernet), then per frame a 16-byte record header (seconds,
//! nanoseconds, captured length, original length) and the frame bytes; all little-endian.

use std::io::{self, Write};
use std::time::Duration;

/// The magic number of a little-endian capture with nanosecond timestamps.
const MAGIC_NANOSECONDS: u32 = 0xA1B2_3C4D;
/// The largest frame kept whole.
const SNAPLEN: u32 = 65_535;
/// Link type 1: Ethernet (LINKTYPE_ETHERNET).
const LINKTYPE_ETHERNET: u32 = 1;

/// Writes frames to a capture file.
pub struct PcapWriter<W: Write> {
    out: W,
}

impl<W: Write> PcapWriter<W> {
    /// Starts a capture on `out` by writing the global header.
    pub fn new(mut out: W) -> io::Result<Self> {
        let mut header = Vec::with_capacity(24);
        header.extend_from_slice(&MAGIC_NANOSECONDS.to_le_bytes());
        header.extend_from_slice(&2u16.to_le_bytes());
        header.extend_from_slice(&4u16.to_le_bytes());
        header.extend_from_slice(&0i32.to_le_bytes()); // time zone: UTC
        header.extend_from_slice(&0u32.to_le_bytes()); // timestamp accuracy
        header.extend_from_slice(&SNAPLEN.to_le_bytes());
        header.extend_from_slice(&LINKTYPE_ETHERNET.to_le_bytes());
        out.write_all(&header)?;
        Ok(Self { out })
    }

    /// Appends `frame`, captured `at` (since the Unix epoch or any origin the reader accepts).
    pub fn write_frame(&mut self, at: Duration, frame: &[u8]) -> io::Result<()> {
        let len = u32::try_from(frame.len()).unwrap_or(u32::MAX);
        let kept = frame
            .get(..frame.len().min(SNAPLEN as usize))
            .unwrap_or(frame);
        let seconds = u32::try_from(at.as_secs()).unwrap_or(u32::MAX);
        let mut record = Vec::with_capacity(16);
        record.extend_from_slice(&seconds.to_le_bytes());
        record.extend_from_slice(&at.subsec_nanos().to_le_bytes());
        record.extend_from_slice(&len.min(SNAPLEN).to_le_bytes());
        record.extend_from_slice(&len.to_le_bytes());
        self.out.write_all(&record)?;
        self.out.write_all(kept)
    }

    /// Flushes the underlying writer.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn global_and_record_headers_are_exact() {
        let mut pcap = PcapWriter::new(Vec::new()).unwrap();
        pcap.write_frame(Duration::new(3, 500), &[0xAA, 0xBB])
            .unwrap();
        let bytes = pcap.out;
        assert_eq!(
            bytes,
            [
                0x4D, 0x3C, 0xB2, 0xA1, 2, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0,
                0, // magic, 2.4, zone, accuracy
                0xFF, 0xFF, 0, 0, 1, 0, 0, 0, // snaplen, Ethernet
                3, 0, 0, 0, 0xF4, 0x01, 0, 0, 2, 0, 0, 0, 2, 0, 0,
                0, // 3 s 500 ns, 2 of 2 bytes
                0xAA, 0xBB,
            ]
        );
    }
}
