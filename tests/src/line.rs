//! Emulated ESCs on one cable: a frame from the MainDevice passes through each ESC in order on
//! the way out, loops back at the last one (its port 1 is closed) and returns through the others
//! unprocessed, as on a real line.

use ecat_core::register::{self, DlStatus};
use ecat_core::sync_manager::{Channel, Control};

use crate::emulator::Emulator;
use crate::esc::datagram::{Command, Operation};
use crate::frame::{self, Datagram, Frame};
use crate::master::{SM2_CONTROL, SM3_CONTROL};

/// The configured station address [`Line::address`] gives the first ESC; the others follow.
pub const FIRST_STATION: u16 = 0x1000;
/// The source MAC of the frames [`Line::exchange`] sends (locally-administered bit clear).
pub const MAIN_DEVICE_MAC: [u8; 6] = [0x10; 6];
/// FMMU type bits (ETG.1000.4 Table 56): read, write.
const FMMU_READ: u8 = 1;
const FMMU_WRITE: u8 = 2;

/// DL status bit 8 + 2 × port: the port's loop is closed (ETG.1000.4 Table 33).
const fn loop_closed(port: u8) -> u16 {
    1 << (8 + 2 * port)
}

/// Emulated ESCs wired in a line, port 0 towards the MainDevice.
pub struct Line {
    escs: Vec<Emulator>,
}

impl Line {
    /// `escs` in cable order. Sets each ESC's DL status (0x0110): port 0 linked and open for all;
    /// port 1 linked and open for all but the last, whose port 1 loop is closed; ports 2 and 3
    /// closed.
    pub fn new(escs: Vec<Emulator>) -> Self {
        let last = escs.len().saturating_sub(1);
        for (n, emu) in escs.iter().enumerate() {
            let mut status = DlStatus::PDI_OPERATIONAL
                | DlStatus::PDI_WATCHDOG_OK
                | DlStatus::link(0)
                | DlStatus::communication(0)
                | loop_closed(2)
                | loop_closed(3);
            status |= if n < last {
                DlStatus::link(1) | DlStatus::communication(1)
            } else {
                loop_closed(1)
            };
            emu.with(|esc| esc.set_register(register::DL_STATUS, &status.to_le_bytes()));
        }
        Self { escs }
    }

    /// The ESCs, in cable order.
    pub fn escs(&self) -> &[Emulator] {
        &self.escs
    }

    /// Passes `frame` through the line, in place. Returns the length of the frame that comes
    /// back to the MainDevice, or `None` when it is lost (see [`Frame::parse`]).
    pub fn process(&self, frame: &mut [u8]) -> Option<usize> {
        let (start, end) = match Frame::parse(frame) {
            Frame::Datagrams(start, end) => (start, end),
            Frame::Foreign => return Some(frame.len()),
            Frame::Runt => return None,
        };
        let now = embassy_time::Instant::now()
            .as_micros()
            .saturating_mul(1_000);
        let mut passed = Ok(());
        for emu in &self.escs {
            // A frame from the MainDevice: the test script is running, not a spinning runner.
            emu.script_ran();
            // Every ESC processes the datagrams before a malformed one, as on the wire.
            passed = emu.with(|esc| {
                esc.set_local_time(now);
                frame::pass(esc, frame, start, end)
            });
        }
        passed.ok()?;
        frame::mark_processed(frame);
        Some(frame.len())
    }

    /// Sends `datagrams` in one frame from [`MAIN_DEVICE_MAC`]; returns them as they came back,
    /// `None` if the frame was lost.
    pub fn exchange(&self, datagrams: &[Datagram]) -> Option<Vec<Datagram>> {
        let mut frame = frame::build(MAIN_DEVICE_MAC, datagrams);
        self.process(&mut frame)?;
        frame::datagrams(&frame)
    }

    /// What a MainDevice does first: sets each ESC's configured station address (0x0010) to
    /// [`FIRST_STATION`] + its position, one APWR per ESC (ETG.1000.4 §5.4). Returns whether
    /// every ESC took it.
    pub fn address(&self) -> bool {
        let datagrams: Vec<Datagram> = (0..self.escs.len())
            .map(|n| {
                let n = u16::try_from(n).unwrap_or(u16::MAX);
                let station = FIRST_STATION.wrapping_add(n).to_le_bytes();
                let write = Command::Ap(Operation::Write).code();
                Datagram::physical(
                    write,
                    0u16.wrapping_sub(n),
                    register::STATION_ADDRESS,
                    &station,
                )
            })
            .collect();
        self.all_counted(&datagrams)
    }

    /// Maps the process data as a MainDevice does before SAFEOP: on each addressed ESC `n`,
    /// SM2 (3-buffer, outputs at `outputs`) and SM3 (3-buffer, inputs at `inputs`) of `length`
    /// bytes, FMMU 0 writing logical `2·length·n` into the outputs and FMMU 1 reading the inputs
    /// into the `length` logical bytes after them (ETG.1000.4 Tables 56 and 58). Returns whether
    /// every ESC took every write.
    pub fn map_process_data(&self, outputs: u16, inputs: u16, length: u16) -> bool {
        (0..self.escs.len()).all(|n| {
            let station = FIRST_STATION.wrapping_add(u16::try_from(n).unwrap_or(u16::MAX));
            let logical = 2 * u32::from(length) * u32::try_from(n).unwrap_or(u32::MAX);
            let fmmus = [
                fmmu(logical, length, outputs, FMMU_WRITE),
                fmmu(logical + u32::from(length), length, inputs, FMMU_READ),
            ];
            let write = |address: u16, data: &[u8]| {
                Datagram::physical(Command::Fp(Operation::Write).code(), station, address, data)
            };
            let sm = |n: u8| register::sync_manager(n);
            self.all_counted(&[
                write(sm(2) + 6, &[0]),
                write(sm(3) + 6, &[0]),
                write(sm(2), &sync_manager(outputs, length, SM2_CONTROL)),
                write(sm(3), &sync_manager(inputs, length, SM3_CONTROL)),
                write(register::FMMU_BASE, &fmmus.concat()),
            ])
        })
    }

    /// Whether every datagram came back with a working counter of 1.
    fn all_counted(&self, datagrams: &[Datagram]) -> bool {
        self.exchange(datagrams)
            .is_some_and(|back| back.iter().all(|d| d.wkc == 1))
    }
}

/// An enabled SyncManager channel's 8 registers (ETG.1000.4 Table 58).
fn sync_manager(start: u16, length: u16, control: u8) -> [u8; Channel::SIZE] {
    Channel {
        start,
        length,
        control: Control(control),
        activate: 1,
        ..Channel::default()
    }
    .to_bytes()
}

/// An active, byte-aligned FMMU entity of `kind` (ETG.1000.4 Table 56).
fn fmmu(logical: u32, length: u16, physical: u16, kind: u8) -> Vec<u8> {
    let mut entity = Vec::with_capacity(16);
    entity.extend(logical.to_le_bytes());
    entity.extend(length.to_le_bytes());
    entity.extend([0, 7]);
    entity.extend(physical.to_le_bytes());
    entity.extend([0, kind, 1, 0, 0, 0]);
    entity
}
