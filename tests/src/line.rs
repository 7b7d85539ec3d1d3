//! Emulated ESCs on one cable: a frame from the MainDevice passes through each ESC in order on
//! the way out, loops back at the last one (its port 1 is closed) and returns through the others
//! unprocessed, as on a real line.
//!
//! A line can also be one segment of a longer one ([`Line::open_ended`]): the last ESC's port 1
//! has a link to the next segment, so a processed frame leaves through it ([`Host::pass_on`])
//! instead of looping back, and what comes back from there ([`Host::returned`]) passes the ESCs
//! unprocessed on the return path and leaves through port 0 of the first, as on a real line
//! whose devices are on several cables.

use core::future::Future;

use ecat_core::register::{self, DlStatus};
use ecat_core::sync_manager::{Channel, Control};
use embassy_time::{Duration, Instant, MockDriver};

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

/// The longest a served line sleeps without a frame when no ESC deadline is nearer: the runners'
/// own timers (a transition left pending, an SDO segment timeout, free-run cycles on a silent
/// line) are served at most this late. embassy-time's mock driver, the clock of the whole host
/// workspace, does not tell when its next alarm is due; the ESCs' deadlines are met exactly.
pub const HEARTBEAT: Duration = Duration::from_millis(100);

/// Yields in a row without a PDI access after which the runners count as idle.
const QUIET_YIELDS: u32 = 2;
/// Most yields a settle waits for the runners; a runner busy beyond that is left for later.
const MAX_YIELDS: u32 = 64;
/// The most ESC deadlines (SYNC0 pulses, watchdog expiries) one catch-up steps through: a
/// second of 1 kHz SYNC0 pulses on a line that was held up that long.
const MAX_DEADLINES: u32 = 1000;

/// What a line served in real time runs on: a clock and frames in and out. The virtual slave's
/// host is a network interface and the wall clock; a test's is scripted on virtual time.
pub trait Host {
    /// Time since serving started, on the host's clock.
    fn elapsed(&self) -> Duration;
    /// The next frame that arrived, if any, with the host time it arrived at (time since
    /// serving started).
    fn receive(&mut self) -> Option<(Duration, Vec<u8>)>;
    /// Sends the line's answer to a frame.
    fn send(&mut self, frame: &[u8]);
    /// Waits until a frame arrives, the host stops or its clock reaches `deadline` (time since
    /// serving started). Resolves to `false` once the host stops.
    fn wait(&mut self, deadline: Duration) -> impl Future<Output = bool>;
    /// The next frame that came back from the next segment into port 1 of the last ESC (the
    /// return path), if any. Only an [open-ended](Line::open_ended) line asks; by default none.
    fn returned(&mut self) -> Option<Vec<u8>> {
        None
    }
    /// Sends a frame the line processed out of port 1 of its last ESC, to the next segment.
    /// Only an [open-ended](Line::open_ended) line sends; by default the frame is lost.
    fn pass_on(&mut self, frame: &[u8]) {
        let _ = frame;
    }
}

/// What [`Line::serve`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Served {
    /// Frames that came back to the MainDevice (out of port 0 of the first ESC).
    pub frames: u64,
    /// Frames lost on the line (runts, malformed datagrams).
    pub lost: u64,
    /// Times the line woke up: for a frame, an ESC deadline or the [`HEARTBEAT`].
    pub wakeups: u64,
}

/// DL status bit 8 + 2 × port: the port's loop is closed (ETG.1000.4 Table 33).
const fn loop_closed(port: u8) -> u16 {
    1 << (8 + 2 * port)
}

/// Emulated ESCs wired in a line, port 0 towards the MainDevice.
pub struct Line {
    escs: Vec<Emulator>,
    /// The last ESC's port 1 has a link to the next segment.
    open_end: bool,
}

impl Line {
    /// `escs` in cable order. Sets each ESC's DL status (0x0110): port 0 linked and open for all;
    /// port 1 linked and open for all but the last, whose port 1 loop is closed; ports 2 and 3
    /// closed.
    pub fn new(escs: Vec<Emulator>) -> Self {
        Self::wired(escs, false)
    }

    /// `escs` in cable order, a segment of a longer line with more segments after it: like
    /// [`Line::new`], but the last ESC's port 1 has a link to the next segment too (DL status:
    /// link and communication on port 1, its loop open), so [`Line::serve`] passes processed
    /// frames on through it ([`Host::pass_on`]) and sends what comes back ([`Host::returned`])
    /// to the MainDevice.
    pub fn open_ended(escs: Vec<Emulator>) -> Self {
        Self::wired(escs, true)
    }

    fn wired(escs: Vec<Emulator>, open_end: bool) -> Self {
        let last = escs.len().saturating_sub(1);
        for (n, emu) in escs.iter().enumerate() {
            let mut status = DlStatus::PDI_OPERATIONAL
                | DlStatus::PDI_WATCHDOG_OK
                | DlStatus::link(0)
                | DlStatus::communication(0)
                | loop_closed(2)
                | loop_closed(3);
            status |= if n < last || open_end {
                DlStatus::link(1) | DlStatus::communication(1)
            } else {
                loop_closed(1)
            };
            emu.with(|esc| esc.set_register(register::DL_STATUS, &status.to_le_bytes()));
        }
        Self { escs, open_end }
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

    /// Serves the frames of `host` until it stops, with time acting on the ESCs between frames:
    /// whenever the line wakes, the runners' clock (embassy-time's mock driver) catches up with
    /// the host's, the ESCs see it ([`Emulator::tick`]: watchdog expiry, SYNC0, DC system time)
    /// and the runners settle before the frames that arrived pass. Then the line sleeps until
    /// the next ESC deadline ([`Emulator::next_deadline`]), the [`HEARTBEAT`] or a frame: no
    /// polling while idle. An [open-ended](Line::open_ended) line passes each processed frame
    /// on to the next segment and sends the frames that come back from there to the MainDevice.
    pub async fn serve(&self, host: &mut impl Host) -> Served {
        let origin = Instant::now();
        let mut served = Served::default();
        loop {
            loop {
                if self.open_end
                    && let Some(frame) = host.returned()
                {
                    // The return path: through the ESCs unprocessed, out of port 0.
                    host.send(&frame);
                    served.frames += 1;
                    continue;
                }
                let Some((arrived, mut frame)) = host.receive() else {
                    break;
                };
                // The ESCs see each frame at the time it arrived, and what fell due before it
                // (a SYNC0 pulse, a watchdog expiry) before it, however late this thread got to
                // it: the order of frames and SYNC0 pulses is the wire's, not the scheduler's.
                // A long burst keeps the clock going too.
                self.catch_up(origin + arrived).await;
                match self.process(&mut frame) {
                    Some(len) => {
                        let frame = frame.get(..len).unwrap_or_default();
                        if self.open_end {
                            host.pass_on(frame);
                        } else {
                            host.send(frame);
                            served.frames += 1;
                        }
                    }
                    None => served.lost += 1,
                }
                self.settle().await;
            }
            self.catch_up(origin + host.elapsed()).await;
            let heartbeat = Instant::now() + HEARTBEAT;
            let next = self
                .escs
                .iter()
                .filter_map(Emulator::next_deadline)
                .fold(heartbeat, Instant::min);
            if !host.wait(next.saturating_duration_since(origin)).await {
                return served;
            }
            served.wakeups += 1;
        }
    }

    /// Brings the runners' clock up to `target` and lets the ESCs see the time.
    async fn catch_up(&self, target: Instant) {
        // Step by step through the ESC deadlines before `target` (bounded: a deadline that
        // does not move on ends it), so that a runner sees each SYNC0 pulse and watchdog
        // expiry at its own time, not at the time the line got to it.
        for _ in 0..MAX_DEADLINES {
            match self.escs.iter().filter_map(Emulator::next_deadline).min() {
                Some(due) if due < target && due > Instant::now() => {
                    self.advance_to(due);
                    self.settle().await;
                }
                _ => break,
            }
        }
        self.advance_to(target);
        self.settle().await;
    }

    /// Moves the runners' clock to `target` (never back) and lets the ESCs see the time.
    fn advance_to(&self, target: Instant) {
        let now = Instant::now();
        if target > now {
            MockDriver::get().advance(target - now);
        }
        for emu in &self.escs {
            emu.tick();
            emu.script_ran();
        }
    }

    /// Lets the runners run until they stop accessing the PDI (or [`MAX_YIELDS`] passed).
    async fn settle(&self) {
        let accesses = || -> u64 {
            self.escs
                .iter()
                .map(|emu| {
                    let stats = emu.stats();
                    stats.reads + stats.writes
                })
                .sum()
        };
        let (mut last, mut quiet) = (accesses(), 0);
        for _ in 0..MAX_YIELDS {
            embassy_futures::yield_now().await;
            let now = accesses();
            quiet = if now == last { quiet + 1 } else { 0 };
            last = now;
            if quiet >= QUIET_YIELDS {
                return;
            }
        }
    }

    /// Sends `datagrams` in one frame from [`MAIN_DEVICE_MAC`]; returns them as they came back,
    /// `None` if the frame was lost.
    pub fn exchange(&self, datagrams: &[Datagram]) -> Option<Vec<Datagram>> {
        let mut frame = frame::build(MAIN_DEVICE_MAC, datagrams);
        self.process(&mut frame)?;
        frame::datagrams(&frame)
    }

    /// What a MainDevice does first: sets each ESC's configured station address (0x0010) to
    /// [`FIRST_STATION`] + its position, one APWR per ESC (ETG.1000.4 §5.4), 64 to a frame (the
    /// datagrams of a frame hold at most 2 047 bytes). Returns whether every ESC took it.
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
        datagrams.chunks(64).all(|frame| self.all_counted(frame))
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
