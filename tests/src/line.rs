//! Emulated ESCs on one cable: a frame from the MainDevice passes through each ESC in order on
//! the way out, loops back at the last one (its port 1 is closed) and returns through the others
//! unprocessed, as on a real line.

use ecat_core::register::{self, DlStatus};

use crate::emulator::Emulator;
use crate::frame::{self, Frame};

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
}
