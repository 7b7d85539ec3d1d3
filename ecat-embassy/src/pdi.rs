//! The Process Data Interface (PDI): how the microcontroller reaches the ESC's registers and
//! process RAM.

use ecat_core::AlEvent;
use ecat_core::chip::Chip;

/// The data of one PDI access: the buffer a read fills, or the bytes a write sends.
#[derive(Debug)]
pub enum Data<'a> {
    /// Read `buf.len()` bytes into the buffer.
    Read(&'a mut [u8]),
    /// Write these bytes.
    Write(&'a [u8]),
}

impl<'a> Data<'a> {
    /// The number of bytes the access moves.
    pub fn len(&self) -> usize {
        match self {
            Data::Read(buf) => buf.len(),
            Data::Write(data) => data.len(),
        }
    }

    /// Whether the access moves no byte.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first `mid` bytes and the rest (all of it and nothing when `mid` is beyond the end).
    pub fn split_at(self, mid: usize) -> (Data<'a>, Data<'a>) {
        match self {
            Data::Read(buf) => {
                let mid = mid.min(buf.len());
                let (head, tail) = buf.split_at_mut(mid);
                (Data::Read(head), Data::Read(tail))
            }
            Data::Write(data) => {
                let mid = mid.min(data.len());
                let (head, tail) = data.split_at(mid);
                (Data::Write(head), Data::Write(tail))
            }
        }
    }
}

/// What the next access's AL event must be ([`Pdi::sample`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sample {
    /// As the driver reports it for any access: the first chunk of an access while the IRQ line
    /// is free.
    Usual,
    /// A later chunk of the same access while the IRQ line is free: no read the IRQ line
    /// prompted, so a driver that reads the AL event register for those may report what it
    /// knows.
    Continued,
    /// State-machine events hold the level IRQ line: a new event (the process-data trigger)
    /// makes no edge, and only an access's fresh AL event shows it. The driver reads it for any
    /// access, writes included.
    Fresh,
}

/// Register and RAM access to the ESC over its PDI (SPI, parallel bus, or an emulator).
///
/// Each access samples the AL event register (0x0220) value, which [`Pdi::al_event`] tells after
/// it: SPI ESCs shift it out during the address phase of every transaction, so the runners learn
/// about events without spending a transaction on it. A driver whose bus does not deliver it reads
/// 0x0220 itself after the access. The value may be sampled before the access: callers discount
/// the bits the access itself clears. An empty read moves no data and samples the AL event: the
/// cheapest way to read it alone (a NOP on the Beckhoff SPI, one CSR read of 0x0220 on the
/// LAN9252).
///
/// Reads and writes are one method, so that the runners hold one access future each and the
/// firmware carries one copy of the driver's access code. The AL event is asked for after the
/// access, not returned by it: a driver whose access is one bus transaction returns the bus's
/// future itself, with no future of its own around it to decode the event
/// (docs/size-history.md, "Session 14: the PDI access one future less").
#[allow(async_fn_in_trait)]
pub trait Pdi {
    /// A bus error; the runners stop and hand it to the firmware.
    type Error: core::fmt::Debug;

    /// The ESC the driver talks to, when the driver knows it: the
    /// [`Resources`](crate::Resources) take its SyncManager count and process RAM
    /// ([`Chip::fit`]). `None` (the default) keeps the device description's.
    const CHIP: Option<Chip> = None;

    /// Reads into or writes from `data`, starting at `address`, in one transaction; then
    /// [`Pdi::al_event`] tells the AL event it sampled.
    /// One lifetime for the driver and the data: a driver may hand a future that borrows both
    /// in one array of transaction parts.
    async fn access<'a>(&'a mut self, address: u16, data: Data<'a>) -> Result<(), Self::Error>;

    /// The AL event the last access sampled (after an error or before the first access: any
    /// value).
    fn al_event(&self) -> AlEvent;

    /// How many of the `len` bytes at `address` (more than 0) the next chunk of a state-machine
    /// access moves, given the chunk size `chunk` the firmware configured
    /// ([`Resources::with_chunk`](crate::Resources::with_chunk)): a driver cuts at its own
    /// boundaries. The default is `chunk` bytes.
    fn chunk(&self, address: u16, len: usize, chunk: usize) -> usize {
        let _ = address;
        len.min(chunk)
    }

    /// What the AL event the next access reports must be: called before each chunk of a
    /// state-machine access. The default does nothing: a
    /// driver whose every access samples the AL event (the Beckhoff SPI's address phase) needs
    /// no hint.
    fn sample(&mut self, sample: Sample) {
        let _ = sample;
    }

    /// Reads `buf.len()` bytes starting at `address` in one transaction; returns the AL event
    /// it sampled.
    async fn read(&mut self, address: u16, buf: &mut [u8]) -> Result<AlEvent, Self::Error> {
        self.access(address, Data::Read(buf)).await?;
        Ok(self.al_event())
    }

    /// Writes `data` starting at `address` in one transaction; returns the AL event it sampled.
    async fn write(&mut self, address: u16, data: &[u8]) -> Result<AlEvent, Self::Error> {
        self.access(address, Data::Write(data)).await?;
        Ok(self.al_event())
    }
}
