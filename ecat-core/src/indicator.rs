//! The RUN and ERR indicators of ETG.1300 (EtherCAT Indicator and Labeling Specification), sans-IO:
//! the AL state and error in, the LED levels and the instant of the next edge out.
//!
//! ## Patterns (ETG.1300, the indicator states it shares with CiA 303-3)
//!
//! | pattern | timeline, repeated |
//! |---|---|
//! | [`Pattern::Off`] | off |
//! | [`Pattern::On`] | on |
//! | [`Pattern::Flickering`] | on 50 ms, off 50 ms (10 Hz) |
//! | [`Pattern::Blinking`] | on 200 ms, off 200 ms (2.5 Hz) |
//! | [`Pattern::SingleFlash`] | on 200 ms, off 1000 ms |
//! | [`Pattern::DoubleFlash`] | on 200 ms, off 200 ms, on 200 ms, off 1000 ms |
//!
//! A pattern starts with its first on phase at the instant it is set; an indicator whose pattern
//! does not change keeps its phase. So a new state is visible at once (a SAFEOP single flash
//! starts with its flash, not with up to a second of darkness), and RUN and ERR run independently.
//!
//! ## RUN (ETG.1300, the EtherCAT state)
//!
//! INIT off, PREOP blinking, SAFEOP single flash, OP on, BOOT flickering ([`run_pattern`]).
//!
//! ## ERR (ETG.1300, the error state)
//!
//! With the AL status error indication (0x0130 bit 4) clear, ERR is off. With it set, the AL
//! status code decides ([`err_pattern`]), as the EtherCAT Slave Stack Code (ET9300,
//! `SetALStatus` in `ecatslv.c`) maps it:
//!
//! | ERR | ETG.1300 meaning | AL status codes |
//! |---|---|---|
//! | single flash | local error: the device changed its state on its own | 0x001A synchronisation error, 0x002C fatal sync error, 0x002D no sync, 0x0032 PLL error, 0x0033 DC sync IO error, 0x0034 DC sync timeout |
//! | double flash | process-data (SyncManager) watchdog timeout | 0x001B |
//! | blinking | invalid configuration: a state change the MainDevice asked for is impossible with the register or object settings | every other code |
//!
//! SSC maps 0x001A, 0x002D and 0x0032 to the single flash; 0x002C, 0x0033 and 0x0034 are added
//! here because this stack only reports them when it left OP on its own (SYNC0 lost) or when the
//! distributed clock failed locally. The two remaining ERR states do not come from an AL status
//! code: flickering (booting error) and on (application controller failure, e.g. the PDI
//! watchdog) are what the application reports with [`Indicators::set_fault`].
//!
//! ## One bicolour LED (ETG.1300)
//!
//! A device with one red/green LED shows both indicators on it ([`Levels::bicolour`]): red where
//! ERR is on, green where RUN is on and ERR is off, dark otherwise: the error wins a conflict,
//! as CiA 303-3 (the source of ETG.1300's indicator rules) has its combined status LED do.
//!
//! ## The ESC's own LED outputs (ETG.1000.4 registers 0x0138/0x0139)
//!
//! An ESC with RUN/ERR LED pins drives RUN from the AL status register itself; the firmware then
//! needs no RUN pin. The override registers take a code ([`Pattern::led_code`]) with bit 4
//! ([`LED_OVERRIDE`]) set; a write of the AL status clears RUN's override enable.
//! [`Pattern::override_register`] gives the byte to write.

//!
//! ## Sources
//!
//! The ETG.1300 text itself is for ETG members; what is implemented here was checked against
//! public material that reproduces it: the timings and the RUN/ERR meanings in device manuals
//! (Bronkhorst's EtherCAT manual: blinking 200/200 ms, single flash 200/1000 ms, double flash
//! 200/200/200/1000 ms; Novanta's drive manual: flickering 50/50 ms; Stöber's: the RUN and ERR
//! meanings), the ESC's own ERR LED
//! states in Beckhoff's "EtherCAT Slave Controller Technology" (Section I, ERR LED: double flash
//! for a process-data watchdog timeout in OP, single flash for the error indication set
//! locally), the LED override registers 0x0138/0x0139 in the ESC register descriptions
//! (Section II), and the code classes in SSC's `SetALStatus`. Two choices are this crate's, not
//! found in those sources: a changed pattern restarts with its on phase, and the bicolour LED
//! shows red whenever ERR is on (CiA 303-3's rule for its combined LED).

use crate::al::{AlState, AlStatus, AlStatusCode};
use crate::time::{Duration, Instant};

/// An indicator's blink pattern (ETG.1300).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Pattern {
    /// Constantly off.
    #[default]
    Off,
    /// Constantly on.
    On,
    /// On 50 ms, off 50 ms.
    Flickering,
    /// On 200 ms, off 200 ms.
    Blinking,
    /// On 200 ms, off 1000 ms.
    SingleFlash,
    /// On 200 ms, off 200 ms, on 200 ms, off 1000 ms.
    DoubleFlash,
}

/// Bit 4 of the LED override registers 0x0138/0x0139: the code in bits 3:0 drives the LED
/// instead of the ESC's own logic (ETG.1000.4, RUN/ERR LED override).
pub const LED_OVERRIDE: u8 = 0x10;

impl Pattern {
    /// The phases in milliseconds: on, off, on, off (a second flash only in the double flash;
    /// all 0 for a steady pattern).
    const fn phases(self) -> [u32; 4] {
        match self {
            Self::Off | Self::On => [0; 4],
            Self::Flickering => [50, 50, 0, 0],
            Self::Blinking => [200, 200, 0, 0],
            Self::SingleFlash => [200, 1000, 0, 0],
            Self::DoubleFlash => [200, 200, 200, 1000],
        }
    }

    /// The level `elapsed` after the pattern started, and how long it keeps it (`None`: for
    /// ever). Phases are half-open: at an edge the level is already the new one.
    pub fn level_at(self, elapsed: Duration) -> (bool, Option<Duration>) {
        let phases = self.phases();
        let [a, b, c, d] = phases;
        // At most 1.6 s: microseconds fit 32 bits (the Cortex-M4 divides those in hardware).
        let period = (a + b + c + d) * 1_000;
        if period == 0 {
            return (self == Self::On, None);
        }
        let at = remainder(elapsed.as_micros(), u64::from(period)) as u32;
        let mut end = 0;
        let mut on = true;
        for phase in phases {
            end += phase * 1_000;
            if at < end {
                return (on, Some(Duration::from_micros(u64::from(end - at))));
            }
            on = !on;
        }
        // Not reached: `at` is below the period, the last `end`.
        (false, None)
    }

    /// The LED code of the ESC's LED override registers (0x0138 RUN, 0x0139 ERR, bits 3:0):
    /// 0x0 off, 0x1..=0xC that many flashes, 0xD blinking, 0xE flickering, 0xF on.
    pub const fn led_code(self) -> u8 {
        match self {
            Self::Off => 0x0,
            Self::SingleFlash => 0x1,
            Self::DoubleFlash => 0x2,
            Self::Blinking => 0xD,
            Self::Flickering => 0xE,
            Self::On => 0xF,
        }
    }

    /// The byte to write into an LED override register so that the ESC shows this pattern.
    pub const fn override_register(self) -> u8 {
        LED_OVERRIDE | self.led_code()
    }
}

/// `x % m` for `m > 0` by shifts and subtractions (at most 64 steps): a 64-bit `%` would pull
/// the 64-bit division routine (about 0.9 KB on a Cortex-M4, which divides 32 bits in hardware)
/// into a firmware that has none otherwise.
fn remainder(mut x: u64, m: u64) -> u64 {
    if m == 0 || x < m {
        return x;
    }
    // `x >= m > 0`, so `m`'s highest bit is at or below `x`'s: the shift keeps every bit of `m`.
    let shift = m.leading_zeros() - x.leading_zeros();
    let mut d = m << shift;
    for _ in 0..=shift {
        if x >= d {
            x -= d;
        }
        d >>= 1;
    }
    x
}

/// RUN for an AL state (ETG.1300).
pub const fn run_pattern(state: AlState) -> Pattern {
    match state {
        AlState::Init => Pattern::Off,
        AlState::PreOp => Pattern::Blinking,
        AlState::SafeOp => Pattern::SingleFlash,
        AlState::Op => Pattern::On,
        AlState::Boot => Pattern::Flickering,
    }
}

/// ERR for the AL status code shown with the error indication set, `None` when it is clear
/// (ETG.1300; the code classes as SSC's `SetALStatus` draws them, see the module docs).
pub const fn err_pattern(error: Option<AlStatusCode>) -> Pattern {
    match error {
        None => Pattern::Off,
        Some(code) => match code.0 {
            0x001A | 0x002C | 0x002D | 0x0032 | 0x0033 | 0x0034 => Pattern::SingleFlash,
            0x001B => Pattern::DoubleFlash,
            _ => Pattern::Blinking,
        },
    }
}

/// An error the AL status code does not tell, which the application reports (ETG.1300).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Fault {
    /// Booting error (e.g. a firmware checksum error): ERR flickers.
    Booting,
    /// Application controller failure (e.g. the PDI watchdog expired): ERR is on.
    ApplicationController,
}

/// The levels of the two indicators at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Levels {
    /// The green RUN indicator is lit.
    pub run: bool,
    /// The red ERR indicator is lit.
    pub err: bool,
}

/// What one red/green LED shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Colour {
    /// Dark.
    Off,
    /// Green: RUN.
    Green,
    /// Red: ERR.
    Red,
}

impl Levels {
    /// Both indicators on one bicolour LED: ERR wins (ETG.1300, see the module docs).
    pub const fn bicolour(self) -> Colour {
        if self.err {
            Colour::Red
        } else if self.run {
            Colour::Green
        } else {
            Colour::Off
        }
    }
}

/// One indicator: its pattern and when the pattern started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Indicator {
    pattern: Pattern,
    since: Instant,
}

impl Indicator {
    /// Starts `pattern` at `now`, unless it is the pattern already running (which keeps its
    /// phase).
    fn set(&mut self, now: Instant, pattern: Pattern) {
        if pattern != self.pattern {
            *self = Self {
                pattern,
                since: now,
            };
        }
    }

    fn elapsed(&self, now: Instant) -> Duration {
        Duration::from_micros(now.as_micros().saturating_sub(self.since.as_micros()))
    }

    fn level(&self, now: Instant) -> bool {
        self.pattern.level_at(self.elapsed(now)).0
    }

    /// The first instant after `now` at which the level changes.
    fn next_edge(&self, now: Instant) -> Option<Instant> {
        // Before the pattern started (a `now` from the past) the pattern's start is the edge.
        if now < self.since {
            return Some(self.since);
        }
        let (_, left) = self.pattern.level_at(self.elapsed(now));
        left.map(|left| now.saturating_add(left))
    }
}

/// The RUN and ERR indicators of one SubDevice.
///
/// Feed it the AL status whenever it may have changed ([`Indicators::update`] or
/// [`Indicators::update_status`]), read the levels at any instant ([`Indicators::levels`]) and
/// sleep until [`Indicators::poll_at`], the next edge: no polling loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Indicators {
    run: Indicator,
    err: Indicator,
    error: Option<AlStatusCode>,
    fault: Option<Fault>,
}

impl Default for Indicators {
    fn default() -> Self {
        Self::new()
    }
}

impl Indicators {
    /// INIT without error: both off. `const`, so it can live in a `static`.
    pub const fn new() -> Self {
        let off = Indicator {
            pattern: Pattern::Off,
            since: Instant::from_micros(0),
        };
        Self {
            run: off,
            err: off,
            error: None,
            fault: None,
        }
    }

    /// The SubDevice is in `state`, with `error` the AL status code when the error indication
    /// is set (`None` when it is clear). An indicator whose pattern changes restarts it at
    /// `now`.
    pub fn update(&mut self, now: Instant, state: AlState, error: Option<AlStatusCode>) {
        self.run.set(now, run_pattern(state));
        self.error = error;
        self.refresh_err(now);
    }

    /// [`Indicators::update`] from the AL status and AL status code registers' values (the
    /// code counts only with the error indication set: otherwise it may be the device ID).
    pub fn update_status(&mut self, now: Instant, status: AlStatus, code: AlStatusCode) {
        self.update(now, status.state, status.error.then_some(code));
    }

    /// Reports an error no AL status code tells (`None`: it went away). It takes precedence
    /// over the AL status code on ERR.
    pub fn set_fault(&mut self, now: Instant, fault: Option<Fault>) {
        self.fault = fault;
        self.refresh_err(now);
    }

    fn refresh_err(&mut self, now: Instant) {
        let pattern = match self.fault {
            Some(Fault::Booting) => Pattern::Flickering,
            Some(Fault::ApplicationController) => Pattern::On,
            None => err_pattern(self.error),
        };
        self.err.set(now, pattern);
    }

    /// RUN's current pattern.
    pub fn run(&self) -> Pattern {
        self.run.pattern
    }

    /// ERR's current pattern.
    pub fn err(&self) -> Pattern {
        self.err.pattern
    }

    /// The levels at `now` (not before the last update).
    pub fn levels(&self, now: Instant) -> Levels {
        Levels {
            run: self.run.level(now),
            err: self.err.level(now),
        }
    }

    /// The first instant after `now` at which either level changes; `None` while both are
    /// steady.
    #[must_use]
    pub fn poll_at(&self, now: Instant) -> Option<Instant> {
        match (self.run.next_edge(now), self.err.next_edge(now)) {
            (Some(a), Some(b)) => Some(if a < b { a } else { b }),
            (a, b) => a.or(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::remainder;

    #[test]
    fn remainder_is_the_remainder() {
        let moduli = [
            1,
            3,
            100_000,
            400_000,
            1_200_000,
            1_600_000,
            u64::from(u32::MAX),
            u64::MAX,
        ];
        let values = [
            0,
            1,
            99_999,
            100_000,
            1_599_999,
            1_600_001,
            1 << 40,
            u64::MAX - 1,
            u64::MAX,
        ];
        for m in moduli {
            for x in values {
                assert_eq!(remainder(x, m), x % m, "{x} % {m}");
            }
        }
        assert_eq!(remainder(7, 0), 7);
    }
}
