//! The ESC's memory image: registers 0x0000..0x0FFF followed by the process RAM.

use alloc::boxed::Box;
use alloc::vec;
use core::ops::Range;

use ecat_core::register;
use ecat_core::sync_manager::Channel;

use super::area::MAX_CHANNELS;

/// The SyncManager register blocks (ETG.1000.4 Table 58: 0x0800..0x087F).
const CHANNEL_REGISTERS: Range<usize> = {
    let start = register::SM_BASE as usize;
    start..start + MAX_CHANNELS * Channel::SIZE
};

/// The bytes of the ESC's address space that exist (ESC datasheet section I, "Address space"):
/// the register file and the process RAM up to the configured end. Bytes beyond the end do not
/// exist: they read as 0 and writes to them are lost, as on a real ESC.
pub(super) struct Memory {
    bytes: Box<[u8]>,
    /// Counts the writes that touched a SyncManager register block: what is derived from those
    /// registers (the area map) is valid while this stays the same.
    channels_version: u64,
}

impl Memory {
    /// Memory of `size` bytes, all 0.
    pub(super) fn new(size: usize) -> Self {
        Self {
            bytes: vec![0; size].into_boxed_slice(),
            channels_version: 0,
        }
    }

    /// The byte at `address` (0 when it does not exist).
    pub(super) fn byte(&self, address: usize) -> u8 {
        self.bytes.get(address).copied().unwrap_or(0)
    }

    /// Stores `value` at `address` (ignored when it does not exist).
    pub(super) fn set_byte(&mut self, address: usize, value: u8) {
        self.write(address, &[value]);
    }

    /// The bytes from `address` on that exist, at most `len` of them.
    fn existing(&self, address: usize, len: usize) -> Range<usize> {
        let end = address.saturating_add(len).min(self.bytes.len());
        address.min(end)..end
    }

    /// Fills `buf` from `address` on.
    pub(super) fn read(&self, address: usize, buf: &mut [u8]) {
        let existing = self.existing(address, buf.len());
        let (present, absent) = buf.split_at_mut(existing.len());
        present.copy_from_slice(self.bytes.get(existing).unwrap_or_default());
        absent.fill(0);
    }

    /// Stores `data` from `address` on.
    pub(super) fn write(&mut self, address: usize, data: &[u8]) {
        let existing = self.existing(address, data.len());
        if existing.start < CHANNEL_REGISTERS.end && CHANNEL_REGISTERS.start < existing.end {
            self.channels_version = self.channels_version.wrapping_add(1);
        }
        let len = existing.len();
        if let (Some(bytes), Some(data)) = (self.bytes.get_mut(existing), data.get(..len)) {
            bytes.copy_from_slice(data);
        }
    }

    /// Changes whenever a SyncManager register byte is written.
    pub(super) fn channels_version(&self) -> u64 {
        self.channels_version
    }

    /// The little-endian u32 at `address`.
    pub(super) fn u32_le(&self, address: usize) -> u32 {
        let mut bytes = [0; 4];
        self.read(address, &mut bytes);
        u32::from_le_bytes(bytes)
    }

    /// The registers of SyncManager channel `n` (ETG.1000.4 Table 58). The status byte is kept
    /// by the buffer logic, not here: it reads as 0 in the result.
    pub(super) fn channel(&self, n: u8) -> Channel {
        let mut bytes = [0; Channel::SIZE];
        self.read(usize::from(register::sync_manager(n)), &mut bytes);
        Channel::from_bytes(bytes)
    }
}
