//! The ESC's memory image: registers 0x0000..0x0FFF followed by the process RAM.

use ecat_core::register;
use ecat_core::sync_manager::Channel;

/// The bytes of the ESC's address space that exist (ESC datasheet section I, "Address space"):
/// the register file and the process RAM up to the configured end. Bytes beyond the end do not
/// exist: they read as 0 and writes to them are lost, as on a real ESC.
pub(super) struct Memory(Box<[u8]>);

impl Memory {
    /// Memory of `size` bytes, all 0.
    pub(super) fn new(size: usize) -> Self {
        Self(vec![0; size].into_boxed_slice())
    }

    /// The byte at `address` (0 when it does not exist).
    pub(super) fn byte(&self, address: usize) -> u8 {
        self.0.get(address).copied().unwrap_or(0)
    }

    /// Stores `value` at `address` (ignored when it does not exist).
    pub(super) fn set_byte(&mut self, address: usize, value: u8) {
        if let Some(byte) = self.0.get_mut(address) {
            *byte = value;
        }
    }

    /// Fills `buf` from `address` on.
    pub(super) fn read(&self, address: usize, buf: &mut [u8]) {
        for (byte, address) in buf.iter_mut().zip(address..) {
            *byte = self.byte(address);
        }
    }

    /// Stores `data` from `address` on.
    pub(super) fn write(&mut self, address: usize, data: &[u8]) {
        for (&value, address) in data.iter().zip(address..) {
            self.set_byte(address, value);
        }
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
