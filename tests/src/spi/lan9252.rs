//! A Microchip LAN9252 with its host interface in SPI mode, in front of the emulated ESC
//! (LAN9252 datasheet, "SPI/SQI Slave", "System Control and Status Registers", "EtherCAT CSR and
//! Process Data RAM Access").
//!
//! - SPI: READ 0x03 (2 address bytes), FAST READ 0x0B (2 address bytes and a dummy byte), WRITE
//!   0x02 (2 address bytes), then little-endian DWORDs. Address bits 15:14 = 01b increment the
//!   address from DWORD to DWORD, 00b keep it (FIFO bursts). The fake insists on DWORD-aligned
//!   addresses and whole DWORDs, which is all a driver needs; other instructions (SQI, dual/quad)
//!   are flagged.
//! - System registers: `ID_REV`, `IRQ_CFG`, `INT_STS` (bit 0: the ESC's IRQ), `INT_EN`, `BYTE_TEST`
//!   (0 while in reset), `HW_CFG` (`READY`, bit 27), `RESET_CTL` (`DIGITAL_RST`, bit 0). Anything
//!   else is flagged as not modelled.
//! - EtherCAT CSR: `ECAT_CSR_DATA`/`ECAT_CSR_CMD`; a command (busy bit 31, read bit 30, size 1/2/4
//!   in bits 18:16 with the alignment of Table 12-14, register address below 0x1000) is one PDI
//!   access of the emulated ESC, done [`Lan9252Config::csr_latency`] transactions after the one that
//!   started it; a read zero-extends the result into the data register. Touching data or command
//!   while busy is flagged.
//! - PRAM: `ECAT_PRAM_RD/WR_ADDR_LEN` (address 15:0, length 31:16) and `ECAT_PRAM_RD/WR_CMD`
//!   (busy 31, abort 30, FIFO count 12:8, available 0). A read is one PDI access at its start; its
//!   DWORDs (first byte in lane `address % 4`) enter the 16-DWORD FIFO
//!   [`Lan9252Config::fifo_fill`] at a time as each transaction ends. A write takes DWORDs from its
//!   FIFO [`Lan9252Config::fifo_drain`] at a time as each transaction ends and is one PDI access
//!   once complete. Reading an
//!   empty FIFO, overfilling one, or feeding one without a command is flagged.
//!
//! - `RESET_CTL.DIGITAL_RST` resets the LAN9252's own registers and engines; the emulated ESC
//!   behind them keeps its state (the tests start from its power-on state anyway).
//!
//! Each transaction's effects on the engines happen when chip select rises, as in the chip, where
//! they run concurrently with the SPI slave.

use std::collections::VecDeque;

use ecat_core::chip::SpiMode;

use crate::emulator::Emulator;
use crate::spi::{Chip, Progress};

const READ: u8 = 0x03;
const FAST_READ: u8 = 0x0B;
const WRITE: u8 = 0x02;

const ID_REV: u16 = 0x050;
const IRQ_CFG: u16 = 0x054;
const INT_STS: u16 = 0x058;
const INT_EN: u16 = 0x05C;
const BYTE_TEST: u16 = 0x064;
const HW_CFG: u16 = 0x074;
const RESET_CTL: u16 = 0x1F8;
const CSR_DATA: u16 = 0x300;
const CSR_CMD: u16 = 0x304;
const PRAM_RD_ADDR_LEN: u16 = 0x308;
const PRAM_RD_CMD: u16 = 0x30C;
const PRAM_WR_ADDR_LEN: u16 = 0x310;
const PRAM_WR_CMD: u16 = 0x314;

const BUSY: u32 = 1 << 31;
const ABORT: u32 = 1 << 30;
const CSR_READ: u32 = 1 << 30;
const FIFO_DWORDS: usize = 16;
/// `ID_REV` of a LAN9252, revision 1.
pub const LAN9252_ID_REV: u32 = 0x9252_0001;
/// What `BYTE_TEST` reads on a working chip.
pub const BYTE_TEST_PATTERN: u32 = 0x8765_4321;

/// How the fake behaves where the real chip's timing varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lan9252Config {
    /// `BYTE_TEST` reads after a digital reset that still find the chip in reset (reading 0).
    pub reset_polls: u32,
    /// What `BYTE_TEST` reads out of reset: [`BYTE_TEST_PATTERN`], or a wrong value to model a
    /// miswired bus or wrong SPI mode.
    pub byte_test: u32,
    /// `HW_CFG` reads out of reset before `READY` is set; `None`: never.
    pub ready_after: Option<u32>,
    /// Transactions after the starting one during which an EtherCAT CSR command stays busy.
    pub csr_latency: u32,
    /// DWORDs the PRAM read engine moves into its FIFO as each transaction ends.
    pub fifo_fill: usize,
    /// DWORDs the PRAM write engine takes from its FIFO as each transaction ends.
    pub fifo_drain: usize,
}

impl Default for Lan9252Config {
    /// A chip that comes out of reset at once, finishes CSR commands before the next transaction
    /// and fills and drains its FIFOs as fast as it can.
    fn default() -> Self {
        Self {
            reset_polls: 0,
            byte_test: BYTE_TEST_PATTERN,
            ready_after: Some(0),
            csr_latency: 0,
            fifo_fill: FIFO_DWORDS,
            fifo_drain: FIFO_DWORDS,
        }
    }
}

/// The EtherCAT CSR interface.
#[derive(Default)]
struct Csr {
    data: u32,
    command: u32,
    /// Transactions to go before the busy command is done.
    countdown: u32,
}

/// The PRAM read engine.
#[derive(Default)]
struct PramRead {
    address_length: u32,
    busy: bool,
    /// DWORDs read from the ESC, not yet in the FIFO.
    pending: VecDeque<u32>,
    fifo: VecDeque<u32>,
}

/// The PRAM write engine.
#[derive(Default)]
struct PramWrite {
    address_length: u32,
    busy: bool,
    /// DWORDs the command needs.
    expected: usize,
    /// DWORDs taken from the FIFO.
    received: Vec<u32>,
    fifo: VecDeque<u32>,
}

/// The chip; put it behind a [`FakeSpi`](crate::spi::FakeSpi).
pub struct Lan9252Chip {
    emu: Emulator,
    config: Lan9252Config,
    /// `BYTE_TEST` reads left that still see the chip in reset.
    in_reset: u32,
    /// `HW_CFG` reads left before `READY`; `None`: never.
    not_ready: Option<u32>,
    irq_cfg: u32,
    int_en: u32,
    csr: Csr,
    read: PramRead,
    write: PramWrite,
}

impl Lan9252Chip {
    /// A LAN9252 on `emu`'s ESC, just powered on (not in reset).
    pub fn new(emu: Emulator, config: Lan9252Config) -> Self {
        Self {
            emu,
            config,
            in_reset: 0,
            not_ready: Some(0),
            irq_cfg: 0,
            int_en: 0,
            csr: Csr::default(),
            read: PramRead::default(),
            write: PramWrite::default(),
        }
    }

    /// `RESET_CTL.DIGITAL_RST`: everything back to its reset value, in reset for a while.
    fn digital_reset(&mut self) {
        *self = Self {
            in_reset: self.config.reset_polls,
            not_ready: self.config.ready_after,
            ..Self::new(self.emu.clone(), self.config)
        };
    }

    fn read_register(&mut self, address: u16, violations: &mut Vec<String>) -> u32 {
        match address {
            0x000..=0x01F => self.read.fifo.pop_front().unwrap_or_else(|| {
                violations.push("PRAM read FIFO read while empty".to_string());
                0
            }),
            ID_REV => LAN9252_ID_REV,
            IRQ_CFG => self.irq_cfg,
            INT_STS => u32::from(self.emu.with(|esc| esc.irq())),
            INT_EN => self.int_en,
            BYTE_TEST if self.in_reset > 0 => {
                self.in_reset -= 1;
                0
            }
            BYTE_TEST => self.config.byte_test,
            HW_CFG => match &mut self.not_ready {
                Some(0) => 1 << 27,
                Some(left) => {
                    *left -= 1;
                    0
                }
                None => 0,
            },
            RESET_CTL => 0,
            CSR_DATA => self.csr.data,
            CSR_CMD => self.csr.command,
            PRAM_RD_ADDR_LEN => self.read.address_length,
            PRAM_RD_CMD => fifo_status(self.read.busy, self.read.fifo.len()),
            PRAM_WR_ADDR_LEN => self.write.address_length,
            PRAM_WR_CMD => fifo_status(self.write.busy, FIFO_DWORDS - self.write.fifo.len()),
            other => {
                violations.push(format!("read of register {other:#05x}, not modelled"));
                0
            }
        }
    }

    fn write_register(&mut self, address: u16, value: u32, violations: &mut Vec<String>) {
        match address {
            0x020..=0x03F if !self.write.busy => {
                violations.push("PRAM write FIFO written without a write command".to_string());
            }
            0x020..=0x03F if self.write.fifo.len() >= FIFO_DWORDS => {
                violations.push("PRAM write FIFO overflow".to_string());
            }
            0x020..=0x03F => self.write.fifo.push_back(value),
            IRQ_CFG => self.irq_cfg = value,
            INT_EN => self.int_en = value,
            RESET_CTL if value & 1 != 0 => self.digital_reset(),
            CSR_DATA | CSR_CMD if self.csr.command & BUSY != 0 => {
                violations.push(format!(
                    "{address:#05x} written while a CSR command is busy"
                ));
            }
            CSR_DATA => self.csr.data = value,
            CSR_CMD => self.start_csr(value, violations),
            PRAM_RD_ADDR_LEN | PRAM_WR_ADDR_LEN if self.engine_busy(address) => {
                violations.push(format!(
                    "{address:#05x} written while its PRAM command is busy"
                ));
            }
            PRAM_RD_ADDR_LEN => self.read.address_length = value,
            PRAM_WR_ADDR_LEN => self.write.address_length = value,
            PRAM_RD_CMD => self.command_read(value, violations),
            PRAM_WR_CMD => self.command_write(value, violations),
            other => violations.push(format!(
                "write of {value:#010x} to register {other:#05x}, not modelled or read-only"
            )),
        }
    }

    fn engine_busy(&self, address_length: u16) -> bool {
        if address_length == PRAM_RD_ADDR_LEN {
            self.read.busy
        } else {
            self.write.busy
        }
    }

    fn start_csr(&mut self, command: u32, violations: &mut Vec<String>) {
        if command & BUSY == 0 {
            return;
        }
        let address = (command & 0xFFFF) as u16;
        let size = (command >> 16) & 0x7;
        let aligned = match size {
            1 => true,
            2 => address.is_multiple_of(2),
            4 => address.is_multiple_of(4),
            _ => false,
        };
        if !aligned || address >= 0x1000 {
            violations.push(format!(
                "CSR command {command:#010x}: size {size} at {address:#06x} is not allowed"
            ));
            return;
        }
        self.csr.command = command;
        self.csr.countdown = self.config.csr_latency;
    }

    /// Performs the busy CSR command on the ESC.
    fn finish_csr(&mut self) {
        let command = self.csr.command;
        let address = (command & 0xFFFF) as u16;
        let size = ((command >> 16) & 0x7) as usize;
        let mut bytes = [0; 4];
        if command & CSR_READ != 0 {
            self.emu
                .with(|esc| esc.pdi_read(address, &mut bytes[..size]));
            self.csr.data = u32::from_le_bytes(bytes);
        } else {
            bytes = self.csr.data.to_le_bytes();
            self.emu.with(|esc| esc.pdi_write(address, &bytes[..size]));
        }
        self.csr.command &= !BUSY;
    }

    fn command_read(&mut self, value: u32, violations: &mut Vec<String>) {
        if value & ABORT != 0 {
            self.read = PramRead::default();
            return;
        }
        if value & BUSY == 0 {
            return;
        }
        let Some((address, length)) = pram_range(self.read.address_length, violations) else {
            return;
        };
        let lane = usize::from(address % 4);
        let mut stream = vec![0; (lane + length).div_ceil(4) * 4];
        self.emu
            .with(|esc| esc.pdi_read(address, &mut stream[lane..lane + length]));
        self.read.pending = stream
            .chunks(4)
            .map(|d| u32::from_le_bytes([d[0], d[1], d[2], d[3]]))
            .collect();
        self.read.fifo.clear();
        self.read.busy = true;
    }

    fn command_write(&mut self, value: u32, violations: &mut Vec<String>) {
        if value & ABORT != 0 {
            self.write = PramWrite::default();
            return;
        }
        if value & BUSY == 0 {
            return;
        }
        let Some((address, length)) = pram_range(self.write.address_length, violations) else {
            return;
        };
        self.write.expected = (usize::from(address % 4) + length).div_ceil(4);
        self.write.received.clear();
        self.write.busy = true;
    }

    /// Chip select rose: the engines move on.
    fn end_of_transaction(&mut self, violations: &mut Vec<String>) {
        if self.csr.command & BUSY != 0 {
            if self.csr.countdown == 0 {
                self.finish_csr();
            } else {
                self.csr.countdown -= 1;
            }
        }
        let room = FIFO_DWORDS - self.read.fifo.len();
        let moved = self.config.fifo_fill.min(room).min(self.read.pending.len());
        let dwords: Vec<u32> = self.read.pending.drain(..moved).collect();
        self.read.fifo.extend(dwords);
        self.read.busy &= !self.read.pending.is_empty();
        let taken = self.config.fifo_drain.min(self.write.fifo.len());
        self.write.received.extend(self.write.fifo.drain(..taken));
        if self.write.received.len() > self.write.expected {
            violations.push(format!(
                "PRAM write got {} DWORDs for {} expected",
                self.write.received.len(),
                self.write.expected
            ));
            self.write.received.truncate(self.write.expected);
        }
        if self.write.busy && self.write.received.len() == self.write.expected {
            let (address, length) = split_address_length(self.write.address_length);
            let lane = usize::from(address % 4);
            let stream: Vec<u8> = self
                .write
                .received
                .iter()
                .flat_map(|d| d.to_le_bytes())
                .collect();
            self.emu
                .with(|esc| esc.pdi_write(address, &stream[lane..lane + length]));
            self.write.busy = false;
        }
    }
}

/// `ECAT_PRAM_RD/WR_CMD` as read: busy, FIFO count (bits 12:8), count non-zero (bit 0).
fn fifo_status(busy: bool, count: usize) -> u32 {
    (u32::from(busy) << 31) | ((count as u32) << 8) | u32::from(count > 0)
}

fn split_address_length(value: u32) -> (u16, usize) {
    ((value & 0xFFFF) as u16, (value >> 16) as usize)
}

/// Address and length of a PRAM command, if the chip accepts them.
fn pram_range(address_length: u32, violations: &mut Vec<String>) -> Option<(u16, usize)> {
    let (address, length) = split_address_length(address_length);
    if address < 0x1000 || length == 0 || usize::from(address) + length > 0x1_0000 {
        violations.push(format!(
            "PRAM command for {length} bytes at {address:#06x}: not process RAM"
        ));
        return None;
    }
    Some((address, length))
}

/// PDI control (0x0140) value that selects the SPI host interface (LAN9252 datasheet, "PDI
/// Control Register": 80h SPI).
const PDI_SPI: u8 = 0x80;

impl Chip for Lan9252Chip {
    /// Register reads happen before their DWORD is clocked out, register writes once it is in,
    /// the engines' work (CSR command, PRAM access) when chip select rises.
    fn transaction(
        &mut self,
        mosi: &[u8],
        miso: &mut [u8],
        violations: &mut Vec<String>,
        progress: &mut Progress,
    ) {
        self.decode(mosi, miso, violations, progress);
        progress.reach(mosi.len());
        self.end_of_transaction(violations);
    }

    /// The SPI host interface runs only when the EEPROM selected it (0x0140 = 0x80), and in SPI
    /// modes 0 and 3 only ("SPI/SQI Slave").
    fn refusal(&self, mode: SpiMode) -> Option<String> {
        let pdi = self.emu.with(|esc| esc.register(0x0140));
        if pdi != PDI_SPI {
            return Some(format!(
                "PDI control 0x0140 = {pdi:#04x}, not SPI (0x80): the host interface is not in SPI mode"
            ));
        }
        (!matches!(mode, SpiMode::Mode0 | SpiMode::Mode3)).then(|| {
            format!(
                "bus in SPI mode {}: the LAN9252 takes modes 0 and 3",
                mode as u8
            )
        })
    }
}

impl Lan9252Chip {
    fn decode(
        &mut self,
        mosi: &[u8],
        miso: &mut [u8],
        violations: &mut Vec<String>,
        progress: &mut Progress,
    ) {
        let (header, write) = match mosi.first() {
            Some(&READ) => (3, false),
            Some(&FAST_READ) => (4, false),
            Some(&WRITE) => (3, true),
            other => {
                violations.push(format!(
                    "instruction {other:02x?} not supported in SPI mode"
                ));
                return;
            }
        };
        if mosi.len() < header {
            violations.push(format!("transaction ends in its header: {mosi:02x?}"));
            return;
        }
        let address = u16::from_be_bytes([mosi[1], mosi[2]]);
        let increment = match address >> 14 {
            0b00 => false,
            0b01 => true,
            _ => {
                violations.push(format!("address mode {:02b} not modelled", address >> 14));
                return;
            }
        };
        let base = address & 0x3FFF;
        let data = &mosi[header..];
        if !base.is_multiple_of(4) || !data.len().is_multiple_of(4) {
            violations.push(format!(
                "{} bytes at {base:#05x}: not whole, aligned DWORDs",
                data.len()
            ));
            return;
        }
        for (i, (dword, out)) in data.chunks(4).zip(miso[header..].chunks_mut(4)).enumerate() {
            let register = if increment {
                base.wrapping_add(4 * i as u16)
            } else {
                base
            };
            if write {
                progress.reach(header + 4 * i + 4);
                let value = u32::from_le_bytes([dword[0], dword[1], dword[2], dword[3]]);
                self.write_register(register, value, violations);
            } else {
                progress.reach(header + 4 * i);
                out.copy_from_slice(&self.read_register(register, violations).to_le_bytes());
            }
        }
    }
}
