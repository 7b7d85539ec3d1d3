//! The power drive system state machine (IEC 61800-7-201 §6.2.1.1, Figure 19; transitions in
//! Table 27).
//!
//! One [`PowerDriveSystem::update`] per cycle takes the controlword and the motor's standstill and
//! returns the [`Motion`] to execute. Stops run over several cycles: the PDS holds the pending
//! [`Reaction`] and completes the transition once the motion layer reports standstill (at once
//! for [`Ramp::Disable`]). While a shutdown (8) or disable operation (5) stop runs, the state
//! stays Operation enabled — those transitions have no state of their own — and only disable
//! voltage (9) or quick stop (11) replace it.

use super::controlword::FAULT_RESET;
use super::{Command, OptionCodes, Ramp, Reaction, State};

/// What the motion layer does this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// The drive function is disabled: no torque (every state but the three below).
    Off,
    /// Execute the mode of operation (Operation enabled).
    Follow,
    /// Decelerate to standstill with the ramp, then report standstill.
    Stop(Ramp),
    /// Hold the motor at standstill, powered (Quick stop active after codes 5..8 completed).
    Hold,
}

/// The transitions (0..=16 of Table 27) one update took: bit `n` for transition `n`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Transitions(pub u32);

impl Transitions {
    /// Whether transition `n` was taken.
    pub const fn contains(self, n: u8) -> bool {
        n < 32 && self.0 & (1 << n) != 0
    }

    /// Whether no transition was taken.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    const fn with(self, n: u8) -> Self {
        Self(self.0 | (1 << n))
    }
}

/// What one update did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    /// The transitions taken (an application clears its error code on 15).
    pub transitions: Transitions,
    /// What to do with the motor.
    pub motion: Motion,
}

/// The PDS state machine of one axis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PowerDriveSystem {
    state: State,
    /// The stop in progress.
    pending: Option<Reaction>,
    /// Bit 7 of the previous controlword, for the rising edge.
    fault_reset: bool,
}

impl PowerDriveSystem {
    /// A drive after transition 0 (power on): Not ready to switch on. The first
    /// [`update`](Self::update) takes transition 1, the drive's initialisation being done when
    /// the application starts updating.
    pub const fn new() -> Self {
        Self {
            state: State::NotReadyToSwitchOn,
            pending: None,
            fault_reset: false,
        }
    }

    /// The current state.
    pub const fn state(&self) -> State {
        self.state
    }

    /// The stop in progress, if any.
    pub const fn pending(&self) -> Option<Reaction> {
        self.pending
    }

    /// A fault occurred: transition 13 into Fault reaction active with the fault reaction of
    /// 0x605E, from any state but Fault reaction active and Fault (where it is already handled).
    pub fn fault(&mut self, options: &OptionCodes) {
        if !matches!(self.state, State::FaultReactionActive | State::Fault) {
            self.state = State::FaultReactionActive;
            self.pending = Some(options.fault_reaction());
        }
    }

    /// One cycle: completes a pending stop when `standstill` (or at once for a disabling one),
    /// then applies the command in `controlword`, and tells the motion layer what to do.
    pub fn update(&mut self, controlword: u16, options: &OptionCodes, standstill: bool) -> Step {
        let edge = controlword & FAULT_RESET != 0 && !self.fault_reset;
        self.fault_reset = controlword & FAULT_RESET != 0;
        let transitions = match self.complete(standstill) {
            Some(completed) => completed,
            None => self.command(Command::decode(controlword), edge, options),
        };
        Step {
            transitions,
            motion: self.motion(),
        }
    }

    /// The automatic transitions: 1 after initialisation, and the end of a pending stop (5, 8,
    /// 12, 14, or staying in Quick stop active). `Some` when one happened: the cycle's command
    /// then waits for the next cycle.
    fn complete(&mut self, standstill: bool) -> Option<Transitions> {
        let none = Transitions::default();
        if self.state == State::NotReadyToSwitchOn {
            self.state = State::SwitchOnDisabled;
            return Some(none.with(1));
        }
        let reaction = self.pending?;
        if !standstill && reaction.ramp != Ramp::Disable {
            return None;
        }
        self.pending = None;
        let from = core::mem::replace(&mut self.state, reaction.then);
        Some(match (from, reaction.then) {
            (State::OperationEnabled, State::SwitchedOn) => none.with(5),
            (State::OperationEnabled, _) => none.with(8),
            (State::QuickStopActive, State::SwitchOnDisabled) => none.with(12),
            (State::FaultReactionActive, _) => none.with(14),
            _ => none,
        })
    }

    /// The transition a command takes in the current state (Table 27); a stop becomes pending.
    fn command(
        &mut self,
        command: Option<Command>,
        edge: bool,
        options: &OptionCodes,
    ) -> Transitions {
        use Command::*;
        use State::*;
        let none = Transitions::default();
        let stopping = self.pending.is_some();
        let (next, taken) = match (self.state, command) {
            (Fault, _) if edge => (SwitchOnDisabled, none.with(15)),
            (SwitchOnDisabled, Some(Shutdown)) => (ReadyToSwitchOn, none.with(2)),
            (ReadyToSwitchOn, Some(SwitchOn)) => (SwitchedOn, none.with(3)),
            (ReadyToSwitchOn, Some(EnableOperation)) => (OperationEnabled, none.with(3).with(4)),
            (ReadyToSwitchOn, Some(DisableVoltage | QuickStop)) => (SwitchOnDisabled, none.with(7)),
            (SwitchedOn, Some(EnableOperation)) => (OperationEnabled, none.with(4)),
            (SwitchedOn, Some(Shutdown)) => (ReadyToSwitchOn, none.with(6)),
            (SwitchedOn, Some(DisableVoltage | QuickStop)) => (SwitchOnDisabled, none.with(10)),
            (OperationEnabled, Some(DisableVoltage)) => (SwitchOnDisabled, none.with(9)),
            (OperationEnabled, Some(QuickStop)) => {
                self.pending = Some(options.quick_stop());
                (QuickStopActive, none.with(11))
            }
            (OperationEnabled, Some(SwitchOn)) if !stopping => {
                self.pending = Some(options.disable_operation());
                (OperationEnabled, none)
            }
            (OperationEnabled, Some(Shutdown)) if !stopping => {
                self.pending = Some(options.shutdown());
                (OperationEnabled, none)
            }
            (QuickStopActive, Some(DisableVoltage)) => (SwitchOnDisabled, none.with(12)),
            (QuickStopActive, Some(EnableOperation))
                if !stopping && options.quick_stop().then == QuickStopActive =>
            {
                (OperationEnabled, none.with(16))
            }
            (state, _) => (state, none),
        };
        if next != self.state && next != QuickStopActive {
            self.pending = None;
        }
        self.state = next;
        taken
    }

    /// The motion of the current state and pending stop.
    fn motion(&self) -> Motion {
        match (self.state, self.pending) {
            (_, Some(reaction)) => Motion::Stop(reaction.ramp),
            (State::OperationEnabled, None) => Motion::Follow,
            (State::QuickStopActive, None) => Motion::Hold,
            _ => Motion::Off,
        }
    }
}

impl Default for PowerDriveSystem {
    fn default() -> Self {
        Self::new()
    }
}
