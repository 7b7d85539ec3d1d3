//! The LAN9252 SPI driver at the byte level, against a fake LAN9252 that decodes the stream and
//! runs its CSR and PRAM engines as the chip does (LAN9252 datasheet, "SPI/SQI Slave",
//! "EtherCAT CSR and Process Data RAM Access"), and end to end: the real runners bring a SubDevice
//! to OP through the driver. Start-up polling and timeouts, which need virtual time, are in
//! `spi_lan9252_waits.rs`.

mod common;

use common::walk_to;
use core::pin::pin;
use core::task::{Context, Poll, Waker};
use ecat_core::chip::Chip;
use ecat_core::device::{Area, ProcessDataSizes};
use ecat_core::{AlEvent, AlState, DeviceConfig, register};
use ecat_embassy::Pdi;
use ecat_embassy::spi::lan9252::{self, Lan9252, ReadInstruction, WriteSpace};
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::master::TestMaster;
use ecat_emu::spi::lan9252::{Lan9252Chip, Lan9252Config};
use ecat_emu::spi::{BusError, FakeSpi, Probe, SpiStats};

type Driver = Lan9252<FakeSpi<Lan9252Chip>>;

/// Runs `future`, which must not wait for time (these tests never advance the clock): a driver
/// that waits here fails the test instead of hanging it.
fn finish<F: Future>(future: F) -> F::Output {
    let mut future = pin!(future);
    let mut cx = Context::from_waker(Waker::noop());
    for _ in 0..100_000 {
        if let Poll::Ready(output) = future.as_mut().poll(&mut cx) {
            return output;
        }
    }
    panic!("the driver waits for something that never comes");
}

/// The ESC inside a LAN9252 (4 SyncManagers, 3 FMMUs, 4 KiB of process RAM), its EEPROM
/// holding the configuration area the stack writes for it (PDI control 0x80: SPI).
fn lan9252_esc() -> EscConfig {
    EscConfig::of(Chip::LAN9252)
}

/// A started driver with `config` on a fake chip with `chip`; the start-up traffic is cleared.
fn setup_with(config: lan9252::Config, chip: Lan9252Config) -> (Driver, TestMaster, Probe) {
    let emu = Emulator::new(lan9252_esc());
    let probe = Probe::default();
    let spi = FakeSpi::new(Lan9252Chip::new(emu.clone(), chip), probe.clone());
    let driver = finish(Lan9252::start(spi, config)).expect("start");
    probe.take_log();
    (driver, TestMaster::new(emu), probe)
}

fn setup() -> (Driver, TestMaster, Probe) {
    setup_with(lan9252::Config::default(), Lan9252Config::default())
}

/// Transactions and bytes since the last call.
fn traffic(probe: &Probe) -> SpiStats {
    let log = probe.take_log();
    SpiStats {
        transactions: log.len() as u64,
        bytes: log.iter().map(|t| t.len() as u64).sum(),
    }
}

/// The CSR read of `size` bytes at `address` the driver sends: marker and command in one
/// auto-incrementing write, then a read of the data register.
fn csr_read(address: u16, size: u8) -> Vec<Vec<u8>> {
    let [lo, hi] = address.to_le_bytes();
    vec![
        vec![0x02, 0x43, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, lo, hi, size, 0xC0],
        vec![0x03, 0x03, 0x00, 0, 0, 0, 0],
    ]
}

#[test]
fn start_up_resets_checks_byte_order_and_readiness_and_enables_the_irq() {
    let emu = Emulator::new(lan9252_esc());
    let probe = Probe::default();
    let spi = FakeSpi::new(
        Lan9252Chip::new(emu, Lan9252Config::default()),
        probe.clone(),
    );
    finish(Lan9252::start(spi, lan9252::Config::default())).expect("start");
    assert_eq!(
        probe.take_log(),
        vec![
            // RESET_CTL (0x01F8) = DIGITAL_RST.
            vec![0x02, 0x01, 0xF8, 0x01, 0x00, 0x00, 0x00],
            // BYTE_TEST (0x0064), HW_CFG (0x0074).
            vec![0x03, 0x00, 0x64, 0, 0, 0, 0],
            vec![0x03, 0x00, 0x74, 0, 0, 0, 0],
            // IRQ_CFG (0x0054) = IRQ_EN | push-pull, active low; INT_EN (0x005C) = ECAT_EVENT_EN.
            vec![0x02, 0x00, 0x54, 0x01, 0x01, 0x00, 0x00],
            vec![0x02, 0x00, 0x5C, 0x01, 0x00, 0x00, 0x00],
        ]
    );
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn register_reads_go_through_the_csr_interface_with_a_marker_instead_of_a_busy_poll() {
    let (mut driver, master, probe) = setup();
    master.write_al_control(0x0004);
    let mut control = [0; 2];
    let event = finish(driver.read(register::AL_CONTROL, &mut control)).expect("read");
    assert_eq!(control, [0x04, 0x00]);
    assert_eq!(
        event,
        AlEvent::NONE,
        "a register read does not read the AL event register"
    );
    // ECAT_CSR_CMD = busy | read | size 2 | 0x0120.
    assert_eq!(probe.take_log(), csr_read(0x0120, 2));
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn register_accesses_follow_the_csr_address_vs_size_table() {
    let (mut driver, _master, probe) = setup();
    finish(driver.read(0x0121, &mut [0; 7])).expect("read");
    let commands: Vec<Vec<u8>> = probe
        .take_log()
        .into_iter()
        .filter(|t| t.len() == 11)
        .map(|t| t[7..].to_vec())
        .collect();
    // 0x0121: 1 byte, 0x0122: 2 bytes, 0x0124: 4 bytes.
    assert_eq!(
        commands,
        vec![
            vec![0x21, 0x01, 0x01, 0xC0],
            vec![0x22, 0x01, 0x02, 0xC0],
            vec![0x24, 0x01, 0x04, 0xC0],
        ]
    );
}

#[test]
fn register_writes_carry_data_and_command_in_one_transaction_then_wait_for_the_command() {
    let (mut driver, master, probe) = setup();
    finish(driver.write(register::AL_STATUS_CODE, &[0x11, 0x00])).expect("write");
    assert_eq!(
        probe.take_log(),
        vec![
            // ECAT_CSR_DATA = 0x0011, ECAT_CSR_CMD = busy | write | size 2 | 0x0134.
            vec![
                0x02, 0x43, 0x00, 0x11, 0x00, 0x00, 0x00, 0x34, 0x01, 0x02, 0x80
            ],
            vec![0x03, 0x03, 0x04, 0, 0, 0, 0],
        ]
    );
    assert_eq!(master.al_status_code(), 0x0011);
}

#[test]
fn a_register_that_holds_the_marker_value_is_still_read_correctly() {
    let (mut driver, _master, probe) = setup();
    finish(driver.write(register::AL_EVENT_MASK, &[0xFF; 4])).expect("write");
    probe.take_log();
    let mut mask = [0; 4];
    finish(driver.read(register::AL_EVENT_MASK, &mut mask)).expect("read");
    assert_eq!(mask, [0xFF; 4]);
    let mut expected = csr_read(0x0204, 4);
    // The data register reads the marker: is the command done? Yes: read the data again.
    expected.push(vec![0x03, 0x03, 0x04, 0, 0, 0, 0]);
    expected.push(vec![0x03, 0x03, 0x00, 0, 0, 0, 0]);
    assert_eq!(probe.take_log(), expected);
}

#[test]
fn a_slow_csr_command_is_waited_for() {
    let chip = Lan9252Config {
        csr_latency: 1,
        ..Lan9252Config::default()
    };
    let (mut driver, master, probe) = setup_with(lan9252::Config::default(), chip);
    master.write_al_control(0x0002);
    let mut control = [0; 2];
    finish(driver.read(register::AL_CONTROL, &mut control)).expect("read");
    assert_eq!(control, [0x02, 0x00]);
    let mut expected = csr_read(0x0120, 2);
    expected.push(vec![0x03, 0x03, 0x04, 0, 0, 0, 0]);
    expected.push(vec![0x03, 0x03, 0x00, 0, 0, 0, 0]);
    assert_eq!(probe.take_log(), expected);
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn process_ram_reads_fetch_the_al_event_then_drain_the_fifo() {
    let (mut driver, master, probe) = setup();
    let data: Vec<u8> = (1..=11).collect();
    assert!(master.write(0x1100, &data));
    master.write_al_control(0x0002);
    let mut buf = [0; 11];
    let event = finish(driver.read(0x1100, &mut buf)).expect("read");
    assert_eq!(buf.to_vec(), data);
    assert_eq!(event, AlEvent::AL_CONTROL, "fresh AL event");
    let mut expected = csr_read(0x0220, 4);
    expected.extend([
        // ECAT_PRAM_RD_ADDR_LEN = 11 bytes at 0x1100, ECAT_PRAM_RD_CMD = busy.
        vec![
            0x02, 0x43, 0x08, 0x00, 0x11, 0x0B, 0x00, 0x00, 0x00, 0x00, 0x80,
        ],
        // ECAT_PRAM_RD_CMD: DWORDs available.
        vec![0x03, 0x03, 0x0C, 0, 0, 0, 0],
        // Three DWORDs from the FIFO at 0x0000, address fixed.
        [vec![0x03, 0x00, 0x00], vec![0; 12]].concat(),
    ]);
    assert_eq!(probe.take_log(), expected);
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn process_ram_writes_start_the_command_and_fill_the_fifo_without_polling() {
    let (mut driver, master, probe) = setup();
    let data: Vec<u8> = (1..=11).collect();
    finish(driver.write(0x1180, &data)).expect("write");
    assert_eq!(master.read(0x1180, 11), Some(data.clone()));
    assert_eq!(
        probe.take_log(),
        vec![
            vec![
                0x02, 0x43, 0x10, 0x80, 0x11, 0x0B, 0x00, 0x00, 0x00, 0x00, 0x80,
            ],
            [vec![0x02, 0x00, 0x20], data, vec![0]].concat(),
        ]
    );
}

#[test]
fn unaligned_process_ram_uses_byte_lanes() {
    let (mut driver, master, probe) = setup();
    finish(driver.write(0x1103, &[1, 2, 3])).expect("write");
    let log = probe.take_log();
    assert_eq!(log[1], vec![0x02, 0x00, 0x20, 0, 0, 0, 1, 2, 3, 0, 0]);
    assert_eq!(master.read(0x1102, 5), Some(vec![0, 1, 2, 3, 0]));
    assert!(master.write(0x1201, &[9, 8, 7, 6, 5]));
    let mut buf = [0; 5];
    finish(driver.read(0x1201, &mut buf)).expect("read");
    assert_eq!(buf, [9, 8, 7, 6, 5]);
    assert_eq!(probe.take_log().last().map(Vec::len), Some(3 + 8));
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn transfers_larger_than_the_fifo_take_several_loads() {
    for write_space in [WriteSpace::EmptyAtStart, WriteSpace::Polled] {
        for fifo_fill in [16, 3] {
            let config = lan9252::Config {
                write_space,
                ..lan9252::Config::default()
            };
            let chip = Lan9252Config {
                fifo_fill,
                ..Lan9252Config::default()
            };
            let (mut driver, master, probe) = setup_with(config, chip);
            let data: Vec<u8> = (0..150u8).collect();
            finish(driver.write(0x1401, &data)).expect("write");
            assert_eq!(master.read(0x1401, 150), Some(data.clone()));
            let mut buf = vec![0; 150];
            finish(driver.read(0x1401, &mut buf)).expect("read");
            assert_eq!(buf, data, "{write_space:?}, fill {fifo_fill}");
            assert!(probe.violations().is_empty(), "{:?}", probe.violations());
        }
    }
}

#[test]
fn polled_writes_read_the_space_count_first() {
    let config = lan9252::Config {
        write_space: WriteSpace::Polled,
        ..lan9252::Config::default()
    };
    let (mut driver, _master, probe) = setup_with(config, Lan9252Config::default());
    finish(driver.write(0x1180, &[0; 11])).expect("write");
    let log = probe.take_log();
    assert_eq!(log[1], vec![0x03, 0x03, 0x14, 0, 0, 0, 0]);
    assert_eq!(log.len(), 3);
}

#[test]
fn fast_read_adds_the_dummy_byte() {
    let config = lan9252::Config {
        read: ReadInstruction::FastRead,
        ..lan9252::Config::default()
    };
    let (mut driver, _master, probe) = setup_with(config, Lan9252Config::default());
    finish(driver.read(register::AL_STATUS, &mut [0; 2])).expect("read");
    let log = probe.take_log();
    assert_eq!(log[1], vec![0x0B, 0x03, 0x00, 0x00, 0, 0, 0, 0]);
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

/// What each access reports: a fresh AL event for process-RAM reads and reads of 0x0220; the
/// state-machine events known to be pending for everything else, until a read clears them.
#[test]
fn al_event_reporting() {
    let (mut driver, master, probe) = setup();
    master.write_al_control(0x0002);
    let mut buf = [0; 4];
    let fresh = finish(driver.read(0x1000, &mut buf)).expect("read");
    assert_eq!(fresh, AlEvent::AL_CONTROL);
    probe.take_log();
    let known = finish(driver.read(register::AL_STATUS, &mut buf[..2])).expect("read");
    assert_eq!(known, AlEvent::AL_CONTROL, "still pending");
    assert_eq!(traffic(&probe).transactions, 2, "no AL event read");
    let before_clear = finish(driver.read(register::AL_CONTROL, &mut buf[..2])).expect("read");
    assert_eq!(
        before_clear,
        AlEvent::AL_CONTROL,
        "sampled before the access"
    );
    let after = finish(driver.write(register::AL_STATUS, &[2, 0])).expect("write");
    assert_eq!(after, AlEvent::NONE, "reading AL control cleared it");
    assert_eq!(master.al_status(), 0x0002);

    master.write_al_control(0x0004);
    probe.take_log();
    let explicit = finish(driver.read(register::AL_EVENT_REQUEST, &mut buf)).expect("read");
    assert_eq!(
        explicit,
        AlEvent::AL_CONTROL,
        "0x0220 read reports its own value"
    );
    assert_eq!(buf, [1, 0, 0, 0]);
    assert_eq!(traffic(&probe), traffic_of(csr_read(0x0220, 4)));
    let known = finish(driver.write(register::AL_STATUS, &[4, 0])).expect("write");
    assert_eq!(known, AlEvent::AL_CONTROL);
}

#[test]
fn buffer_events_are_reported_only_by_the_read_that_saw_them() {
    let (mut driver, master, _probe) = setup();
    master.configure_sm(2, 0x1100, 11, ecat_emu::master::SM2_CONTROL, true);
    assert!(master.write(0x1100, &[5; 11]));
    let sm2 = AlEvent::sync_manager(2);
    let mut buf = [0; 11];
    let event = finish(driver.read(0x1100, &mut buf)).expect("read");
    assert!(event.contains(sm2), "{event:?}");
    assert_eq!(buf, [5; 11]);
    let next = finish(driver.write(0x1180, &[0; 11])).expect("write");
    assert_eq!(
        next,
        AlEvent::SM_CHANGE,
        "the read cleared the SM2 event; the SM change (no SM register read yet) is still pending"
    );
}

/// On the IRQ the process-data runner samples the AL event (an empty read) and reads the output
/// area only when SM2 is among the events: the PRAM read right after reports the sample instead
/// of reading the AL event again (one AL event read per cycle). With any access between them it
/// reads it again.
#[test]
fn a_process_ram_read_right_after_an_empty_read_reports_its_event() {
    let (mut driver, master, probe) = setup();
    master.configure_sm(2, 0x1100, 11, ecat_emu::master::SM2_CONTROL, true);
    assert!(master.write(0x1100, &[5; 11]));
    let sm2 = AlEvent::sync_manager(2);
    let sampled = finish(driver.read(0x1100, &mut [])).expect("read");
    assert!(sampled.contains(sm2), "{sampled:?}");
    assert_eq!(probe.take_log(), csr_read(0x0220, 4), "the AL event alone");
    let mut buf = [0; 11];
    let reported = finish(driver.read(0x1100, &mut buf)).expect("read");
    assert_eq!(reported, sampled);
    assert_eq!(buf, [5; 11]);
    let log = probe.take_log();
    assert_eq!(
        log.iter().map(|t| t[..3].to_vec()).collect::<Vec<_>>(),
        vec![
            vec![0x02, 0x43, 0x08],
            vec![0x03, 0x03, 0x0C],
            vec![0x03, 0x00, 0x00]
        ],
        "PRAM start, available count, FIFO: no CSR command"
    );

    finish(driver.read(register::AL_EVENT_REQUEST, &mut [])).expect("read");
    finish(driver.read(register::AL_STATUS, &mut [0; 2])).expect("read");
    probe.take_log();
    let again = finish(driver.read(0x1100, &mut buf)).expect("read");
    assert!(
        !again.intersects(sm2),
        "the first PRAM read took the buffer"
    );
    assert_eq!(probe.take_log()[..2], csr_read(0x0220, 4)[..], "read again");
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

fn traffic_of(log: Vec<Vec<u8>>) -> SpiStats {
    SpiStats {
        transactions: log.len() as u64,
        bytes: log.iter().map(|t| t.len() as u64).sum(),
    }
}

#[test]
fn bus_errors_reach_the_caller() {
    let (mut driver, _master, probe) = setup();
    probe.fail_next();
    assert_eq!(
        finish(driver.read(0x1000, &mut [0; 4])),
        Err(lan9252::Error::Spi(BusError))
    );
    probe.fail_next();
    assert_eq!(
        finish(driver.write(0x0130, &[0; 2])),
        Err(lan9252::Error::Spi(BusError))
    );
}

/// The fake rejects what a LAN9252 would: these streams are sent by hand, not by the driver.
#[test]
fn the_fake_chip_flags_malformed_streams() {
    use embedded_hal_async::spi::SpiDevice;
    let emu = Emulator::new(lan9252_esc());
    let probe = Probe::default();
    let mut spi = FakeSpi::new(
        Lan9252Chip::new(emu, Lan9252Config::default()),
        probe.clone(),
    );
    let cases: [(&[u8], &str); 8] = [
        (&[0x3B, 0x00, 0x64, 0, 0, 0, 0], "instruction"),
        (&[0x03, 0x00, 0x66, 0, 0, 0, 0], "aligned"),
        (&[0x03, 0x00, 0x64, 0, 0], "whole"),
        (&[0x03, 0x80, 0x64, 0, 0, 0, 0], "address mode"),
        (
            &[0x03, 0x00, 0x00, 0, 0, 0, 0],
            "read FIFO read while empty",
        ),
        (&[0x02, 0x00, 0x20, 0, 0, 0, 0], "without a write command"),
        // CSR command: size 4 at 0x0122 is not DWORD aligned.
        (
            &[0x02, 0x03, 0x04, 0x22, 0x01, 0x04, 0xC0],
            "is not allowed",
        ),
        (&[0x03, 0x01], "header"),
    ];
    for (stream, expected) in cases {
        let mut buf = stream.to_vec();
        finish(spi.transfer_in_place(&mut buf)).expect("transaction");
        let violations = probe.violations();
        let last = violations.last().expect("a violation");
        assert!(last.contains(expected), "{stream:02x?}: {last}");
    }
    assert_eq!(probe.violations().len(), cases.len());
}

/// A drive-like device on the LAN9252's ESC: 4 SyncManagers, 4 KiB of process RAM.
fn lan9252_drive(outputs: u16, inputs: u16) -> DeviceConfig {
    let mut config = DeviceConfig::new(common::MAILBOX, ProcessDataSizes { outputs, inputs });
    config.sync_manager_count = 4;
    config.process_ram_end = 0x2000;
    config
}

#[test]
fn a_subdevice_reaches_op_and_exchanges_process_data_over_spi() {
    let probe = Probe::default();
    let bus = probe.clone();
    let mut device = Device::new(lan9252_drive(12, 11), AcceptAll, Loopback);
    device.esc = lan9252_esc();
    harness::run_with_pdi(
        device,
        move |emu: &Emulator| {
            let chip = Lan9252Chip::new(emu.clone(), Lan9252Config::default());
            finish(Lan9252::start(
                FakeSpi::new(chip, bus),
                lan9252::Config::default(),
            ))
            .expect("start")
        },
        move |master| async move {
            walk_to(&master, AlState::Op).await;
            let (outputs, inputs) = (Area::new(0x1100, 12), Area::new(0x1180, 11));
            for cycle in 0u8..20 {
                let image: Vec<u8> = (0..12).map(|i| i ^ cycle).collect();
                let before = probe.stats();
                assert!(master.write(outputs.start, &image));
                master.settle().await;
                // AL event (11 + 7), PRAM read start, poll, FIFO (11 + 7 + 3 + 12), PRAM write
                // start and FIFO (11 + 3 + 12).
                assert_eq!(
                    probe.stats() - before,
                    SpiStats {
                        transactions: 7,
                        bytes: 18 + 33 + 26
                    },
                    "cycle {cycle}"
                );
                assert_eq!(
                    master.read(inputs.start, 11),
                    Some(image[..11].to_vec()),
                    "cycle {cycle}"
                );
            }
            assert_eq!(master.request(0x01).await, (0x01, 0), "back to INIT");
            assert!(probe.violations().is_empty(), "{:?}", probe.violations());
        },
    );
}
