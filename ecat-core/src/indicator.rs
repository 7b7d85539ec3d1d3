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
//! An ESC with a RUN LED output (ET1100/ET1200, LAN9252, AX58100) drives it from its AL status
//! register by itself, with the RUN patterns above; the firmware then needs no RUN pin and
//! writes nothing for it: the stack writes only valid states into 0x0130, so the ESC always
//! knows the state RUN shows. The override registers (0x0138 RUN, 0x0139 ERR; both ports may
//! write them) take an LED code ([`LedCode`], [`Pattern::led_code`]) with bit 4
//! ([`LED_OVERRIDE`]) set; the next ESM state change (a new valid state in 0x0130) ends RUN's
//! override, e.g. a MainDevice's "device identification" flashes. An ESC that drives ERR shows
//! only the errors it detects itself (a single flash for the error indication 0x0130 bit 4, a
//! double flash for a process-data watchdog timeout in OP): the error classes above need the
//! ERR override, the byte [`Pattern::override_register`] gives (what SSC's `SetALStatus` writes
//! with `ESC_SUPPORT_ECAT_LED`).

//! ## Sources
//!
//! The ETG.1300 text itself is for ETG members; what is implemented here was checked against
//! public material that reproduces it: the timings and the RUN/ERR meanings in device manuals
//! (Bronkhorst's EtherCAT manual: blinking 200/200 ms, single flash 200/1000 ms, double flash
//! 200/200/200/1000 ms; Novanta's drive manual: flickering 50/50 ms; Stöber's: the RUN and ERR
//! meanings), the ESC's own ERR LED
//! states in Beckhoff's "EtherCAT Slave Controller Technology" (Section I, ERR LED: double flash
//! for a process-data watchdog timeout in OP, single flash for the error indication set
//! locally; RUN: the AL status's patterns, "the RUN LED override is disabled automatically by
//! a following ESM state change"), the LED override registers 0x0138/0x0139 in the ESC
//! register descriptions (Section II), and the code classes in SSC's `SetALStatus`. The
//! timeline of 3 to 12 flashes (200 ms apart, the 1000 ms pause after the last) extends the
//! single and double flash as ETG.1300 counts them. Two choices are this crate's, not
//! found in those sources: a changed pattern restarts with its on phase, and the bicolour LED
//! shows red whenever ERR is on (CiA 303-3's rule for its combined LED).

use crate::al::{AlState, AlStatus, AlStatusCode};
use crate::time::{Duration, Instant};

/// An indicator's blink pattern (ETG.1300); its value is its LED code ([`Pattern::led_code`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum Pattern {
    /// Constantly off.
    #[default]
    Off = 0x0,
    /// Constantly on.
    On = 0xF,
    /// On 50 ms, off 50 ms.
    Flickering = 0xE,
    /// On 200 ms, off 200 ms.
    Blinking = 0xD,
    /// On 200 ms, off 1000 ms.
    SingleFlash = 0x1,
    /// On 200 ms, off 200 ms, on 200 ms, off 1000 ms.
    DoubleFlash = 0x2,
}

/// Bit 4 of the LED override registers 0x0138/0x0139: the code in bits 3:0 drives the LED
/// instead of the ESC's own logic (ETG.1000.4, RUN/ERR LED override).
pub const LED_OVERRIDE: u8 = 0x10;

impl Pattern {
    /// The level `elapsed` after the pattern started, and how long it keeps it (`None`: for
    /// ever). Phases are half-open: at an edge the level is already the new one.
    pub fn level_at(self, elapsed: Duration) -> (bool, Option<Duration>) {
        self.code().level_at(elapsed)
    }

    /// The pattern's LED code.
    pub const fn code(self) -> LedCode {
        LedCode(self.led_code())
    }

    /// The pattern `code` shows; [`Pattern::Off`] for the flash counts no pattern has (3 to 12).
    pub const fn of(code: LedCode) -> Self {
        match code.0 {
            0x1 => Self::SingleFlash,
            0x2 => Self::DoubleFlash,
            0xD => Self::Blinking,
            0xE => Self::Flickering,
            0xF => Self::On,
            _ => Self::Off,
        }
    }

    /// The LED code of the ESC's LED override registers (0x0138 RUN, 0x0139 ERR, bits 3:0):
    /// 0x0 off, 0x1..=0xC that many flashes, 0xD blinking, 0xE flickering, 0xF on.
    pub const fn led_code(self) -> u8 {
        self as u8
    }

    /// The byte to write into an LED override register so that the ESC shows this pattern.
    pub const fn override_register(self) -> u8 {
        LED_OVERRIDE | self.led_code()
    }
}

/// A code of the ESC's LED outputs (the LED code of the override registers 0x0138/0x0139, bits
/// 3:0), and its timeline: 0x0 off, 0x1..=0xC that many flashes (each on 200 ms, off 200 ms
/// between two of them, off 1000 ms after the last: ETG.1300's single and double flash are 0x1
/// and 0x2), 0xD blinking, 0xE flickering, 0xF on. The [`Pattern`]s are its codes 0x0, 0x1,
/// 0x2, 0xD, 0xE and 0xF; an ESC's own RUN and ERR outputs show any code
/// (`ecat_esc`, the emulated ESC, runs its outputs on this).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct LedCode(u8);

impl LedCode {
    /// Off.
    pub const OFF: Self = Self(0x0);
    /// On.
    pub const ON: Self = Self(0xF);

    /// The code in bits 3:0 of an override register's value (the enable bit and the reserved
    /// bits are not part of it).
    pub const fn from_register(value: u8) -> Self {
        Self(value & 0x0F)
    }

    /// The code, 0x0..=0xF.
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// The level `elapsed` after the code started, and how long it keeps it (`None`: for
    /// ever). Phases are half-open: at an edge the level is already the new one.
    pub fn level_at(self, elapsed: Duration) -> (bool, Option<Duration>) {
        let (level, left) = self.phase(elapsed.as_micros());
        (
            level,
            (left != NEVER).then_some(Duration::from_micros(left)),
        )
    }

    /// [`LedCode::level_at`] in microseconds, [`NEVER`] for ever: the LED task compares and
    /// adds plain numbers.
    fn phase(self, elapsed: u64) -> (bool, u64) {
        let (slot, slots, bits) = match self.0 {
            0x0 => return (false, NEVER),
            0xF => return (true, NEVER),
            _ => self.slots(),
        };
        // At most 5.6 s: microseconds fit 32 bits (the Cortex-M4 divides those in hardware).
        let at = remainder(elapsed, slot * slots);
        // `checked_div`: no division-by-zero panic path, `slot` is never 0.
        let index = at.checked_div(slot).unwrap_or(0);
        let ahead = bits.wrapping_shr(index);
        let level = ahead & 1 != 0;
        // The slots left with this level: every timeline starts on and ends off, so a run of
        // either level ends within the period, or (dark) at its end.
        let run = if level {
            (!ahead).trailing_zeros()
        } else {
            ahead.trailing_zeros().min(slots - index)
        };
        (level, u64::from((index + run) * slot - at))
    }

    /// A blinking code's timeline (not 0x0, not 0xF) as a row of equal slots: the slot's length
    /// in microseconds, the slots in a period, and the levels (bit `i`: lit in slot `i`). Every
    /// ETG.1300 phase is 50 ms or a multiple of 200 ms: flickering is on, off in 50 ms slots,
    /// blinking the same in 200 ms slots, `n` flashes are on, off `n` times less the last off,
    /// then 5 slots (1000 ms) off.
    const fn slots(self) -> (u32, u32, u32) {
        match self.0 {
            0xE => (50_000, 2, 0b1),
            0xD => (200_000, 2, 0b1),
            // 1..=12: the even slots below slot `2 n - 1`.
            n => (
                200_000,
                2 * n as u32 + 4,
                0x5555_5555 >> (32 - 2 * n as u32),
            ),
        }
    }
}

/// `x % m` for `0 < m < 2^24`, a byte at a time in 32 bits (`r < m`, so `r << 8 | byte` fits):
/// a 64-bit `%` would pull the 64-bit division routine (about 0.9 KB on a Cortex-M4, which
/// divides 32 bits in hardware) into a firmware that has none otherwise, and 64-bit shifts
/// their own routines. `m` is 0 never (`checked_rem`: no panic path).
fn remainder(x: u64, m: u32) -> u32 {
    x.to_be_bytes().iter().fold(0, |r: u32, &byte| {
        (r << 8 | u32::from(byte)).checked_rem(m).unwrap_or(0)
    })
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

/// One LED output on the caller's clock: the code it shows and when that code started. The
/// firmware's indicators ([`Indicators`]) and the emulated ESC's own LED outputs (`ecat_esc`)
/// run their LEDs on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
// 12 bytes, not 16: the instant is read whole (never borrowed), and 32-bit targets load it
// from any word (the two in an LED task's state: docs/size-history.md, "Session 10: the
// indicators' code").
#[repr(C, packed(4))]
pub struct LedOutput {
    code: LedCode,
    since: Instant,
}

impl Default for LedOutput {
    fn default() -> Self {
        Self::new()
    }
}

impl LedOutput {
    /// Off since 0.
    pub const fn new() -> Self {
        Self {
            code: LedCode::OFF,
            since: Instant::from_micros(0),
        }
    }

    /// Shows `code` from `now` on, unless it is the code shown already (which keeps its
    /// phase).
    pub fn show(&mut self, now: Instant, code: LedCode) {
        if code != self.code {
            *self = Self { code, since: now };
        }
    }

    /// The code shown.
    pub const fn code(&self) -> LedCode {
        self.code
    }

    fn elapsed(&self, now: Instant) -> Duration {
        Duration::from_micros(now.as_micros().saturating_sub(self.since.as_micros()))
    }

    /// The level at `now` (not before the code started).
    pub fn level(&self, now: Instant) -> bool {
        self.at(now).0
    }

    /// The first instant after `now` at which the level changes; `None` while it is steady (an
    /// edge at the end of time, `u64::MAX` µs, counts as none).
    pub fn next_edge(&self, now: Instant) -> Option<Instant> {
        self.at(now).1
    }

    /// [`LedOutput::level`] and [`LedOutput::next_edge`] at once: one look at the timeline.
    pub fn at(&self, now: Instant) -> (bool, Option<Instant>) {
        let (level, edge) = self.edge(now);
        (level, instant(edge))
    }

    /// [`LedOutput::at`] in microseconds, [`NEVER`] while the level is steady.
    fn edge(&self, now: Instant) -> (bool, u64) {
        let (level, left) = self.code.phase(self.elapsed(now).as_micros());
        let since = self.since;
        // Before the code started (a `now` from the past) the code's start is the edge.
        let edge = if now < since {
            since.as_micros()
        } else {
            now.as_micros().saturating_add(left)
        };
        (level, edge)
    }
}

/// No edge: the level is steady (in microseconds, as an instant the end of time, which no
/// clock reaches).
const NEVER: u64 = u64::MAX;

/// An edge's instant in microseconds as an instant, `None` for [`NEVER`].
fn instant(micros: u64) -> Option<Instant> {
    (micros != NEVER).then_some(Instant::from_micros(micros))
}

/// The RUN and ERR indicators of one SubDevice.
///
/// Feed it the AL status whenever it may have changed ([`Indicators::update`] or
/// [`Indicators::update_status`]), read the levels at any instant ([`Indicators::levels`]) and
/// sleep until [`Indicators::poll_at`], the next edge: no polling loop ([`Indicators::at`]: both
/// at once).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Indicators {
    run: LedOutput,
    err: LedOutput,
    /// ERR's pattern from the AL status and code ([`err_pattern`]).
    al_error: Pattern,
    /// ERR's pattern for the application's fault, which outranks `al_error`.
    fault: Option<Pattern>,
}

impl Default for Indicators {
    fn default() -> Self {
        Self::new()
    }
}

impl Indicators {
    /// INIT without error: both off. `const`, so it can live in a `static`.
    pub const fn new() -> Self {
        Self {
            run: LedOutput::new(),
            err: LedOutput::new(),
            al_error: Pattern::Off,
            fault: None,
        }
    }

    /// The SubDevice is in `state`, with `error` the AL status code when the error indication
    /// is set (`None` when it is clear). An indicator whose pattern changes restarts it at
    /// `now`.
    pub fn update(&mut self, now: Instant, state: AlState, error: Option<AlStatusCode>) {
        self.run.show(now, run_pattern(state).code());
        self.al_error = err_pattern(error);
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
        self.fault = fault.map(|fault| match fault {
            Fault::Booting => Pattern::Flickering,
            Fault::ApplicationController => Pattern::On,
        });
        self.refresh_err(now);
    }

    fn refresh_err(&mut self, now: Instant) {
        self.err
            .show(now, self.fault.unwrap_or(self.al_error).code());
    }

    /// RUN's current pattern.
    pub fn run(&self) -> Pattern {
        Pattern::of(self.run.code())
    }

    /// ERR's current pattern.
    pub fn err(&self) -> Pattern {
        Pattern::of(self.err.code())
    }

    /// The levels at `now` (not before the last update).
    pub fn levels(&self, now: Instant) -> Levels {
        self.at(now).0
    }

    /// The first instant after `now` at which either level changes; `None` while both are
    /// steady.
    #[must_use]
    pub fn poll_at(&self, now: Instant) -> Option<Instant> {
        self.at(now).1
    }

    /// [`Indicators::levels`] and [`Indicators::poll_at`] at once, each timeline looked at
    /// once: what an LED task computes at each wake-up.
    #[must_use]
    pub fn at(&self, now: Instant) -> (Levels, Option<Instant>) {
        let (run, run_edge) = self.run.edge(now);
        let (err, err_edge) = self.err.edge(now);
        (Levels { run, err }, instant(run_edge.min(err_edge)))
    }
}

#[cfg(test)]
mod tests {
    use super::{LedCode, remainder};
    use crate::time::Duration;

    /// A code's level and time to its next edge (µs) from its phases in milliseconds (on, off
    /// between flashes, off after the last, flashes), as ETG.1300 states them.
    fn by_phases(code: u8, elapsed: u64) -> (bool, Option<u64>) {
        let (on, off, last_off, flashes) = match code {
            0x0 => return (false, None),
            0xF => return (true, None),
            0xE => (50, 50, 50, 1),
            0xD => (200, 200, 200, 1),
            n => (200, 200, 1000, u64::from(n)),
        };
        let (on, step, last) = (on * 1_000, (on + off) * 1_000, (on + last_off) * 1_000);
        let at = elapsed % (step * (flashes - 1) + last);
        let flash = (at / step).min(flashes - 1);
        let within = at - flash * step;
        if within < on {
            (true, Some(on - within))
        } else if flash + 1 == flashes {
            (false, Some(last - within))
        } else {
            (false, Some(step - within))
        }
    }

    #[test]
    fn every_code_matches_its_phases() {
        for code in 0..=0xF {
            // Every microsecond around each 50 ms boundary of 12 s (two periods of the longest
            // code), and far out.
            let boundaries = (0..240u64)
                .map(|i| i * 50_000)
                .chain([1 << 40, u64::MAX - 60_000]);
            for base in boundaries {
                for elapsed in base..base + 3 {
                    let elapsed = elapsed.saturating_sub(1);
                    let (level, left) = LedCode(code).level_at(Duration::from_micros(elapsed));
                    assert_eq!(
                        (level, left.map(Duration::as_micros)),
                        by_phases(code, elapsed),
                        "code {code:#x} at {elapsed} µs"
                    );
                }
            }
        }
    }

    #[test]
    fn remainder_is_the_remainder() {
        let moduli = [1, 3, 100_000, 400_000, 1_200_000, 5_600_000, (1 << 24) - 1];
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
                assert_eq!(u64::from(remainder(x, m)), x % u64::from(m), "{x} % {m}");
            }
        }
    }
}
