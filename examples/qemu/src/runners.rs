//! The glue to ecat-embassy's entry point: the resources in one `StaticCell`, split into the
//! two runners, each in its executor.

use ecat_embassy::{ProcessDataRunner, Resources};
use embassy_executor::SendSpawner;
use static_cell::StaticCell;

use crate::app::{App, DEVICE, IMAGE, Od};
use crate::esc::{IrqPin, ModelPdi};

type Ecat = Resources<ModelPdi, App, Od, IMAGE, IMAGE>;
static ECAT: StaticCell<Ecat> = StaticCell::new();

/// The thread executor's task: starts the process-data runner in the interrupt executor, then
/// runs the state machine and the mailbox.
#[embassy_executor::task]
pub async fn state_machine(high: SendSpawner) {
    let ecat = ECAT.init_with(|| Ecat::new(&DEVICE, ModelPdi::new(), App, Od::default()));
    let (state_machine, process_data, _control) = ecat.split();
    match exchange(process_data) {
        Ok(token) => high.spawn(token),
        Err(_) => crate::fail("cannot spawn the process-data runner"),
    }
    state_machine
        .run_then(|_| crate::fail("the state-machine runner stopped"))
        .await;
}

/// The process-data exchange, in the interrupt executor; owns the ESC's IRQ line.
#[embassy_executor::task]
async fn exchange(runner: ProcessDataRunner<'static, ModelPdi, App, Od>) {
    runner
        .run_then(IrqPin, |_| crate::fail("the process-data runner stopped"))
        .await;
}
