//! Which area of the ESC an address falls into, so that each byte of an access follows the
//! rules of its area (ESC datasheet section I, "Address space").

use alloc::vec::Vec;
use ecat_core::register;

use super::sync_manager::Buffer;

/// The most SyncManager channels an ESC has (ETG.1000.4 Table 58: 0x0800..0x087F).
pub(super) const MAX_CHANNELS: usize = 16;

/// The kind of memory at an address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Area {
    /// The register file 0x0000..0x0FFF: per-byte access rights and side effects.
    Registers,
    /// Process RAM guarded by the effective SyncManager channel `n`.
    SyncManager(u8, Buffer),
    /// Process RAM no effective SyncManager guards: plain dual-ported memory.
    Ram,
    /// The buffer area of a channel the PDI deactivated ([`Buffer::locked`]): closed to the
    /// MainDevice, plain memory for the PDI.
    Locked,
    /// Beyond the end of the process RAM: no memory answers.
    Absent,
}

/// The areas of the address space as the SyncManager registers define them at one instant.
#[derive(Debug, Clone, Default)]
pub(super) struct AreaMap {
    /// First address after the process RAM.
    ram_end: usize,
    /// The area each channel guards, if it is effective. A byte two channels claim belongs to the
    /// lower-numbered one.
    buffers: [Option<Buffer>; MAX_CHANNELS],
    /// The areas the PDI locked by deactivating their channel.
    locked: [Option<core::ops::Range<usize>>; MAX_CHANNELS],
    /// The addresses where an area may begin or end, ascending: the start of the process RAM,
    /// its end, and both ends of every channel's buffer and locked area. Between two
    /// neighbours the area is the same for every address.
    boundaries: Vec<usize>,
}

impl AreaMap {
    /// The map for process RAM ending at `ram_end`, the given channel areas and the areas of
    /// deactivated channels.
    pub(super) fn new(
        ram_end: usize,
        buffers: [Option<Buffer>; MAX_CHANNELS],
        locked: [Option<core::ops::Range<usize>>; MAX_CHANNELS],
    ) -> Self {
        let buffer_ends = buffers
            .iter()
            .flatten()
            .flat_map(|buffer| [buffer.start(), buffer.start() + buffer.length()]);
        let locked_ends = locked
            .iter()
            .flatten()
            .flat_map(|area| [area.start, area.end]);
        let mut boundaries: Vec<usize> = [usize::from(register::PROCESS_RAM), ram_end]
            .into_iter()
            .chain(buffer_ends)
            .chain(locked_ends)
            .collect();
        boundaries.sort_unstable();
        boundaries.dedup();
        Self {
            ram_end,
            buffers,
            locked,
            boundaries,
        }
    }

    /// The area `address` falls into.
    fn area(&self, address: usize) -> Area {
        if address < usize::from(register::PROCESS_RAM) {
            return Area::Registers;
        }
        if address >= self.ram_end {
            return Area::Absent;
        }
        self.buffers
            .iter()
            .zip(&self.locked)
            .zip(0..)
            .find_map(|((buffer, locked), n)| {
                if locked.as_ref().is_some_and(|area| area.contains(&address)) {
                    return Some(Area::Locked);
                }
                buffer
                    .filter(|buffer| buffer.contains(address))
                    .map(|buffer| Area::SyncManager(n, buffer))
            })
            .unwrap_or(Area::Ram)
    }

    /// The buffer channel `n` guards, if it is effective.
    pub(super) fn buffer(&self, n: u8) -> Option<Buffer> {
        self.buffers.get(usize::from(n)).copied().flatten()
    }

    /// The area of `start` and the end of the run of bytes from `start` (before `end`) that
    /// belong to it.
    pub(super) fn run(&self, start: usize, end: usize) -> (Area, usize) {
        let area = self.area(start);
        let mut at = start;
        loop {
            // The area can change only at a boundary.
            let next = self
                .boundaries
                .iter()
                .copied()
                .find(|&boundary| boundary > at)
                .unwrap_or(end)
                .min(end);
            if next >= end || self.area(next) != area {
                return (area, next);
            }
            at = next;
        }
    }
}
