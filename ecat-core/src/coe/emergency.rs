//! Emergency messages (ETG.1000.6 §5.6.4, Table 54): CoE service 1 with 8 data bytes.

/// One emergency: CiA 301 error code, error register (0x1001), 5 manufacturer-specific bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Emergency {
    /// The error code (e.g. 0xA000 "transition from PREOP to SAFEOP failed").
    pub code: u16,
    /// The error register.
    pub register: u8,
    /// Manufacturer-specific data.
    pub data: [u8; 5],
}

impl Emergency {
    /// Size of the emergency data after the CoE header.
    pub const SIZE: usize = 8;

    /// Error code 0x0000 "no error", register 0, no data: what an empty queue slot holds.
    pub const NONE: Self = Self {
        code: 0,
        register: 0,
        data: [0; 5],
    };

    /// The 8 data bytes on the wire.
    pub const fn to_bytes(self) -> [u8; 8] {
        let c = self.code.to_le_bytes();
        let d = self.data;
        [c[0], c[1], self.register, d[0], d[1], d[2], d[3], d[4]]
    }
}
