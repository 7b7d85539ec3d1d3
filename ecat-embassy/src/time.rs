//! Conversions between Embassy's clock and the core's time inputs.

use embassy_time::Timer;

use crate::or_never::OrNever;

/// The current time as the core takes it.
pub(crate) fn now() -> ecat_core::Instant {
    ecat_core::Instant::from_micros(embassy_time::Instant::now().as_micros())
}

/// The core's duration as Embassy's.
pub(crate) fn to_embassy(duration: ecat_core::Duration) -> embassy_time::Duration {
    embassy_time::Duration::from_micros(duration.as_micros())
}

/// Completes at the Embassy `deadline`, or never when there is none.
pub(crate) fn until_instant(deadline: Option<embassy_time::Instant>) -> OrNever<Timer> {
    OrNever(deadline.map(Timer::at))
}

/// Completes at `deadline`, or never when there is none.
pub(crate) fn until(deadline: Option<ecat_core::Instant>) -> OrNever<Timer> {
    until_instant(deadline.map(|at| embassy_time::Instant::from_micros(at.as_micros())))
}
