//! A device's firmware update on the host (issue #16): FoE in BOOT streams an update file into
//! the DFU partition of the device's [`Flash`] through embassy-boot's
//! `BlockingFirmwareUpdater`, the bootloader's `prepare_boot` swaps it in at the next reset
//! ([`reset`]), and the new image confirms itself once it reaches PREOP, or is rolled back.
//!
//! An update file is a 12-byte [`Header`] (magic `ECFW`, the image's length, its CRC-32) and the
//! image. [`FlashFiles`] keeps the header, writes the image into DFU a page at a time (one 4 KiB
//! page buffered, never the whole file), reads it back from DFU at the end to verify its length
//! and CRC, and marks it for the swap only when the MainDevice leaves BOOT
//! ([`FlashFiles::leave_boot`]): a file written twice in one BOOT session never leaves a half
//! image marked. Refusals, each with its FoE code and nothing marked:
//!
//! | case | code |
//! |---|---|
//! | another file name | 0x8001 not found |
//! | a wrong password | 0x800A no rights |
//! | a new image not confirmed yet (a trial boot) | 0x8002 access denied |
//! | an image longer than ACTIVE | 0x8003 disk full |
//! | a header without the magic, a length or CRC that does not match, a flash error | 0x8000 not defined |
//!
//! Reading [`FILE_NAME`] gives the last image received and verified in DFU (0x8001 before
//! one): what the MainDevice wrote, as the device holds it.
//!
//! The host's images ([`image`]) start with their version (u32, little-endian): what a device
//! built from the flash reports as its revision. A sample device becomes updatable with a
//! [`Firmware`] (`devices::dio_update`, the virtual axis of `examples/host`): its application in
//! [`Updatable`], the bootstrap mailbox, the revision of its image. Leaving BOOT with an image
//! marked, [`Updatable`] asks for a reset; run as [`restarting`], the device then restarts on its
//! own as firmware under the bootloader does: the swap, the new image, its confirmation in PREOP.

use crc::{CRC_32_ISO_HDLC, Crc};
use ecat_core::coe::Emergency;
use ecat_core::device::{Identity, MailboxConfig};
use ecat_core::dictionary::{Communication, ObjectHooks};
use ecat_core::foe::{Files, Foe, FoeError, Progress};
use ecat_core::mailbox::Handlers;
use ecat_core::{AlState, AlStatusCode, DeviceConfig, Transition};
use ecat_embassy::Application;
use embassy_boot::{
    BlockingFirmwareState, BlockingFirmwareUpdater, BootLoader, BootLoaderConfig,
    FirmwareUpdaterConfig, State,
};
use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};

use crate::flash::{DOUBLE_WORD, Flash, PAGE, Partition, layout};
use crate::harness::Spawn;
use crate::restart::{Reset, Restarting};

/// The file a [`FlashFiles`] accepts.
pub const FILE_NAME: &str = "firmware.bin";
/// The password of the updatable sample devices' [`FILE_NAME`].
pub const PASSWORD: u32 = 0x0000_0016;
/// The bootstrap mailbox of the updatable sample devices: 256 bytes each way at 0x1800 (FoE
/// segments of 244 bytes).
pub const BOOT_MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1800, 256);

/// The CRC of the [`Header`]: CRC-32 (ISO HDLC, as zlib's `crc32`).
const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// What an update file starts with; not written to flash.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// The image's length in bytes.
    pub length: u32,
    /// The image's CRC-32.
    pub crc: u32,
}

impl Header {
    /// Its size in bytes.
    pub const SIZE: usize = 12;
    /// Its first 4 bytes.
    pub const MAGIC: [u8; 4] = *b"ECFW";

    /// The header of `image`.
    pub fn of(image: &[u8]) -> Self {
        Self {
            length: image.len() as u32,
            crc: CRC32.checksum(image),
        }
    }

    /// The bytes on the wire: magic, length and CRC little-endian.
    pub fn to_bytes(self) -> [u8; Self::SIZE] {
        let mut bytes = [0; Self::SIZE];
        bytes[..4].copy_from_slice(&Self::MAGIC);
        bytes[4..8].copy_from_slice(&self.length.to_le_bytes());
        bytes[8..].copy_from_slice(&self.crc.to_le_bytes());
        bytes
    }

    /// The header in `bytes`, if they start with the magic.
    pub fn parse(bytes: &[u8; Self::SIZE]) -> Option<Self> {
        let word = |at: usize| {
            u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
        };
        (bytes[..4] == Self::MAGIC).then(|| Self {
            length: word(4),
            crc: word(8),
        })
    }
}

/// The update file of `image`: its header, then the image.
pub fn file(image: &[u8]) -> Vec<u8> {
    let mut file = Header::of(image).to_bytes().to_vec();
    file.extend_from_slice(image);
    file
}

/// A host image of `len` bytes (at least 4) that reports `version`: the version, then bytes that
/// differ from version to version.
pub fn image(version: u32, len: usize) -> Vec<u8> {
    let mut x = 0x9E37_79B9u32 ^ version;
    let mut image = version.to_le_bytes().to_vec();
    image.extend((4..len).map(|_| {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x as u8
    }));
    image
}

/// The version the image in ACTIVE reports ([`image`]).
pub fn running_version(flash: &Flash) -> u32 {
    let active = flash.bytes(layout::ACTIVE.start..layout::ACTIVE.start + 4);
    u32::from_le_bytes([active[0], active[1], active[2], active[3]])
}

/// A flash with `image` in ACTIVE and the bootloader's state erased (booted), as the probe
/// leaves it.
pub fn flashed(image: &[u8]) -> Flash {
    let flash = Flash::default();
    let mut padded = image.to_vec();
    padded.resize(image.len().next_multiple_of(PAGE), 0xFF);
    flash
        .partition(layout::ACTIVE)
        .write(0, &padded)
        .expect("a new flash takes the image");
    flash
}

/// A reset: the bootloader prepares ACTIVE (swap, revert or nothing); returns the state the
/// image that then runs reads: `Swap` on a trial boot of a new image that must confirm itself,
/// `Revert` after a rollback, `Boot` otherwise.
pub fn reset(flash: &Flash) -> Result<State, embassy_boot::BootError> {
    let mut bootloader = BootLoader::new(BootLoaderConfig {
        active: flash.partition(layout::ACTIVE),
        dfu: flash.partition(layout::DFU),
        state: flash.partition(layout::STATE),
    });
    let mut page = vec![0; PAGE];
    bootloader.prepare_boot(&mut page)?;
    Ok(state(flash).expect("the state partition reads with the power on"))
}

/// The bootloader's state as the running image reads it.
pub fn state(flash: &Flash) -> Result<State, embassy_boot::FirmwareUpdaterError> {
    let mut aligned = [0; DOUBLE_WORD];
    BlockingFirmwareState::new(flash.partition(layout::STATE), &mut aligned).get_state()
}

/// The header of the file being received: 0x8000 when it is short or has no magic.
fn received_header(receive: &Receive) -> Result<Header, FoeError> {
    <&[u8; Header::SIZE]>::try_from(receive.header.as_slice())
        .ok()
        .and_then(Header::parse)
        .ok_or(FoeError::NOT_DEFINED)
}

/// A file being received.
struct Receive {
    /// The header's bytes so far, then the header.
    header: Vec<u8>,
    /// The image's bytes not yet in DFU: less than a page.
    page: Vec<u8>,
    /// The image's bytes in DFU.
    flushed: usize,
}

/// The device's FoE files: [`FILE_NAME`] with its password, into DFU (module docs).
pub struct FlashFiles {
    flash: Flash,
    password: u32,
    receive: Option<Receive>,
    /// A whole, verified image is in DFU, to be marked when BOOT is left.
    verified: bool,
    /// The last image verified in DFU: what reading [`FILE_NAME`] gives.
    received: Option<Header>,
}

impl FlashFiles {
    /// The files of the device whose flash is `flash`, written with `password`.
    pub fn new(flash: Flash, password: u32) -> Self {
        Self {
            flash,
            password,
            receive: None,
            verified: false,
            received: None,
        }
    }

    /// The MainDevice left BOOT: a verified image is marked for the swap at the next reset.
    /// Whether one was.
    pub fn leave_boot(&mut self) -> bool {
        self.receive = None;
        std::mem::take(&mut self.verified) && self.updater(|updater| updater.mark_updated()).is_ok()
    }

    /// The device reached PREOP: a new image on its trial boot confirms itself. Whether it was
    /// one.
    pub fn confirm(&mut self) -> bool {
        matches!(state(&self.flash), Ok(State::Swap))
            && self.updater(|updater| updater.mark_booted()).is_ok()
    }

    /// Runs `f` on an updater over the flash's DFU and state.
    fn updater<R>(
        &self,
        f: impl FnOnce(
            &mut BlockingFirmwareUpdater<'_, Partition, Partition>,
        ) -> Result<R, embassy_boot::FirmwareUpdaterError>,
    ) -> Result<R, FoeError> {
        let mut aligned = [0; DOUBLE_WORD];
        let config = FirmwareUpdaterConfig {
            dfu: self.flash.partition(layout::DFU),
            state: self.flash.partition(layout::STATE),
        };
        f(&mut BlockingFirmwareUpdater::new(config, &mut aligned))
            .map_err(|_| FoeError::NOT_DEFINED)
    }

    /// Writes the buffered page at its place in DFU (erasing that page first), padded to whole
    /// double words.
    fn flush(&self, receive: &mut Receive) -> Result<(), FoeError> {
        let mut page = std::mem::take(&mut receive.page);
        let len = page.len();
        page.resize(len.next_multiple_of(DOUBLE_WORD), 0xFF);
        self.updater(|updater| updater.write_firmware(receive.flushed, &page))?;
        receive.flushed += len;
        Ok(())
    }

    /// Whether DFU holds the image `header` describes: its CRC, read back from flash.
    fn verify(&self, header: Header) -> bool {
        let mut dfu = self.flash.partition(layout::DFU);
        let mut digest = CRC32.digest();
        let mut chunk = vec![0; PAGE];
        let mut offset = 0;
        while offset < header.length as usize {
            let n = (header.length as usize - offset).min(PAGE);
            if dfu.read(offset as u32, &mut chunk[..n]).is_err() {
                return false;
            }
            digest.update(&chunk[..n]);
            offset += n;
        }
        digest.finalize() == header.crc
    }
}

impl Files for FlashFiles {
    fn open_write(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        if name != FILE_NAME.as_bytes() {
            return Err(FoeError::NOT_FOUND);
        }
        if password != self.password {
            return Err(FoeError::NO_RIGHTS);
        }
        if !matches!(state(&self.flash), Ok(State::Boot)) {
            return Err(FoeError::ACCESS_DENIED);
        }
        self.verified = false;
        self.received = None;
        self.receive = Some(Receive {
            header: Vec::with_capacity(Header::SIZE),
            page: Vec::with_capacity(PAGE),
            flushed: 0,
        });
        Ok(())
    }

    fn write(&mut self, _offset: u32, mut data: &[u8]) -> Result<Progress, FoeError> {
        let mut receive = self.receive.take().ok_or(FoeError::ILLEGAL)?;
        let missing = Header::SIZE - receive.header.len();
        let (head, rest) = data.split_at(missing.min(data.len()));
        receive.header.extend_from_slice(head);
        data = rest;
        if receive.header.len() == Header::SIZE && missing > 0 {
            let header = received_header(&receive)?;
            if header.length as usize > layout::ACTIVE.len() {
                return Err(FoeError::DISK_FULL);
            }
        }
        while !data.is_empty() {
            let (part, rest) = data.split_at((PAGE - receive.page.len()).min(data.len()));
            receive.page.extend_from_slice(part);
            data = rest;
            if receive.page.len() == PAGE {
                if receive.flushed + PAGE > layout::ACTIVE.len() {
                    return Err(FoeError::DISK_FULL);
                }
                self.flush(&mut receive)?;
            }
        }
        self.receive = Some(receive);
        Ok(Progress::Written)
    }

    fn finish_write(&mut self, _length: u32) -> Result<(), FoeError> {
        let mut receive = self.receive.take().ok_or(FoeError::ILLEGAL)?;
        let header = received_header(&receive)?;
        if !receive.page.is_empty() {
            self.flush(&mut receive)?;
        }
        if receive.flushed != header.length as usize || !self.verify(header) {
            return Err(FoeError::NOT_DEFINED);
        }
        self.verified = true;
        self.received = Some(header);
        Ok(())
    }

    fn open_read(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        if name != FILE_NAME.as_bytes() || self.received.is_none() {
            return Err(FoeError::NOT_FOUND);
        }
        if password != self.password {
            return Err(FoeError::NO_RIGHTS);
        }
        Ok(())
    }

    fn read(&mut self, offset: u32, out: &mut [u8]) -> Result<usize, FoeError> {
        let length = self.received.map_or(0, |header| header.length);
        let n = length.saturating_sub(offset).min(out.len() as u32) as usize;
        self.flash
            .partition(layout::DFU)
            .read(offset, &mut out[..n])
            .map_err(|_| FoeError::NOT_DEFINED)?;
        Ok(n)
    }

    fn abort(&mut self) {
        self.receive = None;
    }
}

/// What an updatable sample device runs on: its flash, and the reset it asks for after an
/// update.
#[derive(Clone)]
pub struct Firmware {
    flash: Flash,
    reset: Reset,
}

impl Firmware {
    /// The firmware in `flash`, asking for resets through `reset`.
    pub fn new(flash: Flash, reset: Reset) -> Self {
        Self { flash, reset }
    }

    /// The identity of the image in ACTIVE, set in the dictionary's `area` (0x1018) and
    /// returned for the SII: the revision is the version the image reports
    /// ([`running_version`]).
    pub fn identify(&self, area: &mut Communication) -> Identity {
        area.identity.revision = running_version(&self.flash);
        area.identity
    }

    /// `config` with the bootstrap mailbox [`BOOT_MAILBOX`] (BOOT supported).
    pub fn bootstrap(&self, mut config: DeviceConfig) -> DeviceConfig {
        config.bootstrap_mailbox = Some(BOOT_MAILBOX);
        config
    }

    /// `app` with the update on this flash ([`FILE_NAME`], [`PASSWORD`]).
    pub fn app<A>(&self, app: A) -> Updatable<A> {
        Updatable {
            app,
            foe: (Foe::new(FlashFiles::new(self.flash.clone(), PASSWORD)),),
            reset: self.reset.clone(),
        }
    }
}

/// An application `A` with the firmware update, as examples/stm32's `Updatable`: FoE in BOOT
/// into the device's flash ([`FlashFiles`]); leaving BOOT with a verified image marks it for the
/// bootloader and asks for a reset; reaching PREOP confirms a new image on its trial boot.
pub struct Updatable<A> {
    app: A,
    foe: (Foe<FlashFiles>,),
    reset: Reset,
}

/// The state-machine side of a harness `Device` (`harness::Pair`'s hooks): the cycle and the safe
/// state are the device's other half.
impl<A: Application<D>, D> Application<D> for Updatable<A> {
    fn on_state_change(&mut self, transition: Transition) {
        self.app.on_state_change(transition);
        let files = self.foe.0.files_mut();
        if transition.from == AlState::Boot && files.leave_boot() {
            self.reset.request();
        }
        if transition.to == AlState::PreOp {
            files.confirm();
        }
    }

    fn on_transition(
        &mut self,
        transition: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> + use<A, D> {
        self.app.on_transition(transition)
    }

    fn object_hooks(&mut self) -> impl ObjectHooks<D> + '_ {
        self.app.object_hooks()
    }

    fn mailbox(&mut self) -> (impl ObjectHooks<D> + '_, impl Handlers + '_) {
        (self.app.object_hooks(), &mut self.foe)
    }

    fn take_emergency(&mut self) -> Option<Emergency> {
        self.app.take_emergency()
    }
}

/// A device on `flash` that restarts as firmware under the bootloader does ([`Restarting`]): at
/// power-on and at every reset the bootloader runs ([`reset`]: the swap of a marked image, the
/// rollback of one never confirmed), then `boot` makes the device from the image in ACTIVE.
pub fn restarting(
    flash: Flash,
    mut boot: impl FnMut(&Firmware) -> Box<dyn Spawn> + 'static,
) -> Restarting {
    Restarting::new(move |line: &Reset| {
        reset(&flash).expect("the bootloader runs on a powered flash");
        boot(&Firmware::new(flash.clone(), line.clone()))
    })
}
