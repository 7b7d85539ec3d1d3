//! The devices the host programs emulate, by name: the sample devices of `ecat_emu::devices` and
//! the CiA402 dummy axis of `ecat-axis`, each with its SII image. The [`UPDATABLE`] ones, the axis
//! (`cia402`) and `dio-update` (the digital I/O module), have a flash of their own (image version 1)
//! that FoE updates in BOOT (`ecat_emu::update`: file `firmware.bin`, password 0x16); on a line
//! ([`device`]) they restart into the new image when the MainDevice leaves BOOT.

use ecat_core::dictionary::ObjectDictionary;
use ecat_embassy::Application;
use ecat_emu::devices::{self, Sample};
use ecat_emu::flash::Flash;
use ecat_emu::harness::Spawn;
use ecat_emu::restart::Reset;
use ecat_emu::update::{self, Firmware};

/// The names [`device`] knows.
pub const NAMES: [&str; 5] = ["cia402", "drive", "dio", "dio-update", "sensor"];
/// The device when none is named.
pub const DEFAULT: &str = "dio";
/// The most devices on one line (one process). The runners of a line share at most
/// [`ecat_emu::harness::SERVED_TASKS`] tasks, so embassy-time's timer queue (128 entries) never
/// overflows however long the line; what grows with the line is the time a frame takes through
/// it (every ESC processes every frame): a longer line is several instances chained with
/// `--out`, one process per core.
pub const MAX_COUNT: usize = 256;
/// Why a line holds at most [`MAX_COUNT`] devices, for the user.
pub const MAX_COUNT_REASON: &str =
    "a frame passes every ESC of the line in one thread; chain instances with --out for more";
/// The vendor of every device here (vendor ID [`devices::VENDOR_ID`], in the range the ETG
/// leaves for tests): the ESI file's `Vendor/Name`.
pub const VENDOR: &str = "ecat (test vendor ID)";

/// Something done with a typed sample device (its dictionary type, application and cycle).
pub trait Visit {
    /// What it gives.
    type Output;
    /// Does it with `sample`.
    fn visit<A, C, D>(self, sample: Sample<A, C, D>) -> Self::Output
    where
        A: Application<D> + 'static,
        C: Application<D> + 'static,
        D: ObjectDictionary;
}

/// The names of the devices with a firmware update.
pub const UPDATABLE: [&str; 2] = ["cia402", "dio-update"];

/// Runs `visitor` on a new instance of the device called `name` (an updatable one on a new
/// flash).
pub fn visit<V: Visit>(name: &str, visitor: V) -> Option<V::Output> {
    visit_running(name, &Firmware::new(flashed(), Reset::default()), visitor)
}

/// A new flash with a page-long image of version 1.
fn flashed() -> Flash {
    update::flashed(&update::image(1, 4096))
}

/// Runs `visitor` on a new instance of the device called `name`; an updatable one runs
/// `firmware`.
fn visit_running<V: Visit>(name: &str, firmware: &Firmware, visitor: V) -> Option<V::Output> {
    Some(match name {
        "cia402" => visitor.visit(crate::axis::sample(firmware)),
        "drive" => visitor.visit(devices::drive()),
        "dio" => visitor.visit(devices::dio()),
        "dio-update" => visitor.visit(devices::dio_update(firmware)),
        "sensor" => visitor.visit(devices::sensor()),
        _ => return None,
    })
}

/// Boxes the runnable device.
struct Boxed;

impl Visit for Boxed {
    type Output = Box<dyn Spawn>;
    fn visit<A, C, D>(self, sample: Sample<A, C, D>) -> Self::Output
    where
        A: Application<D> + 'static,
        C: Application<D> + 'static,
        D: ObjectDictionary,
    {
        Box::new(sample.device)
    }
}

/// A new instance of the device called `name`; an [updatable](UPDATABLE) one restarts when its
/// firmware asks (`update::restarting`), as after an update.
pub fn device(name: &str) -> Option<Box<dyn Spawn>> {
    let Some(&name) = UPDATABLE.iter().find(|&&updatable| updatable == name) else {
        return visit(name, Boxed);
    };
    Some(Box::new(update::restarting(flashed(), move |firmware| {
        visit_running(name, firmware, Boxed).expect("the catalog knows its updatable devices")
    })))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An updatable name the catalog did not know would fail only when its device boots.
    #[test]
    fn the_updatable_devices_are_in_the_catalog() {
        for name in UPDATABLE {
            assert!(NAMES.contains(&name), "{name}");
            assert!(visit(name, Boxed).is_some(), "{name}");
        }
    }
}
