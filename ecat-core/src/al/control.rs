//! AL control, register 0x0120 (ETG.1000.6 Table 9).

use super::AlState;

/// The AL control register as the MainDevice wrote it: requested state, error acknowledge,
/// device-ID request (ETG.1000.6 Table 9).
///
/// The raw value is kept: a requested state that names no state is data the state machine answers
/// with AL status code 0x0012, not a parse failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct AlControl(u16);

impl AlControl {
    /// Bit 4: the MainDevice acknowledges the error indication.
    pub const ACKNOWLEDGE: u16 = 1 << 4;
    /// Bit 5: the MainDevice requests the explicit device ID in AL status code.
    pub const DEVICE_ID_REQUEST: u16 = 1 << 5;

    /// The register value `bits`.
    pub const fn from_bits(bits: u16) -> Self {
        Self(bits)
    }

    /// The register as read over the PDI (little endian).
    pub const fn from_le_bytes(bytes: [u8; 2]) -> Self {
        Self(u16::from_le_bytes(bytes))
    }

    /// The raw register value.
    pub const fn bits(self) -> u16 {
        self.0
    }

    /// Bits 3:0, the requested state code as written.
    const fn requested_bits(self) -> u8 {
        (self.0 & 0x0F) as u8
    }

    /// The requested state, or `None` when bits 3:0 name no state.
    pub const fn requested(self) -> Option<AlState> {
        AlState::from_bits(self.requested_bits())
    }

    /// Whether the error indication is acknowledged (bit 4).
    pub const fn acknowledge(self) -> bool {
        self.0 & Self::ACKNOWLEDGE != 0
    }

    /// Whether the explicit device ID is requested (bit 5).
    pub const fn device_id_request(self) -> bool {
        self.0 & Self::DEVICE_ID_REQUEST != 0
    }
}
