//! AL status, register 0x0130 (ETG.1000.6 Table 10).

use super::AlState;

/// The AL status register the SubDevice presents: current state, error indication, device ID loaded
/// (ETG.1000.6 Table 10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AlStatus {
    /// Bits 3:0: the current state.
    pub state: AlState,
    /// Bit 4: the last requested transition failed or an error forced a state change;
    /// AL status code tells why.
    pub error: bool,
    /// Bit 5: AL status code holds the explicit device ID instead of an error code.
    pub id_loaded: bool,
}

impl AlStatus {
    /// Bit 4, the error indication.
    pub const ERROR: u16 = 1 << 4;
    /// Bit 5, explicit device ID loaded.
    pub const ID_LOADED: u16 = 1 << 5;

    /// `state` with no error and no device ID.
    pub const fn new(state: AlState) -> Self {
        Self {
            state,
            error: false,
            id_loaded: false,
        }
    }

    /// The register value's low byte, which holds every bit (the high byte is reserved, 0).
    pub(crate) const fn byte(self) -> u8 {
        let [low, _] = self.bits().to_le_bytes();
        low
    }

    /// The register value.
    pub const fn bits(self) -> u16 {
        let mut bits = self.state.bits() as u16;
        if self.error {
            bits |= Self::ERROR;
        }
        if self.id_loaded {
            bits |= Self::ID_LOADED;
        }
        bits
    }

    /// Parses a register value; `None` when bits 3:0 name no state.
    pub const fn from_bits(bits: u16) -> Option<Self> {
        match AlState::from_bits(bits as u8) {
            Some(state) => Some(Self {
                state,
                error: bits & Self::ERROR != 0,
                id_loaded: bits & Self::ID_LOADED != 0,
            }),
            None => None,
        }
    }
}
