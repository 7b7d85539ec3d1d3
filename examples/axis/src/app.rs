//! The ESM and SDO side of the axis.

use ecat_core::cia402::homing::Method;
use ecat_core::cia402::mode;
use ecat_core::cia402::objects::MODES_OF_OPERATION;
use ecat_core::coe::AbortCode;
use ecat_core::dictionary::ObjectHooks;
use ecat_embassy::Application;

use crate::AxisOd;

/// 0x6098 homing method.
const HOMING_METHOD: u16 = 0x6098;

/// The axis' SDO checks: refuses an SDO download of an unsupported mode to 0x6060
/// ([`mode::check_write`]) or of a reserved homing method to 0x6098 ([`Method::of`]) with
/// 0x06090030. As an [`Application`] of its own (accepting every ESM transition, no cycle) for
/// hosts that pair it with the cycle of an [`Axis`](crate::Axis), which carries the same checks.
#[derive(Debug, Clone, Copy, Default)]
pub struct AxisApp;

impl Application<AxisOd> for AxisApp {
    fn object_hooks(&mut self) -> impl ObjectHooks<AxisOd> + '_ {
        *self
    }
}

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
            (HOMING_METHOD, 0) => match data {
                [code] if Method::of(i8::from_le_bytes([*code])).is_none() => {
                    Err(AbortCode::VALUE_RANGE)
                }
                _ => Ok(()),
            },
            _ => Ok(()),
        }
    }
}
