//! The dictionary of the axis: the communication area, the error register, the PDOs and the
//! CiA 402 objects of [`ecat_core::cia402::objects`].

use ecat_core::cia402::SoftwarePositionLimit;
use ecat_core::cia402::objects::HomingSpeeds;
use ecat_core::device::Identity;
use ecat_core::diagnosis::DiagnosisHistory;
use ecat_core::dictionary::{Communication, DeviceInfo};
use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
use ecat_core::sync_error::{DEFAULT_LIMIT, ErrorSettings, REACTION_SAFEOP};
use ecat_core::sync_mode::SupportedSyncModes;

/// 0x1018 of the axis; the SII image carries the same value.
pub const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 0x0001_0402,
    revision: 1,
    serial: 1,
};

/// The communication area of the axis: 0x1000 = 0x0002_0192 (CiA 402, servo drive), 0x1008 the
/// name the SII image and the ESI file carry.
pub const INFO: DeviceInfo = DeviceInfo {
    device_type: 0x0002_0192,
    name: crate::NAMES.name,
    hardware_version: "sim",
    software_version: env!("CARGO_PKG_VERSION"),
    identity: IDENTITY,
};

/// 0x6502 of the axis: PP (bit 0), PV (bit 2), HM (bit 5), CSP (bit 7), CSV (bit 8), CST
/// (bit 9).
pub const SUPPORTED_MODES: u32 = 0x0000_03A5;

/// RxPDO 0x1600: controlword, target position, target velocity, target torque, modes of operation
/// (13 bytes).
pub const RX_MAPPING: [MappingEntry; 5] = [
    MappingEntry::new(0x6040, 0, 16),
    MappingEntry::new(0x607A, 0, 32),
    MappingEntry::new(0x60FF, 0, 32),
    MappingEntry::new(0x6071, 0, 16),
    MappingEntry::new(0x6060, 0, 8),
];

/// TxPDO 0x1A00: statusword, position actual, velocity actual, torque actual, modes of operation
/// display, following error actual value, error code (19 bytes).
pub const TX_MAPPING: [MappingEntry; 7] = [
    MappingEntry::new(0x6041, 0, 16),
    MappingEntry::new(0x6064, 0, 32),
    MappingEntry::new(0x606C, 0, 32),
    MappingEntry::new(0x6077, 0, 16),
    MappingEntry::new(0x6061, 0, 8),
    MappingEntry::new(0x60F4, 0, 32),
    MappingEntry::new(0x603F, 0, 16),
];

/// RxPDO 0x1601, the profile set (assign it in 0x1C12 instead of 0x1600): controlword, target
/// position, target velocity, profile velocity, profile acceleration, profile deceleration,
/// modes of operation, touch probe function (25 bytes).
pub const RX_PROFILE_MAPPING: [MappingEntry; 8] = [
    MappingEntry::new(0x6040, 0, 16),
    MappingEntry::new(0x607A, 0, 32),
    MappingEntry::new(0x60FF, 0, 32),
    MappingEntry::new(0x6081, 0, 32),
    MappingEntry::new(0x6083, 0, 32),
    MappingEntry::new(0x6084, 0, 32),
    MappingEntry::new(0x6060, 0, 8),
    MappingEntry::new(0x60B8, 0, 16),
];

/// TxPDO 0x1A01, the profile set (assign it in 0x1C13 instead of 0x1A00): statusword, position
/// actual, velocity actual, modes of operation display, following error, digital inputs, touch
/// probe status, touch probe 1 positive and negative edge, error code (31 bytes).
pub const TX_PROFILE_MAPPING: [MappingEntry; 10] = [
    MappingEntry::new(0x6041, 0, 16),
    MappingEntry::new(0x6064, 0, 32),
    MappingEntry::new(0x606C, 0, 32),
    MappingEntry::new(0x6061, 0, 8),
    MappingEntry::new(0x60F4, 0, 32),
    MappingEntry::new(0x60FD, 0, 32),
    MappingEntry::new(0x60B9, 0, 16),
    MappingEntry::new(0x60BA, 0, 32),
    MappingEntry::new(0x60BB, 0, 32),
    MappingEntry::new(0x603F, 0, 16),
];

/// The object dictionary of the axis; `AxisOd::default()` is the dictionary at power on.
#[derive(Debug)]
pub struct AxisOd {
    /// The communication area ([`INFO`]); 0x1C32:02 (`SyncParameters::CYCLE_TIME` of `area.outputs`) is the cycle
    /// time the motor integrates over.
    pub area: Communication,
    /// 0x1001 error register: bit 0 (generic error) while 0x603F is not 0.
    pub error_register: u8,
    /// 0x10F1 error settings (ETG.1020): the local error reaction and the sync error counter
    /// limit the stack's sync error supervision applies in DC mode (`ecat_core::sync_error`).
    pub error_settings: ErrorSettings,
    /// 0x10F3 diagnosis history (ETG.1020): the AL status codes the stack set, and the axis's
    /// own messages, for a MainDevice's "Diag History".
    pub diagnosis: DiagnosisHistory<8>,
    /// 0x1600.
    pub rx_mapping: PdoMapping<8>,
    /// 0x1A00.
    pub tx_mapping: PdoMapping<8>,
    /// 0x1C12.
    pub rx_assign: PdoAssignment<1>,
    /// 0x1C13.
    pub tx_assign: PdoAssignment<1>,
    /// 0x603F error code (CiA 301 emergency error codes).
    pub error_code: u16,
    /// 0x6040.
    pub controlword: u16,
    /// 0x6041.
    pub statusword: u16,
    /// 0x605A.
    pub quick_stop_option: i16,
    /// 0x605B.
    pub shutdown_option: i16,
    /// 0x605C.
    pub disable_operation_option: i16,
    /// 0x605E.
    pub fault_reaction_option: i16,
    /// 0x6060.
    pub mode: i8,
    /// 0x6061.
    pub mode_display: i8,
    /// 0x6064, counts.
    pub position: i32,
    /// 0x6065, counts; 0xFFFF_FFFF switches the following error check off.
    pub following_error_window: u32,
    /// 0x606C, counts/s.
    pub velocity: i32,
    /// 0x6071, 0.1 % of rated torque.
    pub target_torque: i16,
    /// 0x6077, 0.1 % of rated torque.
    pub torque: i16,
    /// 0x607A, counts.
    pub target_position: i32,
    /// 0x607D, counts; active when min < max.
    pub position_limit: SoftwarePositionLimit,
    /// 0x607F, counts/s: the speed limit of every mode.
    pub max_profile_velocity: u32,
    /// 0x6084, counts/s²: the slow down ramp.
    pub profile_deceleration: u32,
    /// 0x6085, counts/s²: the quick stop ramp.
    pub quick_stop_deceleration: u32,
    /// 0x60B1, counts/s.
    pub velocity_offset: i32,
    /// 0x60B2, 0.1 % of rated torque.
    pub torque_offset: i16,
    /// 0x60F4, counts.
    pub following_error: i32,
    /// 0x60FF, counts/s.
    pub target_velocity: i32,
    /// 0x6502.
    pub supported_modes: u32,
    /// 0x1601.
    pub rx_profile_mapping: PdoMapping<8>,
    /// 0x1A01.
    pub tx_profile_mapping: PdoMapping<12>,
    /// 0x605D halt option code, 1..=4.
    pub halt_option: i16,
    /// 0x6067 position window, counts (PP target reached).
    pub position_window: u32,
    /// 0x6068 position window time, ms.
    pub position_window_time: u16,
    /// 0x606D velocity window, counts/s (PV target reached).
    pub velocity_window: u16,
    /// 0x606E velocity window time, ms.
    pub velocity_window_time: u16,
    /// 0x606F velocity threshold, counts/s (PV speed zero).
    pub velocity_threshold: u16,
    /// 0x6070 velocity threshold time, ms.
    pub velocity_threshold_time: u16,
    /// 0x6072 max torque, 0.1 % of rated torque.
    pub max_torque: u16,
    /// 0x607C home offset, counts.
    pub home_offset: i32,
    /// 0x6081 profile velocity, counts/s.
    pub profile_velocity: u32,
    /// 0x6083 profile acceleration, counts/s².
    pub profile_acceleration: u32,
    /// 0x6098 homing method.
    pub homing_method: i8,
    /// 0x6099 homing speeds, counts/s.
    pub homing_speeds: HomingSpeeds,
    /// 0x609A homing acceleration, counts/s².
    pub homing_acceleration: u32,
    /// 0x60B8 touch probe function.
    pub touch_probe_function: u16,
    /// 0x60B9 touch probe status.
    pub touch_probe_status: u16,
    /// 0x60BA touch probe 1 positive edge position, counts.
    pub probe1_positive: i32,
    /// 0x60BB touch probe 1 negative edge position, counts.
    pub probe1_negative: i32,
    /// 0x60BC touch probe 2 positive edge position, counts.
    pub probe2_positive: i32,
    /// 0x60BD touch probe 2 negative edge position, counts.
    pub probe2_negative: i32,
    /// 0x60FD digital inputs.
    pub digital_inputs: u32,
}

ecat_core::dictionary! {
    AxisOd {
        sync(SupportedSyncModes(
            SupportedSyncModes::FREE_RUN | SupportedSyncModes::SM | SupportedSyncModes::SYNC0,
        ));
        communication(area, INFO);
        0x1001 => var(error_register, RO, "Error register");
        // A MainDevice's start-up may set the sync error counter limit (SSC's default 4: two
        // SYNC0 cycles in a row without new outputs take the axis to SAFEOP with 0x001A; 0
        // switches the supervision off); the local error reaction is SSC's 1, the only one.
        0x10F1 => record(error_settings: ErrorSettings, "Error settings") {
            1 => local_error_reaction, RW, "Local error reaction", default = REACTION_SAFEOP,
                 min = REACTION_SAFEOP, max = REACTION_SAFEOP;
            2 => sync_error_counter_limit, RW, "Sync error counter limit", default = DEFAULT_LIMIT;
        };
        0x10F3 => diagnosis(diagnosis);
        0x1600 => pdo(rx_mapping, RW_PREOP, "RxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&RX_MAPPING));
        0x1601 => pdo(rx_profile_mapping, RW_PREOP, "RxPDO 2 mapping (profile modes)", "Mapped object", default = PdoMapping::mapping(&RX_PROFILE_MAPPING));
        0x1A00 => pdo(tx_mapping, RW_PREOP, "TxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&TX_MAPPING));
        0x1A01 => pdo(tx_profile_mapping, RW_PREOP, "TxPDO 2 mapping (profile modes)", "Mapped object", default = PdoMapping::mapping(&TX_PROFILE_MAPPING));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x603F => var(error_code, RO | TXPDO, "Error code");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x6041 => var(statusword, RO | TXPDO, "Statusword");
        0x605A => var(quick_stop_option, RW, "Quick stop option code", default = 2, min = 0, max = 8);
        0x605B => var(shutdown_option, RW, "Shutdown option code", default = 0, min = 0, max = 1);
        0x605C => var(disable_operation_option, RW, "Disable operation option code", default = 1, min = 0, max = 1);
        0x605D => var(halt_option, RW, "Halt option code", default = 1, min = 1, max = 4);
        0x605E => var(fault_reaction_option, RW, "Fault reaction option code", default = 2, min = 0, max = 4);
        0x6060 => var(mode, RW | RXPDO, "Modes of operation");
        0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
        0x6064 => var(position, RO | TXPDO, "Position actual value");
        0x6065 => var(following_error_window, RW, "Following error window", default = 10_000);
        0x6067 => var(position_window, RW, "Position window", default = 0);
        0x6068 => var(position_window_time, RW, "Position window time", default = 0);
        0x606C => var(velocity, RO | TXPDO, "Velocity actual value");
        0x606D => var(velocity_window, RW, "Velocity window", default = 100);
        0x606E => var(velocity_window_time, RW, "Velocity window time", default = 0);
        0x606F => var(velocity_threshold, RW, "Velocity threshold", default = 100);
        0x6070 => var(velocity_threshold_time, RW, "Velocity threshold time", default = 0);
        0x6071 => var(target_torque, RW | RXPDO, "Target torque");
        0x6072 => var(max_torque, RW, "Max torque", default = 3_000);
        0x6077 => var(torque, RO | TXPDO, "Torque actual value");
        0x607A => var(target_position, RW | RXPDO, "Target position");
        0x607C => var(home_offset, RW, "Home offset");
        0x607D => record(position_limit: SoftwarePositionLimit, "Software position limit") {
            1 => min, RW, "Min position limit";
            2 => max, RW, "Max position limit";
        };
        0x607F => var(max_profile_velocity, RW, "Max profile velocity", default = 1_000_000);
        0x6081 => var(profile_velocity, RW | RXPDO, "Profile velocity", default = 100_000);
        0x6083 => var(profile_acceleration, RW | RXPDO, "Profile acceleration", default = 1_000_000);
        0x6084 => var(profile_deceleration, RW | RXPDO, "Profile deceleration", default = 1_000_000);
        0x6085 => var(quick_stop_deceleration, RW, "Quick stop deceleration", default = 10_000_000);
        0x6098 => var(homing_method, RW, "Homing method", default = 37);
        0x6099 => record(homing_speeds: HomingSpeeds, "Homing speeds") {
            1 => switch_search, RW, "Speed during search for switch", default = 50_000;
            2 => zero_search, RW, "Speed during search for zero", default = 1_000;
        };
        0x609A => var(homing_acceleration, RW, "Homing acceleration", default = 1_000_000);
        0x60B1 => var(velocity_offset, RW | RXPDO, "Velocity offset");
        0x60B2 => var(torque_offset, RW | RXPDO, "Torque offset");
        0x60B8 => var(touch_probe_function, RW | RXPDO, "Touch probe function");
        0x60B9 => var(touch_probe_status, RO | TXPDO, "Touch probe status");
        0x60BA => var(probe1_positive, RO | TXPDO, "Touch probe 1 positive edge");
        0x60BB => var(probe1_negative, RO | TXPDO, "Touch probe 1 negative edge");
        0x60BC => var(probe2_positive, RO | TXPDO, "Touch probe 2 positive edge");
        0x60BD => var(probe2_negative, RO | TXPDO, "Touch probe 2 negative edge");
        0x60F4 => var(following_error, RO | TXPDO, "Following error actual value");
        0x60FD => var(digital_inputs, RO | TXPDO, "Digital inputs");
        0x60FF => var(target_velocity, RW | RXPDO, "Target velocity");
        0x6502 => var(supported_modes, RO, "Supported drive modes", default = SUPPORTED_MODES);
    }
}
