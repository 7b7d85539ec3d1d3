//! Sample devices for tests, benchmarks, demos and the virtual slave: each one description
//! (names, identity, [`DeviceConfig`]), one dictionary, one application, and the SII image
//! generated from them ([`Sample::eeprom`]).
//!
//! | device | process data | application |
//! |---|---|---|
//! | [`drive`] | CiA402-like, 11 bytes each way, configurable PDOs | echoes the set-points as actual values |
//! | [`dio`] | 2 output bytes, 2 input bytes | inputs = outputs (outputs wired to inputs) |
//! | [`sensor`] | inputs only: i32 value + u16 status | the value counts the cycles |
//! | [`dio_update`] | as [`dio`] | as [`dio`]; FoE in BOOT updates its flash ([`crate::update`]) |

use ecat_core::DeviceConfig;
use ecat_core::coe::Emergency;
use ecat_core::device::{Identity, MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::{
    Communication, DeviceInfo, ObjectDictionary, ObjectHooks, OctetString,
};
use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
use ecat_core::sii::{self, Names};
use ecat_core::sync_mode::SupportedSyncModes;
use ecat_embassy::Application;

use crate::harness::{AcceptAll, Device};
use crate::update::{Firmware, Updatable};
use ecat_core::diagnosis::DiagnosisHistory;

/// A CiA402-like drive's process data: RxPDO 0x1600 = controlword, target position, target
/// velocity, mode of operation (11 bytes); TxPDO 0x1A00 = statusword, actual position, actual
/// velocity, mode display (11 bytes); both configurable in PREOP.
///
/// `SYNC` tells the declarations apart: [`Drive`] supports free-run and SM-synchronous, the
/// others ([`DriveDc`], [`DriveSync1`], [`DriveSm`], [`DriveSmDc`]) the sync modes their
/// declaration states (`SYNC`'s bits, 0x1C32:04).
#[derive(Debug)]
pub struct Drive<const SYNC: u16 = 0> {
    /// The communication area (0x1000..0x1018, 0x1C00, 0x1C32, 0x1C33).
    pub area: Communication,
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
    /// 0x2000: 128 bytes a MainDevice may write and read back, more than one SDO message of a
    /// 128-byte mailbox carries: segmented transfers both ways.
    pub scratch: OctetString<128>,
    /// 0x2001: a CiA 301 error code a MainDevice writes to make the drive report it in an
    /// emergency ([`DriveApp`]), for testing a MainDevice's emergency handling.
    pub simulated_error: u16,
    /// 0x10F3: the diagnosis history the stack logs its AL status codes into.
    pub history: DiagnosisHistory<8>,
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

/// Declares the dictionary of [`Drive`], or of `Drive<SYNC>` named `$name`, supporting the sync
/// modes `SYNC`.
macro_rules! drive_dictionary {
    ($name:ident) => {
        drive_dictionary!(@declare $name);
    };
    ($(#[$doc:meta])* $name:ident = $sync:literal) => {
        $(#[$doc])*
        pub type $name = Drive<$sync>;
        drive_dictionary!(@declare $name sync(SupportedSyncModes($sync)););
    };
    (@declare $name:ident $($sync:tt)*) => {
ecat_core::dictionary! {
    $name {
        $($sync)*
        communication(area, DRIVE_INFO);
        0x10F3 => diagnosis(history);
        0x1600 => pdo(rx1, RW_PREOP, "RxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&DRIVE_RX));
        0x1A00 => pdo(tx1, RW_PREOP, "TxPDO 1 mapping", "Mapped object", default = PdoMapping::mapping(&DRIVE_TX));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x2000 => var(scratch, RW, "Scratch pad");
        0x2001 => var(simulated_error, RW, "Simulated error");
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
    };
}

drive_dictionary!(Drive);
drive_dictionary!(
    /// [`Drive`] with DC SYNC0: free-run, SM-synchronous and DC SYNC0.
    DriveDc = 7
);
drive_dictionary!(
    /// [`Drive`] declaring DC SYNC1 beside SYNC0 (free-run, SM-synchronous, SYNC0, SYNC1).
    DriveSync1 = 15
);
drive_dictionary!(
    /// [`Drive`] with SM-synchronous only.
    DriveSm = 2
);
drive_dictionary!(
    /// [`Drive`] with SM-synchronous and DC SYNC0, no free-run.
    DriveSmDc = 6
);

/// The vendor ID of the sample devices (in the range the ETG leaves for tests).
pub const VENDOR_ID: u32 = 0xE000_0001;

/// The identity of a sample device: [`VENDOR_ID`], `product_code`, revision 1, serial 1.
pub const fn sample_identity(product_code: u32) -> Identity {
    Identity {
        vendor_id: VENDOR_ID,
        product_code,
        revision: 1,
        serial: 1,
    }
}

/// 0x1018 of [`Drive`].
pub const DRIVE_IDENTITY: Identity = sample_identity(0x0000_0402);

/// The communication area of [`Drive`]: a CiA 402 servo drive (0x1000 = 0x0002_0192).
pub const DRIVE_INFO: DeviceInfo = sample_info(0x0002_0192, "ecat sample drive", DRIVE_IDENTITY);

/// The communication area of a sample device: `device_type`, `name` (also the SII's),
/// hardware version "1", the crate's version as software version, `identity`.
pub const fn sample_info(device_type: u32, name: &'static str, identity: Identity) -> DeviceInfo {
    DeviceInfo {
        device_type,
        name,
        hardware_version: "1",
        software_version: env!("CARGO_PKG_VERSION"),
        identity,
    }
}

/// 128-byte mailboxes at 0x1000 and 0x1080, as every sample device has.
const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);

/// A sample device: what the harness runs and what the EEPROM holds.
pub struct Sample<A, C, D> {
    /// The names in the SII strings.
    pub names: Names<'static>,
    /// The identity (= 0x1018).
    pub identity: Identity,
    /// The device, ready for [`harness::run_many`](crate::harness::run_many).
    pub device: Device<A, C, D>,
}

impl<A, C, D: ObjectDictionary> Sample<A, C, D> {
    /// The sample with `device.eeprom` generated from the names, identity, configuration and
    /// dictionary.
    pub fn new(names: Names<'static>, identity: Identity, device: Device<A, C, D>) -> Self {
        let mut sample = Self {
            names,
            identity,
            device,
        };
        let eeprom = sample.eeprom();
        sample.device.eeprom = eeprom;
        sample
    }

    /// The SII image generated from the description and the dictionary's defaults, for the chip
    /// of the device's ESC (`device.esc.chip`: its configuration area).
    pub fn eeprom(&self) -> Vec<u8> {
        let mut image = vec![0; sii::MAX_SIZE];
        match sii::write(
            &self.names,
            &self.identity,
            &self.device.config,
            &self.device.esc.chip,
            &self.device.od,
            &mut image,
        ) {
            Ok(len) => image.truncate(len),
            Err(e) => panic!("sample device's SII image: {e:?}"),
        }
        image
    }
}

/// A sample device in the samples group: its communication area (name and identity), order
/// code, fixed (output, input) sizes for the description, its cycle, its dictionary at its
/// defaults, 128-byte mailboxes.
fn sample<A, C, D: ObjectDictionary + Default>(
    info: &DeviceInfo,
    order_code: &'static str,
    (outputs, inputs): (u16, u16),
    app: A,
    cycle: C,
) -> Sample<A, C, D> {
    let config = DeviceConfig::new(MAILBOX, ProcessDataSizes { outputs, inputs });
    let device = Device::new(config, app, cycle).with_dictionary(D::default());
    let names = Names {
        name: info.name,
        order_code,
        group: "ecat samples",
    };
    Sample::new(names, info.identity, device)
}

/// Echoes the set-points of [`Drive`] as its actual values.
pub struct DriveEcho;

impl<const SYNC: u16> Application<Drive<SYNC>> for DriveEcho {
    fn cycle(&mut self, od: &mut Drive<SYNC>, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        od.statusword = od.controlword;
        od.position = od.target_position;
        od.velocity = od.target_velocity;
        od.mode_display = od.mode;
    }
}

/// The drive's application: accepts every transition; a write of a non-zero error code to
/// 0x2001 raises an emergency with that code and error register 0x01 (generic error, CiA 301).
#[derive(Debug, Default)]
pub struct DriveApp {
    emergency: Option<Emergency>,
}

impl<const SYNC: u16> Application<Drive<SYNC>> for DriveApp {
    fn object_hooks(&mut self) -> impl ObjectHooks<Drive<SYNC>> + '_ {
        self
    }

    fn take_emergency(&mut self) -> Option<Emergency> {
        self.emergency.take()
    }
}

impl<const SYNC: u16> ObjectHooks<Drive<SYNC>> for &mut DriveApp {
    fn after_write(&mut self, od: &mut Drive<SYNC>, index: u16, _sub: u8) {
        if index == 0x2001 && od.simulated_error != 0 {
            self.emergency = Some(Emergency {
                code: od.simulated_error,
                register: 0x01,
                data: [0; 5],
            });
        }
    }
}

/// The CiA402-like drive: configurable PDOs, SM-synchronous or free-run.
pub fn drive() -> Sample<DriveApp, DriveEcho, Drive> {
    drive_with()
}

/// The drive with DC SYNC0 ([`DriveDc`]).
pub fn drive_dc() -> Sample<DriveApp, DriveEcho, DriveDc> {
    drive_with()
}

/// The drive with the sync modes of `Drive<SYNC>`.
fn drive_with<const SYNC: u16>() -> Sample<DriveApp, DriveEcho, Drive<SYNC>>
where
    Drive<SYNC>: ObjectDictionary + Default,
{
    sample(
        &DRIVE_INFO,
        "ECAT-DRIVE",
        (11, 11),
        DriveApp::default(),
        DriveEcho,
    )
}

/// A digital I/O module: 16 outputs, 16 inputs, fixed PDOs.
#[derive(Debug)]
pub struct Dio {
    /// The communication area.
    pub area: Communication,
    /// 0x1600.
    pub rx: PdoMapping<2>,
    /// 0x1A00.
    pub tx: PdoMapping<2>,
    /// 0x1C12.
    pub rx_assign: PdoAssignment<1>,
    /// 0x1C13.
    pub tx_assign: PdoAssignment<1>,
    /// 0x6000: the input bytes.
    pub inputs: [u8; 2],
    /// 0x7000: the output bytes.
    pub outputs: [u8; 2],
}

/// 0x1018 of [`Dio`].
pub const DIO_IDENTITY: Identity = sample_identity(0x0000_1001);

/// The communication area of [`Dio`]: device type 0x0000_1389 (ETG.5001 modular device
/// profile, no modules).
pub const DIO_INFO: DeviceInfo = sample_info(0x0000_1389, "ecat sample dio", DIO_IDENTITY);

const DIO_RX: [MappingEntry; 2] = [
    MappingEntry::new(0x7000, 1, 8),
    MappingEntry::new(0x7000, 2, 8),
];
const DIO_TX: [MappingEntry; 2] = [
    MappingEntry::new(0x6000, 1, 8),
    MappingEntry::new(0x6000, 2, 8),
];

ecat_core::dictionary! {
    Dio {
        communication(area, DIO_INFO);
        0x1600 => pdo(rx, RO, "Outputs", "Mapped object", default = PdoMapping::mapping(&DIO_RX));
        0x1A00 => pdo(tx, RO, "Inputs", "Mapped object", default = PdoMapping::mapping(&DIO_TX));
        0x1C12 => pdo(rx_assign, RO, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x6000 => array(inputs, RO | TXPDO, "Digital inputs", "Input byte");
        0x7000 => array(outputs, RW | RXPDO, "Digital outputs", "Output byte");
    }
}

/// The outputs of [`Dio`] wired to its inputs.
pub struct DioLoop;

impl Application<Dio> for DioLoop {
    fn cycle(&mut self, od: &mut Dio, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        od.inputs = od.outputs;
    }
}

/// The digital I/O module.
pub fn dio() -> Sample<AcceptAll, DioLoop, Dio> {
    sample(&DIO_INFO, "ECAT-DIO-16", (2, 2), AcceptAll, DioLoop)
}

/// An input-only sensor: a measured value and a status word.
///
/// `SYNC` tells the declarations apart: [`Sensor`] supports free-run and SM-synchronous,
/// [`SensorDc`] also DC SYNC0.
#[derive(Debug)]
pub struct Sensor<const SYNC: u16 = 0> {
    /// The communication area.
    pub area: Communication,
    /// 0x1A00.
    pub tx: PdoMapping<2>,
    /// 0x1C12: no RxPDO.
    pub rx_assign: PdoAssignment<1>,
    /// 0x1C13.
    pub tx_assign: PdoAssignment<1>,
    /// 0x6000.
    pub value: i32,
    /// 0x6001.
    pub status: u16,
}

/// 0x1018 of [`Sensor`].
pub const SENSOR_IDENTITY: Identity = sample_identity(0x0000_2001);

/// The communication area of [`Sensor`].
pub const SENSOR_INFO: DeviceInfo = sample_info(0x0000_1389, "ecat sample sensor", SENSOR_IDENTITY);

const SENSOR_TX: [MappingEntry; 2] = [
    MappingEntry::new(0x6000, 0, 32),
    MappingEntry::new(0x6001, 0, 16),
];

/// Declares the dictionary of [`Sensor`], or of `Sensor<SYNC>` named `$name`, supporting the
/// sync modes `SYNC`.
macro_rules! sensor_dictionary {
    ($name:ident $($sync:tt)*) => {
ecat_core::dictionary! {
    $name {
        $($sync)*
        communication(area, SENSOR_INFO);
        0x1A00 => pdo(tx, RO, "Measurement", "Mapped object", default = PdoMapping::mapping(&SENSOR_TX));
        0x1C12 => pdo(rx_assign, RO, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[]));
        0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x6000 => var(value, RO | TXPDO, "Value");
        0x6001 => var(status, RO | TXPDO, "Status");
    }
}
    };
}

sensor_dictionary!(Sensor);
/// [`Sensor`] with DC SYNC0: free-run, SM-synchronous and DC SYNC0.
pub type SensorDc = Sensor<7>;
sensor_dictionary!(SensorDc sync(SupportedSyncModes(7)););

/// Counts the cycles in the sensor's value; status 0x0001 = "valid".
pub struct SensorCounter;

impl<const SYNC: u16> Application<Sensor<SYNC>> for SensorCounter {
    fn cycle(&mut self, od: &mut Sensor<SYNC>, _outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        od.value = od.value.wrapping_add(1);
        od.status = 0x0001;
    }
}

/// The input-only sensor.
pub fn sensor() -> Sample<AcceptAll, SensorCounter, Sensor> {
    sensor_with()
}

/// The sensor with DC SYNC0 ([`SensorDc`]).
pub fn sensor_dc() -> Sample<AcceptAll, SensorCounter, SensorDc> {
    sensor_with()
}

/// The sensor with the sync modes of `Sensor<SYNC>`.
fn sensor_with<const SYNC: u16>() -> Sample<AcceptAll, SensorCounter, Sensor<SYNC>>
where
    Sensor<SYNC>: ObjectDictionary + Default,
{
    sample(
        &SENSOR_INFO,
        "ECAT-SENSOR",
        (0, 6),
        AcceptAll,
        SensorCounter,
    )
}

/// The digital I/O module running `firmware`, updatable in BOOT ([`Firmware`]: FoE file
/// [`crate::update::FILE_NAME`], password [`crate::update::PASSWORD`]): its revision (SII and
/// 0x1018:03) is the version its image reports. A restart is a new device on the same flash
/// after [`crate::update::reset`], or [`crate::update::restarting`] does it.
pub fn dio_update(firmware: &Firmware) -> Sample<Updatable<AcceptAll>, DioLoop, Dio> {
    let mut od = Dio::default();
    let identity = firmware.identify(&mut od.area);
    let sizes = ProcessDataSizes {
        outputs: 2,
        inputs: 2,
    };
    let config = firmware.bootstrap(DeviceConfig::new(MAILBOX, sizes));
    let device = Device::new(config, firmware.app(AcceptAll), DioLoop).with_dictionary(od);
    let names = Names {
        name: DIO_INFO.name,
        order_code: "ECAT-DIO-16-U",
        group: "ecat samples",
    };
    Sample::new(names, identity, device)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ecat_core::dictionary::At;

    fn indices<D: ObjectDictionary>() -> Vec<u16> {
        D::OBJECTS.iter().map(|o| o.info.index).collect()
    }

    /// Every sample carries the communication area and both PDO assignments (what SOEM's
    /// `config_map` reads of every CoE device), then its own objects.
    #[test]
    fn every_sample_has_the_mandatory_objects() {
        const AREA: [u16; 6] = [0x1000, 0x1008, 0x1009, 0x100A, 0x1018, 0x1C00];
        let with = |pdos: &[u16], own: &[u16]| -> Vec<u16> {
            let mut all = AREA.to_vec();
            all.extend_from_slice(pdos);
            all.extend_from_slice(&[0x1C00, 0x1C12, 0x1C13, 0x1C32, 0x1C33]);
            all.extend_from_slice(own);
            all.sort_unstable();
            all.dedup();
            all
        };
        assert_eq!(
            indices::<Drive>(),
            with(
                &[0x1600, 0x1A00],
                &[
                    0x10F3, 0x2000, 0x2001, 0x6040, 0x6041, 0x6060, 0x6061, 0x6064, 0x606C, 0x607A,
                    0x60FF
                ]
            )
        );
        assert_eq!(indices::<Dio>(), with(&[0x1600, 0x1A00], &[0x6000, 0x7000]));
        assert_eq!(indices::<Sensor>(), with(&[0x1A00], &[0x6000, 0x6001]));
    }

    /// 0x1008 and 0x1018 say what the SII image says: the same constants.
    #[test]
    fn names_and_identity_agree_with_the_sii_description() {
        let read = |od: &Dio, index: u16, sub: u8| {
            let object = Dio::object(index).unwrap();
            let mut out = [0u8; 64];
            let n = (object.read)(od, At::start(sub), &mut out)
                .unwrap()
                .copied();
            out[..n].to_vec()
        };
        let sample = dio();
        assert_eq!(
            read(&sample.device.od, 0x1008, 0),
            sample.names.name.as_bytes()
        );
        assert_eq!(
            read(&sample.device.od, 0x1018, 2),
            sample.identity.product_code.to_le_bytes()
        );
        assert_eq!(read(&sample.device.od, 0x1000, 0), 0x1389u32.to_le_bytes());
    }
}
