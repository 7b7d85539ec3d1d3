//! The ESC's 16-bit asynchronous microcontroller interface (ET1100 datasheet section II, "PDI
//! description", "Asynchronous 8/16 bit microcontroller interface"; PDI control 0x0140 = 0x08),
//! which the ET1100 and the AX58100 offer besides SPI: a parallel bus with chip select, read and
//! write strobes, a byte address ADR\[15:0\], 16 data lines, BHE (byte high enable) and BUSY. A
//! microcontroller's external memory controller (the STM32's FMC) drives it as 16-bit SRAM, and
//! an access costs one bus cycle per word instead of eight SPI clocks per byte.
//!
//! The crates forbid `unsafe`, and reaching memory-mapped hardware takes it: the firmware
//! implements [`Bus16`] with volatile accesses in its own code, and [`Mcu16`] turns it into a
//! [`Pdi`].
//!
//! ## Byte lanes and byte order
//! The ESC is little-endian: the byte at an even address travels on D\[7:0\], the byte after it
//! on D\[15:8\]. ADR\[0\] and BHE select the lanes of a write: both (ADR\[0\] = 0, BHE low), the
//! low byte alone (ADR\[0\] = 0, BHE high) or the high byte alone (ADR\[0\] = 1, BHE low).
//! Memory controllers drive every byte lane on reads (the FMC holds NBL\[1:0\] low), so a read is
//! always a whole word at an even address.
//!
//! The driver moves whole words where it can, and handles odd ends so that every byte of an
//! access is read or written exactly once and in ascending order — what SyncManager buffers
//! require, the last byte of a buffer accessed last (ET1100 datasheet section I, "SyncManager",
//! "Buffered Mode"):
//! - a write that starts at an odd address writes its first byte alone, one that ends at an even
//!   address its last byte alone (BHE);
//! - a read that starts at an odd address reads the word before it, one that ends at an even
//!   address the word after it, and keeps the byte asked for. The other byte is read as well:
//!   SyncManager buffers must start at even addresses (every configuration the stack writes
//!   does), and a register read at an odd address also reads the register byte before it.
//!
//! [`Pdi::chunk`] cuts long accesses at even addresses, so a chunked buffer is read word by word
//! without reading a byte twice.
//!
//! ## The AL event
//! The bus does not shift the AL event register out. The driver reads it (0x0220..0x0221: the AL
//! control event, the SyncManager change event and the events of SyncManagers 0..7, every event
//! an ET1100 or AX58100 has) before every access but an empty write, one word, and reports it:
//! sampled before the access, as the Beckhoff SPI address phase samples it, which is what [`Pdi`]
//! allows and the runners' handling of a buffer that arrives during an access is built for. An
//! empty read reads it alone: one bus cycle. A read right after an empty read reports that
//! one's value instead of reading it again, as the LAN9252 driver does: on the IRQ the
//! process-data runner samples the AL event with an empty read and reads the output area only
//! if SM2 is among the events, so the sample it acts on is always taken before the read.
//!
//! ## BUSY
//! The ESC holds BUSY while it completes an access; the memory controller waits for it (the
//! FMC's NWAIT, asynchronous wait enabled). [`Bus16`] accesses return when the bus cycle is done.
#![deny(clippy::arithmetic_side_effects)]

use core::convert::Infallible;
use core::future::{Future, poll_fn};
use core::task::Poll;

use ecat_core::AlEvent;
use ecat_core::chip::Chip;
use ecat_core::register::AL_EVENT_REQUEST;

use crate::Pdi;
use crate::pdi::Data;

/// A 16-bit asynchronous bus to the ESC: one bus cycle per call, complete when the call returns
/// (the memory controller waits out the ESC's BUSY). Addresses are the ESC's byte addresses.
pub trait Bus16 {
    /// Reads the word at `address` (even): the byte at `address` in bits 7:0, the next one in
    /// bits 15:8.
    fn read(&mut self, address: u16) -> u16;

    /// Writes the word at `address` (even), both byte lanes.
    fn write(&mut self, address: u16, value: u16);

    /// Writes the byte at `address`, its byte lane only (ADR\[0\] and BHE select it).
    fn write_byte(&mut self, address: u16, value: u8);
}

/// A [`Pdi`] over the 16-bit asynchronous microcontroller interface of an ET1100 or AX58100.
pub struct Mcu16<B> {
    /// The AL event the last access reported ([`Pdi::al_event`]).
    reported: AlEvent,
    /// The last access was an empty read: a read right after it reports its AL event instead of
    /// reading the register again.
    sampled: bool,
    bus: B,
}

impl<B: Bus16> Mcu16<B> {
    /// The driver on `bus`, whose ESC's EEPROM selects the 16-bit asynchronous microcontroller
    /// interface (0x0140 = 0x08). The ESC needs no start-up sequence.
    pub const fn new(bus: B) -> Self {
        Self {
            reported: AlEvent::NONE,
            sampled: false,
            bus,
        }
    }

    /// The AL event register's events of an ET1100 (0x0220..0x0221).
    fn read_al_event(&mut self) -> AlEvent {
        let [low, high] = self.bus.read(AL_EVENT_REQUEST).to_le_bytes();
        AlEvent::from_le_bytes([low, high, 0, 0])
    }

    /// Reads `buf.len()` bytes from `address` on: whole words, an odd first or last byte from its
    /// word.
    fn read_bytes(&mut self, mut address: u16, buf: &mut [u8]) {
        let odd = usize::from(address % 2 == 1).min(buf.len());
        let (head, rest) = buf.split_at_mut(odd);
        if let [first] = head {
            *first = self.bus.read(address & !1).to_le_bytes()[1];
            address = address.wrapping_add(1);
        }
        let mut words = rest.chunks_exact_mut(2);
        for pair in &mut words {
            pair.copy_from_slice(&self.bus.read(address).to_le_bytes());
            address = address.wrapping_add(2);
        }
        if let [last] = words.into_remainder() {
            *last = self.bus.read(address).to_le_bytes()[0];
        }
    }

    /// Writes `data` from `address` on: whole words, an odd first or last byte on its lane alone.
    fn write_bytes(&mut self, mut address: u16, data: &[u8]) {
        let odd = usize::from(address % 2 == 1).min(data.len());
        let (head, rest) = data.split_at(odd);
        if let &[first] = head {
            self.bus.write_byte(address, first);
            address = address.wrapping_add(1);
        }
        let mut words = rest.chunks_exact(2);
        for pair in &mut words {
            if let &[low, high] = pair {
                self.bus.write(address, u16::from_le_bytes([low, high]));
            }
            address = address.wrapping_add(2);
        }
        if let &[last] = words.remainder() {
            self.bus.write_byte(address, last);
        }
    }
}

impl<B: Bus16> Pdi for Mcu16<B> {
    /// The bus cycles cannot fail: a memory controller reports nothing (a wrong wiring reads
    /// nonsense, as it does over SPI).
    type Error = Infallible;

    /// The ET1100's SyncManagers and process RAM, which the AX58100 shares.
    const CHIP: Option<Chip> = Some(Chip::ET1100);

    /// At most `chunk` bytes, cut so that the next chunk starts at an even address: no word is
    /// read twice.
    fn chunk(&self, address: u16, len: usize, chunk: usize) -> usize {
        if len <= chunk {
            return len;
        }
        let start = usize::from(address);
        let end = start.saturating_add(chunk) & !1;
        match end.saturating_sub(start) {
            0 => len.min(2),
            n => n,
        }
    }

    /// The AL event (one word), then the access; an empty read is the AL event alone, an empty
    /// write costs nothing and reports no event. A read right after an empty read (no access in
    /// between) reports the empty read's event without reading it again.
    ///
    /// The bus cycles complete within the call: the access is made at once and the future only
    /// says it is done (a `poll_fn`, no state machine: docs/performance.md, "Codegen
    /// rules").
    fn access(
        &mut self,
        address: u16,
        data: Data<'_>,
    ) -> impl Future<Output = Result<(), Infallible>> {
        // Taken by every access: only the next one may report it.
        let sampled = core::mem::take(&mut self.sampled);
        self.reported = match data {
            Data::Write([]) => AlEvent::NONE,
            Data::Write(data) => {
                let event = self.read_al_event();
                self.write_bytes(address, data);
                event
            }
            Data::Read([]) => {
                self.sampled = true;
                self.read_al_event()
            }
            Data::Read(buf) => {
                let event = if sampled {
                    self.reported
                } else {
                    self.read_al_event()
                };
                self.read_bytes(address, buf);
                event
            }
        };
        poll_fn(|_| Poll::Ready(Ok(())))
    }

    fn al_event(&self) -> AlEvent {
        self.reported
    }
}
