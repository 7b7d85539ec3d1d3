//! Microchip LAN9252 (and LAN9253) with its host interface in SPI mode (LAN9252 datasheet, "SPI/SQI
//! Slave" and "EtherCAT CSR and Process Data RAM Access").
//!
//! The LAN9252 puts its own system registers in front of the EtherCAT core; the ESC address space
//! is reached indirectly:
//!
//! - ESC registers (below 0x1000) through the EtherCAT CSR interface: write the data register
//!   (`ECAT_CSR_DATA`, 0x0300) and/or the command register (`ECAT_CSR_CMD`, 0x0304: busy, read,
//!   size 1/2/4, address), wait until the command is no longer busy. Sizes and alignment follow
//!   Table 12-14, "EtherCAT CSR Address vs Size".
//! - Process RAM (0x1000 on) through the PRAM FIFOs: write address and length
//!   (`ECAT_PRAM_RD/WR_ADDR_LEN`) and the start bit (`ECAT_PRAM_RD/WR_CMD`) in one transaction,
//!   then move whole DWORDs through the FIFO (`ECAT_PRAM_RD_DATA` at 0x0000, `ECAT_PRAM_WR_DATA`
//!   at 0x0020), the first byte in byte lane `address % 4` of the first DWORD.
//!
//! Every SPI transaction is an instruction byte (READ 0x03, FAST READ 0x0B with one dummy byte,
//! WRITE 0x02), two address bytes (bit 14 set: the address increments from DWORD to DWORD; clear:
//! it stays, which is how a burst drains a FIFO) and whole little-endian DWORDs.
//!
//! ## The AL event
//! Unlike the Beckhoff SPI protocol, nothing delivers the AL event register (0x0220) for free: it
//! costs an EtherCAT CSR read. The driver reads it only for the reads the IRQ line prompts — reads
//! of process RAM (the process-data runner's output read, the mailbox) and reads of 0x0220 itself —
//! and reports it sampled before the access, as [`Pdi`] asks; an empty read reads it and nothing
//! else. A read of process RAM right after an empty read (no access between them) reports the
//! empty read's value instead of reading it again: on the IRQ the process-data runner samples
//! the AL event that way and reads the output area only if SM2 is among the events (reading it
//! takes the SM2 buffer and clears the event, so a sample taken by the same access could miss a
//! buffer the read takes), and so still pays one AL event read per cycle. Every other access
//! (register reads
//! and writes of the state machine, the input write) reports the state-machine events of the last
//! value read, less those the driver's reads have cleared since (reads of AL control and of the
//! SyncManager activation registers):
//! events that are known to be still pending, never stale ones. Events that arose meanwhile are
//! not lost: they hold the IRQ line asserted, and the process-data runner, waiting on it, reads
//! again.
//!
//! ## Polling
//! Only where the chip gives no other guarantee, and each poll shares its transaction with useful
//! data where it can:
//! - a CSR read writes a marker into the data register together with the command (one
//!   transaction), then reads the data register: a value other than the marker is the result, so
//!   the common case costs no busy poll;
//! - a CSR write waits for the command to finish (the next CSR command must not overlap it);
//! - a PRAM read reads the FIFO's available count once per FIFO load;
//! - a PRAM write trusts a freshly started command with an empty FIFO
//!   ([`WriteSpace::EmptyAtStart`], 16 DWORDs) and polls only for more, or polls before every
//!   FIFO load ([`WriteSpace::Polled`]).

use core::future::Future;
use core::ops::Range;

use ecat_core::AlEvent;
use ecat_core::chip::{Chip, SpiMode};
use ecat_core::register::{AL_EVENT_REQUEST, PROCESS_RAM};
use embassy_time::{Duration, Instant, Timer};

use crate::Pdi;
use crate::pdi::{Data, Sample};
use crate::spi::port::{Part, Port};

/// The SPI mode the bus must run in ([`Chip::LAN9252`]'s, which the SII image's configuration
/// area is written for): the LAN9252's SPI host interface takes mode 0 or 3.
pub const SPI_MODE: SpiMode = Chip::LAN9252.spi_mode;

const _: () = assert!(matches!(SPI_MODE, SpiMode::Mode0 | SpiMode::Mode3));

/// SPI instruction READ: address, then data (LAN9252 datasheet, "SPI/SQI Slave", "SPI Read").
const READ: u8 = 0x03;
/// SPI instruction FAST READ: address, one dummy byte, then data ("SPI Fast Read").
const FAST_READ: u8 = 0x0B;
/// SPI instruction WRITE: address, then data ("SPI Write").
const WRITE: u8 = 0x02;
/// SPI address bit 14: the address increments after each DWORD of a burst.
const AUTO_INCREMENT: u16 = 1 << 14;

/// `ECAT_PRAM_RD_DATA`: the PRAM read FIFO (0x0000..0x001F, all aliases of one FIFO).
const PRAM_READ_FIFO: u16 = 0x0000;
/// `ECAT_PRAM_WR_DATA`: the PRAM write FIFO (0x0020..0x003F).
const PRAM_WRITE_FIFO: u16 = 0x0020;
/// `IRQ_CFG`, "Interrupt Configuration Register".
const IRQ_CFG: u16 = 0x0054;
/// `IRQ_CFG` bit 8 `IRQ_EN` (IRQ output enabled), bit 4 `IRQ_POL` clear (active low), bit 0
/// `IRQ_BUF_TYPE` (push-pull).
const IRQ_CFG_ENABLED_ACTIVE_LOW_PUSH_PULL: u32 = 1 << 8 | 1;
/// `INT_EN`, "Interrupt Enable Register".
const INT_EN: u16 = 0x005C;
/// `INT_EN` bit 0 `ECAT_EVENT_EN`: the EtherCAT core's interrupt (AL event & AL event mask) drives
/// the IRQ output.
const ECAT_EVENT_EN: u32 = 1 << 0;
/// `BYTE_TEST`, "Byte Order Test Register": reads [`BYTE_TEST_PATTERN`] once the host interface
/// works.
const BYTE_TEST: u16 = 0x0064;
/// What `BYTE_TEST` reads on a working host interface with the right byte order.
pub const BYTE_TEST_PATTERN: u32 = 0x8765_4321;
/// `HW_CFG`, "Hardware Configuration Register".
const HW_CFG: u16 = 0x0074;
/// `HW_CFG` bit 27 `READY`: the device is ready to be accessed.
const HW_CFG_READY: u32 = 1 << 27;
/// `RESET_CTL`, "Reset Control Register".
const RESET_CTL: u16 = 0x01F8;
/// `RESET_CTL` bit 0 `DIGITAL_RST`: resets the whole chip but the PHYs' analog parts.
const DIGITAL_RST: u32 = 1 << 0;
/// `ECAT_CSR_DATA`, "EtherCAT CSR Interface Data Register".
const CSR_DATA: u16 = 0x0300;
/// `ECAT_CSR_CMD`, "EtherCAT CSR Interface Command Register".
const CSR_CMD: u16 = 0x0304;
/// `ECAT_CSR_CMD` bit 31 `CSR_BUSY`: write 1 to start, reads 1 until done.
const CSR_BUSY: u32 = 1 << 31;
/// `ECAT_CSR_CMD` bit 30 `R_nW`: 1 = read.
const CSR_READ: u32 = 1 << 30;
/// `ECAT_CSR_CMD` bits 18:16 `CSR_SIZE`: 1, 2 or 4 bytes; bits 15:0 `CSR_ADDR`.
const CSR_SIZE_SHIFT: u32 = 16;
/// Written into `ECAT_CSR_DATA` before a CSR read: a result other than this proves the read done.
const CSR_MARKER: u32 = 0xFFFF_FFFF;
/// `ECAT_PRAM_RD_ADDR_LEN`: bits 15:0 address, bits 31:16 length in bytes.
const PRAM_READ_ADDR_LEN: u16 = 0x0308;
/// `ECAT_PRAM_RD_CMD`: bit 31 busy (write 1 to start), bits 12:8 DWORDs available in the FIFO.
const PRAM_READ_CMD: u16 = 0x030C;
/// `ECAT_PRAM_WR_ADDR_LEN`: bits 15:0 address, bits 31:16 length in bytes.
const PRAM_WRITE_ADDR_LEN: u16 = 0x0310;
/// `ECAT_PRAM_WR_CMD`: bit 31 busy (write 1 to start), bits 12:8 DWORDs of space in the FIFO.
const PRAM_WRITE_CMD: u16 = 0x0314;
/// `ECAT_PRAM_RD/WR_CMD` bit 31: write 1 to start the transfer; reads 1 until it is done.
const PRAM_BUSY: u32 = 1 << 31;
/// Depth of each PRAM FIFO in DWORDs (the 5-bit count fields reach 16).
pub const PRAM_FIFO_DWORDS: usize = 16;

/// The events the driver keeps reporting after reading them: those whose clearing it can follow
/// ([`AlEvent::cleared_by_register_read`]), which are also the state-machine events.
const TRACKED: AlEvent = AlEvent::AL_CONTROL.union(AlEvent::SM_CHANGE);

/// The start-up's register transactions: a value to write, or `None` for a register read until
/// it shows the chip ready (see [`Lan9252::start`]).
const START_UP: [(u16, Option<u32>); 5] = [
    (RESET_CTL, Some(DIGITAL_RST)),
    (BYTE_TEST, None),
    (HW_CFG, None),
    (IRQ_CFG, Some(IRQ_CFG_ENABLED_ACTIVE_LOW_PUSH_PULL)),
    (INT_EN, Some(ECAT_EVENT_EN)),
];

/// Between two polls of a register that is not ready yet.
const POLL_INTERVAL: Duration = Duration::from_micros(10);

/// The instruction for reads of the LAN9252's registers and FIFOs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadInstruction {
    /// READ (0x03): no dummy byte; for the SPI clocks the datasheet allows READ at.
    Read,
    /// FAST READ (0x0B): one dummy byte per read, for the full SPI clock range.
    FastRead,
}

/// How a PRAM write learns that the write FIFO has room.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WriteSpace {
    /// A write command starts on an empty FIFO (the previous write consumed all its data, which
    /// the chip moves into process RAM long before the next command's start transaction ends): the
    /// first 16 DWORDs go without a poll, the rest after polling the space count. Saves one
    /// register read per process-data cycle.
    EmptyAtStart,
    /// Poll the space count before every FIFO load, as the datasheet's write flow chart does.
    Polled,
}

/// The driver's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// The read instruction.
    pub read: ReadInstruction,
    /// The PRAM write flow control.
    pub write_space: WriteSpace,
    /// How long the chip may take to come out of reset (byte-order test, then `HW_CFG.READY`).
    pub startup_timeout: Duration,
    /// How long a CSR command or a PRAM FIFO may stay busy or empty.
    pub busy_timeout: Duration,
}

impl Default for Config {
    /// READ, [`WriteSpace::EmptyAtStart`], 1 s to come out of reset, 1 ms per busy wait (a CSR
    /// command takes well under a microsecond).
    fn default() -> Self {
        Self {
            read: ReadInstruction::Read,
            write_space: WriteSpace::EmptyAtStart,
            startup_timeout: Duration::from_secs(1),
            busy_timeout: Duration::from_millis(1),
        }
    }
}

/// What the driver waited for when it gave up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Wait {
    /// `HW_CFG.READY` after the reset.
    Ready,
    /// An EtherCAT CSR command to finish.
    Csr,
    /// Data in the PRAM read FIFO.
    PramRead,
    /// Space in the PRAM write FIFO.
    PramWrite,
}

/// Why the driver failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E> {
    /// The SPI transaction failed.
    Spi(E),
    /// `BYTE_TEST` never read [`BYTE_TEST_PATTERN`] within the start-up timeout: wiring, SPI
    /// mode or chip select is wrong (the value read tells which bits go astray).
    ByteTest {
        /// The last value read.
        read: u32,
    },
    /// A wait timed out.
    Timeout(Wait),
}

/// A [`Pdi`] for the LAN9252 in SPI mode.
// `repr(C)`: small fields first (docs/performance.md, "Codegen rules").
#[repr(C)]
pub struct Lan9252<S> {
    /// State-machine events of the last AL event value read, less those cleared since.
    known: AlEvent,
    /// The AL event read by the last access if it was an empty read, else none: what a read of
    /// process RAM right after it reports.
    sampled: AlEvent,
    /// What the next access's AL event must be ([`Pdi::sample`]).
    sample: Sample,
    /// The AL event the last access reported ([`Pdi::al_event`]).
    reported: AlEvent,
    config: Config,
    spi: S,
}

impl<S: Port> Lan9252<S> {
    /// Resets the chip (`RESET_CTL.DIGITAL_RST`), waits for the byte-order test to read
    /// [`BYTE_TEST_PATTERN`] and for `HW_CFG.READY`, then routes the EtherCAT interrupt to the IRQ
    /// output, active low, push-pull. `spi` must be in [`SPI_MODE`].
    #[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
    pub fn start(spi: S, config: Config) -> impl Future<Output = Result<Self, Error<S::Error>>> {
        // An `async` block: `spi` is its capture, moved into the driver in place rather than
        // kept as an argument beside it.
        async move {
            let mut chip = Self {
                spi,
                config,
                known: AlEvent::NONE,
                sampled: AlEvent::NONE,
                sample: Sample::Usual,
                reported: AlEvent::NONE,
            };
            let mut deadline = Deadline(Instant::MAX);
            // One transaction per pass, the register polls repeated after a pause.
            for &(register, write) in &START_UP {
                loop {
                    let (mut header, mut bytes) = (Header::NONE, [0; 8]);
                    let write = write.as_ref().map(core::slice::from_ref);
                    let parts =
                        register_parts(&mut header, &mut bytes, config.read, register, write);
                    chip.spi.transaction(parts).await.map_err(Error::Spi)?;
                    let read = dword(&bytes);
                    let failure = match register {
                        RESET_CTL => {
                            deadline = Deadline::after(config.startup_timeout);
                            break;
                        }
                        BYTE_TEST if read != BYTE_TEST_PATTERN => Error::ByteTest { read },
                        HW_CFG if read & HW_CFG_READY == 0 => Error::Timeout(Wait::Ready),
                        _ => break,
                    };
                    deadline.pause().await.map_err(|Expired| failure)?;
                }
            }
            Ok(chip)
        }
    }
}

impl<S: Port> Pdi for Lan9252<S> {
    type Error = Error<S::Error>;

    /// 4 SyncManagers, 4 KiB of process RAM.
    const CHIP: Option<Chip> = Some(Chip::LAN9252);

    /// ESC registers: one CSR command (the driver moves them one command at a time anyway, so
    /// the process-data runner may come in between any two). Process RAM: at most `chunk`
    /// bytes, ending on a DWORD boundary when the chunk is cut short, so that the next chunk
    /// starts in byte lane 0 (no padding in its FIFO stream). Each chunk of process RAM is a
    /// PRAM command of its own: the FIFOs hold one command at a time, and the process-data
    /// runner's read needs the read FIFO.
    fn chunk(&self, address: u16, len: usize, chunk: usize) -> usize {
        let registers = register_bytes(address, len);
        if registers > 0 {
            return csr_size(address, registers);
        }
        if len <= chunk {
            return len;
        }
        let end = (usize::from(address) + chunk) & !3;
        end.saturating_sub(usize::from(address)).max(chunk.min(4))
    }

    /// [`Sample::Continued`]: a later chunk of a read of process RAM reports the events known
    /// instead of reading the AL event register. [`Sample::Fresh`]: any access reads it, writes
    /// included (18 bytes; only while state-machine events hold the IRQ line).
    fn sample(&mut self, sample: Sample) {
        self.sample = sample;
    }

    fn al_event(&self) -> AlEvent {
        self.reported
    }

    /// Registers through the CSR interface, process RAM through the PRAM FIFOs. A read that
    /// touches process RAM first reads the AL event register (unless the access before it was an
    /// empty read: then it reports that one's), and so do an empty read (nothing else) and a read
    /// of 0x0220 itself; any other access reports the state-machine events known to be pending
    /// (see the module docs).
    #[allow(clippy::manual_async_fn)] // docs/performance.md, "Codegen rules"
    fn access(
        &mut self,
        address: u16,
        data: Data<'_>,
    ) -> impl Future<Output = Result<(), Self::Error>> {
        async move {
            let clears = match &data {
                Data::Read(buf) => {
                    AlEvent::cleared_by_register_read(address, buf.len()).intersection(TRACKED)
                }
                Data::Write(_) => AlEvent::NONE,
            };
            let reading = matches!(data, Data::Read(_));
            let len = data.len();
            let (mut registers, mut ram) = data.split_at(register_bytes(address, len));
            // Taken by every access: only the next one may report it.
            let sampled = core::mem::replace(&mut self.sampled, AlEvent::NONE);
            let sample = core::mem::replace(&mut self.sample, Sample::Usual);
            let prompted = reading && (len == 0 || !ram.is_empty() && sample != Sample::Continued);
            let sampling = prompted || sample == Sample::Fresh;
            // The AL event register is read first where the access must report a fresh value
            // and no empty read just before left one.
            let read_event = sampling && (len == 0 || sampled.is_empty());
            let mut event = [0; 4];
            let ram_address = address.max(PROCESS_RAM);
            let stream = FifoStream::new(ram_address, ram.len());
            let (address_length, command, wait, fresh_space) = match &ram {
                Data::Read(_) => (PRAM_READ_ADDR_LEN, PRAM_READ_CMD, Wait::PramRead, 0),
                Data::Write(_) => (
                    PRAM_WRITE_ADDR_LEN,
                    PRAM_WRITE_CMD,
                    Wait::PramWrite,
                    match self.config.write_space {
                        WriteSpace::EmptyAtStart => 4 * PRAM_FIFO_DWORDS,
                        WriteSpace::Polled => 0,
                    },
                ),
            };
            let mut step = Step::Piece(if read_event {
                Region::Event
            } else {
                Region::Access
            });
            let (mut offset, mut piece) = (0, Piece::NONE);
            let (mut position, mut space) = (0, 0);
            let mut deadline = Deadline(Instant::MIN);
            // One pause or one transaction per pass: the driver's only two awaits.
            loop {
                let (register, write) = match step {
                    Step::Piece(region) => {
                        let (base, len, write) = match (region, &registers) {
                            (Region::Event, _) => (AL_EVENT_REQUEST, event.len(), None),
                            (Region::Access, Data::Read(buf)) => (address, buf.len(), None),
                            (Region::Access, Data::Write(bytes)) => {
                                (address, bytes.len(), Some(*bytes))
                            }
                        };
                        if offset >= len {
                            offset = 0;
                            step = match region {
                                Region::Event => Step::Piece(Region::Access),
                                Region::Access if ram.is_empty() => break,
                                Region::Access => Step::Pram,
                            };
                            continue;
                        }
                        piece = Piece::new(region, base, offset, len, write);
                        (CSR_DATA, Some(piece.command()))
                    }
                    Step::Poll(register) => (register, None),
                    Step::Pram => {
                        let value = [stream.address_length(ram_address), PRAM_BUSY];
                        (address_length, Some(value))
                    }
                    Step::Load if position >= stream.len() => break,
                    Step::Load if space == 0 => (command, None),
                    // A FIFO load: its parts are the stream's (below), not a register's.
                    Step::Load => (PRAM_READ_FIFO, None),
                    Step::Pause(wait) => {
                        deadline
                            .pause()
                            .await
                            .map_err(|Expired| Error::Timeout(wait))?;
                        step = match wait {
                            Wait::Csr => Step::Poll(piece.first_poll()),
                            _ => Step::Load,
                        };
                        continue;
                    }
                };
                let mut bytes = [0; 8];
                let (mut head, mut tail) = ([0; 3], [0; 3]);
                let end = stream.len().min(position + space);
                let mut header = Header::NONE;
                let parts = match (step, write, &mut ram) {
                    // One FIFO load, a read's or a write's: the padding is clocked out as zeros
                    // either way (in place: what comes back is dropped), a read's data too.
                    (Step::Load, _, ram) if space > 0 => {
                        let layout = stream.layout(position..end);
                        let data = match ram {
                            Data::Read(buf) => {
                                header = Header::read(self.config.read, PRAM_READ_FIFO);
                                let buf = buf.get_mut(layout.data).unwrap_or_default();
                                buf.fill(0);
                                Part::Exchange(buf)
                            }
                            Data::Write(data) => {
                                header = Header::write(PRAM_WRITE_FIFO, false);
                                Part::Write(data.get(layout.data).unwrap_or_default())
                            }
                        };
                        [
                            Part::Write(header.as_slice()),
                            Part::Exchange(head.get_mut(..layout.head).unwrap_or_default()),
                            data,
                            Part::Exchange(tail.get_mut(..layout.tail).unwrap_or_default()),
                        ]
                    }
                    // One LAN9252 register read, or two consecutive ones written.
                    (_, write, _) => {
                        let write = write.as_ref().map(|values| &values[..]);
                        register_parts(&mut header, &mut bytes, self.config.read, register, write)
                    }
                };
                self.spi.transaction(parts).await.map_err(Error::Spi)?;
                let value = dword(&bytes);
                step = match step {
                    Step::Piece(_) => {
                        deadline = Deadline::after(self.config.busy_timeout);
                        Step::Poll(piece.first_poll())
                    }
                    // A read's data register: the marker means still busy, or a register that
                    // holds the marker's value; the command register tells which.
                    Step::Poll(CSR_DATA) if value == CSR_MARKER && !piece.done => {
                        Step::Poll(CSR_CMD)
                    }
                    Step::Poll(CSR_CMD) if value & CSR_BUSY != 0 => Step::Pause(Wait::Csr),
                    Step::Poll(CSR_CMD) if piece.write.is_none() => {
                        piece.done = true;
                        Step::Poll(CSR_DATA)
                    }
                    // The piece is done: a read's value is the data register's.
                    Step::Poll(_) => {
                        let buf = match (piece.region, &mut registers) {
                            (Region::Event, _) => &mut event[..],
                            (Region::Access, Data::Read(buf)) => &mut buf[..],
                            (Region::Access, Data::Write(_)) => &mut [],
                        };
                        // Little-endian: the low byte first.
                        let mut value = value;
                        for byte in buf.iter_mut().skip(offset).take(piece.size) {
                            *byte = value as u8;
                            value >>= 8;
                        }
                        offset += piece.size;
                        Step::Piece(piece.region)
                    }
                    Step::Pram => {
                        deadline = Deadline::after(self.config.busy_timeout);
                        space = fresh_space;
                        Step::Load
                    }
                    // A read polls the data available before every FIFO load, a write when the
                    // space it knows of is used up.
                    Step::Load if space == 0 => match fifo_bytes(value) {
                        0 => Step::Pause(wait),
                        bytes => {
                            space = bytes;
                            Step::Load
                        }
                    },
                    Step::Load => {
                        space -= end - position;
                        position = end;
                        Step::Load
                    }
                    Step::Pause(_) => step,
                };
            }
            let fresh = sampling.then(|| {
                let event = if read_event {
                    AlEvent(u32::from_le_bytes(event))
                } else {
                    sampled
                };
                if len == 0 {
                    self.sampled = event;
                }
                event
            });
            let fresh = match &registers {
                Data::Read(registers) => fresh.or_else(|| al_event_in(address, registers)),
                Data::Write(_) => fresh,
            };
            self.reported = fresh.unwrap_or(self.known);
            self.known = fresh
                .map_or(self.known, |e| e.intersection(TRACKED))
                .difference(clears);
            Ok(())
        }
    }
}

/// Where an access is: one step per pass of [`Pdi::access`]'s loop, which moves the ESC
/// registers one CSR command at a time, then the process RAM one FIFO load at a time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// Start the CSR command of the next piece of the region, or move on when it is done.
    Piece(Region),
    /// Read this register (`ECAT_CSR_DATA` or `ECAT_CSR_CMD`) for the CSR command in flight.
    ///
    /// A read writes [`CSR_MARKER`] into the data register together with the command (one
    /// transaction), then reads the data register: a value other than the marker is the result.
    /// The marker means still busy, or a register that holds the marker's value: the command
    /// register tells which. A write waits for the command to finish (the next CSR command must
    /// not overlap it).
    Poll(u16),
    /// Start the PRAM command: address and length, then the start bit.
    Pram,
    /// The next FIFO load; first the FIFO's count when no data or space is known.
    Load,
    /// Wait [`POLL_INTERVAL`] before polling again, or give up at the deadline.
    Pause(Wait),
}

/// ESC registers an access moves through the CSR interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Region {
    /// The AL event register, read for the access's report.
    Event,
    /// The registers of the access itself.
    Access,
}

/// One EtherCAT CSR command: 1, 2 or 4 bytes of a [`Region`].
#[derive(Debug, Clone, Copy)]
struct Piece {
    region: Region,
    /// The ESC address.
    position: u16,
    size: usize,
    /// The value a write stores (in the low bytes); `None` for a read.
    write: Option<u32>,
    /// A read's command register read not busy: the data register holds the value.
    done: bool,
}

impl Piece {
    /// No command yet.
    const NONE: Self = Self {
        region: Region::Access,
        position: 0,
        size: 0,
        write: None,
        done: false,
    };

    /// The command for the bytes from `offset` (below `len`) of the region at `base`, in the
    /// largest piece the CSR interface takes; `write` holds the region's bytes of a write.
    fn new(region: Region, base: u16, offset: usize, len: usize, write: Option<&[u8]>) -> Self {
        let position = base.wrapping_add(offset as u16);
        let size = csr_size(position, len - offset);
        // The piece's bytes as a little-endian value, the last one first.
        let write = write.map(|bytes| {
            let bytes = bytes.iter().skip(offset).take(size);
            bytes
                .rev()
                .fold(0, |value, &byte| value << 8 | u32::from(byte))
        });
        Self {
            region,
            position,
            size,
            write,
            done: false,
        }
    }

    /// The `ECAT_CSR_DATA` and `ECAT_CSR_CMD` values that start it: the value to write, or
    /// [`CSR_MARKER`] for a read.
    fn command(&self) -> [u32; 2] {
        let (data, read) = match self.write {
            Some(value) => (value, 0),
            None => (CSR_MARKER, CSR_READ),
        };
        [data, csr_command(read, self.position, self.size)]
    }

    /// The register polled first: a read's data register, a write's command register.
    fn first_poll(&self) -> u16 {
        match self.write {
            None => CSR_DATA,
            Some(_) => CSR_CMD,
        }
    }
}

/// How many of `len` bytes at `address` are ESC registers (below 0x1000).
fn register_bytes(address: u16, len: usize) -> usize {
    usize::from(PROCESS_RAM.saturating_sub(address)).min(len)
}

/// The AL event register, if `registers` (read at `address`) holds all of it.
fn al_event_in(address: u16, registers: &[u8]) -> Option<AlEvent> {
    let offset = usize::from(AL_EVENT_REQUEST.checked_sub(address)?);
    let bytes = registers.get(offset..offset + 4)?;
    Some(AlEvent(u32::from_le_bytes(bytes.try_into().ok()?)))
}

/// The largest CSR access at `address` for `remaining` bytes (Table 12-14, "EtherCAT CSR Address
/// vs Size": 4 bytes on a DWORD boundary, 2 on a WORD boundary, else 1).
fn csr_size(address: u16, remaining: usize) -> usize {
    if address.is_multiple_of(4) && remaining >= 4 {
        4
    } else if address.is_multiple_of(2) && remaining >= 2 {
        2
    } else {
        1
    }
}

/// An `ECAT_CSR_CMD` value that starts a command.
fn csr_command(read: u32, address: u16, size: usize) -> u32 {
    CSR_BUSY | read | (size as u32) << CSR_SIZE_SHIFT | u32::from(address)
}

/// Bytes the FIFO holds (read) or has room for (write), from `ECAT_PRAM_RD/WR_CMD` bits 12:8.
fn fifo_bytes(command: u32) -> usize {
    4 * ((command >> 8) & 0x1F) as usize
}

/// The DWORD stream of one PRAM transfer: `lane` padding bytes, the data, padding to a whole DWORD.
struct FifoStream {
    lane: usize,
    data: usize,
}

/// Where the bytes of part of a [`FifoStream`] go.
struct Layout {
    /// Leading padding bytes.
    head: usize,
    /// The data bytes, as positions in the data.
    data: Range<usize>,
    /// Trailing padding bytes.
    tail: usize,
}

impl FifoStream {
    fn new(address: u16, data: usize) -> Self {
        Self {
            lane: usize::from(address % 4),
            data,
        }
    }

    /// Stream length in bytes: whole DWORDs.
    fn len(&self) -> usize {
        (self.lane + self.data).div_ceil(4) * 4
    }

    /// The `ECAT_PRAM_RD/WR_ADDR_LEN` value.
    fn address_length(&self, address: u16) -> u32 {
        let length = u32::try_from(self.data).unwrap_or(u32::MAX) & 0xFFFF;
        length << 16 | u32::from(address)
    }

    /// The padding and data bytes of the stream bytes `part`.
    fn layout(&self, part: Range<usize>) -> Layout {
        let data_end = self.lane + self.data;
        let head = self.lane.min(part.end).saturating_sub(part.start);
        // Clamped to lane..=data_end with max/min: `clamp` would carry a formatted panic for
        // bounds that cannot be reversed here.
        let start = part.start.max(self.lane).min(data_end) - self.lane;
        let end = part.end.max(self.lane).min(data_end) - self.lane;
        let tail = part.end.saturating_sub(data_end.max(part.start));
        Layout {
            head,
            data: start..end,
            tail,
        }
    }
}

/// The parts of one transaction on the LAN9252's own registers: a read of the DWORD at
/// `register` into `bytes` (`write` is `None`), or a write of the DWORDs of `write` (at most
/// two, consecutive registers) from `register` on. Every transaction of the driver is four
/// parts: the instruction and address, then the data in up to three pieces (a FIFO stream's
/// padding before and after the data); a read's data is clocked out as zeros.
fn register_parts<'b>(
    header: &'b mut Header,
    bytes: &'b mut [u8; 8],
    instruction: ReadInstruction,
    register: u16,
    write: Option<&[u32]>,
) -> [Part<'b>; 4] {
    let data = match write {
        None => {
            *header = Header::read(instruction, register);
            Part::Exchange(bytes.get_mut(..4).unwrap_or_default())
        }
        Some(values) => {
            // Both DWORDs as one little-endian u64: no `copy_from_slice` (and its length panic).
            let value = |i| u64::from(values.get(i).copied().unwrap_or(0));
            *bytes = (value(1) << 32 | value(0)).to_le_bytes();
            *header = Header::write(register, values.len() > 1);
            Part::Write(bytes.get(..4 * values.len().min(2)).unwrap_or_default())
        }
    };
    [
        Part::Write(header.as_slice()),
        data,
        Part::Write(&[]),
        Part::Write(&[]),
    ]
}

/// The DWORD a register read brought ([`register_parts`]).
fn dword(bytes: &[u8; 8]) -> u32 {
    let [b0, b1, b2, b3, ..] = *bytes;
    u32::from_le_bytes([b0, b1, b2, b3])
}

/// Instruction and address bytes of one transaction.
struct Header {
    bytes: [u8; 4],
    len: usize,
}

impl Header {
    /// No transaction yet.
    const NONE: Self = Self {
        bytes: [0; 4],
        len: 0,
    };

    /// A read of `address`, without address increment (a burst drains a FIFO or reads one DWORD).
    fn read(instruction: ReadInstruction, address: u16) -> Self {
        let [high, low] = address.to_be_bytes();
        match instruction {
            ReadInstruction::Read => Self {
                bytes: [READ, high, low, 0],
                len: 3,
            },
            ReadInstruction::FastRead => Self {
                bytes: [FAST_READ, high, low, 0],
                len: 4,
            },
        }
    }

    /// A write at `address`, incrementing from DWORD to DWORD if `increment`.
    fn write(address: u16, increment: bool) -> Self {
        let address = if increment {
            address | AUTO_INCREMENT
        } else {
            address
        };
        let [high, low] = address.to_be_bytes();
        Self {
            bytes: [WRITE, high, low, 0],
            len: 3,
        }
    }

    fn as_slice(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or_default()
    }
}

/// A wait ran out of time.
struct Expired;

/// When a wait gives up.
struct Deadline(Instant);

impl Deadline {
    fn after(timeout: Duration) -> Self {
        Self(Instant::now().checked_add(timeout).unwrap_or(Instant::MAX))
    }

    /// Waits [`POLL_INTERVAL`] before the next poll, or fails if the deadline has passed.
    async fn pause(&self) -> Result<(), Expired> {
        if Instant::now() >= self.0 {
            return Err(Expired);
        }
        Timer::after(POLL_INTERVAL).await;
        Ok(())
    }
}
