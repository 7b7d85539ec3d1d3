//! A register file standing in for the ESC, so the sans-IO core can be driven and watched
//! access by access.
#![allow(dead_code)]

use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_core::{AlEvent, DeviceConfig, Instant, RegisterAccess, SubDevice, register};

/// One access the core asked for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Op {
    Read(u16, usize),
    Write(u16, Vec<u8>),
}

/// ESC registers as plain memory plus the AL event register.
pub struct Regs {
    pub mem: Vec<u8>,
    pub event: u32,
}

impl Regs {
    /// Registers at zero but the process-data watchdog time (0x0420), at its ESC reset value.
    pub fn new() -> Self {
        let mut regs = Self {
            mem: vec![0; 0x1_0000],
            event: 0,
        };
        regs.put(register::WATCHDOG_TIME_PROCESS_DATA, &1000u16.to_le_bytes());
        regs
    }

    /// The MainDevice writes AL control.
    pub fn al_control(&mut self, value: u16) {
        self.put(register::AL_CONTROL, &value.to_le_bytes());
        self.event |= AlEvent::AL_CONTROL.bits();
    }

    /// The MainDevice writes SyncManager `n`.
    pub fn sm(&mut self, n: u8, start: u16, length: u16, control: u8, enable: bool) {
        let a = register::sync_manager(n);
        self.put(a, &start.to_le_bytes());
        self.put(a + 2, &length.to_le_bytes());
        self.put(a + 4, &[control, 0, u8::from(enable)]);
        self.event |= AlEvent::SM_CHANGE.bits();
    }

    pub fn put(&mut self, address: u16, data: &[u8]) {
        let a = usize::from(address);
        self.mem[a..a + data.len()].copy_from_slice(data);
    }

    pub fn u16_at(&self, address: u16) -> u16 {
        let a = usize::from(address);
        u16::from_le_bytes([self.mem[a], self.mem[a + 1]])
    }

    fn write(&mut self, log: &mut Vec<Op>, address: u16, data: &[u8]) {
        self.put(address, data);
        log.push(Op::Write(address, data.to_vec()));
    }

    /// Performs every access the core asks for; returns them in order (an [`RegisterAccess::Send`] as
    /// its two writes).
    pub fn drive(&mut self, sub: &mut SubDevice<'_>, now: Instant) -> Vec<Op> {
        let mut log = Vec::new();
        while let Some(access) = sub.poll_access() {
            assert!(log.len() < 64, "unbounded work: {log:?}");
            let event = AlEvent(self.event);
            let clears = access.clears();
            match access {
                RegisterAccess::Read { address, buf, .. } => {
                    let register_events =
                        AlEvent::AL_CONTROL | AlEvent::SM_CHANGE | AlEvent::WATCHDOG_PROCESS_DATA;
                    assert_eq!(
                        clears.intersection(register_events),
                        AlEvent::cleared_by_register_read(address, buf.len()),
                        "the core's idea of what reading {address:#06x} clears is the ESC's"
                    );
                    let a = usize::from(address);
                    buf.copy_from_slice(&self.mem[a..a + buf.len()]);
                    log.push(Op::Read(address, buf.len()));
                }
                RegisterAccess::Write { address, data, .. } => self.write(&mut log, address, data),
                RegisterAccess::Send {
                    address,
                    data,
                    last,
                    ..
                } => {
                    self.write(&mut log, address, data);
                    if let Some(last) = last {
                        self.write(&mut log, last, &[0]);
                    }
                }
            }
            self.event &= !clears.bits();
            sub.access_done(now, event);
        }
        log
    }
}

pub const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
pub const OUTPUTS: Area = Area::new(0x1100, 12);
pub const INPUTS: Area = Area::new(0x1200, 11);

/// A device with a 128-byte mailbox, 12 bytes out, 11 bytes in.
pub const DEVICE: DeviceConfig = DeviceConfig::new(
    MAILBOX,
    ProcessDataSizes {
        outputs: 12,
        inputs: 11,
    },
);

/// Configures all four SyncManagers as a MainDevice would for [`DEVICE`].
pub fn configure_all(regs: &mut Regs) {
    regs.sm(0, MAILBOX.receive.start, MAILBOX.receive.length, 0x26, true);
    regs.sm(1, MAILBOX.send.start, MAILBOX.send.length, 0x22, true);
    regs.sm(2, OUTPUTS.start, OUTPUTS.length, 0x64, true);
    regs.sm(3, INPUTS.start, INPUTS.length, 0x20, true);
}
