//! The EtherCAT state machine (ESM) transition rules (ETG.1000.6 §6.4.1, Table 17 "state
//! transitions"), as a pure function of the current AL status and the AL control the MainDevice
//! wrote.
//!
//! ```text
//!          ┌──────┐  IP   ┌───────┐  PS   ┌────────┐  SO   ┌────┐
//!          │ INIT │ ────▶ │ PREOP │ ────▶ │ SAFEOP │ ────▶ │ OP │
//!          └──────┘ ◀──── └───────┘ ◀──── └────────┘ ◀──── └────┘
//!           │   ▲          (every downward transition is valid and always succeeds)
//!        IB │   │ BI
//!           ▼   │
//!          ┌──────┐
//!          │ BOOT │   only from and back to INIT
//!          └──────┘
//! ```
//!
//! - Any other change between known states is invalid: 0x0011, the state stays.
//! - A requested value that names no state: 0x0012, the state stays.
//! - INIT→BOOT on a device without BOOT support: 0x0013.
//! - While the error indication is set, a request without the acknowledge bit is ignored unless it
//!   requests INIT (SSC `AL_ControlInd`; ETG.1000.6 §6.4.1.4). Acknowledge clears the indication
//!   and the request is then handled as usual. A request for the current state changes nothing.
//!
//! What a valid upward transition still has to pass (SyncManager checks, the application's
//! consent) is decided by [`crate::SubDevice`].

use crate::{AlControl, AlState, AlStatus, AlStatusCode};

/// A change from one state to another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Transition {
    /// The state before.
    pub from: AlState,
    /// The state after.
    pub to: AlState,
}

impl Transition {
    /// Whether the transition goes up the ladder (INIT→PREOP, PREOP→SAFEOP, SAFEOP→OP, INIT→BOOT).
    pub const fn is_upward(self) -> bool {
        self.to.rank() > self.from.rank()
    }
}

/// What the state machine does with one AL control write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Decision {
    /// The error indication is set and the request neither acknowledges it nor asks for INIT:
    /// nothing changes, nothing is written.
    Ignore,
    /// The requested state is the current one: no transition; the error indication is cleared
    /// when acknowledged.
    Stay,
    /// A valid upward transition, subject to the SyncManager checks and the application.
    Up(Transition),
    /// A downward transition: always succeeds.
    Down(Transition),
    /// The request is refused with this code; the state stays, the error indication is set.
    Refuse(AlStatusCode),
}

/// Decides what the AL control write `control` does to a SubDevice whose AL status is `status`.
pub(crate) fn decide(status: AlStatus, control: AlControl, boot_supported: bool) -> Decision {
    let requested = control.requested();
    if status.error && !control.acknowledge() && requested != Some(AlState::Init) {
        return Decision::Ignore;
    }
    let Some(to) = requested else {
        return Decision::Refuse(AlStatusCode::UNKNOWN_STATE);
    };
    let t = Transition {
        from: status.state,
        to,
    };
    // Table 17 as two sets of (from, to) pairs.
    let pair = 1 << pair_bit(t);
    if t.from == t.to {
        Decision::Stay
    } else if pair & UPWARD != 0 {
        if t.to == AlState::Boot && !boot_supported {
            Decision::Refuse(AlStatusCode::BOOTSTRAP_NOT_SUPPORTED)
        } else {
            Decision::Up(t)
        }
    } else if pair & DOWNWARD != 0 {
        Decision::Down(t)
    } else {
        Decision::Refuse(AlStatusCode::INVALID_STATE_CHANGE)
    }
}

/// The valid upward transitions, a bit each ([`pair_bit`]).
const UPWARD: u32 = pairs(&[
    (AlState::Init, AlState::PreOp),
    (AlState::PreOp, AlState::SafeOp),
    (AlState::SafeOp, AlState::Op),
    (AlState::Init, AlState::Boot),
]);

/// The valid downward transitions, a bit each ([`pair_bit`]).
const DOWNWARD: u32 = pairs(&[
    (AlState::PreOp, AlState::Init),
    (AlState::SafeOp, AlState::Init),
    (AlState::Op, AlState::Init),
    (AlState::Boot, AlState::Init),
    (AlState::SafeOp, AlState::PreOp),
    (AlState::Op, AlState::PreOp),
    (AlState::Op, AlState::SafeOp),
]);

/// The bit of a pair of states in a set of transitions: the state codes 1, 2, 3, 4, 8 modulo 8
/// are five distinct numbers below 5, so a pair is one of 25 bits.
const fn pair_bit(t: Transition) -> u32 {
    (t.from.bits() % 8) as u32 * 5 + (t.to.bits() % 8) as u32
}

/// The set of the transitions in `list`.
const fn pairs(mut list: &[(AlState, AlState)]) -> u32 {
    let mut set = 0;
    while let [(from, to), rest @ ..] = list {
        set |= 1
            << pair_bit(Transition {
                from: *from,
                to: *to,
            });
        list = rest;
    }
    set
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(state: AlState, error: bool) -> AlStatus {
        AlStatus {
            state,
            error,
            id_loaded: false,
        }
    }

    #[test]
    fn every_invalid_pair_is_refused_with_0x0011() {
        use AlState::*;
        let invalid = [
            (Init, SafeOp),
            (Init, Op),
            (PreOp, Op),
            (PreOp, Boot),
            (SafeOp, Boot),
            (Op, Boot),
            (Boot, PreOp),
            (Boot, SafeOp),
            (Boot, Op),
        ];
        for (from, to) in invalid {
            let d = decide(
                status(from, false),
                AlControl::from_bits(to.bits().into()),
                true,
            );
            assert_eq!(
                d,
                Decision::Refuse(AlStatusCode::INVALID_STATE_CHANGE),
                "{from}->{to}"
            );
        }
    }

    #[test]
    fn every_pair_of_states_decides_as_table_17() {
        use AlState::*;
        for from in AlState::ALL {
            for to in AlState::ALL {
                let t = Transition { from, to };
                let expected = match (from, to) {
                    (a, b) if a == b => Decision::Stay,
                    (Init, PreOp) | (PreOp, SafeOp) | (SafeOp, Op) | (Init, Boot) => {
                        Decision::Up(t)
                    }
                    (PreOp | SafeOp | Op | Boot, Init) | (SafeOp | Op, PreOp) | (Op, SafeOp) => {
                        Decision::Down(t)
                    }
                    _ => Decision::Refuse(AlStatusCode::INVALID_STATE_CHANGE),
                };
                let control = AlControl::from_bits(to.bits().into());
                assert_eq!(
                    decide(status(from, false), control, true),
                    expected,
                    "{from}->{to}"
                );
            }
        }
    }

    #[test]
    fn boot_only_when_supported() {
        let d = decide(status(AlState::Init, false), AlControl::from_bits(3), false);
        assert_eq!(d, Decision::Refuse(AlStatusCode::BOOTSTRAP_NOT_SUPPORTED));
        let d = decide(status(AlState::Init, false), AlControl::from_bits(3), true);
        assert_eq!(
            d,
            Decision::Up(Transition {
                from: AlState::Init,
                to: AlState::Boot
            })
        );
    }

    #[test]
    fn error_latch_ignores_unacknowledged_requests_except_init() {
        let s = status(AlState::SafeOp, true);
        assert_eq!(
            decide(s, AlControl::from_bits(0x04), false),
            Decision::Ignore
        );
        assert_eq!(
            decide(s, AlControl::from_bits(0x08), false),
            Decision::Ignore
        );
        assert_eq!(
            decide(s, AlControl::from_bits(0x02), false),
            Decision::Ignore
        );
        assert_eq!(
            decide(s, AlControl::from_bits(0x0F), false),
            Decision::Ignore
        );
        assert_eq!(decide(s, AlControl::from_bits(0x14), false), Decision::Stay);
        let down = Transition {
            from: AlState::SafeOp,
            to: AlState::Init,
        };
        assert_eq!(
            decide(s, AlControl::from_bits(0x01), false),
            Decision::Down(down)
        );
    }
}
