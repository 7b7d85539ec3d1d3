//! The bootloader under the ecat STM32G474 firmware: embassy-boot's power-fail-safe swap.
//!
//! At every reset it looks at the state partition (memory.x): when the application marked a new
//! image in DFU as updated (the MainDevice wrote it by FoE and left BOOT), it swaps ACTIVE and DFU
//! page by page, recording each step in the state partition so that a power loss mid-swap
//! resumes where it stopped; when the previous boot was a trial that the image never confirmed
//! (it marks itself booted once it reaches PREOP), it swaps back: the old image runs again.
//! Then it jumps to ACTIVE.
#![no_std]
#![no_main]
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

use core::cell::RefCell;

use cortex_m_rt::{entry, exception};
use embassy_boot_stm32::{BootLoader, BootLoaderConfig};
use embassy_stm32::flash::{BANK1_REGION, Flash};
use embassy_sync::blocking_mutex::Mutex;

/// Bytes moved per flash write during a swap: one 4 KiB page of the G474 in single-bank mode.
const PAGE: usize = 4096;

#[entry]
fn main() -> ! {
    let p = embassy_stm32::init(Default::default());
    let flash = Flash::new_blocking(p.FLASH).into_blocking_regions();
    let flash = Mutex::new(RefCell::new(flash.bank1_region));
    let config = BootLoaderConfig::from_linkerfile_blocking(&flash, &flash, &flash);
    let active = BANK1_REGION.base() + config.active.offset();
    let bootloader = BootLoader::prepare::<_, _, _, PAGE>(config);
    // SAFETY: `active` is the start of the ACTIVE partition, where the application's vector
    // table is linked (examples/stm32, feature `bootloader`); nothing of the bootloader's
    // state is used after the jump.
    unsafe { bootloader.load(active) }
}

/// A fault in the bootloader (a flash error during the swap): reset and let the next boot resume
/// the swap from the progress the state partition recorded.
#[exception]
unsafe fn HardFault(_: &cortex_m_rt::ExceptionFrame) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}

/// A panic (embassy-boot's `prepare` panics on a flash error): the same as a fault.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}
