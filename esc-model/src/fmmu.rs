//! Fieldbus Memory Management Units (ETG.1000.4 §6.6, Table 56): each maps a bit range of the
//! logical address space that LRD/LWR/LRW datagrams address onto a bit range of the ESC's physical
//! memory.
//!
//! Entity layout (16 bytes): logical start address u32, length in bytes u16, logical start bit
//! u8, logical stop bit u8, physical start address u16, physical start bit u8, type u8 (bit 0
//! read, bit 1 write), activate u8 (bit 0), 3 reserved bytes. The mapped logical bits run from
//! (start, start bit) to (start + length − 1, stop bit) inclusive.

/// One FMMU entity as the MainDevice configured it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Fmmu {
    /// Logical start address (bytes).
    pub logical_start: u32,
    /// Length in bytes (the logical bytes touched).
    pub length: u16,
    /// First mapped bit of the first logical byte.
    pub logical_start_bit: u8,
    /// Last mapped bit of the last logical byte.
    pub logical_stop_bit: u8,
    /// Physical start address.
    pub physical_start: u16,
    /// First mapped bit of the first physical byte.
    pub physical_start_bit: u8,
    /// Type bit 0: read (the ESC puts physical data into the datagram).
    pub read: bool,
    /// Type bit 1: write (the ESC takes datagram data into physical memory).
    pub write: bool,
    /// Activate bit 0.
    pub active: bool,
}

impl Fmmu {
    /// Size of an entity in the register map.
    pub const SIZE: usize = 16;

    /// The entity in its 16 register bytes.
    pub fn from_bytes(b: &[u8; Self::SIZE]) -> Self {
        Self {
            logical_start: u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            length: u16::from_le_bytes([b[4], b[5]]),
            logical_start_bit: b[6] & 7,
            logical_stop_bit: b[7] & 7,
            physical_start: u16::from_le_bytes([b[8], b[9]]),
            physical_start_bit: b[10] & 7,
            read: b[11] & 1 != 0,
            write: b[11] & 2 != 0,
            active: b[12] & 1 != 0,
        }
    }

    /// The mapped logical bits, as a half-open range of absolute bit numbers (logical address ×
    /// 8 + bit). Empty when the length is 0 or the stop bit precedes the start bit in a one-byte
    /// mapping.
    pub fn logical_bits(&self) -> core::ops::Range<u64> {
        if self.length == 0 {
            return 0..0;
        }
        let start = u64::from(self.logical_start) * 8 + u64::from(self.logical_start_bit);
        let last_byte = u64::from(self.logical_start) + u64::from(self.length) - 1;
        let end = last_byte * 8 + u64::from(self.logical_stop_bit) + 1;
        start..end.max(start)
    }

    /// The absolute physical bit (address × 8 + bit) that logical bit `bit` maps to.
    pub fn physical_bit(&self, bit: u64) -> u64 {
        let start = u64::from(self.logical_start) * 8 + u64::from(self.logical_start_bit);
        u64::from(self.physical_start) * 8 + u64::from(self.physical_start_bit) + (bit - start)
    }

    /// Whether the mapping is byte-aligned on both sides: whole bytes move as one physical
    /// access, so SyncManager buffers see exactly the accesses a real ESC makes.
    pub fn byte_aligned(&self) -> bool {
        self.logical_start_bit == 0 && self.logical_stop_bit == 7 && self.physical_start_bit == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entity_fields_and_bit_ranges() {
        let bytes = [
            0x00, 0x01, 0, 0, // logical 0x100
            2, 0, // 2 bytes
            3, 4, // bits 3..=4 of the second byte
            0x00, 0x10, // physical 0x1000
            5,    // physical bit 5
            2, 1, 0, 0, 0,
        ];
        let f = Fmmu::from_bytes(&bytes);
        assert_eq!(f.logical_start, 0x100);
        assert!(f.write && !f.read && f.active);
        assert_eq!(f.logical_bits(), 0x800 + 3..0x808 + 5);
        assert_eq!(f.physical_bit(0x800 + 3), 0x1000 * 8 + 5);
        assert_eq!(f.physical_bit(0x808 + 4), 0x1000 * 8 + 5 + 9);
        assert!(!f.byte_aligned());
    }
}
