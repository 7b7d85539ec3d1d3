//! The SDO request frame (ETG.1000.6 Tables 33–40): a typed view over the bytes after the CoE
//! header, in the shape of smoltcp's `wire` packets (field ranges, `new_checked`, accessors).
//!
//! | bytes | initiate (upload, download) | segment |
//! |---|---|---|
//! | 0 | command ([`Request`](super::command::Request)) | command |
//! | 1..3 | index | data |
//! | 3 | subindex | data |
//! | 4..8 | expedited data, or a normal download's size | data |
//! | 8.. | a normal download's first data | data |

use crate::abort::AbortCode;

/// Where each field sits.
mod field {
    use core::ops::{Range, RangeFrom};

    /// The command, index and subindex.
    pub(crate) const HEAD: Range<usize> = 0..4;
    /// An expedited download's data, a normal one's size.
    pub(crate) const DATA: Range<usize> = 4..8;
    /// A normal download's first data.
    pub(crate) const PAYLOAD: RangeFrom<usize> = 8..;
    /// A segment's data, after the command.
    pub(crate) const SEGMENT: RangeFrom<usize> = 1..;
}

/// An SDO request as it came: `buffer` holds at least the command, index and subindex.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// The frame in `buffer`; shorter than command, index and subindex: no request a server
    /// knows (0x05040001).
    pub(crate) fn new_checked(buffer: T) -> Result<Self, AbortCode> {
        match buffer.as_ref().len() >= field::HEAD.end {
            true => Ok(Self { buffer }),
            false => Err(AbortCode::COMMAND_SPECIFIER),
        }
    }

    fn head(&self) -> [u8; 4] {
        let head = self.buffer.as_ref().first_chunk::<{ field::HEAD.end }>();
        head.copied().unwrap_or_default()
    }

    /// The command byte.
    pub(crate) fn command(&self) -> u8 {
        let [command, ..] = self.head();
        command
    }

    /// The object index.
    pub(crate) fn index(&self) -> u16 {
        let [_, i0, i1, _] = self.head();
        u16::from_le_bytes([i0, i1])
    }

    /// The subindex.
    pub(crate) fn sub(&self) -> u8 {
        let [.., sub] = self.head();
        sub
    }

    /// The first `len` bytes of an expedited download's data; `None` when the frame is shorter.
    pub(crate) fn expedited(&self, len: usize) -> Option<&[u8]> {
        let data = self.buffer.as_ref().get(field::DATA.start..)?;
        data.get(..len.min(field::DATA.len()))
    }

    /// A normal download's size (the bytes the frame lacks count as 0).
    pub(crate) fn size(&self) -> u32 {
        let mut size = [0u8; 4];
        let data = self.buffer.as_ref().get(field::DATA.start..);
        crate::bytes::copy(&mut size, data.unwrap_or_default());
        u32::from_le_bytes(size)
    }

    /// A normal download's data in this frame.
    pub(crate) fn payload(&self) -> &[u8] {
        self.buffer.as_ref().get(field::PAYLOAD).unwrap_or_default()
    }

    /// A segment's data: what follows the command.
    pub(crate) fn segment(&self) -> &[u8] {
        self.buffer.as_ref().get(field::SEGMENT).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_read_from_their_places() {
        let bytes = [0x21, 0x34, 0x12, 0x05, 0x0A, 0, 0, 0, 0xAA, 0xBB];
        let frame = Frame::new_checked(&bytes[..]).unwrap();
        assert_eq!(
            (frame.command(), frame.index(), frame.sub()),
            (0x21, 0x1234, 5)
        );
        assert_eq!(frame.size(), 10);
        assert_eq!(frame.payload(), [0xAA, 0xBB]);
        assert_eq!(frame.segment(), &bytes[1..]);
        assert_eq!(frame.expedited(2), Some(&[0x0A, 0][..]));
    }

    #[test]
    fn a_short_frame_is_refused_and_its_missing_fields_are_absent() {
        assert_eq!(
            Frame::new_checked(&[0x40, 0x00, 0x10][..]).err(),
            Some(AbortCode::COMMAND_SPECIFIER)
        );
        let frame = Frame::new_checked(&[0x23, 0x00, 0x10, 0x00, 0x01, 0x02][..]).unwrap();
        assert_eq!(frame.expedited(4), None);
        assert_eq!(frame.expedited(2), Some(&[0x01, 0x02][..]));
        assert_eq!(frame.size(), 0x0201);
        assert_eq!(frame.payload(), [0u8; 0]);
    }
}
