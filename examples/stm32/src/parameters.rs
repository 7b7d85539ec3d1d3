//! Stored parameters (feature `storage`): 0x1010/0x1011 of the digital I/O dictionary kept in two
//! 4 KiB pages of the G474's flash through embassy-stm32's async flash driver and
//! `ecat_embassy::storage::FlashStorage` (sequential-storage's map).
//!
//! Where: the last two pages of the 512 KiB flash (0x0807E000..0x08080000), which this firmware,
//! linked from 0x08000000 over the whole flash, never reaches (about 50 KiB). Under the
//! bootloader's layout (`examples/stm32-bootloader/memory.x`) the firmware links at ACTIVE and
//! the PARAMETERS partition (0x08005000, 8 KiB) is the place an update leaves alone: a firmware
//! built for that layout sets [`PARAMETERS`] to it.
//!
//! While a page is erased or a double word programmed the CPU stalls on instruction fetches
//! from the same (single) bank: tens of milliseconds per page erase (the datasheet's tERASE),
//! which a "save" costs only when it moves to the other page; the process data waits meanwhile.

use core::ops::Range;

use ecat_embassy::storage::FlashStorage;
use embassy_embedded_hal::flash::partition::Partition;
use embassy_stm32::flash::{Async, Flash, InterruptHandler};
use embassy_stm32::{Peri, bind_interrupts, peripherals};
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::mutex::Mutex;
use static_cell::StaticCell;

/// The two pages, as offsets from the start of flash.
pub const PARAMETERS: Range<u32> = 0x7_E000..0x8_0000;

/// Room for the digital I/O dictionary's record (`parameters::record_size`: 8 bytes) and the
/// map's word rounding; two buffers of it in RAM.
const BUFFER: usize = 64;

bind_interrupts!(struct Irqs {
    FLASH => InterruptHandler;
});

/// The flash driver, shared by the partition.
type Driver = Mutex<NoopRawMutex, Flash<'static, Async>>;

/// The storage the state-machine runner performs 0x1010/0x1011 with.
pub type Storage = FlashStorage<Partition<'static, NoopRawMutex, Flash<'static, Async>>, BUFFER>;

static DRIVER: StaticCell<Driver> = StaticCell::new();

/// The storage on [`PARAMETERS`]; `None` (logged) if the partition is not two whole pages.
pub fn storage(flash: Peri<'static, peripherals::FLASH>) -> Option<Storage> {
    let driver = DRIVER.init(Mutex::new(Flash::new(flash, Irqs)));
    let partition = Partition::new(driver, PARAMETERS.start, PARAMETERS.end - PARAMETERS.start);
    FlashStorage::new(partition)
        .inspect_err(|e| defmt::error!("parameter storage: {}", e))
        .ok()
}
