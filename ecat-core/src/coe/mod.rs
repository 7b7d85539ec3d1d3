//! CANopen over EtherCAT (CoE, ETG.1000.6 §5.6): the CoE header, the SDO server, SDO
//! Information and emergencies; `server` makes them the mailbox's CoE handler.
//!
//! A CoE message is the payload of a mailbox message of type 3. It starts with a 2-byte CoE
//! header (ETG.1000.6 Table 29): bits 0..8 a number (0 for SDO), bits 12..15 the service.

mod emergency;
pub mod sdo;
pub mod sdo_info;
pub(crate) mod server;

pub use crate::abort::AbortCode;
pub use emergency::Emergency;
pub use server::EMERGENCY_QUEUE;

/// The CoE service (ETG.1000.6 Table 29).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Service {
    /// 1: emergency.
    Emergency,
    /// 2: SDO request.
    SdoRequest,
    /// 3: SDO response.
    SdoResponse,
    /// 4..=7: PDOs over the mailbox (not supported).
    Pdo(u8),
    /// 8: SDO Information.
    SdoInformation,
    /// Any other value.
    Unknown(u8),
}

impl Service {
    /// The service of the 4-bit code `code`.
    pub const fn from_code(code: u8) -> Self {
        match code & 0x0F {
            1 => Self::Emergency,
            2 => Self::SdoRequest,
            3 => Self::SdoResponse,
            c @ 4..=7 => Self::Pdo(c),
            8 => Self::SdoInformation,
            c => Self::Unknown(c),
        }
    }

    /// The 4-bit code.
    pub const fn code(self) -> u8 {
        match self {
            Self::Emergency => 1,
            Self::SdoRequest => 2,
            Self::SdoResponse => 3,
            Self::SdoInformation => 8,
            Self::Pdo(c) | Self::Unknown(c) => c & 0x0F,
        }
    }
}

/// The 2-byte CoE header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CoeHeader {
    /// Bits 0..8: the number (PDO number; 0 for SDO and SDO Information).
    pub number: u16,
    /// Bits 12..15: the service.
    pub service: Service,
}

impl CoeHeader {
    /// Size on the wire.
    pub const SIZE: usize = 2;

    /// A header of `service` with number 0.
    pub const fn new(service: Service) -> Self {
        Self { number: 0, service }
    }

    /// Parses the first two bytes; `None` when there are fewer.
    pub fn parse(bytes: &[u8]) -> Option<Self> {
        let raw = u16::from_le_bytes([*bytes.first()?, *bytes.get(1)?]);
        Some(Self {
            number: raw & 0x01FF,
            service: Service::from_code((raw >> 12) as u8),
        })
    }

    /// The two bytes on the wire.
    pub const fn to_bytes(self) -> [u8; 2] {
        ((self.number & 0x01FF) | ((self.service.code() as u16) << 12)).to_le_bytes()
    }
}
