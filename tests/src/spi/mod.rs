//! Fake SPI ESC chips in front of the emulated ESC: [`FakeSpi`] implements
//! `embedded_hal_async::spi::SpiDevice`, hands the bytes of each transaction (chip select low to
//! chip select high) to a [`Chip`] that decodes them exactly as the real chip would, and counts
//! transactions and bytes as a logic analyser on the bus would.
//!
//! The chips model the silicon, not the drivers: they keep their own command codes and register
//! addresses (an oracle that shared the driver's constants could not catch a wrong one) and record
//! every stream the real chip would reject or misread as a [`Probe::violations`] entry.
//!
//! | chip | module |
//! |---|---|
//! | ET1100/ET1200/AX58100 (Beckhoff SPI slave interface) | [`beckhoff`] |
//! | LAN9252 in SPI mode | [`lan9252`] |

pub mod beckhoff;
pub mod lan9252;

use core::cell::RefCell;
use std::rc::Rc;

use ecat_core::chip::SpiMode;
use embedded_hal_async::spi::{ErrorKind, ErrorType, Operation, SpiDevice};

/// What a logic analyser on the SPI bus counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SpiStats {
    /// Chip-select cycles.
    pub transactions: u64,
    /// Bytes clocked (each byte goes out on MOSI while one comes in on MISO).
    pub bytes: u64,
}

impl core::ops::Sub for SpiStats {
    type Output = SpiStats;

    fn sub(self, before: SpiStats) -> SpiStats {
        SpiStats {
            transactions: self.transactions - before.transactions,
            bytes: self.bytes - before.bytes,
        }
    }
}

/// The test's view of a [`FakeSpi`]: counters, the MOSI streams, violations, error injection.
/// Cloning gives another view of the same bus.
#[derive(Clone, Default)]
pub struct Probe(Rc<RefCell<Record>>);

#[derive(Default)]
struct Record {
    stats: SpiStats,
    log: Vec<Vec<u8>>,
    violations: Vec<String>,
    fail_next: bool,
    /// The transaction (counted from 0) and byte at which [`Probe::at`]'s action runs.
    hook: Option<(u64, usize, Action)>,
}

impl Record {
    /// The [`Progress`] of the transaction about to start: with the test's action if it is for
    /// this transaction.
    fn progress(&mut self) -> Progress {
        let index = self.stats.transactions;
        let action = match self.hook.take() {
            Some((transaction, byte, action)) if transaction == index => Some((byte, action)),
            other => {
                self.hook = other;
                None
            }
        };
        Progress { action }
    }
}

/// Something the test does while a transaction is on the bus.
type Action = Box<dyn FnOnce()>;

impl Probe {
    /// Transactions and bytes so far.
    pub fn stats(&self) -> SpiStats {
        self.0.borrow().stats
    }

    /// The MOSI bytes of each transaction since the last [`Probe::take_log`].
    pub fn take_log(&self) -> Vec<Vec<u8>> {
        core::mem::take(&mut self.0.borrow_mut().log)
    }

    /// What the chip would have rejected or misread, oldest first.
    pub fn violations(&self) -> Vec<String> {
        self.0.borrow().violations.clone()
    }

    /// Makes the next transaction fail with [`BusError`] without reaching the chip.
    pub fn fail_next(&self) {
        self.0.borrow_mut().fail_next = true;
    }

    /// Runs `action` while transaction `transaction` (counted from 0, as
    /// [`SpiStats::transactions`]) is on the bus, just before its byte `byte` is clocked: after
    /// everything the chip does before that byte (see [`Progress`]), before the rest. An action
    /// at a byte beyond the transaction runs when chip select rises. One action at a time; it
    /// must not use this probe.
    pub fn at(&self, transaction: u64, byte: usize, action: impl FnOnce() + 'static) {
        self.0.borrow_mut().hook = Some((transaction, byte, Box::new(action)));
    }

    /// Whether the action of [`Probe::at`] is still waiting for its byte.
    pub fn armed(&self) -> bool {
        self.0.borrow().hook.is_some()
    }

    /// One cycle of a bus that is not SPI (the parallel bus of [`crate::mcu`]), counted and
    /// logged as a transaction of the data bytes `chip` returns (what was on the data lines):
    /// `chip` performs it, reporting what the real chip would reject and calling
    /// [`Progress::reach`] where it acts; the test's action for this cycle ([`Probe::at`]) runs
    /// there, or when the cycle ends.
    pub fn cycle(&self, chip: impl FnOnce(&mut Vec<String>, &mut Progress) -> Vec<u8>) -> Vec<u8> {
        let mut record = self.0.borrow_mut();
        let mut progress = record.progress();
        let data = chip(&mut record.violations, &mut progress);
        progress.reach(usize::MAX);
        record.stats.transactions += 1;
        record.stats.bytes += data.len() as u64;
        record.log.push(data.clone());
        data
    }
}

/// How far a chip has got in the transaction it decodes: before whatever the real chip does once
/// `byte` bytes have been clocked (sample a register, start an access), it calls
/// [`Progress::reach`]`(byte)`, which runs the test's action ([`Probe::at`]) if its byte has come.
pub struct Progress {
    action: Option<(usize, Action)>,
}

impl Progress {
    /// `byte` bytes of the transaction have been clocked.
    pub fn reach(&mut self, byte: usize) {
        if self.action.as_ref().is_some_and(|(at, _)| *at <= byte)
            && let Some((_, action)) = self.action.take()
        {
            action();
        }
    }
}

/// A chip behind an SPI chip-select line.
pub trait Chip {
    /// Why the chip cannot talk on a bus in `mode` now (its PDI not selected, another SPI
    /// mode configured, as its EEPROM's configuration area set them), or `None`. A refused
    /// transaction reaches nothing and reads [`NOT_DRIVEN`].
    fn refusal(&self, mode: SpiMode) -> Option<String> {
        let _ = mode;
        None
    }

    /// One transaction: `mosi` is what the master sent; fill `miso` (same length) with what the
    /// chip shifted out, and report what the real chip would reject or misread.
    /// `progress` marks the points within the transaction where the chip acts (see [`Progress`]).
    fn transaction(
        &mut self,
        mosi: &[u8],
        miso: &mut [u8],
        violations: &mut Vec<String>,
        progress: &mut Progress,
    );
}

/// MISO of a chip that does not talk: the line is not driven (pulled up).
pub const NOT_DRIVEN: u8 = 0xFF;

/// The SPI mode [`FakeSpi::new`] runs the bus in: mode 3, what both PDI drivers ask the board
/// for (`ecat_embassy::spi::beckhoff::SPI_MODE`, `ecat_embassy::spi::lan9252::SPI_MODE`).
pub const BUS_MODE: SpiMode = SpiMode::Mode3;

/// The error [`Probe::fail_next`] injects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusError;

impl embedded_hal_async::spi::Error for BusError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

/// An `SpiDevice` whose far end is `C`.
pub struct FakeSpi<C> {
    chip: C,
    probe: Probe,
    /// The SPI mode the bus (the microcontroller's SPI peripheral) is configured with.
    mode: SpiMode,
}

impl<C: Chip> FakeSpi<C> {
    /// `chip` on a bus in [`BUS_MODE`] watched by `probe`.
    pub fn new(chip: C, probe: Probe) -> Self {
        Self::with_mode(chip, probe, BUS_MODE)
    }

    /// `chip` on a bus in `mode` watched by `probe`.
    pub fn with_mode(chip: C, probe: Probe, mode: SpiMode) -> Self {
        Self { chip, probe, mode }
    }

    /// Flattens the operations into the byte stream on the wire, lets the chip answer and hands
    /// its answer back. During `Operation::Read` the master sends 0x00 (embedded-hal leaves it to
    /// the HAL; 0x00 is what DMA-driven HALs send), as it does for the part of an
    /// `Operation::Transfer` beyond its write buffer.
    fn exchange(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), BusError> {
        let mut record = self.probe.0.borrow_mut();
        if core::mem::take(&mut record.fail_next) {
            return Err(BusError);
        }
        let mut mosi = Vec::new();
        for op in operations.iter() {
            match op {
                Operation::Read(buf) => mosi.resize(mosi.len() + buf.len(), 0),
                Operation::Write(data) => mosi.extend_from_slice(data),
                Operation::Transfer(read, write) => {
                    mosi.extend_from_slice(write);
                    mosi.resize(mosi.len() + read.len().saturating_sub(write.len()), 0);
                }
                Operation::TransferInPlace(buf) => mosi.extend_from_slice(buf),
                Operation::DelayNs(_) => {}
            }
        }
        if let Some(why) = self.chip.refusal(self.mode) {
            if record.violations.last() != Some(&why) {
                record.violations.push(why);
            }
            record.stats.transactions += 1;
            record.stats.bytes += mosi.len() as u64;
            record.log.push(mosi);
            for op in operations.iter_mut() {
                match op {
                    Operation::Read(buf) | Operation::TransferInPlace(buf) => buf.fill(NOT_DRIVEN),
                    Operation::Transfer(read, _) => read.fill(NOT_DRIVEN),
                    Operation::Write(_) | Operation::DelayNs(_) => {}
                }
            }
            return Ok(());
        }
        let mut miso = vec![0; mosi.len()];
        let mut progress = record.progress();
        self.chip
            .transaction(&mosi, &mut miso, &mut record.violations, &mut progress);
        // An action at a byte beyond the transaction: chip select rises.
        progress.reach(usize::MAX);
        let mut incoming = miso.iter();
        for op in operations.iter_mut() {
            let (read, len): (&mut [u8], usize) = match op {
                Operation::Read(buf) | Operation::TransferInPlace(buf) => {
                    let len = buf.len();
                    (buf, len)
                }
                Operation::Transfer(read, write) => {
                    let len = read.len().max(write.len());
                    (read, len)
                }
                Operation::Write(data) => (&mut [], data.len()),
                Operation::DelayNs(_) => (&mut [], 0),
            };
            let clocked: Vec<u8> = incoming.by_ref().take(len).copied().collect();
            for (byte, value) in read.iter_mut().zip(clocked) {
                *byte = value;
            }
        }
        record.stats.transactions += 1;
        record.stats.bytes += mosi.len() as u64;
        record.log.push(mosi);
        Ok(())
    }
}

impl<C> ErrorType for FakeSpi<C> {
    type Error = BusError;
}

impl<C: Chip> SpiDevice for FakeSpi<C> {
    /// Performs the transaction, then yields to the executor once: a DMA transfer lets the
    /// executor run other tasks, so does the fake, and a driver spinning on the bus cannot starve
    /// the test script, which reports the livelock.
    async fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), BusError> {
        self.exchange(operations)?;
        embassy_futures::yield_now().await;
        Ok(())
    }
}
