//! The CiA402 dummy axis (`ecat-axis`) as an emulated device: its description, dictionary and
//! application, and the SII image generated from them.

use ecat_axis::{Axis, AxisApp, AxisOd};
use ecat_emu::devices::Sample;
use ecat_emu::harness::Device;

/// The axis, ready for the harness.
pub fn sample() -> Sample<AxisApp, Axis, AxisOd> {
    let device =
        Device::new(ecat_axis::DEVICE, AxisApp, Axis::new()).with_dictionary(AxisOd::default());
    Sample::new(ecat_axis::NAMES, ecat_axis::IDENTITY, device)
}
