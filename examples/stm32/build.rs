//! Puts the firmware's `memory.x` on the linker's search path, per variant: the whole flash of
//! the STM32G474RE (`memory-standalone.x`, what embassy-stm32's `memory-x` feature generated before), or
//! with feature `bootloader` the ACTIVE partition of examples/stm32-bootloader's layout
//! (`memory-bootloader.x`), where the bootloader jumps. Neither is named `memory.x` here: the
//! linker looks in the working directory before the search path.
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let memory: &[u8] = if std::env::var_os("CARGO_FEATURE_BOOTLOADER").is_some() {
        include_bytes!("memory-bootloader.x")
    } else {
        include_bytes!("memory-standalone.x")
    };
    std::fs::write(out.join("memory.x"), memory).expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory-standalone.x");
    println!("cargo:rerun-if-changed=memory-bootloader.x");
}
