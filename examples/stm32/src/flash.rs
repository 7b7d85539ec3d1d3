//! The chip's flash, shared by the tasks that write it: the firmware update (feature
//! `bootloader`, `crate::update`) and the stored parameters (feature `storage`,
//! `crate::parameters`). One driver behind an async mutex; both run in the thread executor, so
//! the mutex needs no critical section (embassy-boot's `FirmwareUpdaterConfig::from_linkerfile`
//! takes this kind), and a reference to it is not `Send`: the thread executor's `Spawner` hands
//! it to the update's task.

use embassy_stm32::flash::Flash;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::mutex::Mutex;
use static_cell::StaticCell;

/// The flash driver as the tasks share it.
pub type SharedFlash = Mutex<NoopRawMutex, Flash<'static>>;

/// Puts the driver behind its mutex, once.
pub fn share(flash: Flash<'static>) -> &'static SharedFlash {
    static FLASH: StaticCell<SharedFlash> = StaticCell::new();
    FLASH.init(Mutex::new(flash))
}
