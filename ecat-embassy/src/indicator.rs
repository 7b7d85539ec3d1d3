//! The RUN and ERR indicators of ETG.1300 on GPIO pins: a task that follows the AL status the
//! state-machine runner publishes ([`Status`]) and sleeps until the next edge
//! ([`Indicators::at`], with the levels) or the next change of the AL status, whichever comes first.
//!
//! The patterns, the code classes and the bicolour rule are [`ecat_core::indicator`]'s. What
//! this adds is the wiring: [`RunErr`] (two LEDs), [`Bicolour`] (one red/green LED on two pins)
//! and [`ErrOnly`] (the ESC drives RUN from its AL status register by itself, ETG.1000.4
//! register 0x0138, so only ERR is the firmware's; with ERR on the ESC as well, the core writes
//! its override 0x0139 and no task runs: `DeviceConfig::esc_err_led`). A pin is written only
//! when its level changes.
//!
//! What it costs the runners: the state-machine runner publishes the AL status and code with
//! the layout it already publishes after each access (one compare and one store in the same
//! critical section, a wake-up when they changed); nothing when no indicator task runs.

use core::future::{Future, poll_fn};
use core::pin::Pin;
use core::task::Poll;

use ecat_core::indicator::{Colour, Indicators, Levels};
use ecat_core::{AlState, AlStatus};
use embedded_hal::digital::{OutputPin, PinState};

use crate::Pdi;
use crate::shared::Status;
use crate::time::{now, until};

/// Where the indicator levels go.
pub trait Lamps {
    /// Shows `levels`, writing only what differs from `before`, the levels shown last (`None`:
    /// nothing shown yet). Called at each wake-up of the task, also when nothing changed.
    fn show(&mut self, levels: Levels, before: Option<Levels>);
}

/// A green RUN LED and a red ERR LED on two pins, lit when high. Pin errors are ignored: an
/// indicator has nowhere to report them.
pub struct RunErr<R, E> {
    /// The RUN LED.
    pub run: R,
    /// The ERR LED.
    pub err: E,
}

impl<R: OutputPin, E: OutputPin> Lamps for RunErr<R, E> {
    fn show(&mut self, levels: Levels, before: Option<Levels>) {
        if before.map(|b| b.run) != Some(levels.run) {
            let _ = self.run.set_state(PinState::from(levels.run));
        }
        if before.map(|b| b.err) != Some(levels.err) {
            let _ = self.err.set_state(PinState::from(levels.err));
        }
    }
}

/// One red/green LED on two pins (lit when high), ERR winning a conflict
/// ([`Levels::bicolour`]). The pin going low is written first, so both are never high.
pub struct Bicolour<G, R> {
    /// The green element (RUN).
    pub green: G,
    /// The red element (ERR).
    pub red: R,
}

impl<G: OutputPin, R: OutputPin> Lamps for Bicolour<G, R> {
    fn show(&mut self, levels: Levels, before: Option<Levels>) {
        if before.map(Levels::bicolour) == Some(levels.bicolour()) {
            return;
        }
        match levels.bicolour() {
            Colour::Off => {
                let _ = self.green.set_low();
                let _ = self.red.set_low();
            }
            Colour::Green => {
                let _ = self.red.set_low();
                let _ = self.green.set_high();
            }
            Colour::Red => {
                let _ = self.green.set_low();
                let _ = self.red.set_high();
            }
        }
    }
}

/// Only the ERR LED, lit when high: for an ESC that drives the RUN LED from its AL status
/// register itself (ET1100/ET1200, LAN9252, AX58100: the board wires the LED to the ESC's RUN
/// pin). Nothing is written for RUN: the ESC shows the state the stack writes into AL status,
/// and its override register 0x0138 is the MainDevice's (device identification), cleared by the
/// ESC at the next state change. ERR stays on a pin here: the ESC's own ERR output knows only
/// the errors it detects itself (a watchdog expiry's double flash becomes a single flash once
/// the stack sets the error indication; `ecat_core::indicator`, "The ESC's own LED outputs").
/// A board that wires ERR to the ESC too sets
/// [`DeviceConfig::esc_err_led`](ecat_core::DeviceConfig::esc_err_led): the state-machine
/// runner then writes the ERR override after each AL status, and no indicator task runs.
pub struct ErrOnly<E>(pub E);

impl<E: OutputPin> Lamps for ErrOnly<E> {
    fn show(&mut self, levels: Levels, before: Option<Levels>) {
        if before.map(|b| b.err) != Some(levels.err) {
            let _ = self.0.set_state(PinState::from(levels.err));
        }
    }
}

/// Drives `lamps` from the AL status and code of the SubDevice `status` tells
/// ([`Control::status`](crate::Control::status)) for ever: the future never completes. Its
/// output is `()` nonetheless, so that an Embassy task can be this future itself
/// (`#[embassy_executor::task] fn leds(…) -> impl Future<Output = ()>`, which takes no `!`): an
/// `async fn` around it would keep a second copy of its arguments. Before the state-machine runner's first access it shows INIT
/// without error (both off).
///
/// Wakes at each edge of a blinking pattern (`Timer::at` the next edge, never a polling loop)
/// and at each change of the AL status or code; a steady state (INIT or OP without error)
/// sleeps until the next change.
#[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
pub fn run_indicators<'a, P: Pdi, L: Lamps + 'a>(
    status: Status<'a, P>,
    mut lamps: L,
) -> impl Future<Output = ()> + 'a {
    async move {
        let mut indicators = Indicators::new();
        let mut seen = status.indication();
        let mut shown = None;
        loop {
            let at = now();
            // Before the state-machine runner's first publication: the ESC's reset state.
            let state = seen.status().unwrap_or(AlStatus::new(AlState::Init));
            indicators.update_status(at, state, seen.code());
            let (levels, next) = indicators.at(at);
            lamps.show(levels, shown);
            shown = Some(levels);
            // One future: the next edge, or news (`seen` again at the edge).
            let mut edge = until(next);
            seen = poll_fn(move |cx| {
                if Pin::new(&mut edge).poll(cx).is_ready() {
                    return Poll::Ready(seen);
                }
                status.poll_indication(seen, cx)
            })
            .await;
        }
    }
}
