//! The firmware update (feature `bootloader`, under examples/stm32-bootloader): FoE in BOOT
//! writes an update file into the DFU partition with embassy-boot's async `FirmwareUpdater`,
//! leaving BOOT marks a verified image updated and resets into the bootloader (which swaps it
//! in), and the new image confirms itself (`mark_booted`) once the device reaches PREOP; one that
//! never does is rolled back at the next reset.
//!
//! The update file is the host's (`ecat_emu::update`): a 12-byte header (`ECFW`, the image's
//! length, its CRC-32, little-endian), then the image, which goes into DFU. FoE's hooks are
//! synchronous and run with the application locked; the flash is written by the task [`run`]:
//! the image is handed to it [`CHUNK`] bytes at a time, and the segment that filled a chunk is
//! answered busy until that chunk is in flash (FoE's busy: the MainDevice sends the segment
//! again). After the last chunk the task reads DFU back and checks the CRC. (In single-bank mode
//! the G474 stalls instruction fetches from flash while a page is erased or written, whatever
//! the driver: the async one keeps the lock and the executor free between operations, not the
//! bus during one.) Codes: another file
//! name 0x8001, a wrong password 0x800A, an image longer than ACTIVE 0x8003, no magic, a CRC or
//! length that does not match or a flash error 0x8000.

use core::cell::{Cell, RefCell};

use crc::{CRC_32_ISO_HDLC, Crc, NoTable};
use ecat_core::coe::Emergency;
use ecat_core::dictionary::ObjectHooks;
use ecat_core::foe::{Files, Foe, FoeError, Progress};
use ecat_core::mailbox::Handlers;
use ecat_core::{AlState, AlStatusCode, Transition};
use ecat_embassy::Application;
use embassy_boot_stm32::{AlignedBuffer, FirmwareUpdater, FirmwareUpdaterConfig, State};
use embassy_sync::blocking_mutex::Mutex as BlockingMutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;

use crate::flash::SharedFlash;

/// The file FoE accepts.
pub const FILE_NAME: &[u8] = b"firmware.bin";
/// Its password.
pub const PASSWORD: u32 = 0x0000_0016;
/// Bytes of the image handed to the flash task at once: whole double words (the G474's program
/// unit), a quarter of a page.
pub const CHUNK: usize = 1024;
/// The largest image: the ACTIVE partition (memory-bootloader.x).
const ACTIVE_SIZE: u32 = 240 * 1024;
/// The header before the image.
const HEADER: usize = 12;
/// CRC-32 as zlib computes it, without a table (1 KiB of flash saved; it runs once per update).
const CRC32: Crc<u32, NoTable> = Crc::<u32, NoTable>::new(&CRC_32_ISO_HDLC);

/// What the FoE files ask of the flash task, and its answer.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Job {
    /// Nothing asked.
    Idle,
    /// Write the chunk's first `len` bytes at `offset` of DFU; `last`: then check the image of
    /// `length` bytes against `crc`.
    Write {
        offset: u32,
        len: u16,
        last: Option<(u32, u32)>,
    },
    /// The chunk is in flash (and, after the last, the image checked).
    Done,
    /// A flash error or a CRC that does not match.
    Failed,
    /// Mark the image updated, then reset into the bootloader.
    MarkUpdated,
    /// Confirm a trial boot.
    MarkBooted,
}

/// The chunk on its way to flash (zero-initialised: in .bss, not .data).
static CHUNK_BUFFER: BlockingMutex<CriticalSectionRawMutex, RefCell<[u8; CHUNK]>> =
    BlockingMutex::new(RefCell::new([0; CHUNK]));
/// The job asked, then its outcome.
static JOB: BlockingMutex<CriticalSectionRawMutex, Cell<Job>> =
    BlockingMutex::new(Cell::new(Job::Idle));
/// Wakes the flash task for a new job.
static WAKE: Signal<CriticalSectionRawMutex, ()> = Signal::new();

fn job() -> Job {
    JOB.lock(Cell::get)
}

fn submit(job: Job) {
    JOB.lock(|cell| cell.set(job));
    WAKE.signal(());
}

/// The update file as FoE receives it.
pub struct UpdateFiles {
    /// The header's bytes so far.
    header: [u8; HEADER],
    /// The image's bytes received so far (header excluded).
    received: u32,
    /// The image's bytes of the chunk being filled (past `CHUNK`: the next chunk's first bytes,
    /// moved to the front once the chunk is in flash).
    staged: [u8; 2 * CHUNK],
    filled: usize,
    /// The bytes of `staged` with the flash task.
    handed: usize,
    /// The segment (its offset in the file) whose bytes are staged and whose chunk is with the
    /// flash task: answered busy until the task is done.
    waiting: Option<u32>,
    /// A whole image is in DFU and its CRC matched.
    verified: bool,
}

impl UpdateFiles {
    /// No transfer.
    pub const fn new() -> Self {
        Self {
            header: [0; HEADER],
            received: 0,
            staged: [0; 2 * CHUNK],
            filled: 0,
            handed: 0,
            waiting: None,
            verified: false,
        }
    }

    /// The header's fields once it is complete: the image's length and CRC.
    fn header(&self) -> Option<(u32, u32)> {
        let word = |at: usize| {
            let bytes = self.header.get(at..at + 4)?;
            Some(u32::from_le_bytes(bytes.try_into().ok()?))
        };
        (self.header.starts_with(b"ECFW")).then_some(())?;
        Some((word(4)?, word(8)?))
    }

    /// Hands the flash task what is due: the rest of the image with the check once it is all
    /// received and fits a chunk, else a full chunk. Whether it handed something.
    fn hand_next(&mut self) -> bool {
        let Some((length, crc)) = self.header() else {
            return false;
        };
        if self.received == length && self.filled > 0 && self.filled <= CHUNK {
            self.hand_over(self.filled, Some((length, crc)));
        } else if self.filled >= CHUNK {
            self.hand_over(CHUNK, None);
        } else {
            return false;
        }
        true
    }

    /// Hands the chunk's first `len` bytes to the flash task.
    fn hand_over(&mut self, len: usize, last: Option<(u32, u32)>) {
        self.handed = len;
        let offset = self.received - (self.filled as u32);
        let padded = len.next_multiple_of(8);
        CHUNK_BUFFER.lock(|chunk| {
            let mut chunk = chunk.borrow_mut();
            chunk.fill(0xFF);
            chunk[..len].copy_from_slice(&self.staged[..len]);
        });
        submit(Job::Write {
            offset,
            len: padded as u16,
            last,
        });
    }
}

impl Default for UpdateFiles {
    fn default() -> Self {
        Self::new()
    }
}

impl Files for UpdateFiles {
    fn open_write(&mut self, name: &[u8], password: u32) -> Result<(), FoeError> {
        match (name == FILE_NAME, password == PASSWORD) {
            (false, _) => Err(FoeError::NOT_FOUND),
            (true, false) => Err(FoeError::NO_RIGHTS),
            (true, true) => {
                *self = Self::new();
                Ok(())
            }
        }
    }

    fn write(&mut self, offset: u32, data: &[u8]) -> Result<Progress, FoeError> {
        if self.waiting == Some(offset) {
            // The segment sent again while a chunk went to flash.
            match job() {
                Job::Done => {}
                Job::Failed => return Err(FoeError::NOT_DEFINED),
                _ => return Ok(BUSY),
            }
            self.staged.copy_within(self.handed..self.filled, 0);
            self.filled -= self.handed;
            self.handed = 0;
            if self.hand_next() {
                return Ok(BUSY);
            }
            self.waiting = None;
            self.verified = self
                .header()
                .is_some_and(|(length, _)| self.received == length);
            return Ok(Progress::Written);
        }
        let in_header = (HEADER as u32).saturating_sub(offset) as usize;
        let (head, image) = data.split_at(in_header.min(data.len()));
        if let Some(place) = self
            .header
            .get_mut(offset as usize..offset as usize + head.len())
        {
            place.copy_from_slice(head);
        }
        if image.is_empty() {
            return Ok(Progress::Written);
        }
        let (length, _) = self.header().ok_or(FoeError::NOT_DEFINED)?;
        if length > ACTIVE_SIZE {
            return Err(FoeError::DISK_FULL);
        }
        let end = self.received + image.len() as u32;
        let place = self.staged.get_mut(self.filled..self.filled + image.len());
        let (Some(place), true) = (place, end <= length) else {
            return Err(FoeError::NOT_DEFINED);
        };
        place.copy_from_slice(image);
        self.filled += image.len();
        self.received = end;
        if !self.hand_next() {
            return Ok(Progress::Written);
        }
        self.waiting = Some(offset);
        Ok(BUSY)
    }

    fn finish_write(&mut self, _: u32) -> Result<(), FoeError> {
        match (self.verified, self.header()) {
            (true, Some((length, _))) if length > 0 && self.received == length => Ok(()),
            _ => {
                self.verified = false;
                Err(FoeError::NOT_DEFINED)
            }
        }
    }

    fn abort(&mut self) {
        *self = Self::new();
    }
}

/// What a segment waiting for the flash is answered: busy, half done.
const BUSY: Progress = Progress::Busy { done: 1, entire: 2 };

/// An application `A` with the firmware update: FoE in BOOT ([`UpdateFiles`]); leaving BOOT
/// with a verified image marks it updated and resets; reaching PREOP confirms a trial boot.
pub struct Updatable<A> {
    /// The application.
    pub app: A,
    foe: (Foe<UpdateFiles>,),
}

impl<A> Updatable<A> {
    /// `app` with the firmware update.
    pub const fn new(app: A) -> Self {
        Self {
            app,
            foe: (Foe::new(UpdateFiles::new()),),
        }
    }
}

/// The application's own methods (the digital I/O's `on_sync0`) reach through the update.
impl<A> core::ops::Deref for Updatable<A> {
    type Target = A;

    fn deref(&self) -> &A {
        &self.app
    }
}

impl<A> core::ops::DerefMut for Updatable<A> {
    fn deref_mut(&mut self) -> &mut A {
        &mut self.app
    }
}

impl<A: Application<D>, D> Application<D> for Updatable<A> {
    fn cycle(&mut self, od: &mut D, outputs: Option<&[u8]>, inputs: &mut [u8]) {
        self.app.cycle(od, outputs, inputs);
    }

    fn safe_state(&mut self, od: &mut D) {
        self.app.safe_state(od);
    }

    fn on_transition(
        &mut self,
        transition: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> + use<A, D> {
        self.app.on_transition(transition)
    }

    fn on_state_change(&mut self, transition: Transition) {
        self.app.on_state_change(transition);
        if transition.from == AlState::Boot && self.foe.0.files().verified {
            submit(Job::MarkUpdated);
        } else if transition.to == AlState::PreOp {
            submit(Job::MarkBooted);
        }
    }

    fn mailbox(&mut self) -> (impl ObjectHooks<D> + '_, impl Handlers + '_) {
        (self.app.object_hooks(), &mut self.foe)
    }

    fn take_emergency(&mut self) -> Option<Emergency> {
        self.app.take_emergency()
    }
}

/// The flash task, in the thread executor: does the jobs [`UpdateFiles`] and [`Updatable`] hand
/// it, through embassy-boot's `FirmwareUpdater` over the chip's flash (shared with the stored
/// parameters, `crate::flash`).
#[embassy_executor::task]
pub async fn run(flash: &'static SharedFlash) -> ! {
    let config = FirmwareUpdaterConfig::from_linkerfile(flash, flash);
    let mut aligned = AlignedBuffer([0; 8]);
    let mut updater = FirmwareUpdater::new(config, &mut aligned.0);
    let mut chunk = [0; CHUNK];
    loop {
        WAKE.wait().await;
        let outcome = match job() {
            Job::Write { offset, len, last } => {
                CHUNK_BUFFER.lock(|buffer| chunk.copy_from_slice(&*buffer.borrow()));
                let len = usize::from(len).min(CHUNK);
                let written = updater
                    .write_firmware(offset as usize, &chunk[..len])
                    .await
                    .is_ok();
                let checked = match last {
                    Some((length, crc)) if written => {
                        // The image as DFU holds it, read back.
                        let mut digest = CRC32.digest();
                        let (mut offset, mut read) = (0, true);
                        while read && offset < length {
                            let n = (length - offset).min(CHUNK as u32);
                            let part = &mut chunk[..n as usize];
                            read = updater.read_dfu(offset, part).await.is_ok();
                            digest.update(part);
                            offset += n;
                        }
                        read && digest.finalize() == crc
                    }
                    _ => written,
                };
                if checked { Job::Done } else { Job::Failed }
            }
            Job::MarkUpdated => {
                if updater.mark_updated().await.is_ok() {
                    defmt::info!("update marked: resetting into the bootloader");
                    cortex_m::peripheral::SCB::sys_reset();
                }
                Job::Failed
            }
            Job::MarkBooted => {
                if matches!(updater.get_state().await, Ok(State::Swap)) {
                    let confirmed = updater.mark_booted().await.is_ok();
                    defmt::info!("new image confirmed: {}", confirmed);
                }
                Job::Idle
            }
            job => job,
        };
        JOB.lock(|cell| cell.set(outcome));
    }
}
