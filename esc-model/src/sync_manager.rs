//! The SyncManager buffer logic (ETG.1000.4 §6.7 and Table 58; ESC datasheet section I,
//! "SyncManager"): the mailbox (1-buffer) and 3-buffer handshakes between the writer and the
//! reader of a process-RAM area, the status byte (offset 5) and the AL event bit 8 + n.

use core::ops::Range;

use ecat_core::sync_manager::{BufferDirection, Channel, Control, Mode};

use super::access::{Access, Side};
use super::memory::Memory;

/// Offset of the status byte in a channel's register block (ETG.1000.4 Table 58).
pub(super) const STATUS_OFFSET: usize = 5;
/// Offset of the activate byte in a channel's register block (ETG.1000.4 Table 58).
pub(super) const ACTIVATE_OFFSET: usize = 6;
/// Offset of the PDI control byte in a channel's register block (ETG.1000.4 Table 58).
pub(super) const PDI_CONTROL_OFFSET: usize = Channel::PDI_CONTROL_OFFSET as usize;
/// The bytes of a channel's register block the MainDevice may write only while the channel is
/// disabled: start address, length and control (ESC datasheet section II, 0x0800:0x0804).
pub(super) const CONFIGURATION_OFFSETS: Range<usize> = 0..5;

/// Status bit 0: the buffer was completely written ("interrupt write").
const STATUS_WRITE_EVENT: u8 = 1 << 0;
/// Status bit 1: the buffer was completely read ("interrupt read").
const STATUS_READ_EVENT: u8 = 1 << 1;
/// Status bit 3: mailbox full (mailbox mode) or new data available (3-buffer mode).
const STATUS_FULL: u8 = 1 << 3;
/// Shift of the "last written buffer" field, status bits 5:4, in 3-buffer mode.
const STATUS_BUFFER_SHIFT: u8 = 4;
/// Status bits 5:4 value while no buffer has been written in 3-buffer mode.
const NO_BUFFER_WRITTEN: u8 = 0b11;

/// How the ESC hands an area from the writer to the reader (control bits 1:0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Handshake {
    /// 1 buffer: the writer waits for the reader to empty it.
    Mailbox,
    /// 3 buffers: the reader always gets the newest complete buffer.
    ThreeBuffer,
}

/// The process-RAM area an effective SyncManager guards: enabled by the MainDevice (activate
/// bit 0), not deactivated by the PDI (PDI control bit 0), non-empty, with a defined mode and
/// direction. Any other channel leaves its area as plain memory, as a real ESC does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Buffer {
    /// First byte of the area (the only buffer the sides address).
    start: usize,
    /// Bytes in one buffer.
    length: usize,
    /// Mailbox or 3-buffer handshake.
    handshake: Handshake,
    /// The side that writes the buffer (control bits 3:2).
    writer: Side,
    /// Control bit 5: buffer events reach the AL event register.
    pdi_event: bool,
}

impl Buffer {
    /// The area `channel` guards, if the channel is effective.
    pub(super) fn effective(channel: Channel) -> Option<Self> {
        let active = channel.enabled() && channel.pdi_control & Channel::PDI_DEACTIVATE == 0;
        let handshake = match channel.control.mode() {
            Mode::Mailbox => Handshake::Mailbox,
            Mode::Buffered => Handshake::ThreeBuffer,
            Mode::Reserved(_) => return None,
        };
        let writer = match channel.control.direction() {
            BufferDirection::MainDeviceWrites => Side::Ecat,
            BufferDirection::MainDeviceReads => Side::Pdi,
            BufferDirection::Reserved(_) => return None,
        };
        (active && channel.length > 0).then_some(Self {
            start: usize::from(channel.start),
            length: usize::from(channel.length),
            handshake,
            writer,
            pdi_event: channel.control.pdi_event(),
        })
    }

    /// The memory a channel enabled by the MainDevice but deactivated by the PDI locks (PDI
    /// control bit 0; ESC datasheet section I, "SyncManager deactivation by the PDI"): "the
    /// entire SyncManager buffer area is read/write protected" and an access to it does not
    /// count in the working counter, which is how a MainDevice sees the deactivation. The
    /// area is the buffer, three of them in 3-buffer mode. `None` for any other channel.
    pub(super) fn locked(channel: Channel) -> Option<core::ops::Range<usize>> {
        let deactivated = channel.enabled() && channel.pdi_control & Channel::PDI_DEACTIVATE != 0;
        let buffers = match channel.control.mode() {
            Mode::Mailbox => 1,
            Mode::Buffered => 3,
            Mode::Reserved(_) => return None,
        };
        let start = usize::from(channel.start);
        (deactivated && channel.length > 0)
            .then(|| start..start + buffers * usize::from(channel.length))
    }

    /// Whether `address` is one of the bytes the sides address.
    pub(super) fn contains(&self, address: usize) -> bool {
        address
            .checked_sub(self.start)
            .is_some_and(|offset| offset < self.length)
    }

    /// The first byte of the area.
    pub(super) fn start(&self) -> usize {
        self.start
    }

    /// Bytes in one buffer.
    pub(super) fn length(&self) -> usize {
        self.length
    }

    /// The offset of `address` in the area.
    pub(super) fn offset(&self, address: usize) -> usize {
        address.saturating_sub(self.start)
    }

    /// The address of byte `offset` of physical buffer `index`.
    fn physical(&self, index: u8, offset: usize) -> usize {
        self.start + usize::from(index) * self.length + offset
    }
}

/// Which bytes of the area an access touches.
struct Span {
    /// Offset of the first byte touched.
    offset: usize,
    /// The access covers the first byte of the area.
    first: bool,
    /// The access covers the last byte of the area.
    last: bool,
}

impl Span {
    fn new(offsets: &Range<usize>, buffer: &Buffer) -> Self {
        let touched = !offsets.is_empty();
        Self {
            offset: offsets.start,
            first: touched && offsets.start == 0,
            last: touched && offsets.end == buffer.length,
        }
    }
}

/// The 3-buffer rotation (ESC datasheet section I, "3-buffer mode"): the reader holds one
/// buffer, the writer fills another, and the newest complete one waits for the reader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Rotation {
    /// The buffer the reader reads.
    reader: u8,
    /// The buffer the writer fills.
    writer: u8,
    /// The newest complete buffer the reader has not taken yet.
    latest: Option<u8>,
    /// The last buffer completed (status bits 5:4).
    last_written: Option<u8>,
}

impl Default for Rotation {
    /// Fresh: the reader sees buffer 0 until the writer completes buffer 1.
    fn default() -> Self {
        Self {
            reader: 0,
            writer: 1,
            latest: None,
            last_written: None,
        }
    }
}

impl Rotation {
    /// The writer completed its buffer: it becomes the latest (releasing an untaken one) and the
    /// writer moves to the buffer nobody holds.
    fn publish(&mut self) {
        let done = self.writer;
        self.writer = (0..3)
            .find(|&index| index != self.reader && index != done)
            .unwrap_or(0);
        self.latest = Some(done);
        self.last_written = Some(done);
    }

    /// The reader starts a read: it takes the latest complete buffer if there is one.
    fn take_latest(&mut self) {
        if let Some(latest) = self.latest.take() {
            self.reader = latest;
        }
    }
}

/// The run-time state of one SyncManager channel, next to its registers.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ChannelState {
    /// The MainDevice wrote the activate byte since the PDI last read it (AL event bit 4).
    pub(super) changed: bool,
    /// Status bit 0.
    write_event: bool,
    /// Status bit 1.
    read_event: bool,
    /// Status bit 3.
    full: bool,
    /// The 3-buffer rotation (unused in mailbox mode).
    rotation: Rotation,
}

impl ChannelState {
    /// Enabling, disabling or deactivating a channel starts its buffer logic afresh: mailbox
    /// empty, buffers unwritten, status events cleared (ESC datasheet section II, 0x0806/0x0807).
    pub(super) fn reset(&mut self) {
        *self = Self {
            changed: self.changed,
            ..Self::default()
        };
    }

    /// The status byte (offset 5, ETG.1000.4 Table 58) for a channel with control byte `control`.
    pub(super) fn status(&self, control: Control) -> u8 {
        let mut status = 0;
        for (set, bit) in [
            (self.write_event, STATUS_WRITE_EVENT),
            (self.read_event, STATUS_READ_EVENT),
            (self.full, STATUS_FULL),
        ] {
            if set {
                status |= bit;
            }
        }
        if control.mode() == Mode::Buffered {
            let last = self.rotation.last_written.unwrap_or(NO_BUFFER_WRITTEN);
            status |= last << STATUS_BUFFER_SHIFT;
        }
        status
    }

    /// Whether the channel requests AL event bit 8 + n: the status event meant for the PDI side
    /// (write event when the PDI reads, read event when the PDI writes), if control bit 5 enables
    /// it. It clears when the PDI accesses the first byte of the area.
    pub(super) fn pdi_event(&self, buffer: &Buffer) -> bool {
        let pending = match buffer.writer {
            Side::Ecat => self.write_event,
            Side::Pdi => self.read_event,
        };
        buffer.pdi_event && pending
    }

    /// An access by `side` to the bytes `offsets` of the area. Returns whether it took effect:
    /// the writer's write into a full mailbox, the MainDevice's read of an empty mailbox and any
    /// write by the reader side are refused.
    pub(super) fn access(
        &mut self,
        buffer: &Buffer,
        side: Side,
        offsets: &Range<usize>,
        access: Access<'_>,
        memory: &mut Memory,
    ) -> bool {
        let span = Span::new(offsets, buffer);
        match access {
            Access::Write(data) if side == buffer.writer => self.write(buffer, &span, data, memory),
            Access::Write(_) => false,
            Access::Read(buf) if side == buffer.writer.other() => {
                self.read(buffer, side, &span, buf, memory)
            }
            Access::Read(buf) => {
                memory.read(buffer.physical(self.reader_index(buffer), span.offset), buf);
                true
            }
        }
    }

    /// The writer's write: refused while a mailbox is full; completes the buffer when it covers
    /// the last byte.
    fn write(&mut self, buffer: &Buffer, span: &Span, data: &[u8], memory: &mut Memory) -> bool {
        if buffer.handshake == Handshake::Mailbox && self.full {
            return false;
        }
        if span.first {
            self.read_event = false;
        }
        memory.write(
            buffer.physical(self.writer_index(buffer), span.offset),
            data,
        );
        if span.last {
            self.write_event = true;
            self.full = true;
            if buffer.handshake == Handshake::ThreeBuffer {
                self.rotation.publish();
            }
        }
        true
    }

    /// The reader's read: the MainDevice's read of an empty mailbox is refused (the PDI reads
    /// the memory as it is); the first byte takes the newest complete buffer and the last byte
    /// ends the read.
    fn read(
        &mut self,
        buffer: &Buffer,
        side: Side,
        span: &Span,
        buf: &mut [u8],
        memory: &mut Memory,
    ) -> bool {
        let mailbox = buffer.handshake == Handshake::Mailbox;
        if mailbox && !self.full && side == Side::Ecat {
            return false;
        }
        if span.first {
            self.write_event = false;
            if !mailbox {
                self.rotation.take_latest();
            }
        }
        memory.read(buffer.physical(self.reader_index(buffer), span.offset), buf);
        if span.last && (self.full || !mailbox) {
            self.full = false;
            self.read_event = true;
        }
        true
    }

    /// The physical buffer the writer fills.
    fn writer_index(&self, buffer: &Buffer) -> u8 {
        match buffer.handshake {
            Handshake::Mailbox => 0,
            Handshake::ThreeBuffer => self.rotation.writer,
        }
    }

    /// The physical buffer the reader reads.
    fn reader_index(&self, buffer: &Buffer) -> u8 {
        match buffer.handshake {
            Handshake::Mailbox => 0,
            Handshake::ThreeBuffer => self.rotation.reader,
        }
    }
}
