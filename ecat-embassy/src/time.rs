//! Conversions between Embassy's clock and the core's time inputs.

use embassy_time::Timer;

/// The current time as the core takes it.
pub(crate) fn now() -> ecat_core::Instant {
    ecat_core::Instant::from_micros(embassy_time::Instant::now().as_micros())
}

/// Completes at `deadline`, or never when there is none.
pub(crate) async fn until(deadline: Option<ecat_core::Instant>) {
    match deadline {
        Some(at) => Timer::at(embassy_time::Instant::from_micros(at.as_micros())).await,
        None => core::future::pending().await,
    }
}
