//! Emulated SubDevices on a Linux network interface: frames from the interface pass through a
//! line of emulated ESCs running the real ecat runners and go back out, so any MainDevice (SOEM,
//! IgH, TwinCAT in a VM, ethercrab on a raw socket) can drive them.
//!
//! Threads: one receives frames from the raw socket into a bounded queue (blocking when it is
//! full, so a burst waits in the socket instead of being dropped); one is an alarm clock that
//! wakes the line at the deadline it asked for; the executor thread runs the runners and the
//! line ([`Line::serve`]), which sleeps until a frame arrives or the next deadline (an ESC's
//! watchdog or SYNC0, or the heartbeat for the runners' own timers) and then brings the
//! runners' clock (embassy-time's mock driver) up to the wall clock. Nothing polls while idle.
//!
//! With [`Options::out`] the line is one segment of a longer one, as EtherCAT wires devices on
//! several cables: the last ESC's port 1 is the second interface. A processed frame leaves
//! through it to the next segment (another instance, in another process or on another host)
//! instead of looping back; a second receiving thread takes what comes back on it (the return
//! path) and the line sends that out of the first interface, to the MainDevice. A frame that
//! comes back has the locally-administered bit set (the ESCs of both segments set it): on the
//! second interface that marks no answer of another line, since only the next segment is there.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, TrySendError};
use std::sync::{Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use ecat_emu::harness;
use ecat_emu::line::{Host, Line, Served};
use ecat_emu::pcap::PcapWriter;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;

use crate::catalog;
use crate::net::{self, Port, Sent};

/// What to serve, and where.
pub struct Options {
    /// The network interface.
    pub iface: String,
    /// The devices on the line, in order (names from [`catalog::NAMES`]).
    pub devices: Vec<String>,
    /// A capture file for every frame in and out.
    pub pcap: Option<String>,
    /// Take frames whose source MAC has the locally-administered bit set as requests too (a
    /// MainDevice on an interface with such a MAC); by default they are answers of a line.
    pub la_requests: bool,
    /// The interface is linked to the [`Options::out`] interface of the previous segment of the
    /// line, not to a MainDevice: every EtherCAT frame arriving on it is a request (the previous
    /// segment's ESCs set its locally-administered bit, and a frame that segment polls comes
    /// again byte for byte, so neither the bit nor the record of sent frames tells anything).
    pub chained: bool,
    /// The interface to the next segment of the line (port 1 of the last ESC): processed frames
    /// leave through it, and what comes back on it goes to the MainDevice. `None`: port 1 of
    /// the last ESC has no link, its loop is closed.
    pub out: Option<String>,
}

/// What [`serve`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Summary {
    /// What the line served.
    pub served: Served,
    /// Frames the receiving thread had to wait to queue (the line was busy): delayed, not
    /// dropped.
    pub waited: u64,
    /// Replies the socket refused to send.
    pub send_failures: u64,
    /// The longest a frame waited between the receiving thread and the line.
    pub longest_wait: Duration,
    /// Frames passed on to the next segment ([`Options::out`]).
    pub passed_on: u64,
    /// Frames that came back from the next segment.
    pub returned: u64,
}

/// Frames that may wait for the line: about 6 MB of full-size frames, far more than a
/// MainDevice has in flight; beyond it the receiving thread waits and the socket holds the rest.
pub const QUEUE: usize = 4096;

/// Ctrl-C, SIGTERM or SIGHUP arrived, or the interface failed.
static STOP: AtomicBool = AtomicBool::new(false);
/// Why the interface failed, if it did.
static FAILURE: Mutex<Option<String>> = Mutex::new(None);
/// Wakes the line: a frame arrived, the alarm rang, or [`STOP`].
static WAKE: Signal<CriticalSectionRawMutex, ()> = Signal::new();
/// When the alarm thread wakes the line next.
static ALARM: Mutex<Option<Instant>> = Mutex::new(None);
/// Tells the alarm thread that [`ALARM`] or [`STOP`] changed.
static ALARM_CHANGED: Condvar = Condvar::new();
/// The frames sent back, which the raw socket sees again.
static SENT: Mutex<Option<Sent>> = Mutex::new(None);

/// Runs `f` on the record of sent frames.
fn sent<R>(f: impl FnOnce(&mut Sent) -> R) -> R {
    let mut guard = SENT.lock().unwrap_or_else(PoisonError::into_inner);
    f(guard.get_or_insert_with(Sent::default))
}

/// Where a frame arrived: port 0 of the first ESC (from the MainDevice or the previous
/// segment), or port 1 of the last (back from the next segment).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    In,
    Back,
}

/// A frame the receiving threads queued for the line: when and where it arrived.
type Arrival = (Instant, Side, Vec<u8>);

type Capture = PcapWriter<std::io::BufWriter<std::fs::File>>;

/// Serves `options.devices` on `options.iface` until Ctrl-C, SIGTERM or SIGHUP. Errors are
/// messages for the user; a failing interface is one, after the summary is printed.
pub fn serve(options: &Options) -> Result<Summary, String> {
    let devices = options
        .devices
        .iter()
        .map(|name| {
            catalog::device(name).ok_or(format!(
                "unknown device {name:?} (known: {})",
                catalog::NAMES.join(", ")
            ))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let pcap = match &options.pcap {
        Some(path) => Some(
            std::fs::File::create(path)
                .and_then(|f| PcapWriter::new(std::io::BufWriter::new(f)))
                .map_err(|e| format!("cannot write {path}: {e}"))?,
        ),
        None => None,
    };
    let Port { tx, rx } = net::open(&options.iface).map_err(|e| e.to_string())?;
    let out = match &options.out {
        Some(name) => Some(net::open(name).map_err(|e| format!("--out: {e}"))?),
        None => None,
    };
    ctrlc::set_handler(stop).map_err(|e| format!("cannot install the signal handler: {e}"))?;
    let (queue, inbox) = std::sync::mpsc::sync_channel(QUEUE);
    let (la_requests, chained) = (options.la_requests, options.chained);
    let (tx_out, returning) = match out {
        Some(Port { tx, rx }) => {
            let queue = queue.clone();
            let thread = std::thread::spawn(move || receive_returning(rx, &queue));
            (Some(tx), Some(thread))
        }
        None => (None, None),
    };
    let receiver = std::thread::spawn(move || {
        if chained {
            forward(rx, &queue, Side::In, net::is_ethercat)
        } else {
            receive(rx, &queue, la_requests)
        }
    });
    let alarm = std::thread::spawn(alarm_clock);
    match &options.out {
        Some(out) => println!(
            "serving {} on {} (port 0) and {out} (port 1 of the last ESC, to the next segment); \
             Ctrl-C to stop",
            options.devices.join(", "),
            options.iface
        ),
        None => println!(
            "serving {} on {}; Ctrl-C to stop",
            options.devices.join(", "),
            options.iface
        ),
    }
    let open_end = tx_out.is_some();
    let host = NetHost {
        start: Instant::now(),
        inbox,
        waiting: Default::default(),
        tx,
        tx_out,
        pcap,
        record_sent: la_requests && !chained,
        send_failures: 0,
        longest_wait: Duration::ZERO,
        passed_on: 0,
        returned: 0,
    };
    let outcome = Rc::new(RefCell::new(None));
    let result = outcome.clone();
    harness::serve(devices, move |escs| async move {
        let mut host = host;
        let line = if open_end {
            Line::open_ended(escs)
        } else {
            Line::new(escs)
        };
        let served = line.serve(&mut host).await;
        *result.borrow_mut() = Some((host, served));
    });
    let (host, served) = outcome.take().ok_or("the line stopped without a summary")?;
    let NetHost {
        inbox,
        mut pcap,
        send_failures,
        longest_wait,
        passed_on,
        returned,
        ..
    } = host;
    if let Some(pcap) = &mut pcap
        && let Err(e) = pcap.flush()
    {
        eprintln!("capture failed: {e}");
    }
    stop();
    // A receiving thread waiting for room in the queue gives up once the queue is gone.
    drop(inbox);
    let waited =
        receiver.join().unwrap_or(0) + returning.map_or(0, |thread| thread.join().unwrap_or(0));
    let _ = alarm.join();
    let summary = Summary {
        served,
        waited,
        send_failures,
        longest_wait,
        passed_on,
        returned,
    };
    println!(
        "stopped after {} frames ({} lost on the line, {} waited for a full queue, {} not sent; \
         longest wait for the line {:.1} ms)",
        summary.served.frames,
        summary.served.lost,
        summary.waited,
        summary.send_failures,
        summary.longest_wait.as_secs_f64() * 1e3
    );
    if let Some(out) = &options.out {
        println!(
            "{} frames passed on through {out}, {} came back",
            summary.passed_on, summary.returned
        );
    }
    match FAILURE
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .take()
    {
        Some(failure) => Err(format!("interface {}: {failure}", options.iface)),
        None => Ok(summary),
    }
}

/// Ends [`serve`]: the threads and the line see the flag and are woken.
fn stop() {
    STOP.store(true, Ordering::SeqCst);
    let _alarm = ALARM.lock().unwrap_or_else(PoisonError::into_inner);
    ALARM_CHANGED.notify_all();
    WAKE.signal(());
}

/// Whether a received frame is a request for the line: an EtherCAT frame that no line processed
/// yet. An ESC sets the locally-administered bit of the source MAC of every frame it processes,
/// so a frame with the bit set is on its way back to a MainDevice (from this program, or from
/// another line on the same interface, which would otherwise bounce frames with this one
/// forever); `la_requests` takes such frames as requests all the same, for a MainDevice whose
/// own MAC has the bit set. Frames this program sent are recognised by content ([`Sent`]):
/// foreign frames go back unchanged.
pub fn is_request(frame: &[u8], la_requests: bool) -> bool {
    net::is_ethercat(frame)
        && (la_requests || !net::locally_administered(frame))
        && !sent(|s| s.take(frame))
}

/// Hands every request ([`is_request`]) from the interface to the line until [`STOP`]; a full
/// queue makes it wait (the socket holds what arrives meanwhile). Returns how many frames
/// waited. An error of the interface stops everything.
fn receive(
    rx: Box<dyn pnet_datalink::DataLinkReceiver>,
    queue: &SyncSender<Arrival>,
    la_requests: bool,
) -> u64 {
    forward(rx, queue, Side::In, |frame| is_request(frame, la_requests))
}

/// Whether a frame received on the interface to the next segment comes back from there: any
/// EtherCAT frame. Its locally-administered bit is set (the next segment's ESCs processed it),
/// and that makes it no less a frame for the return path. The frames passed on through that
/// interface are not seen again: a packet socket does not receive what it sent itself, and
/// only the next segment is on that link. (A frame that the next segment leaves unchanged, an
/// FPRD of a station in this segment, comes back byte for byte as it was passed on.)
pub fn is_returning(frame: &[u8]) -> bool {
    net::is_ethercat(frame)
}

/// Hands every frame that comes back from the next segment ([`is_returning`]) to the line until
/// [`STOP`], as [`receive`] does.
fn receive_returning(
    rx: Box<dyn pnet_datalink::DataLinkReceiver>,
    queue: &SyncSender<Arrival>,
) -> u64 {
    forward(rx, queue, Side::Back, is_returning)
}

/// Queues the frames of `rx` that `wanted` accepts as arrived on `side`, until [`STOP`]; a full
/// queue makes it wait. Returns how many frames waited. An error of the interface stops
/// everything.
fn forward(
    mut rx: Box<dyn pnet_datalink::DataLinkReceiver>,
    queue: &SyncSender<Arrival>,
    side: Side,
    wanted: impl Fn(&[u8]) -> bool,
) -> u64 {
    let mut waited = 0;
    while !STOP.load(Ordering::SeqCst) {
        match rx.next() {
            Ok(frame) if wanted(frame) => {
                let frame = (Instant::now(), side, frame.to_vec());
                let queued = match queue.try_send(frame) {
                    Err(TrySendError::Full(frame)) => {
                        waited += 1;
                        WAKE.signal(());
                        queue.send(frame).is_ok()
                    }
                    result => result.is_ok(),
                };
                if !queued {
                    break;
                }
                WAKE.signal(());
            }
            Ok(_) => {}
            Err(e) if net::is_timeout(&e) => {}
            Err(e) => {
                let port = match side {
                    Side::In => "",
                    Side::Back => " (--out)",
                };
                *FAILURE.lock().unwrap_or_else(PoisonError::into_inner) =
                    Some(format!("receive failed{port}: {e}"));
                stop();
            }
        }
    }
    waited
}

/// Wakes the line when the wall clock reaches [`ALARM`], until [`STOP`].
fn alarm_clock() {
    let mut alarm = ALARM.lock().unwrap_or_else(PoisonError::into_inner);
    while !STOP.load(Ordering::SeqCst) {
        alarm = match *alarm {
            None => ALARM_CHANGED
                .wait(alarm)
                .unwrap_or_else(PoisonError::into_inner),
            Some(at) => match at.checked_duration_since(Instant::now()) {
                Some(left) if !left.is_zero() => {
                    ALARM_CHANGED
                        .wait_timeout(alarm, left)
                        .unwrap_or_else(PoisonError::into_inner)
                        .0
                }
                _ => {
                    *alarm = None;
                    WAKE.signal(());
                    alarm
                }
            },
        };
    }
}

/// The network interfaces and the wall clock, as the line sees them.
struct NetHost {
    start: Instant,
    inbox: Receiver<Arrival>,
    /// Frames taken from the inbox while looking for one of the other side: requests, returns.
    waiting: [std::collections::VecDeque<(Instant, Vec<u8>)>; 2],
    tx: Box<dyn pnet_datalink::DataLinkSender>,
    /// To the next segment.
    tx_out: Option<Box<dyn pnet_datalink::DataLinkSender>>,
    pcap: Option<Capture>,
    /// Record every frame sent in [`SENT`], not only unmarked ones (`--la-requests`).
    record_sent: bool,
    send_failures: u64,
    longest_wait: Duration,
    passed_on: u64,
    returned: u64,
}

impl NetHost {
    /// The next frame that arrived on `side`.
    fn next(&mut self, side: Side) -> Option<(Instant, Vec<u8>)> {
        let index = |side| match side {
            Side::In => 0,
            Side::Back => 1,
        };
        if let Some(frame) = self.waiting[index(side)].pop_front() {
            return Some(frame);
        }
        loop {
            let (arrived, on, frame) = self.inbox.try_recv().ok()?;
            self.longest_wait = self.longest_wait.max(arrived.elapsed());
            if on == side {
                return Some((arrived, frame));
            }
            self.waiting[index(on)].push_back((arrived, frame));
        }
    }

    /// Counts a failed send, telling the first.
    fn failed(&mut self, e: &std::io::Error) {
        if self.send_failures == 0 {
            eprintln!("send failed: {e}");
        }
        self.send_failures += 1;
    }
}

impl Host for NetHost {
    fn elapsed(&self) -> embassy_time::Duration {
        let us = u64::try_from(self.start.elapsed().as_micros()).unwrap_or(u64::MAX);
        embassy_time::Duration::from_micros(us)
    }

    fn receive(&mut self) -> Option<(embassy_time::Duration, Vec<u8>)> {
        let (arrived, frame) = self.next(Side::In)?;
        capture(&mut self.pcap, &frame);
        let us = arrived.saturating_duration_since(self.start).as_micros();
        let at = embassy_time::Duration::from_micros(u64::try_from(us).unwrap_or(u64::MAX));
        Some((at, frame))
    }

    fn returned(&mut self) -> Option<Vec<u8>> {
        let (_, frame) = self.next(Side::Back)?;
        self.returned += 1;
        Some(frame)
    }

    fn pass_on(&mut self, frame: &[u8]) {
        let Some(tx) = &mut self.tx_out else {
            return;
        };
        match tx.send_to(frame, None) {
            Some(Err(e)) => self.failed(&e),
            _ => self.passed_on += 1,
        }
    }

    fn send(&mut self, frame: &[u8]) {
        capture(&mut self.pcap, frame);
        // The raw socket sees the reply again; one with the locally-administered bit set is
        // not taken as a request anyway.
        if self.record_sent || !net::locally_administered(frame) {
            sent(|s| s.push(frame));
        }
        if let Some(Err(e)) = self.tx.send_to(frame, None) {
            self.failed(&e);
        }
    }

    async fn wait(&mut self, deadline: embassy_time::Duration) -> bool {
        if STOP.load(Ordering::SeqCst) {
            return false;
        }
        let at = self.start + Duration::from_micros(deadline.as_micros());
        let earlier = {
            let mut alarm = ALARM.lock().unwrap_or_else(PoisonError::into_inner);
            let earlier = alarm.is_none_or(|set| at < set);
            *alarm = Some(at);
            earlier
        };
        // A later alarm needs no wake-up of the alarm thread (a system call and a context
        // switch per frame): it wakes at the earlier time, finds the new one and sleeps on.
        if earlier {
            ALARM_CHANGED.notify_all();
        }
        WAKE.wait().await;
        !STOP.load(Ordering::SeqCst)
    }
}

fn capture(pcap: &mut Option<Capture>, frame: &[u8]) {
    if let Some(pcap) = pcap {
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap_or_default();
        if let Err(e) = pcap.write_frame(now, frame) {
            eprintln!("capture failed: {e}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(source0: u8, payload: u8) -> Vec<u8> {
        let mut f = vec![0xFF; 6];
        f.extend_from_slice(&[source0, 0x10, 0x10, 0x10, 0x10, 0x10, 0x88, 0xA4]);
        f.extend_from_slice(&[payload; 46]);
        f
    }

    /// Two virtual slaves on one interface: each sees the other's answers, which an ESC marked
    /// (locally-administered bit). Taken as requests, one frame bounced between them for ever.
    #[test]
    fn a_frame_a_line_processed_is_no_request() {
        let request = frame(0x10, 1);
        let answer = frame(0x12, 1);
        assert!(is_request(&request, false));
        assert!(!is_request(&answer, false), "an answer of another line");
        assert!(
            is_request(&answer, true),
            "--la-requests: a MainDevice with such a MAC"
        );
        assert!(!is_request(&frame(0x10, 2)[..13], false), "not EtherCAT");
    }

    /// A foreign frame goes back unchanged, source MAC included: the raw socket sees it again,
    /// and only its content tells it from the request.
    #[test]
    fn a_frame_this_program_sent_is_no_request_once() {
        let foreign = frame(0x10, 3);
        sent(|s| s.push(&foreign));
        assert!(!is_request(&foreign, false), "our own copy");
        assert!(is_request(&foreign, false), "the MainDevice's next one");
    }
}
