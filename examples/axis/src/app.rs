//! The ESM and SDO side of the axis.

use ecat_core::cia402::mode;
use ecat_core::cia402::objects::MODES_OF_OPERATION;
use ecat_core::coe::AbortCode;
use ecat_core::dictionary::ObjectHooks;
use ecat_embassy::Application;

use crate::AxisOd;

/// The axis' [`Application`]: accepts every ESM transition; refuses an SDO download of an
/// unsupported mode to 0x6060 with 0x06090030 ([`mode::check_write`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct AxisApp;

impl Application for AxisApp {}

impl ObjectHooks<AxisOd> for AxisApp {
    fn before_write(
        &mut self,
        od: &AxisOd,
        index: u16,
        sub: u8,
        data: &[u8],
    ) -> Result<(), AbortCode> {
        match (index, sub) {
            (MODES_OF_OPERATION, 0) => mode::check_write(data, od.supported_modes),
            _ => Ok(()),
        }
    }
}
