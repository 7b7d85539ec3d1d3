//! The PDS states and the statusword pattern of each (IEC 61800-7-201 §6.2.1.3, Table 30).

/// One state of the power drive system state machine (IEC 61800-7-201 Figure 19).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum State {
    /// Low-level power on, the drive initialises; the drive function is disabled.
    NotReadyToSwitchOn,
    /// Initialised; high-level power may be applied, the drive function is disabled.
    SwitchOnDisabled,
    /// High-level power may be applied, the drive function is disabled.
    ReadyToSwitchOn,
    /// High-level power is applied, the drive function is disabled.
    SwitchedOn,
    /// No fault, the drive function is enabled and power is applied to the motor.
    OperationEnabled,
    /// The quick stop function is being executed (or done, for option codes 5..8).
    QuickStopActive,
    /// A fault occurred; the fault reaction (0x605E) is being executed.
    FaultReactionActive,
    /// A fault occurred; the drive function is disabled.
    Fault,
}

impl State {
    /// Every state, in the order of Table 30.
    pub const ALL: [Self; 8] = [
        Self::NotReadyToSwitchOn,
        Self::SwitchOnDisabled,
        Self::ReadyToSwitchOn,
        Self::SwitchedOn,
        Self::OperationEnabled,
        Self::QuickStopActive,
        Self::FaultReactionActive,
        Self::Fault,
    ];

    /// The statusword mask and value that identify the state (Table 30): `sw & mask == value`.
    pub const fn pattern(self) -> (u16, u16) {
        match self {
            Self::NotReadyToSwitchOn => (0x004F, 0x0000),
            Self::SwitchOnDisabled => (0x004F, 0x0040),
            Self::ReadyToSwitchOn => (0x006F, 0x0021),
            Self::SwitchedOn => (0x006F, 0x0023),
            Self::OperationEnabled => (0x006F, 0x0027),
            Self::QuickStopActive => (0x006F, 0x0007),
            Self::FaultReactionActive => (0x004F, 0x000F),
            Self::Fault => (0x004F, 0x0008),
        }
    }

    /// The state a statusword shows, `None` when it matches no pattern of Table 30.
    pub fn from_statusword(statusword: u16) -> Option<Self> {
        Self::ALL.into_iter().find(|s| {
            let (mask, value) = s.pattern();
            statusword & mask == value
        })
    }
}
