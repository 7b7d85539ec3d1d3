//! The registers the core keeps at a value in the ESC: the AL event mask (0x0204), PDI control of
//! SM0..SM3 (0x0807 + 8·n, ETG.1000.4 Table 58), AL status code (0x0134) and AL status (0x0130,
//! ETG.1000.6 Tables 11 and 12), the ERR LED override (0x0139, when the ESC drives ERR:
//! [`DeviceConfig::esc_err_led`](crate::DeviceConfig::esc_err_led)), and what the core last
//! wrote there.
//!
//! What the ESM state asks for is computed when a poll looks at a stale part of the plan (the
//! `desired_*` functions of the SubDevice), from the state, the error, the code, the device ID,
//! the process-data configuration and the mailbox's flags.

use crate::sync_manager::Channel;

/// The parts of the register plan that may not be satisfied since a poll last found them so: a
/// bit per part, set by the changes that can affect it, cleared when a poll finds the part
/// satisfied. A poll looks only at the stale parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Stale(u8);

impl Stale {
    /// Nothing: a poll answers `None` at once.
    pub(super) const NONE: Self = Self(0);
    /// The AL event mask.
    pub(super) const EVENT_MASK: Self = Self(1 << 0);
    /// The register reads an AL event asked for.
    pub(super) const READS: Self = Self(1 << 1);
    /// PDI control of SM0..SM3.
    pub(super) const PDI_CONTROL: Self = Self(1 << 2);
    /// The SM0/SM1 accesses.
    pub(super) const MAILBOX: Self = Self(1 << 3);
    /// AL status code and AL status.
    pub(super) const STATUS: Self = Self(1 << 4);
    /// Everything.
    pub(super) const ALL: Self = Self(0x1F);
    /// A message came, went or was queued: the SM0/SM1 events waited for and the SM0/SM1
    /// accesses due.
    pub(super) const MAILBOX_QUEUE: Self = Self(Self::EVENT_MASK.0 | Self::MAILBOX.0);

    /// Whether every part of `other` is stale.
    pub(super) const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Marks `other` stale.
    pub(super) fn insert(&mut self, other: Self) {
        self.0 |= other.0;
    }

    /// Marks `other` satisfied.
    pub(super) fn remove(&mut self, other: Self) {
        self.0 &= !other.0;
    }
}

/// What the core last wrote to the ESC, so that it writes only what changed. A write counts from
/// the moment the plan chooses it: the same access is returned until it is done, and the plan
/// looks again only after that.
#[derive(Debug, Clone, Copy)]
pub(super) struct Written {
    /// AL event mask; 0 until written (the state machine's events are always in it).
    pub(super) event_mask: u32,
    /// PDI control of SM0..SM3; [`Written::UNKNOWN`] until written.
    pub(super) pdi_control: [u8; 4],
    /// AL status code; any value until written (`status` says whether it is).
    pub(super) status_code: u16,
    /// AL status, its low byte (the high one is reserved, written 0); 0 until the status part
    /// is written, [`Written::UNKNOWN`] once the code is and the status not yet (a state code
    /// is always in a status wanted, and the reserved bits never).
    pub(super) status: u8,
    /// The ERR LED override; [`Written::UNKNOWN`] until written and after each AL status
    /// write (the ESC clears the override's enable bit on a new error condition).
    pub(super) err_led: u8,
}
// 12 bytes (a code and a status of 16 bits and 0 standing for neither: 16): the SubDevice's
// fields before its mailbox end on the mailbox's 8-byte alignment, 8 bytes less padding.
const _: () = assert!(size_of::<Written>() == 12);

impl Written {
    /// A PDI control, LED override or AL status value never wanted (PDI control with the
    /// deactivate bit set, an override or a status with reserved bits): not written yet.
    pub(super) const UNKNOWN: u8 = 0xFF;

    pub(super) const fn new() -> Self {
        Self {
            event_mask: 0,
            pdi_control: [Self::UNKNOWN; 4],
            status_code: 0,
            status: 0,
            err_led: Self::UNKNOWN,
        }
    }

    /// The PDI control write that brings SM0..SM3 closer to `desired`: SyncManager n and its
    /// value. Deactivations come first, in the order "stop outputs, then inputs, then mailbox"
    /// of a downward transition (ETG.1000.6 §6.4.1, Table 17; conformance.md "ESM"): SM2, SM3,
    /// SM1, SM0. Then the other changes (activations, SM1's repeat acknowledge) in SM order, so
    /// that on the way up the mailbox is active before the process data.
    pub(super) fn pdi_control_due(&self, desired: [u8; 4]) -> Option<(u8, u8)> {
        // Each SyncManager with whether only its deactivation counts: deactivations in stop
        // order first, then every change in SM order.
        const ORDER: [(u8, bool); 8] = [
            (2, true),
            (3, true),
            (1, true),
            (0, true),
            (0, false),
            (1, false),
            (2, false),
            (3, false),
        ];
        ORDER.iter().find_map(|&(n, deactivation)| {
            let i = usize::from(n);
            let (d, w) = (*desired.get(i)?, *self.pdi_control.get(i)?);
            let counts = !deactivation || d & Channel::PDI_DEACTIVATE != 0;
            (d != w && counts).then_some((n, d))
        })
    }

    /// Whether SM0 and SM1 were last written active.
    pub(super) fn mailbox_active(&self) -> bool {
        let [receive, send, ..] = self.pdi_control;
        (receive | send) & Channel::PDI_DEACTIVATE == 0
    }
}
