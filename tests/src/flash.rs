//! A device's flash on the host: the STM32G474's NOR flash as the firmware's bootloader sees it
//! (`examples/stm32-bootloader/memory.x`), with the power cut wherever a test asks.
//!
//! [`Flash`] holds the bytes; [`Flash::partition`] gives the `NorFlash` views embassy-boot works
//! on (bootloader state, ACTIVE, DFU). The chip's rules are kept: an erase works on whole 4 KiB
//! pages and leaves 0xFF, a write moves whole 8-byte double words into erased ones only (the
//! G474 refuses to program a double word twice: PROGERR, RM0440 §3.3.8). [`Flash::cut_after`]
//! lets `n` more operations complete and tears the next one — the first half of its double
//! words done, the rest as before — as a power loss would; every operation after it fails until
//! [`Flash::power_on`]. A single double word is programmed whole or not at all (embassy-boot's
//! progress words rely on that, as the chip's 64-bit programming with ECC gives it).

use std::cell::RefCell;
use std::ops::Range;
use std::rc::Rc;

use embedded_storage::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

/// Erase unit of the G474 in single-bank mode.
pub const PAGE: usize = 4096;
/// Program unit of the G474: a double word.
pub const DOUBLE_WORD: usize = 8;

/// The partitions of `examples/stm32-bootloader/memory.x`, as byte ranges from the start of flash.
pub mod layout {
    use std::ops::Range;

    /// The bootloader's code: 16 KiB.
    pub const BOOTLOADER: Range<usize> = 0..0x4000;
    /// The bootloader's state: swap magic and progress.
    pub const STATE: Range<usize> = 0x4000..0x5000;
    /// The stored parameters (0x1010), untouched by updates.
    pub const PARAMETERS: Range<usize> = 0x5000..0x7000;
    /// The image that runs.
    pub const ACTIVE: Range<usize> = 0x7000..0x43000;
    /// The image being received; one page larger than ACTIVE.
    pub const DFU: Range<usize> = 0x43000..0x80000;
    /// The whole flash: 512 KiB.
    pub const SIZE: usize = 0x80000;
}

/// Why an operation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error {
    /// The power is off (the operation was cut, or a later one).
    PowerLost,
    /// Outside the partition, or not aligned to the program or erase unit.
    Alignment,
    /// A double word written twice without an erase between.
    NotErased,
}

impl NorFlashError for Error {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            Error::Alignment => NorFlashErrorKind::NotAligned,
            Error::PowerLost | Error::NotErased => NorFlashErrorKind::Other,
        }
    }
}

/// The bytes, a page at a time: a page never written reads erased (0xFF) and takes no memory,
/// so a device's flash costs what it holds (a 4 KiB image: two pages, not 512 KiB per device
/// of a virtual slave's line).
struct Pages(Vec<Option<Box<[u8]>>>);

impl Pages {
    /// The whole flash, erased.
    fn erased() -> Self {
        Self(vec![None; layout::SIZE / PAGE])
    }

    /// The bytes of `range`.
    fn get(&self, range: Range<usize>) -> Vec<u8> {
        let mut bytes = vec![0; range.len()];
        self.read(range.start, &mut bytes);
        bytes
    }

    /// Fills `out` with the bytes from `start` on.
    fn read(&self, start: usize, out: &mut [u8]) {
        let (mut at, mut rest) = (start, out);
        while !rest.is_empty() {
            let (page, offset) = (at / PAGE, at % PAGE);
            let n = (PAGE - offset).min(rest.len());
            let (part, more) = rest.split_at_mut(n);
            match &self.0[page] {
                Some(stored) => part.copy_from_slice(&stored[offset..offset + n]),
                None => part.fill(0xFF),
            }
            (at, rest) = (at + n, more);
        }
    }

    /// Sets the bytes from `start` on to `bytes`.
    fn set(&mut self, start: usize, bytes: &[u8]) {
        let (mut at, mut rest) = (start, bytes);
        while !rest.is_empty() {
            let (page, offset) = (at / PAGE, at % PAGE);
            let n = (PAGE - offset).min(rest.len());
            let stored = self.0[page].get_or_insert_with(|| vec![0xFF; PAGE].into_boxed_slice());
            stored[offset..offset + n].copy_from_slice(&rest[..n]);
            (at, rest) = (at + n, &rest[n..]);
        }
    }
}

/// The bytes and the power.
struct Memory {
    bytes: Pages,
    /// Operations left before the cut; `None`: no cut planned.
    budget: Option<usize>,
    powered: bool,
    /// Erases and writes completed since the flash was made.
    operations: usize,
}

/// A 512 KiB flash, erased; cheap to clone (the clones share the bytes).
#[derive(Clone)]
pub struct Flash(Rc<RefCell<Memory>>);

impl Default for Flash {
    fn default() -> Self {
        Self(Rc::new(RefCell::new(Memory {
            bytes: Pages::erased(),
            budget: None,
            powered: true,
            operations: 0,
        })))
    }
}

impl Flash {
    /// A `NorFlash` over `range` (one of [`layout`]'s).
    pub fn partition(&self, range: Range<usize>) -> Partition {
        Partition {
            flash: self.clone(),
            range,
        }
    }

    /// The bytes of `range`, as they are.
    pub fn bytes(&self, range: Range<usize>) -> Vec<u8> {
        self.0.borrow().bytes.get(range)
    }

    /// Lets `n` more erases or writes complete, then tears the next one and turns the power off.
    pub fn cut_after(&self, n: usize) {
        self.0.borrow_mut().budget = Some(n);
    }

    /// Power back on, no cut planned. Returns whether the power had been lost.
    pub fn power_on(&self) -> bool {
        let mut memory = self.0.borrow_mut();
        memory.budget = None;
        !std::mem::replace(&mut memory.powered, true)
    }

    /// Erases and writes completed so far.
    pub fn operations(&self) -> usize {
        self.0.borrow().operations
    }

    /// Applies one operation on `range` (absolute): `apply` gets the bytes to change; a cut
    /// applies it to the first half only.
    fn operate(
        &self,
        range: Range<usize>,
        apply: impl FnOnce(&mut [u8]) -> Result<(), Error>,
    ) -> Result<(), Error> {
        let mut memory = self.0.borrow_mut();
        if !memory.powered {
            return Err(Error::PowerLost);
        }
        if let Some(budget) = memory.budget.as_mut() {
            if *budget == 0 {
                memory.powered = false;
                // Whole double words: the chip programs one at a time, each as a unit (a
                // page erase is torn the same way, at a double-word boundary).
                let half = range.len() / DOUBLE_WORD / 2 * DOUBLE_WORD;
                let mut copy = memory.bytes.get(range.clone());
                apply(&mut copy)?;
                memory.bytes.set(range.start, &copy[..half]);
                return Err(Error::PowerLost);
            }
            *budget -= 1;
        }
        let mut bytes = memory.bytes.get(range.clone());
        apply(&mut bytes)?;
        memory.bytes.set(range.start, &bytes);
        memory.operations += 1;
        Ok(())
    }
}

/// One partition of a [`Flash`].
pub struct Partition {
    flash: Flash,
    range: Range<usize>,
}

impl Partition {
    /// The absolute range of `len` bytes at `offset` in the partition, aligned to `unit`.
    fn span(&self, offset: u32, len: usize, unit: usize) -> Result<Range<usize>, Error> {
        let start = self.range.start + offset as usize;
        let end = start + len;
        if !(offset as usize).is_multiple_of(unit)
            || !len.is_multiple_of(unit)
            || end > self.range.end
        {
            return Err(Error::Alignment);
        }
        Ok(start..end)
    }
}

impl ErrorType for Partition {
    type Error = Error;
}

impl ReadNorFlash for Partition {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Error> {
        let span = self.span(offset, bytes.len(), 1)?;
        let memory = self.flash.0.borrow();
        if !memory.powered {
            return Err(Error::PowerLost);
        }
        memory.bytes.read(span.start, bytes);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.range.len()
    }
}

impl NorFlash for Partition {
    const WRITE_SIZE: usize = DOUBLE_WORD;
    const ERASE_SIZE: usize = PAGE;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Error> {
        let span = self.span(from, to.saturating_sub(from) as usize, PAGE)?;
        // One operation per page, as the chip erases them.
        for page in span.step_by(PAGE) {
            self.flash.operate(page..page + PAGE, |bytes| {
                bytes.fill(0xFF);
                Ok(())
            })?;
        }
        Ok(())
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Error> {
        let span = self.span(offset, bytes.len(), DOUBLE_WORD)?;
        self.flash.operate(span, |target| {
            let erased = target
                .chunks(DOUBLE_WORD)
                .all(|word| word.iter().all(|&b| b == 0xFF));
            if !erased {
                return Err(Error::NotErased);
            }
            target.copy_from_slice(bytes);
            Ok(())
        })
    }
}

// The async traits sequential-storage works on (the stored parameters, 0x1010): the same
// operations, done at once.

impl embedded_storage_async::nor_flash::ReadNorFlash for Partition {
    const READ_SIZE: usize = 1;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Error> {
        ReadNorFlash::read(self, offset, bytes)
    }

    fn capacity(&self) -> usize {
        self.range.len()
    }
}

impl embedded_storage_async::nor_flash::NorFlash for Partition {
    const WRITE_SIZE: usize = DOUBLE_WORD;
    const ERASE_SIZE: usize = PAGE;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), Error> {
        NorFlash::erase(self, from, to)
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Error> {
        NorFlash::write(self, offset, bytes)
    }
}
