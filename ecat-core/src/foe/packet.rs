//! The FoE frame (ETG.1000.6 §5.9) as a typed view over the bytes after the
//! mailbox header: an opcode byte, a reserved byte, a 32-bit field whose meaning depends on the
//! opcode, then the data.
//!
//! | opcode | 32-bit field | data |
//! |---|---|---|
//! | 1 read request, 2 write request | password | file name |
//! | 3 data | packet number | file data |
//! | 4 acknowledge | packet number | — |
//! | 5 error | error code | optional error text |
//! | 6 busy | done (u16), entire (u16) | — |

use super::FoeError;

/// The FoE opcode (ETG.1000.6 §5.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OpCode {
    /// 1: read request (the MainDevice reads a file from the SubDevice).
    Read,
    /// 2: write request (the MainDevice writes a file to the SubDevice).
    Write,
    /// 3: data.
    Data,
    /// 4: acknowledge.
    Ack,
    /// 5: error.
    Error,
    /// 6: busy.
    Busy,
    /// Any other value.
    Unknown(u8),
}

impl OpCode {
    /// The opcode of byte `code`.
    pub const fn from_code(code: u8) -> Self {
        match code {
            1 => Self::Read,
            2 => Self::Write,
            3 => Self::Data,
            4 => Self::Ack,
            5 => Self::Error,
            6 => Self::Busy,
            c => Self::Unknown(c),
        }
    }

    /// The byte on the wire.
    pub const fn code(self) -> u8 {
        match self {
            Self::Read => 1,
            Self::Write => 2,
            Self::Data => 3,
            Self::Ack => 4,
            Self::Error => 5,
            Self::Busy => 6,
            Self::Unknown(c) => c,
        }
    }
}

/// Byte ranges of the FoE header.
mod field {
    use core::ops::{Range, RangeFrom};
    /// The opcode.
    pub(super) const OPCODE: usize = 0;
    /// The 32-bit field: password, packet number or error code; for busy, done then entire.
    pub(super) const VALUE: Range<usize> = 2..6;
    /// Busy: the progress made.
    pub(super) const DONE: Range<usize> = 2..4;
    /// Busy: the progress to make.
    pub(super) const ENTIRE: Range<usize> = 4..6;
    /// File name, file data or error text.
    pub(super) const DATA: RangeFrom<usize> = 6..;
}

/// An FoE frame over a buffer of at least [`Packet::HEADER`] bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// The FoE header's size.
    pub const HEADER: usize = 6;

    /// A view of `buffer`; `None` when it is shorter than the header.
    pub fn new_checked(buffer: T) -> Option<Self> {
        (buffer.as_ref().len() >= Self::HEADER).then_some(Self { buffer })
    }

    /// The opcode.
    pub fn opcode(&self) -> OpCode {
        OpCode::from_code(
            self.buffer
                .as_ref()
                .get(field::OPCODE)
                .copied()
                .unwrap_or(0),
        )
    }

    /// The 32-bit field: the password of a request, the packet number of data and
    /// acknowledge, the code of an error.
    pub fn value(&self) -> u32 {
        u32::from_le_bytes(self.bytes(field::VALUE))
    }

    /// Busy: the progress made and the progress to make.
    pub fn busy(&self) -> (u16, u16) {
        (
            u16::from_le_bytes(self.bytes(field::DONE)),
            u16::from_le_bytes(self.bytes(field::ENTIRE)),
        )
    }

    /// The file name of a request (up to a NUL, if any), the data, or the error text.
    pub fn data(&self) -> &[u8] {
        self.buffer.as_ref().get(field::DATA).unwrap_or_default()
    }

    fn bytes<const L: usize>(&self, range: core::ops::Range<usize>) -> [u8; L] {
        self.buffer
            .as_ref()
            .get(range)
            .and_then(|b| b.try_into().ok())
            .unwrap_or([0; L])
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Packet<T> {
    /// Writes the header: `opcode`, the reserved byte 0 and `value`.
    pub(crate) fn set_header(&mut self, opcode: OpCode, value: u32) {
        let buffer = self.buffer.as_mut();
        if let Some(b) = buffer.get_mut(field::OPCODE..field::VALUE.start) {
            b.copy_from_slice(&[opcode.code(), 0]);
        }
        if let Some(b) = buffer.get_mut(field::VALUE) {
            b.copy_from_slice(&value.to_le_bytes());
        }
    }

    /// The data area, for writing.
    pub(crate) fn data_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(field::DATA)
            .unwrap_or_default()
    }
}

/// Writes an FoE frame of `opcode` and `value` with no data into `out`: its length, 0 when `out`
/// is shorter than the header.
pub(crate) fn write_header(out: &mut [u8], opcode: OpCode, value: u32) -> usize {
    match Packet::new_checked(out) {
        Some(mut packet) => {
            packet.set_header(opcode, value);
            Packet::<&[u8]>::HEADER
        }
        None => 0,
    }
}

/// Writes an FoE error frame of `error` (no text) into `out`: its length.
pub(crate) fn write_error(out: &mut [u8], error: FoeError) -> usize {
    write_header(out, OpCode::Error, error.0)
}

/// Writes an FoE busy frame into `out`: its length.
pub(crate) fn write_busy(out: &mut [u8], done: u16, entire: u16) -> usize {
    let value = u32::from(done) | (u32::from(entire) << 16);
    write_header(out, OpCode::Busy, value)
}
