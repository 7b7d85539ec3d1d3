//! Sample device dictionaries for tests, benchmarks and demos.

use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
use ecat_core::sync::SyncParameters;

/// A CiA402-like drive's process data: RxPDO 0x1600 = controlword, target position, target
/// velocity, mode of operation (11 bytes); TxPDO 0x1A00 = statusword, actual position, actual
/// velocity, mode display (11 bytes); both configurable in PREOP.
#[derive(Debug)]
pub struct Drive {
    /// 0x6040.
    pub controlword: u16,
    /// 0x607A.
    pub target_position: i32,
    /// 0x60FF.
    pub target_velocity: i32,
    /// 0x6060.
    pub mode: i8,
    /// 0x6041.
    pub statusword: u16,
    /// 0x6064.
    pub position: i32,
    /// 0x606C.
    pub velocity: i32,
    /// 0x6061.
    pub mode_display: i8,
    /// 0x1600.
    pub rx1: PdoMapping<8>,
    /// 0x1A00.
    pub tx1: PdoMapping<8>,
    /// 0x1C12.
    pub rx_assign: PdoAssignment<2>,
    /// 0x1C13.
    pub tx_assign: PdoAssignment<2>,
    /// 0x1C32.
    pub sync_out: SyncParameters,
    /// 0x1C33.
    pub sync_in: SyncParameters,
}

/// The default RxPDO mapping of [`Drive`].
pub const DRIVE_RX: [MappingEntry; 4] = [
    MappingEntry::new(0x6040, 0, 16),
    MappingEntry::new(0x607A, 0, 32),
    MappingEntry::new(0x60FF, 0, 32),
    MappingEntry::new(0x6060, 0, 8),
];

/// The default TxPDO mapping of [`Drive`].
pub const DRIVE_TX: [MappingEntry; 4] = [
    MappingEntry::new(0x6041, 0, 16),
    MappingEntry::new(0x6064, 0, 32),
    MappingEntry::new(0x606C, 0, 32),
    MappingEntry::new(0x6061, 0, 8),
];

ecat_core::dictionary! {
    Drive {
        0x1600 => pdo(rx1, RW_PREOP, "RxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&DRIVE_RX));
        0x1A00 => pdo(tx1, RW_PREOP, "TxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&DRIVE_TX));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x1C32 => record(sync_out: SyncParameters, "SM output parameter") {
            1 => sync_type, RW_PREOP, "Synchronization type", default = 1;
            2 => cycle_time, RO, "Cycle time";
            4 => supported, RO, "Synchronization types supported";
            5 => min_cycle_time, RO, "Minimum cycle time";
            0x0B => sm_event_missed, RO, "SM event missed counter";
            0x0C => cycle_time_too_small, RO, "Cycle time too small counter";
            0x20 => sync_error, RO, "Sync error";
        };
        0x1C33 => record(sync_in: SyncParameters, "SM input parameter") {
            1 => sync_type, RO, "Synchronization type", default = 0x22;
            2 => cycle_time, RO, "Cycle time";
            4 => supported, RO, "Synchronization types supported";
            5 => min_cycle_time, RO, "Minimum cycle time";
            0x0B => sm_event_missed, RO, "SM event missed counter";
            0x0C => cycle_time_too_small, RO, "Cycle time too small counter";
            0x20 => sync_error, RO, "Sync error";
        };
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword");
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
        0x6064 => var(position, RO | TXPDO, "Position actual value");
        0x606C => var(velocity, RO | TXPDO, "Velocity actual value");
        0x607A => var(target_position, RW | RXPDO, "Target position");
        0x60FF => var(target_velocity, RW | RXPDO, "Target velocity");
    }
}
