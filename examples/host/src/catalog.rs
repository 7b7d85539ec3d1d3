//! The devices the host programs emulate, by name: the sample devices of `ecat_emu::devices` and
//! the CiA402 dummy axis of `ecat-axis`, each with its SII image.

use ecat_emu::devices;
use ecat_emu::harness::Spawn;

/// The names [`device`] knows.
pub const NAMES: [&str; 4] = ["cia402", "drive", "dio", "sensor"];
/// The device when none is named.
pub const DEFAULT: &str = "dio";
/// The most devices on one line.
pub const MAX_COUNT: usize = 64;

/// A new instance of the device called `name`.
pub fn device(name: &str) -> Option<Box<dyn Spawn>> {
    Some(match name {
        "cia402" => Box::new(crate::axis::sample().device),
        "drive" => Box::new(devices::drive().device),
        "dio" => Box::new(devices::dio().device),
        "sensor" => Box::new(devices::sensor().device),
        _ => return None,
    })
}
