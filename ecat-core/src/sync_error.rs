//! Sync error supervision (ETG.1020 §6.3, "Error Settings" object 0x10F1): the SubDevice counts
//! missed SM/SYNC events against a limit and, above it, leaves OP for SAFEOP with the AL status
//! code 0x001A "synchronization error".
//!
//! The rule is the EtherCAT Slave Stack Code's (ET9300 `ecatslv.c`, `Sync0_Isr`/`PDI_Isr`/
//! `CheckIfEcatError`, V5.13): each cycle that missed its event adds 3 to a counter (only while
//! the counter is at or below the limit, so it stays bounded), each good cycle takes 1 off
//! (not below 0); the sequence is invalid once the counter reaches the limit (`counter <
//! limit` is valid). A limit of 0 switches the supervision off (SSC V5.13). The limit is
//! 0x10F1:02 "Sync error counter limit" when the dictionary has 0x10F1, else SSC's default
//! `MAX_SM_EVENT_MISSED` = 4 (`ecatslv.h`).
//!
//! 0x10F1:01 "Local error reaction" (UNSIGNED32) selects how the device reacts to a local
//! error. ETG.1020's table of its values is not in the public material this crate was checked
//! against; SSC declares the entry RW with the value 1 (`objdef.h`: `sErrorSettings = {2,
//! 0x01, MAX_SM_EVENT_MISSED}`) and never reads it. This stack has one reaction, the one SSC
//! performs: SAFEOP with the error indication and the AL status code (0x001A here; 0x001B for
//! the SM watchdog, 0x002C/0x002D for a lost SYNC0). So [`ErrorSettings`] declares the entry
//! with SSC's value 1 ([`REACTION_SAFEOP`]) as default, minimum and maximum: a MainDevice reads
//! 1 and the ESI carries it, and a write of any other value is refused (0x06090031/0x06090032)
//! rather than accepted and ignored.
//!
//! With the default limit one missed event is tolerated (3 < 4) and forgiven after three good
//! cycles; two missed events closer together than that trip it: a MainDevice that loses one
//! frame in 4 keeps the SubDevice in OP for ever, one that loses one frame in 3 trips it at the
//! second loss.
//!
//! Which cycles count: in DC SYNC0 mode in OP, each SYNC0 cycle, missed when the MainDevice
//! wrote no new outputs (SM2) since the previous one (the same cycles `CycleMonitor` counts in
//! 0x1C32:0B). In SM-synchronous mode the SM2 event is the cycle itself, so there is no event to
//! miss: like SSC, the supervision does not run there (the SM watchdog, 0x001B, covers a
//! MainDevice that stops).

use crate::dictionary::{Object, ObjectDictionary};

/// The Error Settings object (ETG.1020 §6.3).
pub const ERROR_SETTINGS: u16 = 0x10F1;
/// 0x10F1:01, the local error reaction.
pub const LOCAL_ERROR_REACTION: u8 = 1;
/// 0x10F1:02, the sync error counter limit.
pub(crate) const SYNC_ERROR_COUNTER_LIMIT: u8 = 2;
/// The value of 0x10F1:01 for this stack's reaction to a local error, SSC's value: SAFEOP with
/// the error indication and the AL status code (see the module docs).
pub const REACTION_SAFEOP: u32 = 1;

/// The Error Settings record 0x10F1 (ETG.1020 §6.3) as SSC declares it, for a dictionary
/// field:
///
/// ```text
/// 0x10F1 => record(error_settings: ErrorSettings, "Error settings") {
///     1 => local_error_reaction, RW, "Local error reaction", default = REACTION_SAFEOP,
///          min = REACTION_SAFEOP, max = REACTION_SAFEOP;
///     2 => sync_error_counter_limit, RW, "Sync error counter limit", default = DEFAULT_LIMIT;
/// };
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ErrorSettings {
    /// SI1, the local error reaction: [`REACTION_SAFEOP`], the only value.
    pub local_error_reaction: u32,
    /// SI2, the sync error counter limit ([`limit`]); 0 switches the supervision off.
    pub sync_error_counter_limit: u16,
}

impl ErrorSettings {
    /// SSC's values: the reaction 1, the limit 4.
    pub const fn new() -> Self {
        Self {
            local_error_reaction: REACTION_SAFEOP,
            sync_error_counter_limit: DEFAULT_LIMIT,
        }
    }
}

impl Default for ErrorSettings {
    fn default() -> Self {
        Self::new()
    }
}
/// The limit without 0x10F1: SSC's `MAX_SM_EVENT_MISSED`.
pub const DEFAULT_LIMIT: u16 = 4;
/// What one missed event adds to the counter.
pub(crate) const MISSED_WEIGHT: u16 = 3;

/// The sync error counter of one OP session.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SyncSupervision {
    counter: u16,
    tripped: bool,
    /// The last cycle counted (expected outputs): an OP session is under way.
    active: bool,
}

impl SyncSupervision {
    /// A counter at 0.
    pub const fn new() -> Self {
        Self {
            counter: 0,
            tripped: false,
            active: false,
        }
    }

    /// The counter.
    pub const fn counter(&self) -> u16 {
        self.counter
    }

    /// Whether the limit was reached in the current or the last OP session (until the next one
    /// starts, or a [`SyncSupervision::reset`]).
    pub const fn tripped(&self) -> bool {
        self.tripped
    }

    /// Back to 0, not tripped (a new OP session).
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// Accounts for one cycle against `limit` (0: off). Only cycles that `expect` an event
    /// count (DC mode in OP); the first of a run of them starts a new session at 0. Returns
    /// `true` once, for the cycle whose count reaches the limit: the SubDevice leaves OP with
    /// 0x001A.
    pub fn cycle(&mut self, expect: bool, missed: bool, limit: u16) -> bool {
        if !expect || limit == 0 {
            self.active = false;
            return false;
        }
        if !core::mem::replace(&mut self.active, true) {
            self.counter = 0;
            self.tripped = false;
        }
        if missed {
            if self.counter <= limit {
                self.counter = self.counter.saturating_add(MISSED_WEIGHT);
            }
        } else {
            self.counter = self.counter.saturating_sub(1);
        }
        self.counter >= limit && !core::mem::replace(&mut self.tripped, true)
    }
}

/// The sync error counter limit of `od`: 0x10F1:02, or [`DEFAULT_LIMIT`] when the dictionary
/// has no 0x10F1 (known at compile time: no lookup code then) or the entry is not a u16.
pub fn limit<D: ObjectDictionary>(od: &D) -> u16 {
    if !const { has_error_settings(D::OBJECTS) } {
        return DEFAULT_LIMIT;
    }
    D::object(ERROR_SETTINGS)
        .and_then(|object| object.read_u16(od, SYNC_ERROR_COUNTER_LIMIT))
        .unwrap_or(DEFAULT_LIMIT)
}

/// Whether `objects` has 0x10F1.
#[allow(clippy::indexing_slicing)] // bounded by the loop condition; evaluated at compile time
const fn has_error_settings<D>(objects: &[Object<D>]) -> bool {
    let mut i = 0;
    while i < objects.len() {
        if objects[i].info.index == ERROR_SETTINGS {
            return true;
        }
        i += 1;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cycle (1-based) at which the supervision trips when every `n`th cycle misses, within
    /// `cycles`; `None` if it never does.
    fn trips(n: u32, limit: u16, cycles: u32) -> Option<u32> {
        let mut s = SyncSupervision::new();
        (1..=cycles).find(|k| s.cycle(true, k % n == 0, limit))
    }

    #[test]
    fn one_loss_in_four_is_tolerated_one_in_three_trips_at_the_second() {
        assert_eq!(trips(4, DEFAULT_LIMIT, 10_000), None);
        // 3 at cycle 3, then 2, 1, and the loss at cycle 6 makes 4: the limit.
        assert_eq!(trips(3, DEFAULT_LIMIT, 10_000), Some(6));
        // Two losses in a row: 3, then 6.
        assert_eq!(trips(1, DEFAULT_LIMIT, 10), Some(2));
        assert_eq!(trips(2, DEFAULT_LIMIT, 10), Some(4), "3, 2, 5");
    }

    #[test]
    fn the_counter_steps_as_ssc() {
        let mut s = SyncSupervision::new();
        let seen = [false, true, false, false, true, false, false, false, false].map(|missed| {
            s.cycle(true, missed, 10);
            s.counter()
        });
        assert_eq!(seen, [0, 3, 2, 1, 4, 3, 2, 1, 0]);
        // Bounded: no increment above the limit.
        let mut s = SyncSupervision::new();
        for _ in 0..100 {
            s.cycle(true, true, 4);
        }
        assert_eq!(s.counter(), 6, "3, 6, then 6 > 4: no more");
    }

    #[test]
    fn trips_once_and_a_reset_rearms() {
        let mut s = SyncSupervision::new();
        assert!(!s.cycle(true, true, 4));
        assert!(s.cycle(true, true, 4));
        assert!(!s.cycle(true, true, 4), "reported once");
        assert!(s.tripped());
        assert!(!s.cycle(false, false, 4), "a cycle outside OP");
        assert!(s.tripped(), "still shown after OP");
        assert!(!s.cycle(true, false, 4), "a new OP session");
        assert_eq!((s.counter(), s.tripped()), (0, false));
        assert!(!s.cycle(true, true, 4));
        assert!(s.cycle(true, true, 4));
        s.reset();
        assert_eq!((s.counter(), s.tripped()), (0, false));
        assert!(!s.cycle(true, true, 4));
    }

    #[test]
    fn limit_0_is_off_and_other_limits_scale() {
        assert_eq!(trips(1, 0, 1_000), None);
        // Limit 1: the first loss trips; limit 7: the third loss in a row (3, 6, 9).
        assert_eq!(trips(1, 1, 10), Some(1));
        assert_eq!(trips(1, 7, 10), Some(3));
        assert_eq!(
            trips(1, u16::MAX, 100_000),
            Some(21_845),
            "3 · 21845 = 65535"
        );
    }

    #[test]
    fn without_0x10f1_the_default_applies() {
        assert_eq!(limit(&()), DEFAULT_LIMIT);
    }
}
