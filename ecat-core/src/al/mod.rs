//! Application-layer (AL) registers: how the MainDevice requests a state and how the SubDevice
//! answers (ETG.1000.6 §5.3, Tables 9–12).
//!
//! | register | type |
//! |---|---|
//! | AL control 0x0120 | [`AlControl`] |
//! | AL status 0x0130 | [`AlStatus`] |
//! | AL status code 0x0134 | [`AlStatusCode`] |
//! | AL event request 0x0220 / mask 0x0204 | [`AlEvent`] |

mod control;
mod event;
mod status;
mod status_code;

pub use control::AlControl;
pub use event::AlEvent;
pub use status::AlStatus;
pub use status_code::AlStatusCode;

/// A state of the EtherCAT state machine, as encoded in bits 3:0 of AL control and AL status
/// (ETG.1000.6 Table 9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum AlState {
    /// INIT: no mailbox, no process data; the MainDevice configures the ESC.
    Init = 0x1,
    /// PRE-OPERATIONAL: mailbox communication.
    PreOp = 0x2,
    /// BOOTSTRAP: firmware update over FoE with the bootstrap mailbox.
    Boot = 0x3,
    /// SAFE-OPERATIONAL: inputs are exchanged, outputs stay in their safe state.
    SafeOp = 0x4,
    /// OPERATIONAL: inputs and outputs are exchanged.
    Op = 0x8,
}

impl AlState {
    /// All five states, in the order of their codes.
    pub const ALL: [AlState; 5] = [Self::Init, Self::PreOp, Self::Boot, Self::SafeOp, Self::Op];

    /// The state encoded in the low nibble of `bits`, or `None` for a value that names no state.
    pub const fn from_bits(bits: u8) -> Option<Self> {
        match bits & 0x0F {
            0x1 => Some(Self::Init),
            0x2 => Some(Self::PreOp),
            0x3 => Some(Self::Boot),
            0x4 => Some(Self::SafeOp),
            0x8 => Some(Self::Op),
            _ => None,
        }
    }

    /// The 4-bit code of this state.
    pub const fn bits(self) -> u8 {
        self as u8
    }

    /// The rank of the state on the INIT → PREOP → SAFEOP → OP ladder (BOOT sits beside PREOP,
    /// reachable only from INIT). Used to tell upward from downward transitions.
    pub(crate) const fn rank(self) -> u8 {
        match self {
            Self::Init => 0,
            Self::PreOp | Self::Boot => 1,
            Self::SafeOp => 2,
            Self::Op => 3,
        }
    }

    /// Whether the mailbox SyncManagers (SM0/SM1) are active in this state.
    pub const fn has_mailbox(self) -> bool {
        !matches!(self, Self::Init)
    }

    /// Whether the process-data SyncManagers (SM2/SM3) are active in this state.
    pub const fn has_process_data(self) -> bool {
        matches!(self, Self::SafeOp | Self::Op)
    }

    /// The usual short name (`INIT`, `PREOP`, `BOOT`, `SAFEOP`, `OP`).
    pub const fn name(self) -> &'static str {
        match self {
            Self::Init => "INIT",
            Self::PreOp => "PREOP",
            Self::Boot => "BOOT",
            Self::SafeOp => "SAFEOP",
            Self::Op => "OP",
        }
    }
}

impl core::fmt::Display for AlState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}
