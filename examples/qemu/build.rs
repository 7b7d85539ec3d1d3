//! Puts memory.x and device.x (empty: the firmware defines its interrupt table) on the linker's
//! search path.
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    for file in ["memory.x", "device.x"] {
        fs::copy(file, out.join(file)).expect("copy the linker script");
        println!("cargo:rerun-if-changed={file}");
    }
    println!("cargo:rustc-link-search={}", out.display());
}
