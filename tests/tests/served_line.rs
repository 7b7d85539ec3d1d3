//! A line served in real time (`Line::serve`, what the virtual slave runs on a network
//! interface), here on a scripted host with virtual time: between frames the host's clock acts
//! on the ESCs (the SM watchdog of a silent MainDevice expires on time) and the line sleeps until
//! the next ESC deadline or the heartbeat, never polling.

mod common;

use std::collections::VecDeque;

use common::{send_outputs, walk_to};
use ecat_core::AlState;
use ecat_core::register;
use ecat_emu::frame::{self, Datagram};
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::line::{HEARTBEAT, Host, Line, MAIN_DEVICE_MAC, Served};
use ecat_emu::master::TestMaster;
use embassy_time::Duration;

/// A host whose clock jumps to whatever the line waits for: the next frame of its script, the
/// line's deadline or its end.
#[derive(Default)]
struct Scripted {
    clock: Duration,
    end: Duration,
    frames: VecDeque<(Duration, Vec<u8>)>,
    sent: Vec<Vec<u8>>,
    /// The host times the line woke at.
    wakes: Vec<Duration>,
    /// How far the host's clock moves while the line takes a frame (a frame takes that long).
    per_frame: Duration,
}

impl Scripted {
    fn silent_for(end: Duration) -> Self {
        Self {
            end,
            ..Self::default()
        }
    }
}

impl Host for Scripted {
    fn elapsed(&self) -> Duration {
        self.clock
    }

    /// A frame due by now arrives when the host takes it, and takes the line `per_frame`.
    fn receive(&mut self) -> Option<(Duration, Vec<u8>)> {
        if self.frames.front()?.0 <= self.clock {
            let arrived = self.clock;
            self.clock += self.per_frame;
            self.frames.pop_front().map(|(_, frame)| (arrived, frame))
        } else {
            None
        }
    }

    fn send(&mut self, frame: &[u8]) {
        self.sent.push(frame.to_vec());
    }

    async fn wait(&mut self, deadline: Duration) -> bool {
        if self.clock >= self.end {
            return false;
        }
        let next_frame = self.frames.front().map_or(self.end, |(at, _)| *at);
        self.clock = deadline.min(next_frame).min(self.end).max(self.clock);
        self.wakes.push(self.clock);
        true
    }
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// SOEM without `ec_configdc` writes no watchdog registers: the ESC's reset values give 100 ms.
/// A MainDevice that stops sending outputs in OP finds the SubDevice in SAFEOP + ERROR with
/// 0x001B 100 ms after the last outputs, with no frame in between: the line woke for it.
#[test]
fn a_silent_maindevice_expires_the_sm_watchdog_on_the_hosts_clock() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            walk_to(&master, AlState::Op).await;
            send_outputs(&master).await;
            let line = Line::new(vec![master.emulator().clone()]);
            let mut host = Scripted::silent_for(ms(99));
            line.serve(&mut host).await;
            assert_eq!(
                (master.al_status(), master.al_status_code()),
                (0x08, 0),
                "99 ms: still OP"
            );
            assert_eq!(
                host.wakes,
                [ms(99)],
                "the watchdog and the heartbeat at 100 ms"
            );
            let mut host = Scripted::silent_for(ms(50));
            line.serve(&mut host).await;
            assert_eq!(
                host.wakes.first(),
                Some(&ms(1)),
                "woke at the watchdog's expiry, 100 ms after the outputs"
            );
            assert_eq!(
                (master.al_status(), master.al_status_code()),
                (0x14, 0x001B),
                "SAFEOP + ERROR, SM watchdog"
            );
            assert_eq!(master.read(0x0442, 1), Some(vec![1]), "one expiry counted");
        },
    );
}

/// Idle costs nothing: a minute without frames is one wake-up per heartbeat, no runner polled,
/// no PDI access, and the ESC holds one waker per waiting runner (the virtual slave spun a core
/// and grew by 16 MB/s).
#[test]
fn an_idle_minute_is_a_wake_up_per_heartbeat_and_no_pdi_access() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            walk_to(&master, AlState::PreOp).await;
            let line = Line::new(vec![master.emulator().clone()]);
            // A second for what the walk left due (a runner's timer).
            line.serve(&mut Scripted::silent_for(Duration::from_secs(1)))
                .await;
            // Read without waking the runners (TestMaster::pdi_accesses is an ESC access).
            let accesses = || {
                let stats = master.emulator().stats();
                stats.reads + stats.writes
            };
            let before = accesses();
            let polls = harness::runner_polls();
            let mut host = Scripted::silent_for(Duration::from_secs(60));
            let served = line.serve(&mut host).await;
            let beats = Duration::from_secs(60).as_ticks() / HEARTBEAT.as_ticks();
            assert_eq!(
                served,
                Served {
                    frames: 0,
                    lost: 0,
                    wakeups: beats
                }
            );
            assert_eq!(accesses() - before, 0, "no PDI access");
            assert_eq!(harness::runner_polls() - polls, 0, "no runner polled");
            assert!(
                master.emulator().waiters() <= 1,
                "{} waiters",
                master.emulator().waiters()
            );
        },
    );
}

/// Frames are served when they arrive, on the host's clock, each answered once.
#[test]
fn frames_are_answered_at_their_time() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master: TestMaster| async move {
            let line = Line::new(vec![master.emulator().clone()]);
            let brd = Datagram::physical(0x07, 0, register::AL_STATUS, &[0, 0]);
            let request = frame::build(MAIN_DEVICE_MAC, &[brd]);
            let mut host = Scripted::silent_for(ms(20));
            host.frames = [(ms(3), request.clone()), (ms(3), request.clone())].into();
            let served = line.serve(&mut host).await;
            assert_eq!((served.frames, served.lost), (2, 0));
            assert_eq!(host.wakes, [ms(3), ms(20)], "the frames, the end");
            let answers: Vec<_> = host
                .sent
                .iter()
                .map(|f| frame::datagrams(f).expect("datagrams")[0].wkc)
                .collect();
            assert_eq!(answers, [1, 1], "each BRD counted by the one ESC");
        },
    );
}

/// Time goes on through a burst: 150 frames waiting at once, each taking the line 1 ms, and the
/// watchdog (100 ms after the last outputs) expires at the 100th. Each frame reads the AL status:
/// the first 100 see OP, the 50 after them SAFEOP + ERROR (the runner answered the expiry between
/// two frames).
#[test]
fn the_watchdog_expires_in_the_middle_of_a_burst() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            walk_to(&master, AlState::Op).await;
            send_outputs(&master).await;
            let line = Line::new(vec![master.emulator().clone()]);
            let brd = Datagram::physical(0x07, 0, register::AL_STATUS, &[0, 0]);
            let request = frame::build(MAIN_DEVICE_MAC, &[brd]);
            let mut host = Scripted::silent_for(ms(200));
            host.per_frame = ms(1);
            host.frames = (0..150).map(|_| (ms(0), request.clone())).collect();
            line.serve(&mut host).await;
            let mut seen = std::collections::BTreeMap::<u8, u32>::new();
            for answer in &host.sent {
                let status = frame::datagrams(answer).expect("datagrams")[0].data[0];
                *seen.entry(status).or_default() += 1;
            }
            assert_eq!(
                seen.into_iter().collect::<Vec<_>>(),
                [(0x08, 100), (0x14, 50)]
            );
        },
    );
}
