//! Object access rights: per ESM state, PDO mappability, backup and settings flags
//! (ETG.1000.6 Table 49 "object access", as carried by SDO Information entry descriptions).

use crate::AlState;

/// The access word of an entry (ETG.1000.6 Table 49).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Access(pub u16);

impl Access {
    /// Bit 0..2: readable in PREOP, SAFEOP, OP.
    pub const READ: Self = Self(0x0007);
    /// Bit 3..5: writable in PREOP, SAFEOP, OP.
    pub const WRITE: Self = Self(0x0038);
    /// Read-only in every state.
    pub const RO: Self = Self::READ;
    /// Read and write in every state.
    pub const RW: Self = Self(0x003F);
    /// Write-only in every state.
    pub const WO: Self = Self::WRITE;
    /// Readable always, writable in PREOP only (SSC "PREOP_RW"): configuration parameters.
    pub const RW_PREOP: Self = Self(0x000F);
    /// Readable always, writable in PREOP and SAFEOP.
    pub const RW_PREOP_SAFEOP: Self = Self(0x001F);
    /// Bit 6: may be mapped into an RxPDO (outputs).
    pub const RXPDO: Self = Self(0x0040);
    /// Bit 7: may be mapped into a TxPDO (inputs).
    pub const TXPDO: Self = Self(0x0080);
    /// Bit 8: part of the backup (restored by "restore parameters").
    pub const BACKUP: Self = Self(0x0100);
    /// Bit 9: a setting (device configuration).
    pub const SETTINGS: Self = Self(0x0200);

    /// Whether readable in `state` (BOOT and INIT have no CoE).
    pub const fn readable_in(self, state: AlState) -> bool {
        match state_bit(state) {
            Some(bit) => self.0 & (1 << bit) != 0,
            None => false,
        }
    }

    /// Whether writable in `state`.
    pub const fn writable_in(self, state: AlState) -> bool {
        match state_bit(state) {
            Some(bit) => self.0 & (1 << (bit + 3)) != 0,
            None => false,
        }
    }

    /// Whether readable in some state.
    pub const fn readable(self) -> bool {
        self.0 & Self::READ.0 != 0
    }

    /// Whether writable in some state.
    pub const fn writable(self) -> bool {
        self.0 & Self::WRITE.0 != 0
    }

    /// Whether mappable into an RxPDO.
    pub const fn rxpdo(self) -> bool {
        self.0 & Self::RXPDO.0 != 0
    }

    /// Whether mappable into a TxPDO.
    pub const fn txpdo(self) -> bool {
        self.0 & Self::TXPDO.0 != 0
    }

    /// Whether part of the backup.
    pub const fn backup(self) -> bool {
        self.0 & Self::BACKUP.0 != 0
    }

    /// Whether a setting.
    pub const fn settings(self) -> bool {
        self.0 & Self::SETTINGS.0 != 0
    }
}

impl core::ops::BitOr for Access {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
}

/// Bit position of `state` in the read triple (PREOP 0, SAFEOP 1, OP 2).
const fn state_bit(state: AlState) -> Option<u16> {
    match state {
        AlState::PreOp => Some(0),
        AlState::SafeOp => Some(1),
        AlState::Op => Some(2),
        AlState::Init | AlState::Boot => None,
    }
}
