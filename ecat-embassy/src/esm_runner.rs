//! The state-machine runner: AL control, SyncManager checks, application hooks. Runs in the
//! low-priority (thread) executor; the mailbox joins it later.

use core::pin::pin;

use ecat_core::{Event, SubDevice, Transition};
use embassy_futures::select::{Either3, select, select3};
use embassy_sync::blocking_mutex::raw::RawMutex;

use crate::shared::Runner;
use crate::time::{now, until};
use crate::{Application, Pdi, SharedEsc};

/// Runs the state machine of `sub` on `esc` until the PDI fails; returns the PDI error.
///
/// Woken only by AL events the process-data runner routes to it and by the core's deadlines;
/// never polls the ESC.
pub async fn run_esm<M: RawMutex, P: Pdi, A: Application>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_>,
    app: &mut A,
) -> P::Error {
    match drive(esc, sub, app).await {
        Ok(never) => match never {},
        Err(e) => e,
    }
}

async fn drive<M: RawMutex, P: Pdi, A: Application>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_>,
    app: &mut A,
) -> Result<core::convert::Infallible, P::Error> {
    loop {
        sync(esc, sub).await?;
        while let Some(event) = sub.poll_event() {
            match event {
                Event::TransitionRequested(t) => answer(esc, sub, app, t).await?,
                Event::StateChanged(t) => app.on_state_change(t),
                Event::TransitionAborted(_) => {}
            }
            sync(esc, sub).await?;
        }
        match select(esc.esm_events(), until(sub.poll_timeout())).await {
            embassy_futures::select::Either::First(event) => sub.handle_al_event(event),
            embassy_futures::select::Either::Second(()) => sub.handle_timeout(now()),
        }
    }
}

/// Performs every register access the core asks for, then publishes the process-data layout.
async fn sync<M: RawMutex, P: Pdi>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_>,
) -> Result<(), P::Error> {
    while let Some(access) = sub.poll_access() {
        let clears = access.clears();
        let event = match access {
            ecat_core::Access::Read { address, buf } => {
                esc.read(Runner::Esm, address, buf, clears).await?
            }
            ecat_core::Access::Write { address, data } => {
                esc.write(Runner::Esm, address, data).await?
            }
        };
        sub.access_done(now(), event);
        esc.publish_layout(sub.process_data());
    }
    Ok(())
}

/// Asks the application about `t` while still serving AL events: a new request from the
/// MainDevice or the deadline ends the wait and drops the application's future.
async fn answer<M: RawMutex, P: Pdi, A: Application>(
    esc: &SharedEsc<M, P>,
    sub: &mut SubDevice<'_>,
    app: &mut A,
    t: Transition,
) -> Result<(), P::Error> {
    let mut decision = pin!(app.on_transition(t));
    while sub.pending_transition() == Some(t) {
        match select3(&mut decision, until(sub.poll_timeout()), esc.esm_events()).await {
            Either3::First(result) => sub.complete_transition(t, result),
            Either3::Second(()) => sub.handle_timeout(now()),
            Either3::Third(event) => {
                sub.handle_al_event(event);
                sync(esc, sub).await?;
            }
        }
    }
    Ok(())
}
