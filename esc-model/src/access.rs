//! One access to the ESC memory: which port it comes from and which way the data flows.

use core::ops::Range;

/// The two ports of the ESC's dual-ported memory (ESC datasheet section I, "Process Data RAM"):
/// the SubDevice's controller on the Process Data Interface and the MainDevice on the EtherCAT
/// port. Register rights and SyncManager directions are stated per port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Side {
    /// The Process Data Interface (SPI, µC parallel, …): the SubDevice's controller.
    Pdi,
    /// The EtherCAT port: the MainDevice's datagrams.
    Ecat,
}

impl Side {
    /// The port on the other end of a SyncManager buffer.
    pub(super) const fn other(self) -> Self {
        match self {
            Self::Pdi => Self::Ecat,
            Self::Ecat => Self::Pdi,
        }
    }
}

/// The data of one access: the bytes a read fills or the bytes a write stores, in address order.
#[derive(Debug)]
pub(super) enum Access<'a> {
    /// A read: the ESC fills the buffer.
    Read(&'a mut [u8]),
    /// A write: the ESC stores the data.
    Write(&'a [u8]),
}

impl Access<'_> {
    /// The number of bytes accessed.
    pub(super) fn len(&self) -> usize {
        match self {
            Self::Read(buf) => buf.len(),
            Self::Write(data) => data.len(),
        }
    }

    /// The bytes `range` of this access (empty when the range is out of bounds).
    pub(super) fn part(&mut self, range: Range<usize>) -> Access<'_> {
        match self {
            Self::Read(buf) => Access::Read(buf.get_mut(range).unwrap_or_default()),
            Self::Write(data) => Access::Write(data.get(range).unwrap_or_default()),
        }
    }
}
