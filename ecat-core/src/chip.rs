//! ESC chips: what the silicon fixes (the DL information registers 0x0000..0x0009, ETG.1000.4
//! Table 31) and the EEPROM configuration area the stack writes for it (SII words 0..7,
//! ETG.1000.6 §5.4 Table 2; ESC datasheet section II, "EEPROM configuration area" and registers
//! 0x0140..0x0153, 0x0982, 0x0012).
//!
//! The ESC loads the configuration area into its registers when it loads the EEPROM; a wrong value
//! there breaks a real board before any firmware runs (a PDI of the wrong type or SPI mode answers
//! nothing; a SYNC unit left off never pulses SYNC0). So the area is a function of the chip and of
//! the device's DC support ([`ConfigArea::new`]), and the chip facts a PDI driver depends on (the
//! PDI type, the SPI mode) are the [`Chip`] constants the drivers take theirs from.
//!
//! | word | register | what the stack writes |
//! |---|---|---|
//! | 0 low | 0x0140 PDI control | the chip's SPI PDI ([`Chip::pdi_spi`]: 0x05 Beckhoff SPI slave, 0x80 the LAN9252's SPI) |
//! | 0 high | 0x0141 ESC configuration | bit 2 SYNC out unit on for a DC SYNC0 device, else 0; AL status not emulated (bit 0 = 0) |
//! | 1 low | 0x0150 PDI configuration | Beckhoff SPI: bits 1:0 the SPI mode, IRQ push-pull active low, SEL active low, normal sample; LAN9252: 0 |
//! | 1 high | 0x0151 SYNC/LATCH PDI configuration | DC SYNC0 device: SYNC0 an output, push-pull active high (0x06); else 0 |
//! | 2 | 0x0982 SYNC pulse length | 100 × 10 ns = 1 µs (0 would be acknowledge mode) |
//! | 3 | 0x0152 extended PDI configuration | 0 (none for an SPI PDI) |
//! | 4 | 0x0012 configured station alias | 0 |
//! | 5, 6 | chip-specific | AX58100: word 5 = 0x001A (host interface extend setting and drive strength); else 0 |
//! | 7 | checksum | CRC-8 of words 0..6 ([`crc8`]) |

use crate::DeviceConfig;
use crate::register::PROCESS_RAM;

/// An SPI mode: clock polarity (CPOL, bit 1) and phase (CPHA, bit 0), as the Beckhoff PDI
/// configuration register 0x0150 bits 1:0 encode it (ESC datasheet section II, 0x0150).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum SpiMode {
    /// CPOL 0, CPHA 0.
    Mode0 = 0,
    /// CPOL 0, CPHA 1.
    Mode1 = 1,
    /// CPOL 1, CPHA 0.
    Mode2 = 2,
    /// CPOL 1, CPHA 1: the mode Beckhoff recommends for its SPI slave (seed 000, 0x0150).
    Mode3 = 3,
}

impl SpiMode {
    /// The mode bits 1:0 of `bits` encode.
    pub const fn from_bits(bits: u8) -> Self {
        match bits & 0b11 {
            0 => Self::Mode0,
            1 => Self::Mode1,
            2 => Self::Mode2,
            _ => Self::Mode3,
        }
    }

    /// Clock idle high (CPOL = 1).
    pub const fn idle_high(self) -> bool {
        self as u8 & 0b10 != 0
    }

    /// Data captured on the second clock edge (CPHA = 1).
    pub const fn capture_on_second_edge(self) -> bool {
        self as u8 & 0b01 != 0
    }
}

/// Features register 0x0008 bit 2: distributed clocks (ETG.1000.4 Table 31).
pub const FEATURE_DC: u16 = 1 << 2;
/// Features register 0x0008 bit 3: 64-bit DC system time (ETG.1000.4 Table 31).
pub const FEATURE_DC_64: u16 = 1 << 3;
/// Features register 0x0008 bit 8: enhanced DC SYNC activation (ETG.1000.4 Table 31).
pub const FEATURE_DC_SYNC_ACTIVATION: u16 = 1 << 8;

/// An ESC chip: its DL information (ETG.1000.4 Table 31, registers 0x0000..0x0009) and its SPI
/// PDI. One `const` per chip; the PDI drivers in `ecat-embassy` take their SPI mode from here.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Chip {
    /// The chip's name.
    pub name: &'static str,
    /// 0x0000: type.
    pub esc_type: u8,
    /// 0x0001: revision.
    pub revision: u8,
    /// 0x0004: FMMUs.
    pub fmmus: u8,
    /// 0x0005: SyncManagers.
    pub sync_managers: u8,
    /// 0x0006: process RAM in KiB.
    pub ram_kib: u8,
    /// 0x0007: port descriptor, 2 bits a port (11b: MII); the boards use ports 0 and 1.
    pub port_descriptor: u8,
    /// 0x0008: features supported.
    pub features: u16,
    /// The PDI control value (0x0140) that selects the chip's SPI PDI.
    pub pdi_spi: u8,
    /// The SPI mode its PDI runs in, and the SPI bus with it.
    pub spi_mode: SpiMode,
    /// Whether 0x0150 bits 1:0 set the SPI mode (the Beckhoff SPI slave); the LAN9252's SPI host
    /// interface has no such setting: it takes modes 0 and 3 as the clock's idle level shows them.
    pub spi_mode_configured: bool,
    /// SII words 5 and 6 (reserved in ETG.1000.6 Table 2; some chips load them).
    pub vendor_words: [u16; 2],
}

impl Chip {
    /// Beckhoff ET1100 (ESC datasheet section III): type 0x11, 8 FMMUs, 8 SyncManagers, 8 KiB of
    /// process RAM, features 0x01FC (DC, 64-bit, low-jitter EBUS, enhanced link detection EBUS
    /// and MII, separate FCS errors, enhanced DC SYNC activation); SPI PDI 0x05 in mode 3.
    pub const ET1100: Chip = Chip {
        name: "ET1100",
        esc_type: 0x11,
        revision: 0x00,
        fmmus: 8,
        sync_managers: 8,
        ram_kib: 8,
        port_descriptor: 0x0F,
        features: 0x01FC,
        pdi_spi: 0x05,
        spi_mode: SpiMode::Mode3,
        spi_mode_configured: true,
        vendor_words: [0, 0],
    };

    /// ASIX AX58100: the ET1100's register set and SPI slave (PDI 0x05, mode 3); SII word 5 low
    /// byte is its "host interface extend setting and drive strength" register, 0x1A (INT edge
    /// pulse length, 8 mA drive, IO 9:0 drive select) as ASIX's sample configuration data
    /// (`050403440A00000000001A000000`) has it.
    pub const AX58100: Chip = Chip {
        name: "AX58100",
        vendor_words: [0x001A, 0],
        ..Self::ET1100
    };

    /// Microchip LAN9252 (LAN9252 datasheet, "EtherCAT CSR"): type 0xC0, 3 FMMUs, 4 SyncManagers,
    /// 4 KiB of process RAM, features 0x01CC (DC, 64-bit, enhanced link detection MII, separate
    /// FCS errors, enhanced DC SYNC activation; no EBUS); PDI control 0x80 selects its SPI host
    /// interface, which takes SPI mode 0 or 3 (the boards use 3) and has no mode setting in
    /// 0x0150.
    pub const LAN9252: Chip = Chip {
        name: "LAN9252",
        esc_type: 0xC0,
        revision: 0x02,
        fmmus: 3,
        sync_managers: 4,
        ram_kib: 4,
        port_descriptor: 0x0F,
        features: 0x01CC,
        pdi_spi: 0x80,
        spi_mode: SpiMode::Mode3,
        spi_mode_configured: false,
        vendor_words: [0, 0],
    };

    /// Every chip above.
    pub const ALL: [Chip; 3] = [Self::ET1100, Self::AX58100, Self::LAN9252];

    /// The chip called `name` (case-insensitive).
    pub fn by_name(name: &str) -> Option<Chip> {
        Self::ALL
            .into_iter()
            .find(|chip| chip.name.eq_ignore_ascii_case(name))
    }

    /// One past the last byte of process RAM.
    pub const fn process_ram_end(&self) -> u32 {
        PROCESS_RAM as u32 + self.ram_kib as u32 * 1024
    }

    /// Whether the chip has distributed clocks (features bit 2).
    pub const fn has_dc(&self) -> bool {
        self.features & FEATURE_DC != 0
    }

    /// `config` with this chip's SyncManager count and process RAM.
    pub const fn fit(&self, mut config: DeviceConfig) -> DeviceConfig {
        config.sync_manager_count = self.sync_managers;
        config.process_ram_end = self.process_ram_end();
        config
    }
}

/// 0x0141 bit 2: the DC SYNC out unit is on (0: off, power saving; no SYNC signals).
pub const ESC_CONFIG_SYNC_OUT: u8 = 1 << 2;
/// 0x0141 bit 3: the DC latch in unit is on.
pub const ESC_CONFIG_LATCH_IN: u8 = 1 << 3;
/// 0x0151 for a DC SYNC0 device: SYNC0 an output (bit 2), push-pull active high (bits 1:0 = 10b),
/// the rising edge the process-data runner waits on; SYNC1/LATCH1 a latch input.
pub const SYNC0_OUTPUT_ACTIVE_HIGH: u8 = 0x06;
/// 0x0982: the SYNC pulse length the stack writes, 100 × 10 ns = 1 µs. A length of 0 would be
/// acknowledge mode: SYNC0 stays active until the PDI reads 0x098E, which the stack never does.
pub const SYNC_PULSE_LENGTH: u16 = 100;

/// The ESC configuration area: SII words 0..6 as the ESC loads them into its registers
/// (ETG.1000.6 §5.4 Table 2; ESC datasheet section II, "EEPROM configuration area"), word 7
/// the checksum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ConfigArea {
    /// Word 0 low → 0x0140 PDI control.
    pub pdi_control: u8,
    /// Word 0 high → 0x0141 ESC configuration.
    pub esc_configuration: u8,
    /// Word 1 low → 0x0150 PDI configuration.
    pub pdi_configuration: u8,
    /// Word 1 high → 0x0151 SYNC/LATCH PDI configuration.
    pub sync_latch_configuration: u8,
    /// Word 2 → 0x0982 pulse length of the SYNC signals, in 10 ns.
    pub sync_pulse_length: u16,
    /// Word 3 → 0x0152 extended PDI configuration.
    pub extended_pdi_configuration: u16,
    /// Word 4 → 0x0012 configured station alias.
    pub station_alias: u16,
    /// Words 5 and 6.
    pub vendor_words: [u16; 2],
}

impl ConfigArea {
    /// The area the stack writes for `chip` and a device that does (`dc_sync0`) or does not
    /// support DC SYNC0: the chip's SPI PDI in its SPI mode, and for DC SYNC0 the SYNC out unit on
    /// and SYNC0 an active-high output with 1 µs pulses.
    pub const fn new(chip: &Chip, dc_sync0: bool) -> Self {
        let pdi_configuration = if chip.spi_mode_configured {
            chip.spi_mode as u8
        } else {
            0
        };
        Self {
            pdi_control: chip.pdi_spi,
            esc_configuration: if dc_sync0 { ESC_CONFIG_SYNC_OUT } else { 0 },
            pdi_configuration,
            sync_latch_configuration: if dc_sync0 {
                SYNC0_OUTPUT_ACTIVE_HIGH
            } else {
                0
            },
            sync_pulse_length: SYNC_PULSE_LENGTH,
            extended_pdi_configuration: 0,
            station_alias: 0,
            vendor_words: chip.vendor_words,
        }
    }

    /// Words 0..6.
    pub const fn words(&self) -> [u16; 7] {
        [
            u16::from_le_bytes([self.pdi_control, self.esc_configuration]),
            u16::from_le_bytes([self.pdi_configuration, self.sync_latch_configuration]),
            self.sync_pulse_length,
            self.extended_pdi_configuration,
            self.station_alias,
            self.vendor_words[0],
            self.vendor_words[1],
        ]
    }

    /// Words 0..7 as the EEPROM holds them, little-endian: words 0..6 and the checksum, the
    /// CRC-8 of their 14 bytes, in word 7's low byte.
    pub fn bytes(&self) -> [u8; 16] {
        let mut bytes = [0; 16];
        for (chunk, word) in bytes.chunks_exact_mut(2).zip(self.words()) {
            chunk.copy_from_slice(&word.to_le_bytes());
        }
        let crc = crc8(bytes.get(..14).unwrap_or_default());
        if let Some(byte) = bytes.get_mut(14) {
            *byte = crc;
        }
        bytes
    }
}

/// The CRC-8 of the configuration area (ETG.1000.6 §5.4: polynomial 0x07, initial 0xFF).
pub fn crc8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0xFF, |crc, &byte| {
        (0..8).fold(crc ^ byte, |crc, _| {
            if crc & 0x80 != 0 {
                (crc << 1) ^ 0x07
            } else {
                crc << 1
            }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seed 000's SSC example `050C0344102700000000` read as the fields the area names: SPI,
    /// SYNC out and latch in on, mode 3, SYNC0 and SYNC1 outputs, 100 µs pulses.
    #[test]
    fn the_fields_map_onto_the_words_as_the_ssc_example_shows() {
        let area = ConfigArea {
            pdi_control: 0x05,
            esc_configuration: 0x0C,
            pdi_configuration: 0x03,
            sync_latch_configuration: 0x44,
            sync_pulse_length: 0x2710,
            extended_pdi_configuration: 0,
            station_alias: 0,
            vendor_words: [0, 0],
        };
        assert_eq!(
            area.bytes()[..10],
            [0x05, 0x0C, 0x03, 0x44, 0x10, 0x27, 0, 0, 0, 0]
        );
    }

    #[test]
    fn spi_mode_bits() {
        assert_eq!(SpiMode::from_bits(0x03), SpiMode::Mode3);
        assert_eq!(SpiMode::from_bits(0x44), SpiMode::Mode0);
        assert!(SpiMode::Mode3.idle_high() && SpiMode::Mode3.capture_on_second_edge());
        assert!(!SpiMode::Mode1.idle_high() && SpiMode::Mode1.capture_on_second_edge());
    }
}
