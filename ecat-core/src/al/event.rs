//! AL event request (0x0220) and AL event mask (0x0204).

/// A set of AL event request bits: what the ESC tells the SubDevice's controller (ETG.1000.4
/// "DL-user event", ESC datasheet section II 0x0220).
///
/// The same type describes the mask register 0x0204: the PDI IRQ line is asserted while
/// `request & mask` is not empty. Each bit is cleared by the PDI access that reads its source
/// (see [`RegisterAccess::clears`](crate::RegisterAccess::clears)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct AlEvent(pub u32);

impl AlEvent {
    /// No event.
    pub const NONE: Self = Self(0);
    /// Bit 0: the MainDevice wrote AL control. Cleared by a PDI read of 0x0120.
    pub const AL_CONTROL: Self = Self(1 << 0);
    /// Bit 1: DC latch event.
    pub const DC_LATCH: Self = Self(1 << 1);
    /// Bit 2: DC SYNC0 (when mapped to the AL event).
    pub const DC_SYNC0: Self = Self(1 << 2);
    /// Bit 3: DC SYNC1 (when mapped to the AL event).
    pub const DC_SYNC1: Self = Self(1 << 3);
    /// Bit 4: a SyncManager activation register changed. Cleared by a PDI read of the activation
    /// register (offset 6) of the channels that changed.
    pub const SM_CHANGE: Self = Self(1 << 4);
    /// Bit 5: EEPROM emulation command pending.
    pub const EEPROM_EMULATION: Self = Self(1 << 5);
    /// Bit 6: the process-data watchdog expired.
    pub const WATCHDOG_PROCESS_DATA: Self = Self(1 << 6);

    /// Bit 8 + n: SyncManager `n` has an event for the PDI (buffer written by the MainDevice or read
    /// by it). Cleared when the PDI accesses the buffer.
    pub const fn sync_manager(n: u8) -> Self {
        Self(1 << (8 + (n & 0x0F)))
    }

    /// The register as read over the PDI (little endian).
    pub const fn from_le_bytes(bytes: [u8; 4]) -> Self {
        Self(u32::from_le_bytes(bytes))
    }

    /// The register-sourced events a PDI read of `len` bytes from `address` clears (ESC datasheet
    /// section II, 0x0220): AL control (bit 0) by reading 0x0120, SM change (bit 4) by reading
    /// a SyncManager's activation register (offset 6), the process-data watchdog (bit 6) by
    /// reading 0x0440. SM change stays set until the activation register of every changed channel
    /// is read, so a caller that forgets it after one channel only under-reports. The SyncManager
    /// buffer events (bits 8..) depend on the SyncManager configuration and are not included.
    pub fn cleared_by_register_read(address: u16, len: usize) -> Self {
        use crate::register;
        let start = u32::from(address);
        let end = start.saturating_add(u32::try_from(len).unwrap_or(u32::MAX));
        let covers = |reg: u16| (start..end).contains(&u32::from(reg));
        let mut cleared = Self::NONE;
        if covers(register::AL_CONTROL) {
            cleared |= Self::AL_CONTROL;
        }
        if (0..16).any(|n| covers(register::sync_manager(n).saturating_add(6))) {
            cleared |= Self::SM_CHANGE;
        }
        if covers(register::WATCHDOG_STATUS_PROCESS_DATA) {
            cleared |= Self::WATCHDOG_PROCESS_DATA;
        }
        cleared
    }

    /// The raw register value.
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// Whether no bit is set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether any bit of `other` is set in `self`.
    pub const fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// Whether every bit of `other` is set in `self`.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The bits set in either.
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// The bits of `self` that are not in `other`.
    pub const fn difference(self, other: Self) -> Self {
        Self(self.0 & !other.0)
    }

    /// The bits set in both.
    pub const fn intersection(self, other: Self) -> Self {
        Self(self.0 & other.0)
    }
}

impl core::ops::BitOr for AlEvent {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        self.union(rhs)
    }
}

impl core::ops::BitOrAssign for AlEvent {
    fn bitor_assign(&mut self, rhs: Self) {
        *self = self.union(rhs);
    }
}
