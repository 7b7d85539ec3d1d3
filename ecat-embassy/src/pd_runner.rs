//! The process-data runner: owns the IRQ line, exchanges the process image. Runs in an
//! `InterruptExecutor` at a priority above the thread executor.

use ecat_core::AlEvent;
use ecat_core::process_data::Layout;
use embassy_futures::select::{Either, select};
use embassy_sync::blocking_mutex::raw::RawMutex;
use embedded_hal_async::digital::Wait;

use crate::shared::Runner;
use crate::{CycleHandler, Pdi, SharedEsc};

/// Why the process-data runner stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error<P, I> {
    /// The PDI failed.
    Pdi(P),
    /// Waiting on the IRQ pin failed.
    Irq(I),
    /// The MainDevice configured a process image larger than the buffers given to the runner.
    BufferTooSmall,
}

/// The buffers the process image passes through, sized for the device's images.
pub struct Buffers<'b> {
    /// Receives the output image (SM2).
    pub outputs: &'b mut [u8],
    /// Holds the input image (SM3).
    pub inputs: &'b mut [u8],
}

/// Runs the process-data exchange of `esc` until something fails.
///
/// `irq` is the ESC's IRQ pin (active low, e.g. an `ExtiInput`). In SAFEOP and OP each trigger
/// (SM2 written by the MainDevice, or SM3 read by it for an input-only device) costs one read of
/// the output area — which brings the AL event along — and one write of the input area.
pub async fn run_process_data<M: RawMutex, P: Pdi, I: Wait, C: CycleHandler>(
    esc: &SharedEsc<M, P>,
    irq: &mut I,
    app: &mut C,
    mut buffers: Buffers<'_>,
) -> Error<P::Error, I::Error> {
    let mut current: Option<Layout> = None;
    loop {
        let seen = esc.pd_generation();
        let layout = esc.layout();
        let step = if layout != current {
            current = layout;
            on_new_layout(esc, app, &mut buffers, layout).await
        } else if !esc.take_pd_events().is_empty() {
            on_trigger(esc, app, &mut buffers, layout, true).await
        } else if !esc.esm_started() || esc.esm_holds_irq() {
            esc.pd_news_since(seen).await;
            Ok(())
        } else {
            match select(irq.wait_for_low(), esc.pd_news_since(seen)).await {
                Either::First(Ok(())) => on_trigger(esc, app, &mut buffers, layout, false).await,
                Either::First(Err(e)) => Err(Error::Irq(e)),
                Either::Second(()) => Ok(()),
            }
        };
        if let Err(e) = step {
            return e;
        }
    }
}

/// Entering SAFEOP (or a new layout): present valid inputs at once.
async fn on_new_layout<M: RawMutex, P: Pdi, I, C: CycleHandler>(
    esc: &SharedEsc<M, P>,
    app: &mut C,
    buffers: &mut Buffers<'_>,
    layout: Option<Layout>,
) -> Result<(), Error<P::Error, I>> {
    match layout {
        Some(layout) => cycle(esc, app, buffers.inputs, layout, None).await,
        None => Ok(()),
    }
}

/// The IRQ fired (`known` = false) or the other runner saw the trigger (`known` = true).
async fn on_trigger<M: RawMutex, P: Pdi, I, C: CycleHandler>(
    esc: &SharedEsc<M, P>,
    app: &mut C,
    buffers: &mut Buffers<'_>,
    layout: Option<Layout>,
    known: bool,
) -> Result<(), Error<P::Error, I>> {
    let Some(layout) = layout else {
        // Not exchanging process data: the IRQ is for the state machine; reading the AL event
        // routes it there.
        esc.read_al_event(Runner::ProcessData)
            .await
            .map_err(Error::Pdi)?;
        return Ok(());
    };
    let (event, outputs) = match layout.outputs {
        Some(area) => {
            let buf = buffers
                .outputs
                .get_mut(..usize::from(area.length))
                .ok_or(Error::BufferTooSmall)?;
            let event = esc
                .read(Runner::ProcessData, area.start, buf, AlEvent::NONE)
                .await
                .map_err(Error::Pdi)?;
            (event, layout.outputs_active.then_some(&*buf))
        }
        None => {
            let event = esc
                .read_al_event(Runner::ProcessData)
                .await
                .map_err(Error::Pdi)?;
            (event, None)
        }
    };
    let triggered = known || event.intersects(layout.trigger) || !esc.take_pd_events().is_empty();
    if !triggered {
        return Ok(());
    }
    cycle(esc, app, buffers.inputs, layout, outputs).await
}

/// Runs the application cycle and writes the input image.
async fn cycle<M: RawMutex, P: Pdi, I, C: CycleHandler>(
    esc: &SharedEsc<M, P>,
    app: &mut C,
    inputs: &mut [u8],
    layout: Layout,
    outputs: Option<&[u8]>,
) -> Result<(), Error<P::Error, I>> {
    let Some(area) = layout.inputs else {
        app.cycle(outputs, &mut []);
        return Ok(());
    };
    let buf = inputs
        .get_mut(..usize::from(area.length))
        .ok_or(Error::BufferTooSmall)?;
    app.cycle(outputs, buf);
    esc.write(Runner::ProcessData, area.start, buf)
        .await
        .map_err(Error::Pdi)?;
    Ok(())
}
