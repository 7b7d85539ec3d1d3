//! The CiA402 dummy axis (`ecat-axis`) as an emulated device: its description, dictionary and
//! application, and the SII image generated from them. Updatable as a product is: a flash of its
//! own, FoE in BOOT through the bootstrap mailbox, its revision the version of the image it runs
//! (`ecat_emu::update`).

use ecat_axis::{Axis, AxisApp, AxisOd};
use ecat_emu::devices::Sample;
use ecat_emu::harness::Device;
use ecat_emu::update::{Firmware, Updatable};

/// The axis running `firmware`, ready for the harness.
pub fn sample(firmware: &Firmware) -> Sample<Updatable<AxisApp>, Axis, AxisOd> {
    let mut od = AxisOd::default();
    let identity = firmware.identify(&mut od.area);
    let config = firmware.bootstrap(ecat_axis::DEVICE);
    let device = Device::new(config, firmware.app(AxisApp), Axis::new()).with_dictionary(od);
    Sample::new(ecat_axis::NAMES, identity, device)
}
