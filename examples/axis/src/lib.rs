//! # ecat-axis: a dummy CiA 402 servo axis
//!
//! The object dictionary of a CiA 402 drive ([`AxisOd`]) and its application: [`Axis`] (the
//! process-data cycle: the [`PowerDriveSystem`](ecat_core::cia402::PowerDriveSystem) decides, a
//! simulated [`Motor`] moves; the safe state; the SDO checks of 0x6060 and 0x6098, [`AxisApp`]). No std, no heap: the same code serves the host demo, a virtual SubDevice and the
//! STM32 firmware.
//!
//! Modes: profile position (1), profile velocity (3), homing (6) on a simulated machine
//! ([`Machine`]: limit switches, a home cam, an index pulse), cyclic synchronous position (8),
//! velocity (9) and torque (10); 0x6502 = 0x0000_03A5. Halt (controlword bit 8, 0x605D), touch
//! probe (0x60B8..0x60BD, probe 1 on the home switch) and digital inputs (0x60FD) in every mode.
//! Units: position in counts, velocity in counts/s, acceleration in counts/s², torque in 0.1 %
//! of the rated torque (CiA 402-2 default units).
#![no_std]
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

mod app;
mod axis;
mod motor;
mod od;

pub use app::AxisApp;
pub use axis::{Axis, DEFAULT_CYCLE_NS};
pub use motor::{Machine, Motor, TORQUE_ACCELERATION};
pub use od::{
    AxisOd, IDENTITY, INFO, RX_MAPPING, RX_PROFILE_MAPPING, SUPPORTED_MODES, TX_MAPPING,
    TX_PROFILE_MAPPING,
};

use ecat_core::DeviceConfig;
use ecat_core::device::{MailboxConfig, ProcessDataSizes};
use ecat_core::sii::Names;

/// The axis's device description: 128-byte mailboxes at 0x1000, the default PDOs' image sizes
/// (RxPDO 13 bytes, TxPDO 19 bytes; with 0x1C12/0x1C13 the mapping decides), free-run,
/// SM-synchronous or DC SYNC0.
pub const DEVICE: DeviceConfig = DeviceConfig::new(
    MailboxConfig::contiguous(0x1000, 128),
    ProcessDataSizes {
        outputs: 13,
        inputs: 19,
    },
);

// The axis's DC SYNC0 (its dictionary's sync modes) needs a minimum cycle time.
const _: () = assert!(
    DEVICE
        .validate_sync(<AxisOd as ecat_core::dictionary::ObjectDictionary>::SYNC_MODES)
        .is_ok()
);

/// The names the SII image and the ESI file carry.
pub const NAMES: Names<'static> = Names {
    name: "ecat CiA402 dummy axis",
    order_code: "ECAT-AXIS",
    group: "ecat samples",
};
