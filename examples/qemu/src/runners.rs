//! The glue to ecat-embassy's runners: the only file that names their entry points.

use core::cell::RefCell;

use ecat_core::SubDevice;
use ecat_embassy::pd_runner::{Buffers, NoSync0};
use ecat_embassy::{SharedDictionary, SharedEsc, run_esm, run_process_data};
use embassy_executor::SendSpawner;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use static_cell::StaticCell;

use crate::app::{App, DEVICE, Od};
use crate::esc::{IrqPin, ModelPdi};

type Esc = SharedEsc<CriticalSectionRawMutex, ModelPdi>;
type Dictionary = SharedDictionary<CriticalSectionRawMutex, Od>;

static ESC: StaticCell<Esc> = StaticCell::new();
static DICTIONARY: StaticCell<Dictionary> = StaticCell::new();

/// The thread executor's task: starts the process-data runner in the interrupt executor, then
/// runs the state machine and the mailbox.
#[embassy_executor::task]
pub async fn state_machine(high: SendSpawner) {
    let esc: &'static Esc = ESC.init(SharedEsc::new(ModelPdi));
    let od: &'static Dictionary = DICTIONARY.init(Mutex::new(RefCell::new(Od::default())));
    match process_data(esc, od) {
        Ok(token) => high.spawn(token),
        Err(_) => crate::fail("cannot spawn the process-data runner"),
    }
    let mut sub: SubDevice<'static> = SubDevice::new(&DEVICE);
    match run_esm(esc, &mut sub, &mut App, od).await {}
}

/// The process-data exchange, in the interrupt executor; owns the ESC's IRQ line.
#[embassy_executor::task]
async fn process_data(esc: &'static Esc, od: &'static Dictionary) {
    let (mut outputs, mut inputs) = ([0; 4], [0; 4]);
    let buffers = Buffers {
        outputs: &mut outputs,
        inputs: &mut inputs,
    };
    let error = run_process_data(esc, &mut IrqPin, &mut NoSync0::new(), &mut App, od, buffers).await;
    let _ = error;
    crate::fail("the process-data runner stopped");
}
