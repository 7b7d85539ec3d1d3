//! The SII image's fixed words (ETG.2010 Table 2) for a device with a bootstrap mailbox: the
//! whole-image checks against the ESI and the dictionary are `examples/host/tests/description.rs`
//! (its catalog devices have no BOOT).

use ecat_core::DeviceConfig;
use ecat_core::chip::Chip;
use ecat_core::device::{Identity, MailboxConfig, ProcessDataSizes};
use ecat_core::sii::{self, Names};

const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 2,
    revision: 1,
    serial: 1,
};

/// Words 0x14..0x17 describe the bootstrap mailbox (receive offset and size, send offset and
/// size), 0x18..0x1B the standard mailbox, 0x1C the mailbox protocols (CoE, bit 2); without a
/// bootstrap mailbox 0x14..0x17 are 0.
#[test]
fn the_bootstrap_and_standard_mailbox_words() {
    let names = Names {
        name: "Boot",
        order_code: "B-1",
        group: "Test",
    };
    let mut config = DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, 128),
        ProcessDataSizes::default(),
    );
    let words = |config: &DeviceConfig| {
        let mut image = [0u8; sii::MAX_SIZE];
        let n = sii::write(&names, &IDENTITY, config, &Chip::ET1100, &(), &mut image).unwrap();
        let word = |w: usize| u16::from_le_bytes([image[2 * w], image[2 * w + 1]]);
        assert!(n > 0x40 * 2);
        (0x14..=0x1C).map(word).collect::<Vec<_>>()
    };
    assert_eq!(
        words(&config),
        [0, 0, 0, 0, 0x1000, 128, 0x1080, 128, 0x0004]
    );
    config.bootstrap_mailbox = Some(MailboxConfig::contiguous(0x1800, 256));
    assert_eq!(
        words(&config),
        [0x1800, 256, 0x1900, 256, 0x1000, 128, 0x1080, 128, 0x0004]
    );
}
