//! SyncManager channels: the registers (ETG.1000.4 Table 58) and the checks a SubDevice applies
//! to the MainDevice's configuration of them ([`check`]).
//!
//! A SyncManager guards one area of the process RAM. SM0/SM1 are the mailboxes (MainDevice → device
//! and device → MainDevice), SM2/SM3 carry process data (outputs and inputs).

pub mod check;

use crate::register;

/// How the SyncManager hands the buffer between the two sides (control bits 1:0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Mode {
    /// 0b00: 3-buffer mode; the reader always gets the newest complete buffer (process data).
    Buffered,
    /// 0b10: 1-buffer mailbox mode; the writer waits until the reader has emptied the buffer.
    Mailbox,
    /// 0b01 or 0b11: reserved values.
    Reserved(u8),
}

/// Who writes the buffer (control bits 3:2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BufferDirection {
    /// 0b00: the MainDevice reads, the device writes (inputs, device → MainDevice mailbox).
    MainDeviceReads,
    /// 0b01: the MainDevice writes, the device reads (outputs, MainDevice → device mailbox).
    MainDeviceWrites,
    /// 0b10 or 0b11: reserved values.
    Reserved(u8),
}

/// The control register of a SyncManager channel (offset 4, ETG.1000.4 Table 58).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Control(pub u8);

impl Control {
    /// Bit 4: event in the ECAT event register.
    pub const ECAT_EVENT: u8 = 1 << 4;
    /// Bit 5: event in the AL event register (drives the PDI IRQ).
    pub const PDI_EVENT: u8 = 1 << 5;
    /// Bit 6: this SyncManager triggers the process-data watchdog.
    pub const WATCHDOG: u8 = 1 << 6;

    /// The buffer mode.
    pub const fn mode(self) -> Mode {
        match self.0 & 0b11 {
            0b00 => Mode::Buffered,
            0b10 => Mode::Mailbox,
            other => Mode::Reserved(other),
        }
    }

    /// The direction.
    pub const fn direction(self) -> BufferDirection {
        match (self.0 >> 2) & 0b11 {
            0b00 => BufferDirection::MainDeviceReads,
            0b01 => BufferDirection::MainDeviceWrites,
            other => BufferDirection::Reserved(other),
        }
    }

    /// Whether the PDI event (AL event bit 8 + n) is enabled.
    pub const fn pdi_event(self) -> bool {
        self.0 & Self::PDI_EVENT != 0
    }

    /// Whether the SyncManager triggers the process-data watchdog.
    pub const fn watchdog(self) -> bool {
        self.0 & Self::WATCHDOG != 0
    }
}

/// One SyncManager channel's 8 registers as the PDI reads them (ETG.1000.4 Table 58).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Channel {
    /// Offset 0: physical start address.
    pub start: u16,
    /// Offset 2: length in bytes (of one buffer in 3-buffer mode).
    pub length: u16,
    /// Offset 4: control.
    pub control: Control,
    /// Offset 5: status (mailbox full, buffer state), read-only.
    pub status: u8,
    /// Offset 6: activate, written by the MainDevice (bit 0 enable, bit 1 repeat request).
    pub activate: u8,
    /// Offset 7: PDI control, written by the device (bit 0 deactivate, bit 1 repeat ack).
    pub pdi_control: u8,
}

impl Channel {
    /// Size of the register block.
    pub const SIZE: usize = register::SM_SIZE as usize;
    /// Activate bit 0: the MainDevice enabled the channel.
    pub const ACTIVATE_ENABLE: u8 = 1 << 0;
    /// Activate bit 1: repeat request (toggled by the MainDevice).
    pub const ACTIVATE_REPEAT: u8 = 1 << 1;
    /// PDI control bit 0: the device deactivates the channel.
    pub const PDI_DEACTIVATE: u8 = 1 << 0;
    /// PDI control bit 1: repeat acknowledge.
    pub const PDI_REPEAT_ACK: u8 = 1 << 1;
    /// Offset of the PDI control register inside the channel's block.
    pub const PDI_CONTROL_OFFSET: u16 = 7;

    /// Parses the 8 register bytes.
    pub const fn from_bytes(b: [u8; 8]) -> Self {
        Self {
            start: u16::from_le_bytes([b[0], b[1]]),
            length: u16::from_le_bytes([b[2], b[3]]),
            control: Control(b[4]),
            status: b[5],
            activate: b[6],
            pdi_control: b[7],
        }
    }

    /// The 8 register bytes (as a MainDevice writes them, status and PDI control included).
    pub const fn to_bytes(self) -> [u8; 8] {
        let s = self.start.to_le_bytes();
        let l = self.length.to_le_bytes();
        [
            s[0],
            s[1],
            l[0],
            l[1],
            self.control.0,
            self.status,
            self.activate,
            self.pdi_control,
        ]
    }

    /// Whether the MainDevice enabled the channel (activate bit 0).
    pub const fn enabled(self) -> bool {
        self.activate & Self::ACTIVATE_ENABLE != 0
    }

    /// The bytes of process RAM the channel occupies: one buffer in mailbox mode, three in
    /// 3-buffer mode. `None` when the area does not fit the 16-bit address space.
    pub const fn occupied(self) -> Option<(u32, u32)> {
        let buffers = match self.control.mode() {
            Mode::Buffered => 3,
            _ => 1,
        };
        let start = self.start as u32;
        let end = start + buffers * self.length as u32;
        if end > 0x1_0000 {
            None
        } else {
            Some((start, end))
        }
    }
}

/// What a SyncManager is for (ETG.2010 Table 10 "SM type"; the text of the ESI `Sm` element).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum SmKind {
    /// SM0: the receive mailbox ("MBoxOut").
    MailboxOut = 1,
    /// SM1: the send mailbox ("MBoxIn").
    MailboxIn = 2,
    /// SM2: process data outputs.
    Outputs = 3,
    /// SM3: process data inputs.
    Inputs = 4,
}

/// The value of 0x1C00 "Sync manager communication type" (ETG.1000.6 §5.6.7.1) for SM0..SM3: the
/// same types the SII SyncManager category and the ESI `Sm` elements give them.
pub const STANDARD_KINDS: [u8; 4] = [
    SmKind::MailboxOut as u8,
    SmKind::MailboxIn as u8,
    SmKind::Outputs as u8,
    SmKind::Inputs as u8,
];
