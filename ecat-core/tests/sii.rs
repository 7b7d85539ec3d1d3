//! The SII image's fixed words (ETG.2010 Table 2) for a device with a bootstrap mailbox: the
//! whole-image checks against the ESI and the dictionary are `examples/host/tests/description.rs`
//! (its catalog devices have no BOOT).

use ecat_core::DeviceConfig;
use ecat_core::chip::Chip;
use ecat_core::chip::crc8;
use ecat_core::device::{Identity, MailboxConfig, ProcessDataSizes};
use ecat_core::sii::{self, Names};
use ecat_core::sync_mode::SupportedSyncModes;

const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 2,
    revision: 1,
    serial: 1,
};

const BOOT_NAMES: Names = Names {
    name: "Boot",
    order_code: "B-1",
    group: "Test",
};

/// A device with a 128-byte standard mailbox, and a 256-byte bootstrap mailbox when `boot`.
fn mailbox_device(boot: bool) -> DeviceConfig {
    let mut config = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes::default(),
    );
    if boot {
        config.bootstrap_mailbox = Some(MailboxConfig::contiguous(0x1800, 256));
    }
    config
}

/// The SII image of `config` (with [`BOOT_NAMES`]).
fn image(config: &DeviceConfig) -> [u8; sii::MAX_SIZE] {
    let mut image = [0u8; sii::MAX_SIZE];
    let n = sii::write(
        &BOOT_NAMES,
        &IDENTITY,
        config,
        &Chip::ET1100,
        &(),
        &mut image,
    )
    .unwrap();
    assert!(n > 0x40 * 2);
    image
}

/// Words 0x14..0x17 describe the bootstrap mailbox (receive offset and size, send offset and
/// size), 0x18..0x1B the standard mailbox, 0x1C the mailbox protocols (CoE, bit 2; FoE, bit 3,
/// with the bootstrap mailbox: BOOT serves FoE); without a bootstrap mailbox 0x14..0x17 are 0.
#[test]
fn the_bootstrap_and_standard_mailbox_words() {
    let words = |boot: bool| {
        let image = image(&mailbox_device(boot));
        let word = |w: usize| u16::from_le_bytes([image[2 * w], image[2 * w + 1]]);
        (0x14..=0x1C).map(word).collect::<Vec<_>>()
    };
    assert_eq!(words(false), [0, 0, 0, 0, 0x1000, 128, 0x1080, 128, 0x0004]);
    assert_eq!(
        words(true),
        [0x1800, 256, 0x1900, 256, 0x1000, 128, 0x1080, 128, 0x000C]
    );
}

/// Words 0..7, the ESC configuration area (ETG.1000.6 §5.4 Table 2), per chip, for a device
/// with and without DC SYNC0: PDI control (0x0140: 0x05 the Beckhoff SPI slave, 0x80 the
/// LAN9252's SPI), ESC configuration (0x0141: bit 2 SYNC out unit on with DC), PDI configuration
/// (0x0150: SPI mode 3 on the Beckhoff slave; 0 on the LAN9252, whose SPI has no mode setting),
/// SYNC/LATCH configuration (0x0151: 0x06, SYNC0 push-pull active high, with DC), SYNC pulse
/// length 100 × 10 ns (0x0982), extended PDI configuration and alias 0, the AX58100's word 5
/// (0x001A), and the CRC-8 (poly 0x07, init 0xFF) of words 0..6 in word 7.
#[test]
fn the_configuration_area_of_each_chip() {
    let names = Names {
        name: "Area",
        order_code: "A-1",
        group: "Test",
    };
    let config = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes::default(),
    );
    /// No objects, DC SYNC0 beside SM-synchronous.
    struct DcOd {}
    ecat_core::dictionary! {
        minimal DcOd {
            sync(SupportedSyncModes(SupportedSyncModes::SM | SupportedSyncModes::SYNC0));
        }
    }
    let area = |chip: &Chip, dc: bool| {
        let mut image = [0u8; sii::MAX_SIZE];
        if dc {
            sii::write(&names, &IDENTITY, &config, chip, &DcOd {}, &mut image).unwrap();
        } else {
            sii::write(&names, &IDENTITY, &config, chip, &(), &mut image).unwrap();
        }
        image[..16].to_vec()
    };
    #[rustfmt::skip]
    let expected: [(&Chip, bool, [u8; 16]); 6] = [
        (&Chip::ET1100, true, [0x05, 0x04, 0x03, 0x06, 0x64, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x71, 0]),
        (&Chip::ET1100, false, [0x05, 0x00, 0x03, 0x00, 0x64, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x6D, 0]),
        (&Chip::AX58100, true, [0x05, 0x04, 0x03, 0x06, 0x64, 0, 0, 0, 0, 0, 0x1A, 0, 0, 0, 0x8A, 0]),
        (&Chip::AX58100, false, [0x05, 0x00, 0x03, 0x00, 0x64, 0, 0, 0, 0, 0, 0x1A, 0, 0, 0, 0x96, 0]),
        (&Chip::LAN9252, true, [0x80, 0x04, 0x00, 0x06, 0x64, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x37, 0]),
        (&Chip::LAN9252, false, [0x80, 0x00, 0x00, 0x00, 0x64, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x2B, 0]),
    ];
    for (chip, dc, bytes) in expected {
        assert_eq!(area(chip, dc), bytes, "{} dc {dc}", chip.name);
        assert_eq!(crc8(&bytes[..14]), bytes[14]);
    }
}

/// The General category's flags (ETG.2010 Table 6, byte 0x0B): bit 3 IdentALSts for a device
/// with an explicit device ID, nothing else (ethercrab rejects unknown bits above 4).
#[test]
fn the_general_flags_advertise_an_explicit_device_id() {
    let mut config = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes::default(),
    );
    let names = Names {
        name: "Id",
        order_code: "I-1",
        group: "Test",
    };
    let mut flags = |explicit: bool| {
        config.explicit_device_id = explicit;
        let mut image = [0u8; sii::MAX_SIZE];
        let n = sii::write(&names, &IDENTITY, &config, &Chip::ET1100, &(), &mut image).unwrap();
        // The categories from word 0x40: Strings first, then General.
        let mut at = 0x80;
        while at < n {
            let kind = u16::from_le_bytes([image[at], image[at + 1]]);
            let words = usize::from(u16::from_le_bytes([image[at + 2], image[at + 3]]));
            if kind == 30 {
                return image[at + 4 + 0x0B];
            }
            at += 4 + 2 * words;
        }
        panic!("no General category");
    };
    assert_eq!(flags(false), 0x00);
    assert_eq!(flags(true), 0x08);
    assert_eq!(sii::FLAG_IDENT_AL_STATUS, 1 << 3);
}

/// The General category's "FoE Details" byte (ETG.2010 Table 6, byte 6: bit 0 FoE supported)
/// follows the mailbox protocols word: 1 with a bootstrap mailbox, 0 without.
#[test]
fn the_general_category_enables_foe_with_boot() {
    let foe_details = |boot: bool| {
        let image = image(&mailbox_device(boot));
        // Categories from word 0x40: type, size in words, data.
        let mut at = 0x80;
        loop {
            let kind = u16::from_le_bytes([image[at], image[at + 1]]);
            let words = usize::from(u16::from_le_bytes([image[at + 2], image[at + 3]]));
            assert_ne!(kind, 0xFFFF, "a General category");
            if kind == 30 {
                return image[at + 4 + 6];
            }
            at += 4 + 2 * words;
        }
    };
    assert_eq!(foe_details(false), 0);
    assert_eq!(foe_details(true), 1);
}

/// The Strings category starts with the order code, then the group, then the name, and the
/// General category's indices point at them (ETG.2010 Table 7: GroupIdx, ImgIdx, OrderIdx,
/// NameIdx): SOEM names a SubDevice after string 1 whatever General says, so it shows the order
/// code, as for Beckhoff's own devices.
#[test]
fn string_one_is_the_order_code() {
    let image = image(&mailbox_device(false));
    let category = |wanted: u16| {
        let mut at = 0x80;
        loop {
            let kind = u16::from_le_bytes([image[at], image[at + 1]]);
            let words = usize::from(u16::from_le_bytes([image[at + 2], image[at + 3]]));
            assert_ne!(kind, 0xFFFF, "category {wanted}");
            if kind == wanted {
                return &image[at + 4..at + 4 + 2 * words];
            }
            at += 4 + 2 * words;
        }
    };
    let strings = category(10);
    let mut names = Vec::new();
    let mut at = 1;
    for _ in 0..3 {
        let len = usize::from(strings[at]);
        names.push(std::str::from_utf8(&strings[at + 1..at + 1 + len]).unwrap());
        at += 1 + len;
    }
    assert_eq!(names, ["B-1", "Test", "Boot"]);
    let general = category(30);
    // GroupIdx, ImgIdx, OrderIdx, NameIdx.
    assert_eq!(&general[..4], &[2, 0, 1, 3]);
}
