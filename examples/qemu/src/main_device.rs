//! The scripted MainDevice, in the SysTick handler: what a MainDevice's frames do to the ESC,
//! as register writes and reads on the model's EtherCAT port. INIT → PREOP → SAFEOP → OP with
//! the SyncManagers configured as MainDevices do, then a process-data exchange every cycle
//! (the inputs read, the outputs written: what one LRW does) with every answer checked, while a
//! CoE client uploads the 1 KiB object 0x2000 segmented, again and again, and checks its bytes.
//!
//! SysTick fires twice a cycle, on an absolute schedule (TIMER0 counts): a mailbox step (the last response read, the next request
//! written), then, [`offset`] later, the exchange. The offset sweeps 1 µs to 41 µs after the
//! request in 40 ns steps (a SysTick count; 40 instructions under `-icount shift=0`), so the
//! outputs arrive at every point of the SubDevice's mailbox work: reading the request in chunks,
//! serving it, writing the response in chunks.

use ecat_core::device::{Area, MailboxConfig};
use ecat_core::register;
use ecat_core::sync_manager::{Channel, Control};

use crate::app::{self, BLOB_LEN, DEVICE};
use crate::irq::Irq;

/// The process-data cycle.
pub const CYCLE_US: u32 = 500;
/// Timer counts (TIMER0, SysTick: the system clock) per cycle.
const CYCLE_COUNTS: u32 = crate::SYSCLK_HZ / 1_000_000 * CYCLE_US;
/// Offsets of the exchange after the mailbox step, in SysTick counts: 1 µs + 0..1000 (40 µs).
const OFFSETS: u32 = 1000;
/// The shortest offset: 1 µs.
const MIN_OFFSET: u32 = 25;
/// Cycles exchanged in OP before the verdict.
pub const OP_CYCLES: u32 = 4_000;
/// Cycles a state request may take.
const REQUEST_CYCLES: u32 = 2_000;
/// Cycles in SAFEOP with outputs before OP is requested.
const SAFEOP_CYCLES: u32 = 10;

/// SM2: 3-buffer, MainDevice writes, PDI event, watchdog trigger.
const SM2_CONTROL: u8 = 0x64;
/// SM3: 3-buffer, MainDevice reads, PDI event.
const SM3_CONTROL: u8 = 0x20;
/// SM0: mailbox, MainDevice writes, PDI event.
const SM0_CONTROL: u8 = 0x26;
/// SM1: mailbox, MainDevice reads, PDI event.
const SM1_CONTROL: u8 = 0x22;
/// The output image (three buffers from here).
const OUTPUTS: Area = Area::new(0x1100, 4);
/// The input image.
pub const INPUTS: Area = Area::new(0x1180, 4);
/// The object the client uploads.
const BLOB_INDEX: u16 = 0x2000;

/// What the run counted; the verdict is [`Report::passed`].
#[derive(Debug, Default, Clone, Copy)]
pub struct Report {
    /// Cycles in OP.
    pub op_cycles: u32,
    /// OP cycles whose inputs answered the previous cycle's outputs.
    pub exchanged: u32,
    /// OP cycles whose inputs did not: a cycle the SubDevice did not complete in time.
    pub missed: u32,
    /// Complete uploads of 0x2000 with every byte right.
    pub uploads: u32,
    /// Uploads that ended in an abort, a wrong byte or a malformed response.
    pub failed_uploads: u32,
    /// Segments received.
    pub segments: u32,
    /// Cycles exchanged while an upload was in progress.
    pub cycles_during_uploads: u32,
    /// Cycles the process-data runner completed while the state-machine runner was inside a
    /// chunked mailbox access (part of SM0 read or of SM1 written): preempted mid-transfer.
    pub cycles_inside_transfers: u32,
    /// The longest upload, in cycles.
    pub longest_upload: u32,
}

impl Report {
    /// OP reached, every OP cycle answered, at least 100 uploads, none failed, and cycles ran
    /// during them.
    pub fn passed(&self) -> bool {
        self.op_cycles == OP_CYCLES
            && self.missed == 0
            && self.exchanged + 1 >= OP_CYCLES
            && self.uploads >= 100
            && self.failed_uploads == 0
            && self.cycles_during_uploads >= OP_CYCLES / 2
            && self.cycles_inside_transfers > 0
    }
}

/// Where the script is.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Reset to INIT, SyncManagers cleared.
    Start,
    /// Waiting for the AL status `state` since cycle `since`.
    Requested { state: u16, since: u32 },
    /// SAFEOP with outputs; OP requested at `until`.
    SafeOp { until: u32 },
    /// OP.
    Op,
}

/// The CoE client's position in an upload.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Upload {
    /// The next step sends an initiate request.
    Idle,
    /// A request (initiate or a segment's) waits for SM0 to take it.
    Send { segment: bool },
    /// Waiting for the response in SM1.
    Receive { segment: bool },
}

/// The MainDevice.
pub struct MainDevice {
    tick: u32,
    /// TIMER0's count at cycle 0 of the schedule.
    epoch: Option<u32>,
    cycle: u32,
    phase: Phase,
    /// The inputs the next exchange must read.
    expected: Option<u32>,
    outputs: u32,
    upload: Upload,
    /// Mailbox counter of the next request (1..=7).
    counter: u8,
    toggle: bool,
    received: usize,
    started: u32,
    report: Report,
}

impl MainDevice {
    /// Before the first tick.
    pub const fn new() -> Self {
        Self {
            tick: 0,
            epoch: None,
            cycle: 0,
            phase: Phase::Start,
            expected: None,
            outputs: 0,
            upload: Upload::Idle,
            counter: 1,
            toggle: false,
            received: 0,
            started: 0,
            report: Report {
                op_cycles: 0,
                exchanged: 0,
                missed: 0,
                uploads: 0,
                failed_uploads: 0,
                segments: 0,
                cycles_during_uploads: 0,
                cycles_inside_transfers: 0,
                longest_upload: 0,
            },
        }
    }

    /// One SysTick at TIMER0 count `now`: returns the report once the run is over, and the
    /// TIMER0 count of the next tick. The schedule is absolute (from the first tick on), so a
    /// tick that comes late does not shift the ones after it.
    pub fn on_tick(&mut self, now: u32) -> (Option<Report>, u32) {
        self.tick = self.tick.wrapping_add(1);
        let next = self.cycle.wrapping_add(1);
        let epoch = *self
            .epoch
            .get_or_insert(now.wrapping_sub(CYCLE_COUNTS - offset(1)));
        let (done, deadline) = if self.tick.is_multiple_of(2) {
            self.cycle = next;
            // Next: the mailbox step before the next exchange.
            let after = next.wrapping_add(1);
            (
                self.on_cycle(),
                epoch
                    .wrapping_add(after.wrapping_mul(CYCLE_COUNTS))
                    .wrapping_sub(offset(after)),
            )
        } else {
            if self.phase == Phase::Op {
                self.mailbox_step();
            }
            // Next: the exchange.
            (false, epoch.wrapping_add(next.wrapping_mul(CYCLE_COUNTS)))
        };
        // What the writes did to the IRQ line reaches the NVIC, as the ESC's IRQ pin does.
        if crate::esc::with(|esc| esc.irq()) {
            if self.tick.is_multiple_of(2) && self.phase == Phase::Op {
                crate::figures::irq_raised();
            }
            Irq::Esc.pend();
        }
        (done.then_some(self.report), deadline)
    }

    /// The start of a cycle: the exchange, then the script.
    fn on_cycle(&mut self) -> bool {
        if matches!(self.phase, Phase::SafeOp { .. } | Phase::Op)
            || matches!(self.phase, Phase::Requested { state: 0x08, .. })
        {
            self.exchange();
        }
        match self.phase {
            Phase::Start => {
                write(register::AL_CONTROL, &0x0011u16.to_le_bytes());
                write(register::SM_BASE, &[0; 16 * 8]);
                self.request(0x01);
            }
            Phase::Requested { state, since } => {
                let status = read_u16(register::AL_STATUS);
                if status == state {
                    crate::log(format_args!(
                        "AL status {state:#04x} at cycle {}",
                        self.cycle
                    ));
                    self.entered(state);
                } else if self.cycle.wrapping_sub(since) > REQUEST_CYCLES {
                    let code = read_u16(register::AL_STATUS_CODE);
                    crate::log(format_args!(
                        "state {state:#04x} not reached: AL status {status:#06x}, code {code:#06x}"
                    ));
                    crate::fail("a state request failed");
                }
            }
            Phase::SafeOp { until } => {
                if self.cycle == until {
                    self.request(0x08);
                }
            }
            Phase::Op => {
                self.report.op_cycles += 1;
                if self.report.op_cycles.is_multiple_of(1000) {
                    crate::log(format_args!("{} OP cycles", self.report.op_cycles));
                }
                if self.upload != Upload::Idle {
                    self.report.cycles_during_uploads += 1;
                }
                self.report.cycles_inside_transfers = app::cycles_inside_transfers();
                return self.report.op_cycles == OP_CYCLES;
            }
        }
        false
    }

    /// Writes AL control = `state`; waits for it.
    fn request(&mut self, state: u16) {
        write(register::AL_CONTROL, &state.to_le_bytes());
        self.phase = Phase::Requested {
            state,
            since: self.cycle,
        };
    }

    /// The AL status shows `state`: the next step of the walk.
    fn entered(&mut self, state: u16) {
        match state {
            0x01 => {
                configure_mailbox(&DEVICE.device().mailbox);
                configure_sm(2, OUTPUTS, SM2_CONTROL);
                configure_sm(3, INPUTS, SM3_CONTROL);
                self.request(0x02);
            }
            0x02 => self.request(0x04),
            0x04 => {
                self.phase = Phase::SafeOp {
                    until: self.cycle + SAFEOP_CYCLES,
                }
            }
            _ => {
                // Answers are checked from the first outputs written in OP on.
                self.expected = None;
                self.phase = Phase::Op;
            }
        }
    }

    /// One LRW's worth: the inputs read, the next outputs written.
    fn exchange(&mut self) {
        let mut inputs = [0; 4];
        crate::esc::with(|esc| esc.ecat_read(INPUTS.start, &mut inputs));
        if self.phase == Phase::Op {
            match self.expected {
                Some(expected) if u32::from_le_bytes(inputs) == expected => {
                    self.report.exchanged += 1
                }
                Some(_) => self.report.missed += 1,
                None => {}
            }
        }
        self.outputs = self.outputs.wrapping_add(0x0101_0101);
        write(OUTPUTS.start, &self.outputs.to_le_bytes());
        self.expected = (self.phase == Phase::Op).then_some(app::answer(self.outputs));
    }

    /// One step of the CoE client: the response read if one is due, then the next request sent.
    fn mailbox_step(&mut self) {
        if let Upload::Receive { segment } = self.upload {
            let mut message = [0; 128];
            let full = crate::esc::with(|esc| {
                esc.ecat_read(DEVICE.device().mailbox.send.start, &mut message)
            });
            if full {
                match self.response(segment, &message) {
                    Ok(true) => self.upload = Upload::Send { segment: true },
                    Ok(false) => self.finished(true),
                    Err(why) => {
                        crate::log(format_args!("upload failed: {why}"));
                        self.finished(false);
                    }
                }
            }
        }
        if self.upload == Upload::Idle {
            self.started = self.cycle;
            self.received = 0;
            self.toggle = false;
            self.upload = Upload::Send { segment: false };
        }
        if let Upload::Send { segment } = self.upload {
            let sdo = if segment {
                [0x60 | (u8::from(self.toggle) << 4), 0, 0, 0, 0, 0, 0, 0]
            } else {
                let [lo, hi] = BLOB_INDEX.to_le_bytes();
                [0x40, lo, hi, 0, 0, 0, 0, 0]
            };
            let mut message = [0; 128];
            // Mailbox header: length 10 (CoE header + SDO), address 0, CoE (3) and counter.
            message[..6].copy_from_slice(&[10, 0, 0, 0, 0, 0x03 | (self.counter << 4)]);
            // CoE header: SDO request (service 2).
            message[6..8].copy_from_slice(&0x2000u16.to_le_bytes());
            message[8..16].copy_from_slice(&sdo);
            if write(DEVICE.device().mailbox.receive.start, &message) {
                self.counter = self.counter % 7 + 1;
                self.upload = Upload::Receive { segment };
            }
        }
    }

    /// Checks a response; `Ok(true)`: more segments to come.
    fn response(&mut self, segment: bool, message: &[u8; 128]) -> Result<bool, &'static str> {
        let length = usize::from(u16::from_le_bytes([message[0], message[1]]));
        let coe_service = u16::from_le_bytes([message[6], message[7]]) >> 12;
        if message[5] & 0x0F != 0x03 || coe_service != 3 || !(10..=122).contains(&length) {
            return Err("not an SDO response");
        }
        let command = message[8];
        let data = match (segment, command & 0xE0) {
            (_, 0x80) => return Err("SDO abort"),
            (false, 0x40) => {
                let size = u32::from_le_bytes([message[12], message[13], message[14], message[15]]);
                if command & 0x03 != 0x01 || size as usize != BLOB_LEN {
                    return Err("initiate response without the blob's size");
                }
                &message[16..6 + length]
            }
            (true, 0x00) => {
                if (command >> 4) & 1 != u8::from(self.toggle) {
                    return Err("toggle bit");
                }
                self.report.segments += 1;
                self.toggle = !self.toggle;
                let n = if length > 10 {
                    length - 3
                } else {
                    7 - usize::from((command >> 1) & 7)
                };
                &message[9..9 + n]
            }
            _ => return Err("unexpected SDO command"),
        };
        let offset = self.received;
        if offset + data.len() > BLOB_LEN
            || data
                .iter()
                .enumerate()
                .any(|(i, &b)| b != app::blob_byte(offset + i))
        {
            return Err("wrong bytes");
        }
        self.received += data.len();
        let last = segment && command & 0x01 != 0;
        match (
            last || !segment && self.received == BLOB_LEN,
            self.received == BLOB_LEN,
        ) {
            (true, true) => Ok(false),
            (true, false) => Err("last segment before the end"),
            (false, _) => Ok(true),
        }
    }

    /// An upload ended.
    fn finished(&mut self, ok: bool) {
        if ok {
            self.report.uploads += 1;
        } else {
            self.report.failed_uploads += 1;
        }
        let cycles = self.cycle.wrapping_sub(self.started);
        self.report.longest_upload = self.report.longest_upload.max(cycles);
        self.upload = Upload::Idle;
    }
}

/// How long after the mailbox step of `cycle` its exchange comes, in SysTick counts: a sweep
/// with stride 37 over [`OFFSETS`] counts from [`MIN_OFFSET`] on.
fn offset(cycle: u32) -> u32 {
    MIN_OFFSET + cycle.wrapping_mul(37) % OFFSETS
}

/// A write through the EtherCAT port; whether the ESC took it.
fn write(address: u16, data: &[u8]) -> bool {
    crate::esc::with(|esc| esc.ecat_write(address, data))
}

fn read_u16(address: u16) -> u16 {
    let mut buf = [0; 2];
    crate::esc::with(|esc| esc.ecat_read(address, &mut buf));
    u16::from_le_bytes(buf)
}

/// SyncManager `n` over `area` with `control`, enabled, in one write as MainDevices do.
fn configure_sm(n: u8, area: Area, control: u8) {
    let channel = Channel {
        start: area.start,
        length: area.length,
        control: Control(control),
        activate: 1,
        ..Channel::default()
    };
    write(register::sync_manager(n), &channel.to_bytes());
}

/// SM0/SM1 as the mailboxes of `mailbox`.
fn configure_mailbox(mailbox: &MailboxConfig) {
    configure_sm(0, mailbox.receive, SM0_CONTROL);
    configure_sm(1, mailbox.send, SM1_CONTROL);
}
