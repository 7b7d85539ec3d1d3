//! The 16-bit asynchronous microcontroller interface driver (`ecat_embassy::mcu`) at the bus-cycle
//! level, against a fake ET1100 interface that performs each cycle as the chip does (ET1100
//! datasheet section II, "Asynchronous 8/16 bit microcontroller interface"), and end to end: the
//! real runners bring a SubDevice to OP through the driver.

mod common;

use common::{INPUTS, OUTPUTS, walk_to};
use ecat_core::{AlEvent, AlState, register};
use ecat_embassy::Pdi;
use ecat_embassy::mcu::Mcu16;
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::master::TestMaster;
use ecat_emu::mcu::{Cycle, Cycles, FakeBus16, et1100};
use ecat_emu::spi::{Probe, SpiStats};
use embassy_futures::block_on;

type Driver = Mcu16<FakeBus16>;

/// The driver on a fresh ESC `esc`, its MainDevice side, the cycle log and the bus probe.
fn setup_with(esc: EscConfig) -> (Driver, TestMaster, Cycles, Probe) {
    let emu = Emulator::new(esc);
    let (probe, cycles) = (Probe::default(), Cycles::default());
    let bus = FakeBus16::new(emu.clone(), probe.clone(), cycles.clone());
    (Mcu16::new(bus), TestMaster::new(emu), cycles, probe)
}

fn setup() -> (Driver, TestMaster, Cycles, Probe) {
    setup_with(et1100())
}

#[test]
fn a_read_samples_the_al_event_word_then_reads_words() {
    let (mut driver, master, cycles, probe) = setup();
    master.write_al_control(0x0002);
    let mut buf = [0xEE; 2];
    let event = block_on(driver.read(register::AL_CONTROL, &mut buf)).expect("read");
    assert_eq!(
        cycles.take(),
        vec![Cycle::Read(0x0220, 0x0001), Cycle::Read(0x0120, 0x0002)]
    );
    assert_eq!(buf, [0x02, 0x00]);
    assert_eq!(event, AlEvent::AL_CONTROL, "sampled before the access");
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn odd_ends_of_a_read_come_from_their_words_in_little_endian_order() {
    let (mut driver, master, cycles, _probe) = setup();
    assert!(master.write(0x1000, &[1, 2, 3, 4, 5, 6, 7, 8]));
    let mut buf = [0; 5];
    block_on(driver.read(0x1001, &mut buf)).expect("read");
    assert_eq!(buf, [2, 3, 4, 5, 6]);
    assert_eq!(
        cycles.take(),
        vec![
            Cycle::Read(0x0220, 0),
            Cycle::Read(0x1000, 0x0201),
            Cycle::Read(0x1002, 0x0403),
            Cycle::Read(0x1004, 0x0605),
        ]
    );
    let mut one = [0; 1];
    block_on(driver.read(0x1006, &mut one)).expect("read");
    assert_eq!(one, [7]);
    assert_eq!(
        cycles.take(),
        vec![Cycle::Read(0x0220, 0), Cycle::Read(0x1006, 0x0807)]
    );
}

#[test]
fn odd_ends_of_a_write_go_on_their_byte_lane_alone() {
    let (mut driver, master, cycles, probe) = setup();
    assert!(master.write(0x1100, &[0xEE; 8]));
    block_on(driver.write(0x1101, &[1, 2, 3, 4])).expect("write");
    assert_eq!(
        cycles.take(),
        vec![
            Cycle::Read(0x0220, 0),
            Cycle::WriteByte(0x1101, 1),
            Cycle::Write(0x1102, 0x0302),
            Cycle::WriteByte(0x1104, 4),
        ]
    );
    assert_eq!(
        master.read(0x1100, 8),
        Some(vec![0xEE, 1, 2, 3, 4, 0xEE, 0xEE, 0xEE]),
        "the bytes around the access are untouched"
    );
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn an_empty_read_is_the_al_event_alone_and_an_empty_write_costs_nothing() {
    let (mut driver, master, cycles, probe) = setup();
    master.write_al_control(0x0002);
    let seen = block_on(driver.read(register::AL_EVENT_REQUEST, &mut []));
    assert_eq!(seen, Ok(AlEvent::AL_CONTROL));
    assert_eq!(block_on(driver.write(0x1000, &[])), Ok(AlEvent::NONE));
    assert_eq!(cycles.take(), vec![Cycle::Read(0x0220, 0x0001)]);
    assert_eq!(
        probe.stats(),
        SpiStats {
            transactions: 1,
            bytes: 2
        }
    );
}

#[test]
fn a_read_right_after_an_empty_read_reports_its_event_without_reading_it_again() {
    let (mut driver, master, cycles, _probe) = setup();
    master.write_al_control(0x0002);
    assert_eq!(
        block_on(driver.read(register::AL_EVENT_REQUEST, &mut [])),
        Ok(AlEvent::AL_CONTROL)
    );
    let mut buf = [0; 2];
    // The AL control register's read clears the event; the report is the sample before it.
    assert_eq!(
        block_on(driver.read(register::AL_CONTROL, &mut buf)),
        Ok(AlEvent::AL_CONTROL)
    );
    // Not after another access: this read samples again.
    assert_eq!(
        block_on(driver.read(register::AL_CONTROL, &mut buf)),
        Ok(AlEvent::NONE)
    );
    assert_eq!(
        cycles.take(),
        vec![
            Cycle::Read(0x0220, 0x0001),
            Cycle::Read(0x0120, 0x0002),
            Cycle::Read(0x0220, 0),
            Cycle::Read(0x0120, 0x0002),
        ]
    );
}

#[test]
fn chunks_end_at_even_addresses() {
    let (driver, ..) = setup();
    assert_eq!(driver.chunk(0x1000, 10, 32), 10, "short enough: whole");
    assert_eq!(driver.chunk(0x1000, 128, 31), 30);
    assert_eq!(
        driver.chunk(0x1001, 128, 32),
        31,
        "the next chunk starts at 0x1020"
    );
    assert_eq!(driver.chunk(0x1000, 128, 1), 2, "at least a word");
}

#[test]
fn an_esc_without_the_microcontroller_interface_does_not_answer() {
    // The default ET1100: its EEPROM selects the SPI slave (0x0140 = 0x05).
    let (mut driver, _master, cycles, probe) = setup_with(EscConfig::default());
    let mut buf = [0; 2];
    block_on(driver.read(0x1000, &mut buf)).expect("read");
    assert_eq!(buf, [0xFF, 0xFF], "undriven data lines");
    assert_eq!(cycles.take().len(), 2);
    let violations = probe.violations();
    assert_eq!(violations.len(), 1, "{violations:?}");
    assert!(violations[0].contains("0x0140 = 0x05"), "{violations:?}");
}

#[test]
fn a_subdevice_reaches_op_and_exchanges_process_data_over_the_bus() {
    let probe = Probe::default();
    let cycles = Cycles::default();
    let (bus, log) = (probe.clone(), cycles.clone());
    let mut device = Device::new(common::drive(), AcceptAll, Loopback);
    device.esc = et1100();
    harness::run_with_pdi(
        device,
        move |emu: &Emulator| Mcu16::new(FakeBus16::new(emu.clone(), bus, log)),
        move |master| async move {
            walk_to(&master, AlState::Op).await;
            for cycle in 0u8..20 {
                let outputs: Vec<u8> = (0..OUTPUTS.length as u8).map(|i| i ^ cycle).collect();
                cycles.take();
                assert!(master.write(OUTPUTS.start, &outputs));
                master.settle().await;
                let word = |at: usize| u16::from_le_bytes([outputs[at], outputs[at + 1]]);
                // SM2's event (new outputs), and from the second cycle on SM3's (the MainDevice
                // read the inputs).
                let sm3 = if cycle == 0 { 0 } else { 1 << 11 };
                let events = (1 << 10) | sm3;
                // The AL event alone (an empty read); 0x1100: 6 words (12 bytes), reporting
                // that event; 0x1180: the AL event, 5 words and the 11th byte alone, last.
                let mut expected = vec![Cycle::Read(0x0220, events)];
                expected
                    .extend((0..6).map(|i| Cycle::Read(0x1100 + 2 * i, word(2 * usize::from(i)))));
                expected.push(Cycle::Read(0x0220, sm3));
                expected
                    .extend((0..5).map(|i| Cycle::Write(0x1180 + 2 * i, word(2 * usize::from(i)))));
                expected.push(Cycle::WriteByte(0x118A, outputs[10]));
                assert_eq!(cycles.take(), expected, "cycle {cycle}");
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
