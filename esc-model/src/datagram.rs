//! The EtherCAT port at the datagram level (ETG.1000.4 §5.4, Tables 13–25): how one ESC handles
//! each datagram command as the frame passes through it, and how it counts the working counter.
//!
//! | command | addressed when | does | working counter |
//! |---|---|---|---|
//! | APRD/APWR/APRW | ADP = 0 on arrival (every ESC increments ADP) | read / write / both | +1 / +1 / +3 |
//! | FPRD/FPWR/FPRW | ADP = station address (0x0010) or enabled alias (0x0012) | read / write / both | +1 / +1 / +3 |
//! | BRD/BWR/BRW | always (ADP incremented) | read ORed into the data / write / both | +1 / +1 / +3 per ESC |
//! | LRD/LWR/LRW | an active FMMU of the right type overlaps | through the FMMUs | +1 / +1 / +1 read, +2 write |
//! | ARMW | ADP = 0 reads; every other ESC writes | | +1 |
//! | FRMW | station address reads; every other ESC writes | | +1 |
//!
//! A read-write first reads, then writes the data as it arrived, and returns the read data; only
//! its write counts 2 (ETG.1000.4 §5.4: read +1, write +1, read-write +1 for the read and +2 for
//! the write).
//! Register and memory semantics (SyncManager buffers, read-only bytes) are those of
//! [`Esc::ecat_read`] / [`Esc::ecat_write`]; accesses they refuse do not count. An ESC without
//! distributed clocks does not count (and does not perform) accesses to 0x0900..0x09FF.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::Range;

use ecat_core::register;

use super::Esc;
use super::fmmu::Fmmu;

/// The datagram commands (ETG.1000.4 Table 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// 0: no operation.
    Nop,
    /// 1..3: auto-increment physical read, write, read-write.
    Ap(Operation),
    /// 4..6: configured-address physical read, write, read-write.
    Fp(Operation),
    /// 7..9: broadcast read, write, read-write.
    B(Operation),
    /// 10..12: logical read, write, read-write.
    L(Operation),
    /// 13: auto-increment physical read multiple write.
    Armw,
    /// 14: configured-address physical read multiple write.
    Frmw,
}

/// What a physical or logical command does with the data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Operation {
    /// The ESC puts memory contents into the datagram.
    Read = 0,
    /// The ESC takes the datagram data into memory.
    Write = 1,
    /// Both: reads, then writes the data as it arrived.
    ReadWrite = 2,
}

impl Command {
    /// The command's code (ETG.1000.4 Table 13).
    pub fn code(self) -> u8 {
        let op = |base: u8, op: Operation| base + op as u8;
        match self {
            Self::Nop => 0,
            Self::Ap(o) => op(1, o),
            Self::Fp(o) => op(4, o),
            Self::B(o) => op(7, o),
            Self::L(o) => op(10, o),
            Self::Armw => 13,
            Self::Frmw => 14,
        }
    }

    /// The command with code `code`, `None` for reserved codes (15..255).
    pub fn from_code(code: u8) -> Option<Self> {
        use Operation::*;
        let op = |n: u8| [Read, Write, ReadWrite][usize::from(n % 3)];
        Some(match code {
            0 => Self::Nop,
            1..=3 => Self::Ap(op(code - 1)),
            4..=6 => Self::Fp(op(code - 4)),
            7..=9 => Self::B(op(code - 7)),
            10..=12 => Self::L(op(code - 10)),
            13 => Self::Armw,
            14 => Self::Frmw,
            _ => return None,
        })
    }
}

/// DL control (0x0100) bit 24: the station alias (0x0012) addresses FP* datagrams too.
const ALIAS_ENABLE: u32 = 1 << 24;
/// The DC registers, absent on an ESC without distributed clocks.
const DC_REGISTERS: core::ops::Range<usize> = 0x0900..0x0A00;

impl Esc {
    /// Handles one datagram passing through: `address` is the datagram's 4-byte address field
    /// (ADP is incremented in place where the command says so), `data` its data. Returns what
    /// this ESC adds to the working counter. Reserved commands pass untouched.
    pub fn datagram(&mut self, command: u8, address: &mut [u8; 4], data: &mut [u8]) -> u16 {
        let Some(command) = Command::from_code(command) else {
            return 0;
        };
        let adp = u16::from_le_bytes([address[0], address[1]]);
        let ado = u16::from_le_bytes([address[2], address[3]]);
        let increments = matches!(command, Command::Ap(_) | Command::B(_) | Command::Armw);
        if increments {
            address[..2].copy_from_slice(&adp.wrapping_add(1).to_le_bytes());
        }
        match command {
            Command::Nop => 0,
            Command::Ap(op) if adp == 0 => self.physical(op, ado, data, false),
            Command::Fp(op) if self.is_station(adp) => self.physical(op, ado, data, false),
            Command::Ap(_) | Command::Fp(_) => 0,
            Command::B(op) => self.physical(op, ado, data, true),
            Command::L(op) => self.logical(op, u32::from_le_bytes(*address), data),
            Command::Armw if adp == 0 => self.physical(Operation::Read, ado, data, false),
            Command::Frmw if self.is_station(adp) => {
                self.physical(Operation::Read, ado, data, false)
            }
            Command::Armw | Command::Frmw => self.physical(Operation::Write, ado, data, false),
        }
    }

    /// Whether `adp` is this ESC's configured station address or its enabled alias.
    fn is_station(&self, adp: u16) -> bool {
        let word = |a: u16| {
            let a = usize::from(a);
            u16::from_le_bytes([self.memory.byte(a), self.memory.byte(a + 1)])
        };
        let alias_enabled =
            self.memory.u32_le(usize::from(register::DL_CONTROL)) & ALIAS_ENABLE != 0;
        adp == word(register::STATION_ADDRESS)
            || (alias_enabled && adp == word(register::STATION_ALIAS))
    }

    /// A physical access at `ado`; `or` makes a read OR into the data (broadcast reads).
    fn physical(&mut self, op: Operation, ado: u16, data: &mut [u8], or: bool) -> u16 {
        let start = usize::from(ado);
        let absent = !self.config.dc_supported
            && start < DC_REGISTERS.end
            && start + data.len() > DC_REGISTERS.start;
        if absent {
            return 0;
        }
        // Only a read-write needs the data as it arrived once the read replaced it.
        let arrived = (op == Operation::ReadWrite).then(|| data.to_vec());
        let mut wkc = 0;
        if op != Operation::Write {
            let mut read = vec![0; data.len()];
            if self.ecat_read(ado, &mut read) {
                wkc += 1;
                for (d, r) in data.iter_mut().zip(read) {
                    *d = if or { *d | r } else { r };
                }
            }
        }
        if op != Operation::Read {
            let written = arrived.as_deref().unwrap_or(data);
            if self.ecat_write(ado, written) {
                wkc += if op == Operation::ReadWrite { 2 } else { 1 };
                self.dc_written(start..start + written.len());
            }
        }
        wkc
    }

    /// A logical access to `[address, address + data.len())` through the active FMMUs: reads
    /// first (they see the memory before this datagram's writes), then writes take the data as
    /// it arrived.
    fn logical(&mut self, op: Operation, address: u32, data: &mut [u8]) -> u16 {
        let datagram = u64::from(address) * 8..(u64::from(address) + data.len() as u64) * 8;
        let mapped: Vec<(Fmmu, core::ops::Range<u64>)> = self
            .fmmus()
            .filter(|fmmu| fmmu.active)
            .map(|fmmu| {
                let bits = fmmu.logical_bits();
                let overlap = bits.start.max(datagram.start)..bits.end.min(datagram.end);
                (fmmu, overlap)
            })
            .filter(|(_, overlap)| !overlap.is_empty())
            .collect();
        let offset = datagram.start;
        // The writes take the data as it arrived: the bytes they map, kept before the reads
        // replace them (only those: a line's image is long, an ESC maps a few bytes of it).
        let byte = |bit: u64| usize::try_from((bit - offset) / 8).unwrap_or(usize::MAX);
        let written_bytes = mapped
            .iter()
            .filter(|(f, _)| f.write)
            .map(|(_, overlap)| byte(overlap.start)..byte(overlap.end - 1) + 1)
            .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end))
            .unwrap_or_default();
        let arrived_at = offset + written_bytes.start as u64 * 8;
        let arrived = data.get(written_bytes).unwrap_or_default().to_vec();
        // All reads see the memory before any write of this datagram, as on a physical
        // read-write.
        let mut read = false;
        if op != Operation::Write {
            for (fmmu, overlap) in mapped.iter().filter(|(f, _)| f.read) {
                read |= self.map_read(fmmu, overlap.clone(), offset, data);
            }
        }
        let mut written = false;
        if op != Operation::Read {
            for (fmmu, overlap) in mapped.iter().filter(|(f, _)| f.write) {
                written |= self.map_write(fmmu, overlap.clone(), arrived_at, &arrived);
            }
        }
        let write_weight = if op == Operation::ReadWrite { 2 } else { 1 };
        u16::from(read) + write_weight * u16::from(written)
    }

    /// The FMMU entities.
    fn fmmus(&self) -> impl Iterator<Item = Fmmu> + '_ {
        (0..usize::from(self.config.fmmus)).map(|n| {
            let mut bytes = [0; Fmmu::SIZE];
            self.memory.read(
                usize::from(register::FMMU_BASE) + n * Fmmu::SIZE,
                &mut bytes,
            );
            Fmmu::from_bytes(&bytes)
        })
    }

    /// Copies the logical bits `bits` (absolute; the datagram's data starts at bit `offset`)
    /// from physical memory into `data`. Whole bytes of a byte-aligned FMMU are one physical read.
    fn map_read(
        &mut self,
        fmmu: &Fmmu,
        bits: core::ops::Range<u64>,
        offset: u64,
        data: &mut [u8],
    ) -> bool {
        let (physical, mut buf) = self.physical_bytes(fmmu, &bits);
        if !self.ecat_read(physical, &mut buf) {
            return false;
        }
        if let Some(bytes) = whole_bytes(fmmu, &bits, offset) {
            if let Some(data) = data.get_mut(bytes) {
                data.copy_from_slice(buf.get(..data.len()).unwrap_or_default());
            }
            return true;
        }
        let base = u64::from(physical) * 8;
        for bit in bits {
            let value = get_bit(&buf, fmmu.physical_bit(bit) - base);
            set_bit(data, bit - offset, value);
        }
        true
    }

    /// Copies the logical bits `bits` from `data` into physical memory: one physical write of
    /// whole bytes for a byte-aligned FMMU, read-modify-write of the bytes involved otherwise
    /// (on a SyncManager buffer that read counts as a buffer access: the one place where the
    /// emulation differs from an ESC, which masks bits internally).
    fn map_write(
        &mut self,
        fmmu: &Fmmu,
        bits: core::ops::Range<u64>,
        offset: u64,
        data: &[u8],
    ) -> bool {
        let (physical, mut buf) = self.physical_bytes(fmmu, &bits);
        if !fmmu.byte_aligned() && !self.ecat_read(physical, &mut buf) {
            return false;
        }
        match whole_bytes(fmmu, &bits, offset).and_then(|bytes| data.get(bytes)) {
            Some(bytes) if bytes.len() == buf.len() => buf.copy_from_slice(bytes),
            _ => {
                let base = u64::from(physical) * 8;
                for bit in bits {
                    let value = get_bit(data, bit - offset);
                    set_bit(&mut buf, fmmu.physical_bit(bit) - base, value);
                }
            }
        }
        self.ecat_write(physical, &buf)
    }

    /// The physical bytes that hold the logical bits `bits` of `fmmu`: first address and a buffer
    /// of their length.
    fn physical_bytes(&self, fmmu: &Fmmu, bits: &core::ops::Range<u64>) -> (u16, Vec<u8>) {
        let first = fmmu.physical_bit(bits.start) / 8;
        let last = fmmu.physical_bit(bits.end - 1) / 8;
        let first = u16::try_from(first).unwrap_or(u16::MAX);
        let len = usize::try_from(last + 1).unwrap_or(usize::MAX) - usize::from(first);
        (first, vec![0; len.min(0x1_0000)])
    }
}

/// The bytes of the data (which starts at logical bit `offset`) that hold the logical bits
/// `bits` of a byte-aligned `fmmu`, when they are whole bytes of it: they move as they are,
/// without the bit-by-bit copy (same result).
fn whole_bytes(fmmu: &Fmmu, bits: &core::ops::Range<u64>, offset: u64) -> Option<Range<usize>> {
    let aligned = fmmu.byte_aligned() && bits.start.is_multiple_of(8) && bits.end.is_multiple_of(8);
    let start = usize::try_from((bits.start.checked_sub(offset)?) / 8).ok()?;
    let end = usize::try_from((bits.end.checked_sub(offset)?) / 8).ok()?;
    (aligned && offset.is_multiple_of(8)).then_some(start..end)
}

/// Bit `bit` of `bytes` (LSB first); 0 beyond them.
fn get_bit(bytes: &[u8], bit: u64) -> u8 {
    bytes
        .get(usize::try_from(bit / 8).unwrap_or(usize::MAX))
        .map_or(0, |byte| byte >> (bit % 8) & 1)
}

/// Sets bit `bit` of `bytes` (LSB first) to `value` (0 or 1).
fn set_bit(bytes: &mut [u8], bit: u64, value: u8) {
    if let Some(byte) = bytes.get_mut(usize::try_from(bit / 8).unwrap_or(usize::MAX)) {
        let mask = 1 << (bit % 8);
        *byte = (*byte & !mask) | (value << (bit % 8));
    }
}
