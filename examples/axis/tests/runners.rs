//! The axis behind the real runners and the emulated ESC: the TestMaster enables it through the
//! RxPDO and reads the TxPDO; the 0x6060 check answers over the mailbox.

use ecat_axis::{Axis, AxisApp, AxisOd};
use ecat_core::DeviceConfig;
use ecat_core::coe::AbortCode;
use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_emu::coe_client::{SdoClient, SdoError};
use ecat_emu::harness::{self, Device};
use ecat_emu::master::TestMaster;

const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
/// RxPDO 0x1600: 13 bytes; TxPDO 0x1A00: 19 bytes.
const OUTPUTS: Area = Area::new(0x1100, 13);
const INPUTS: Area = Area::new(0x1180, 19);

/// The RxPDO image: controlword, target position, target velocity, target torque, mode.
fn rx(controlword: u16, velocity: i32, mode: i8) -> Vec<u8> {
    let mut image = controlword.to_le_bytes().to_vec();
    image.extend_from_slice(&0i32.to_le_bytes());
    image.extend_from_slice(&velocity.to_le_bytes());
    image.extend_from_slice(&0i16.to_le_bytes());
    image.extend_from_slice(&mode.to_le_bytes());
    image
}

/// One cyclic frame: writes the outputs, lets the SubDevice run, returns (statusword, position,
/// velocity, mode display, error code) from the inputs.
async fn exchange(master: &TestMaster, outputs: &[u8]) -> (u16, i32, i32, i8, u16) {
    assert!(master.write(OUTPUTS.start, outputs));
    master.settle().await;
    let inputs = master.read(INPUTS.start, 19).expect("inputs readable");
    let word = |at: usize| u16::from_le_bytes([inputs[at], inputs[at + 1]]);
    let long = |at: usize| i32::from_le_bytes(inputs[at..at + 4].try_into().unwrap());
    (word(0), long(2), long(6), inputs[12] as i8, word(17))
}

/// The axis with its dictionary, the CSV PDO set's 13 bytes out and 19 in.
fn axis() -> Device<AxisApp, Axis, AxisOd> {
    let config = DeviceConfig::new(
        MAILBOX,
        ProcessDataSizes {
            outputs: 13,
            inputs: 19,
        },
    );
    Device::new(config, AxisApp, Axis::new()).with_dictionary(AxisOd::default())
}

#[test]
fn a_master_enables_the_axis_in_csv_through_process_data() {
    let device = axis();
    harness::run(device, |master| async move {
        master.reset().await;
        assert_eq!(master.request(0x01).await, (0x01, 0));
        master.configure_mailbox(&MAILBOX);
        master.configure_process_data(Some(OUTPUTS), Some(INPUTS));
        master.settle().await;
        assert_eq!(master.request(0x02).await, (0x02, 0));
        let mut sdo = SdoClient::for_mailbox(&master, &MAILBOX);
        assert_eq!(
            sdo.download(0x6060, 0, false, &[4]).await,
            Err(SdoError::Abort(AbortCode::VALUE_RANGE)),
            "profile torque is not in 0x6502"
        );
        assert_eq!(
            sdo.upload(0x1000, 0, false).await,
            Ok(vec![0x92, 0x01, 0x02, 0x00])
        );
        assert_eq!(master.request(0x04).await, (0x04, 0));
        assert!(master.write(OUTPUTS.start, &rx(0, 0, 0)));
        master.settle().await;
        assert_eq!(master.request(0x08).await, (0x08, 0));

        // Transitions 1, 2, 3+4 with mode 9, then 5 000 counts/s: 5 counts per 1 ms cycle.
        assert_eq!(exchange(&master, &rx(0x00, 0, 9)).await.0 & 0x006F, 0x0040);
        assert_eq!(exchange(&master, &rx(0x06, 0, 9)).await.0, 0x0231);
        let (status, _, _, mode, _) = exchange(&master, &rx(0x0F, 0, 9)).await;
        assert_eq!((status, mode), (0x1637, 9));
        let (_, before, _, _, _) = exchange(&master, &rx(0x0F, 5_000, 9)).await;
        let (status, after, velocity, _, error) = exchange(&master, &rx(0x0F, 5_000, 9)).await;
        assert_eq!(
            (status, after - before, velocity, error),
            (0x1637, 5, 5_000, 0)
        );
        // Quick stop (option code 2, 0x6085 = 10 000 000 counts/s²): at rest within a cycle,
        // Switch on disabled the cycle after.
        let (status, _, velocity, _, _) = exchange(&master, &rx(0x02, 5_000, 9)).await;
        assert_eq!((status, velocity), (0x0617, 0));
        assert_eq!(exchange(&master, &rx(0x02, 5_000, 9)).await.0, 0x0250);
    });
}

/// The profile PDO set: RxPDO 0x1601 (25 bytes), TxPDO 0x1A01 (31 bytes).
const PROFILE_OUTPUTS: Area = Area::new(0x1100, 25);
const PROFILE_INPUTS: Area = Area::new(0x1180, 31);

#[test]
fn the_profile_pdo_set_is_selected_through_0x1c12_and_0x1c13() {
    let device = axis();
    harness::run(device, |master| async move {
        master.reset().await;
        assert_eq!(master.request(0x01).await, (0x01, 0));
        master.configure_mailbox(&MAILBOX);
        assert_eq!(master.request(0x02).await, (0x02, 0));
        let mut sdo = SdoClient::for_mailbox(&master, &MAILBOX);
        for (assignment, pdo) in [(0x1C12u16, 0x1601u16), (0x1C13, 0x1A01)] {
            assert_eq!(sdo.download(assignment, 0, false, &[0]).await, Ok(()));
            assert_eq!(
                sdo.download(assignment, 1, false, &pdo.to_le_bytes()).await,
                Ok(())
            );
            assert_eq!(sdo.download(assignment, 0, false, &[1]).await, Ok(()));
        }
        master.configure_process_data(Some(PROFILE_OUTPUTS), Some(PROFILE_INPUTS));
        master.settle().await;
        assert_eq!(master.request(0x04).await, (0x04, 0));
        // Controlword, target position, target velocity, profile velocity, acceleration,
        // deceleration, mode 1, touch probe function.
        let image = |controlword: u16, target: i32| {
            let mut out = controlword.to_le_bytes().to_vec();
            for value in [target, 0, 100_000, 1_000_000, 1_000_000] {
                out.extend_from_slice(&value.to_le_bytes());
            }
            out.push(1);
            out.extend_from_slice(&0u16.to_le_bytes());
            out
        };
        assert!(master.write(PROFILE_OUTPUTS.start, &image(0, 0)));
        master.settle().await;
        assert_eq!(master.request(0x08).await, (0x08, 0));
        let mut statuswords = Vec::new();
        for controlword in [0x00, 0x06, 0x0F, 0x1F, 0x0F] {
            assert!(master.write(PROFILE_OUTPUTS.start, &image(controlword, 500)));
            master.settle().await;
            let inputs = master.read(PROFILE_INPUTS.start, 31).expect("inputs");
            statuswords.push(u16::from_le_bytes([inputs[0], inputs[1]]));
            assert_eq!(inputs[10], 1, "0x6061 at byte 10");
        }
        // Switch on disabled, ready, enabled + reached, set-point acknowledged, released.
        assert_eq!(statuswords, [0x0250, 0x0231, 0x0637, 0x1237, 0x0237]);
    });
}
