//! Emergency messages (ETG.1000.6 §5.6.4, Table 54): CoE service 1 with 8 data bytes; the
//! ones the stack raises for its own errors ([`Emergency::for_al_status_code`]).

use crate::al::{AlState, AlStatus, AlStatusCode};

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

    /// The emergency the stack raises when it sets the AL status code `code` in `state` (the state
    /// the error occurred in, before any fall back); the code's two bytes, little endian, are the
    /// first of the data, as SSC's transition emergencies carry them.
    ///
    /// | AL status code | error code | error register (0x1001) |
    /// |---|---|---|
    /// | sync: 0x001A, 0x002C, 0x002D, 0x0032..=0x0037 | 0x8700 sync controller error | 0x11: generic, communication |
    /// | 0x001B SM watchdog | 0x8100 communication | 0x11 |
    /// | another, in PREOP | 0xA000 transition from PREOP to SAFEOP failed (ETG.1000.6) | 0x01: generic |
    /// | another, in SAFEOP | 0xA001 transition from SAFEOP to OP failed | 0x01 |
    /// | another, in OP or INIT | 0x8100 communication | 0x11 |
    ///
    /// CiA 301 §7.5.2.2 keeps bit 0 of the error register set while any error is present, bit 4
    /// for a communication error.
    pub const fn for_al_status_code(code: AlStatusCode, state: AlState) -> Emergency {
        const GENERIC: u8 = 0x01;
        const COMMUNICATION: u8 = 0x11;
        let (error, register) = match (code.0, state) {
            (0x001A | 0x002C | 0x002D | 0x0032..=0x0037, _) => (0x8700, COMMUNICATION),
            (0x001B, _) => (0x8100, COMMUNICATION),
            (_, AlState::PreOp) => (0xA000, GENERIC),
            (_, AlState::SafeOp) => (0xA001, GENERIC),
            _ => (0x8100, COMMUNICATION),
        };
        let c = code.0.to_le_bytes();
        Emergency {
            code: error,
            register,
            data: [c[0], c[1], 0, 0, 0],
        }
    }
}

impl Emergency {
    /// The error register (0x1001) of a SubDevice presenting `status` with `code`: 0 without
    /// the error indication, else the register of the code's emergency
    /// ([`Emergency::for_al_status_code`]).
    pub const fn error_register(status: AlStatus, code: AlStatusCode) -> u8 {
        if status.error {
            Self::for_al_status_code(code, status.state).register
        } else {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stack_s_emergencies() {
        let bytes =
            |code, state| Emergency::for_al_status_code(AlStatusCode(code), state).to_bytes();
        assert_eq!(
            bytes(0x001A, AlState::Op),
            [0x00, 0x87, 0x11, 0x1A, 0, 0, 0, 0]
        );
        assert_eq!(
            bytes(0x001B, AlState::Op),
            [0x00, 0x81, 0x11, 0x1B, 0, 0, 0, 0]
        );
        assert_eq!(
            bytes(0x001D, AlState::PreOp),
            [0x00, 0xA0, 0x01, 0x1D, 0, 0, 0, 0]
        );
        assert_eq!(
            bytes(0x002D, AlState::SafeOp),
            [0x00, 0x87, 0x11, 0x2D, 0, 0, 0, 0]
        );
        assert_eq!(
            bytes(0x0001, AlState::SafeOp),
            [0x01, 0xA0, 0x01, 0x01, 0, 0, 0, 0]
        );
    }
}
