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
        self.0 & state_bits(state) != 0
    }

    /// Whether writable in `state`.
    pub const fn writable_in(self, state: AlState) -> bool {
        self.0 & (state_bits(state) << 3) != 0
    }

    /// Whether readable in some state.
    pub const fn readable(self) -> bool {
        self.0 & Self::READ.0 != 0
    }

    /// Whether writable in some state.
    pub const fn writable(self) -> bool {
        self.0 & Self::WRITE.0 != 0
    }

    /// Whether an entry with these rights is ever written through its object's `write`:
    /// writable by SDO, or BACKUP (restored from storage). `dictionary!` gives an object with
    /// neither the shared `read_only` as its write, so that a dictionary carries no decoding,
    /// range or PDO configuration checks for values no one writes.
    pub const fn is_written(self) -> bool {
        self.writable() || self.backup()
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

/// The bit of `state` in the read triple (PREOP 0, SAFEOP 1, OP 2), none for INIT and BOOT: a
/// 3-bit field of one 32-bit constant indexed by the state's code (1, 2, 3, 4, 8: OP's field
/// ends at bit 26), a shift rather than a branch, a table or a 64-bit shift (a library call on
/// a 32-bit target).
const fn state_bits(state: AlState) -> u16 {
    /// Field n: the bits of the state whose code is n.
    const BITS: u32 = (0b001 << (3 * AlState::PreOp as u32))
        | (0b010 << (3 * AlState::SafeOp as u32))
        | (0b100 << (3 * AlState::Op as u32));
    ((BITS >> (3 * state as u32)) & 0b111) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_state_has_its_own_bit_and_init_and_boot_none() {
        let bits = AlState::ALL.map(state_bits);
        // Init, PreOp, Boot, SafeOp, Op.
        assert_eq!(bits, [0, 0b001, 0, 0b010, 0b100]);
        let rw_preop = Access::RW_PREOP;
        let readable = AlState::ALL.map(|s| rw_preop.readable_in(s));
        let writable = AlState::ALL.map(|s| rw_preop.writable_in(s));
        assert_eq!(readable, [false, true, false, true, true]);
        assert_eq!(writable, [false, true, false, false, false]);
    }
}
