//! The ESC configuration area (SII words 0..7, ETG.1000.6 §5.4; ESC datasheet section II,
//! "EEPROM configuration area") as a real board lives with it: the ESC loads it at EEPROM load,
//! the SPI slave answers only in the PDI type and SPI mode it sets, the SYNC unit pulses SYNC0
//! only when it is on, and a pulse length of 0 is acknowledge mode. Each test runs a wrong area
//! next to the stack's and shows the difference.

use ecat_core::chip::{Chip, ConfigArea, SpiMode};
use ecat_embassy::Pdi;
use ecat_embassy::spi::beckhoff::{self, BeckhoffSpi, Config};
use ecat_embassy::spi::lan9252;
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness;
use ecat_emu::spi::beckhoff::BeckhoffEsc;
use ecat_emu::spi::lan9252::{Lan9252Chip, Lan9252Config};
use ecat_emu::spi::{BUS_MODE, FakeSpi, Probe};
use embassy_futures::block_on;
use embassy_time::Duration;
use embedded_hal_async::spi::SpiDevice;

/// A board with `chip` whose EEPROM holds `area`.
fn board(chip: Chip, area: ConfigArea) -> Emulator {
    Emulator::new(EscConfig {
        eeprom: Some(area),
        ..EscConfig::of(chip)
    })
}

/// The drivers' SPI mode is the mode the stack's area sets in the Beckhoff SPI slave (0x0150
/// bits 1:0) and the mode the fakes' bus runs in; the LAN9252 takes it (modes 0 and 3).
#[test]
fn the_drivers_spi_mode_is_the_one_the_area_sets() {
    assert_eq!(beckhoff::SPI_MODE, SpiMode::Mode3);
    assert_eq!(lan9252::SPI_MODE, SpiMode::Mode3);
    assert_eq!(BUS_MODE, beckhoff::SPI_MODE);
    for chip in [Chip::ET1100, Chip::AX58100] {
        for dc in [false, true] {
            let area = ConfigArea::new(&chip, dc);
            assert_eq!(area.pdi_control, 0x05, "{}: SPI slave", chip.name);
            assert_eq!(area.pdi_configuration & 0b11, beckhoff::SPI_MODE as u8);
        }
    }
    assert_eq!(ConfigArea::new(&Chip::LAN9252, true).pdi_control, 0x80);
}

/// The type register (0x0000) through the Beckhoff SPI driver in its mode, on an ET1100 whose
/// EEPROM holds `area`; and what the fake chip flagged.
fn beckhoff_reads_type(area: ConfigArea, bus: SpiMode) -> ([u8; 2], Vec<String>) {
    let probe = Probe::default();
    let spi = FakeSpi::with_mode(
        BeckhoffEsc::new(board(Chip::ET1100, area)),
        probe.clone(),
        bus,
    );
    let mut driver = BeckhoffSpi::new(spi, Config::default());
    let mut buf = [0; 2];
    block_on(driver.read(0x0000, &mut buf)).expect("read");
    (buf, probe.violations())
}

/// SPI mode 0 in 0x0150 against the mode-3 driver: the ESC samples on the other edges and
/// nothing it sends means anything (MISO stays high); so does a bus in mode 0 against the
/// stack's area, and an area that selects another PDI (the LAN9252's 0x80).
#[test]
fn a_beckhoff_esc_answers_only_in_the_pdi_and_spi_mode_its_area_sets() {
    let stack = ConfigArea::new(&Chip::ET1100, false);
    assert_eq!(
        beckhoff_reads_type(stack, beckhoff::SPI_MODE),
        ([0x11, 0x00], vec![]),
        "ET1100: type 0x11, revision 0"
    );
    let mode0 = ConfigArea {
        pdi_configuration: 0x00,
        ..stack
    };
    let (read, violations) = beckhoff_reads_type(mode0, beckhoff::SPI_MODE);
    assert_eq!(read, [0xFF, 0xFF]);
    assert_eq!(
        violations,
        [
            "bus in SPI mode 3, PDI configuration 0x0150 sets mode 0: the ESC does not understand the bus"
        ]
    );
    let (read, violations) = beckhoff_reads_type(stack, SpiMode::Mode0);
    assert_eq!(read, [0xFF, 0xFF]);
    assert!(
        violations[0].contains("bus in SPI mode 0"),
        "{violations:?}"
    );
    let lan = ConfigArea::new(&Chip::LAN9252, false);
    let (read, violations) = beckhoff_reads_type(lan, beckhoff::SPI_MODE);
    assert_eq!(read, [0xFF, 0xFF]);
    assert!(
        violations[0].contains("PDI control 0x0140 = 0x80"),
        "{violations:?}"
    );
}

/// `BYTE_TEST` (0x0064) read over SPI from a LAN9252 whose EEPROM holds `area`.
fn lan9252_byte_test(area: ConfigArea, bus: SpiMode) -> (u32, Vec<String>) {
    let probe = Probe::default();
    let chip = Lan9252Chip::new(board(Chip::LAN9252, area), Lan9252Config::default());
    let mut spi = FakeSpi::with_mode(chip, probe.clone(), bus);
    let mut buf = [0x03, 0x00, 0x64, 0, 0, 0, 0];
    block_on(spi.transfer_in_place(&mut buf)).expect("transaction");
    let value = u32::from_le_bytes(buf[3..].try_into().unwrap());
    (value, probe.violations())
}

/// The LAN9252's SPI host interface runs when its area selects SPI (0x80), in mode 0 or 3; an
/// ET1100 area (0x05) leaves it off, and the driver's byte-order test would never pass.
#[test]
fn a_lan9252_answers_only_when_its_area_selects_spi() {
    let stack = ConfigArea::new(&Chip::LAN9252, true);
    assert_eq!(
        lan9252_byte_test(stack, lan9252::SPI_MODE),
        (0x8765_4321, vec![])
    );
    assert_eq!(lan9252_byte_test(stack, SpiMode::Mode0).0, 0x8765_4321);
    let (read, violations) = lan9252_byte_test(stack, SpiMode::Mode1);
    assert_eq!(read, 0xFFFF_FFFF);
    assert!(violations[0].contains("modes 0 and 3"), "{violations:?}");
    let et1100 = ConfigArea::new(&Chip::ET1100, true);
    let (read, violations) = lan9252_byte_test(et1100, lan9252::SPI_MODE);
    assert_eq!(read, 0xFFFF_FFFF);
    assert!(
        violations[0].contains("PDI control 0x0140 = 0x05"),
        "{violations:?}"
    );
}

/// The sensor as a DC SYNC0 device on an ET1100 whose EEPROM holds `area` (its SII image with
/// words 0..7 replaced): SAFEOP, SYNC0 programmed to start in 2 ms with a 1 ms cycle, OP
/// requested; after 1.1 s, AL status and code and the SYNC0 edges the ESC made.
fn dc_sensor_with(area: impl FnOnce(ConfigArea) -> ConfigArea) -> (u16, u16, u64) {
    let mut sample = ecat_emu::devices::sensor_dc();
    let mut image = sample.eeprom();
    let area = area(ConfigArea::new(&sample.device.esc.chip, true));
    image[..16].copy_from_slice(&area.bytes());
    sample.device.eeprom = image;
    let result = std::rc::Rc::new(core::cell::Cell::new((0, 0, 0)));
    let out = result.clone();
    harness::run(sample.device, move |master| async move {
        master.configure_mailbox(&ecat_core::device::MailboxConfig::contiguous(0x1000, 128));
        assert_eq!(master.request(0x02).await, (0x02, 0));
        let start = (embassy_time::Instant::now() + Duration::from_millis(2)).as_micros() * 1_000;
        assert!(master.write(0x09A0, &1_000_000u32.to_le_bytes()));
        assert!(master.write(0x0990, &start.to_le_bytes()));
        assert!(master.write(0x0981, &[0x03]));
        master.configure_sm(2, 0x1100, 0, 0x64, false);
        master.configure_sm(3, 0x1180, 6, 0x20, true);
        assert_eq!(master.request(0x04).await, (0x04, 0));
        master.write_al_control(0x08);
        master.advance(Duration::from_millis(1_100)).await;
        let pulses = master.emulator().sync0_pulses();
        out.set((master.al_status(), master.al_status_code(), pulses));
    });
    result.get()
}

/// The stack's area: the SYNC out unit is on, SYNC0 pulses every millisecond and the device runs
/// in OP. An area with the unit off (0x0141 bit 2 clear, as every image had it before): no
/// SYNC0 ever, OP refused with 0x002D. SYNC0 not an output (0x0151 = 0, LATCH0): the same.
#[test]
fn sync0_pulses_only_with_the_sync_out_unit_on_and_sync0_an_output() {
    let (status, code, pulses) = dc_sensor_with(|area| area);
    assert_eq!((status, code), (0x08, 0));
    assert!((1_000..=1_100).contains(&pulses), "{pulses} SYNC0 edges");
    let off = dc_sensor_with(|area| ConfigArea {
        esc_configuration: 0,
        ..area
    });
    assert_eq!(off, (0x14, 0x002D, 0), "SYNC unit off");
    let latch = dc_sensor_with(|area| ConfigArea {
        sync_latch_configuration: 0,
        ..area
    });
    assert_eq!(latch, (0x14, 0x002D, 0), "SYNC0 pin a latch input");
}

/// Pulse length 0 is acknowledge mode: SYNC0 stays active until the PDI reads 0x098E, which the
/// stack never does, so the pin rises once. The device enters OP on that edge and falls back to
/// SAFEOP with 0x002C (SYNC0 lost) ten cycles later.
#[test]
fn a_pulse_length_of_0_gives_one_sync0_edge_and_then_sync0_is_lost() {
    let (status, code, pulses) = dc_sensor_with(|area| ConfigArea {
        sync_pulse_length: 0,
        ..area
    });
    assert_eq!((status, code, pulses), (0x14, 0x002C, 1));
}
