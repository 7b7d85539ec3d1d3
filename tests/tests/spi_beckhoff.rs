//! The Beckhoff ESC SPI driver at the byte level, against a fake ESC that decodes the stream as an
//! ET1100 does (ESC datasheet section II, "SPI Slave Interface"), and end to end: the real
//! runners bring a SubDevice to OP through the driver.

mod common;

use common::{INPUTS, OUTPUTS, walk_to};
use ecat_core::{AlEvent, AlState, register};
use ecat_embassy::Pdi;
use ecat_embassy::spi::beckhoff::{BeckhoffSpi, BeckhoffSpiPerByte, Config, ReadLatency};
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::master::TestMaster;
use ecat_emu::spi::beckhoff::BeckhoffEsc;
use ecat_emu::spi::{BusError, FakeSpi, Probe, SpiStats};
use embassy_futures::block_on;

type Driver = BeckhoffSpi<FakeSpi<BeckhoffEsc>>;

/// A driver with `config` on a fresh ET1100-like ESC, the ESC's MainDevice side and the bus probe.
fn setup_with(config: Config, esc: EscConfig) -> (Driver, TestMaster, Probe) {
    let emu = Emulator::new(esc);
    let probe = Probe::default();
    let spi = FakeSpi::new(BeckhoffEsc::new(emu.clone()), probe.clone());
    (BeckhoffSpi::new(spi, config), TestMaster::new(emu), probe)
}

fn setup() -> (Driver, TestMaster, Probe) {
    setup_with(Config::default(), EscConfig::default())
}

#[test]
fn read_below_0x2000_uses_2_byte_addressing_wait_state_and_termination() {
    let (mut driver, master, probe) = setup();
    master.write_al_control(0x0002);
    let mut buf = [0xEE; 2];
    let event = block_on(driver.read(register::AL_CONTROL, &mut buf)).expect("read");
    // 0x0120: A[12:5] = 0x09, A[4:0] = 0x00, CMD0 = 011b; wait state; 0x00, then 0xFF.
    assert_eq!(probe.take_log(), vec![vec![0x09, 0x03, 0xFF, 0x00, 0xFF]]);
    assert_eq!(buf, [0x02, 0x00]);
    assert_eq!(
        event,
        AlEvent::AL_CONTROL,
        "AL event from the address phase"
    );
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn address_bits_are_placed_as_the_datasheet_tables_say() {
    let (mut driver, _master, probe) = setup();
    for address in [0x0000u16, 0x0134, 0x1FFF] {
        block_on(driver.read(address, &mut [0; 1])).expect("read");
    }
    assert_eq!(
        probe.take_log(),
        vec![
            vec![0x00, 0x03, 0xFF, 0xFF],
            vec![0x09, 0xA3, 0xFF, 0xFF],
            vec![0xFF, 0xFB, 0xFF, 0xFF],
        ]
    );
}

#[test]
fn from_0x2000_on_reads_use_3_byte_addressing() {
    let (mut driver, master, probe) = setup();
    assert!(master.write(0x2F21, &[1, 2, 3]));
    let mut buf = [0; 3];
    block_on(driver.read(0x2F21, &mut buf)).expect("read");
    block_on(driver.read(0x2000, &mut [0; 1])).expect("read");
    // A[12:5] = 0x79, A[4:0] = 00001b with CMD0 = 110b, A[15:13] = 001b with CMD1 = 011b.
    assert_eq!(
        probe.take_log(),
        vec![
            vec![0x79, 0x0E, 0x2C, 0xFF, 0x00, 0x00, 0xFF],
            vec![0x00, 0x06, 0x2C, 0xFF, 0xFF],
        ]
    );
    assert_eq!(buf, [1, 2, 3]);
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn writes_use_command_100b_and_no_wait_state() {
    let (mut driver, master, probe) = setup();
    block_on(driver.write(register::AL_STATUS_CODE, &[0x11, 0x00])).expect("write");
    block_on(driver.write(0x2F00, &[0xAB])).expect("write");
    assert_eq!(
        probe.take_log(),
        vec![vec![0x09, 0xA4, 0x11, 0x00], vec![0x78, 0x06, 0x30, 0xAB]]
    );
    assert_eq!(master.al_status_code(), 0x0011);
    assert_eq!(master.read(0x2F00, 1), Some(vec![0xAB]));
}

#[test]
fn a_whole_region_is_one_transaction() {
    let (mut driver, master, probe) = setup();
    let image: Vec<u8> = (0..=255).collect();
    assert!(master.write(0x1400, &image));
    let mut buf = vec![0; 256];
    block_on(driver.read(0x1400, &mut buf)).expect("read");
    block_on(driver.write(0x1600, &image)).expect("write");
    assert_eq!(buf, image);
    assert_eq!(master.read(0x1600, 256), Some(image));
    assert_eq!(
        probe.stats(),
        SpiStats {
            transactions: 2,
            bytes: (3 + 256) + (2 + 256)
        }
    );
}

#[test]
fn three_byte_addressing_also_delivers_al_event_byte_0x0222() {
    let esc = EscConfig {
        sync_managers: 16,
        ..EscConfig::default()
    };
    let (mut driver, master, _probe) = setup_with(Config::default(), esc);
    master.configure_sm(8, 0x1800, 16, ecat_emu::master::SM0_CONTROL, true);
    assert!(master.write(0x1800, &[0; 16]), "mailbox SM8 filled");
    let sm8 = AlEvent::sync_manager(8);
    assert_eq!(sm8, AlEvent(1 << 16));
    let low = block_on(driver.read(0x1000, &mut [0; 1])).expect("read");
    let high = block_on(driver.read(0x2000, &mut [0; 1])).expect("read");
    assert!(
        !low.intersects(sm8),
        "2-byte addressing carries 0x0220..0x0221 only"
    );
    assert!(
        high.contains(sm8),
        "3-byte addressing carries 0x0222: {high:?}"
    );
}

#[test]
fn slow_clock_reads_use_command_010b_without_wait_state() {
    let config = Config {
        read_latency: ReadLatency::SlowClock,
    };
    let (mut driver, _master, probe) = setup_with(config, EscConfig::default());
    block_on(driver.read(register::AL_CONTROL, &mut [0; 2])).expect("read");
    block_on(driver.read(0x2000, &mut [0; 1])).expect("read");
    assert_eq!(
        probe.take_log(),
        vec![vec![0x09, 0x02, 0x00, 0xFF], vec![0x00, 0x06, 0x28, 0xFF]]
    );
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn per_byte_fallback_sends_one_terminated_transaction_per_byte() {
    let emu = Emulator::new(EscConfig::default());
    let probe = Probe::default();
    let spi = FakeSpi::new(BeckhoffEsc::new(emu.clone()), probe.clone());
    let (mut driver, master) = (
        BeckhoffSpiPerByte::new(spi, Config::default()),
        TestMaster::new(emu),
    );
    assert!(master.write(0x1FFF, &[7, 8]));
    master.write_al_control(0x0001);
    let mut control = [0; 2];
    // Reading 0x0120 clears the AL control event: the event reported is the one sampled before the
    // access, i.e. in the first transaction.
    let event = block_on(driver.read(register::AL_CONTROL, &mut control)).expect("read");
    assert_eq!((control, event), ([0x01, 0x00], AlEvent::AL_CONTROL));
    let mut buf = [0; 2];
    block_on(driver.read(0x1FFF, &mut buf)).expect("read");
    block_on(driver.write(0x1100, &[5, 6])).expect("write");
    assert_eq!(buf, [7, 8]);
    assert_eq!(
        probe.take_log(),
        vec![
            vec![0x09, 0x03, 0xFF, 0xFF],
            vec![0x09, 0x0B, 0xFF, 0xFF],
            vec![0xFF, 0xFB, 0xFF, 0xFF],
            vec![0x00, 0x06, 0x2C, 0xFF, 0xFF],
            vec![0x88, 0x04, 0x05],
            vec![0x88, 0x0C, 0x06],
        ]
    );
    assert_eq!(master.read(0x1100, 2), Some(vec![5, 6]));
}

#[test]
fn an_empty_access_is_a_nop_that_brings_the_al_event() {
    let (mut driver, master, probe) = setup();
    master.write_al_control(0x0002);
    let seen = block_on(driver.read(register::AL_EVENT_REQUEST, &mut []));
    assert_eq!(seen, Ok(AlEvent::AL_CONTROL));
    // 0x0220 = A[12:5] 0x11, A[4:0] 0 with CMD0 000b (NOP): the address phase alone.
    assert_eq!(probe.take_log(), vec![vec![0x11, 0x00]]);
    // An empty write as well: a NOP at its address, no write command.
    let seen = block_on(driver.write(0x1000, &[]));
    assert_eq!(seen, Ok(AlEvent::AL_CONTROL));
    assert_eq!(probe.take_log(), vec![vec![0x80, 0x00]]);
    assert_eq!(
        probe.stats(),
        SpiStats {
            transactions: 2,
            bytes: 4
        }
    );
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn bus_errors_reach_the_caller() {
    let (mut driver, _master, probe) = setup();
    probe.fail_next();
    assert_eq!(block_on(driver.read(0x1000, &mut [0; 4])), Err(BusError));
    probe.fail_next();
    assert_eq!(block_on(driver.write(0x1000, &[0; 4])), Err(BusError));
}

/// The fake rejects what an ESC would: these streams are sent by hand, not by the driver.
#[test]
fn the_fake_esc_flags_malformed_reads() {
    use embedded_hal_async::spi::SpiDevice;
    let emu = Emulator::new(EscConfig::default());
    let probe = Probe::default();
    let mut spi = FakeSpi::new(BeckhoffEsc::new(emu), probe.clone());
    let cases: [(&[u8], &str); 5] = [
        (&[0x09, 0x03, 0xFF, 0x00, 0x00], "read not terminated"),
        (
            &[0x09, 0x03, 0xFF, 0xFF, 0xFF],
            "only the last byte may be non-zero",
        ),
        (&[0x09, 0x03, 0x00, 0x00, 0xFF], "wait state byte"),
        (&[0x09, 0x01, 0x00], "reserved command"),
        (&[0x09], "address phase"),
    ];
    for (stream, expected) in cases {
        let mut buf = stream.to_vec();
        block_on(spi.transfer_in_place(&mut buf)).expect("transaction");
        let violations = probe.violations();
        let last = violations.last().expect("a violation");
        assert!(last.contains(expected), "{stream:02x?}: {last}");
    }
    assert_eq!(probe.violations().len(), cases.len());
}

#[test]
fn a_subdevice_reaches_op_and_exchanges_process_data_over_spi() {
    let probe = Probe::default();
    let bus = probe.clone();
    harness::run_with_pdi(
        Device::new(common::drive(), AcceptAll, Loopback),
        move |emu: &Emulator| {
            BeckhoffSpi::new(
                FakeSpi::new(BeckhoffEsc::new(emu.clone()), bus),
                Config::default(),
            )
        },
        move |master| async move {
            walk_to(&master, AlState::Op).await;
            for cycle in 0u8..20 {
                let outputs: Vec<u8> = (0..OUTPUTS.length as u8).map(|i| i ^ cycle).collect();
                let before = probe.stats();
                assert!(master.write(OUTPUTS.start, &outputs));
                master.settle().await;
                // The AL event (a NOP: 2 bytes), then 0x1100: read with wait state, 12 bytes;
                // 0x1180: write, 11 bytes.
                assert_eq!(
                    probe.stats() - before,
                    SpiStats {
                        transactions: 3,
                        bytes: 2 + (3 + 12) + (2 + 11)
                    },
                    "cycle {cycle}"
                );
                assert_eq!(
                    master.read(INPUTS.start, usize::from(INPUTS.length)),
                    Some(outputs[..usize::from(INPUTS.length)].to_vec())
                );
            }
            assert_eq!(master.request(0x01).await, (0x01, 0), "back to INIT");
            assert!(probe.violations().is_empty(), "{:?}", probe.violations());
        },
    );
}
