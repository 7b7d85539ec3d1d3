//! Stored parameters (feature `storage`): 0x1010/0x1011 of the digital I/O dictionary (the input
//! polarity 0x6002, `ecat_dio`'s feature `storage`) kept in two 4 KiB pages of the G474's flash
//! through embassy-stm32's async flash driver and `ecat_embassy::storage::FlashStorage`
//! (sequential-storage's map).
//!
//! Where: the PARAMETERS pages of the memory map. Standalone (`memory-standalone.x`), the last two
//! pages of the 512 KiB flash, 0x0807E000..0x08080000, which the linker's FLASH region (504 KiB)
//! leaves out; under the bootloader (`bootloader`, `memory-bootloader.x`, as
//! examples/stm32-bootloader/memory.x lays the flash out) 0x08005000..0x08007000, between
//! BOOTLOADER_STATE and ACTIVE, which neither the bootloader nor an update touches.
//!
//! While a page is erased or a double word programmed the CPU stalls on instruction fetches
//! from the same (single) bank: tens of milliseconds per page erase (the datasheet's tERASE),
//! which a "save" costs only when it moves to the other page; the process data waits meanwhile.

use core::ops::Range;

use ecat_embassy::storage::FlashStorage;
use embassy_embedded_hal::flash::partition::Partition;
use embassy_stm32::flash::Flash;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;

use crate::flash::SharedFlash;

/// The two pages, as offsets from the start of flash (the PARAMETERS region of the memory map).
#[cfg(not(feature = "bootloader"))]
pub const PARAMETERS: Range<u32> = 0x7_E000..0x8_0000;
/// The two pages, as offsets from the start of flash (the bootloader's PARAMETERS partition).
#[cfg(feature = "bootloader")]
pub const PARAMETERS: Range<u32> = 0x5000..0x7000;

/// Room for the digital I/O dictionary's record (`parameters::record_size`: 8 bytes) and the
/// map's word rounding; two buffers of it in RAM.
const BUFFER: usize = 64;

/// The storage the state-machine runner performs 0x1010/0x1011 with.
pub type Storage = FlashStorage<Partition<'static, NoopRawMutex, Flash<'static>>, BUFFER>;

/// The storage on [`PARAMETERS`]; `None` (logged) if the partition is not two whole pages.
pub fn storage(flash: &'static SharedFlash) -> Option<Storage> {
    let partition = Partition::new(flash, PARAMETERS.start, PARAMETERS.end - PARAMETERS.start);
    FlashStorage::new(partition)
        .inspect_err(|e| defmt::error!("parameter storage: {}", e))
        .ok()
}
