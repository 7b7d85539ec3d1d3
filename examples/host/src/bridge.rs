//! Emulated SubDevices on a Linux network interface: frames from the interface pass through a
//! line of emulated ESCs running the real ecat runners and go back out, so any MainDevice (SOEM,
//! IgH, TwinCAT in a VM, ethercrab on a raw socket) can drive them.
//!
//! Threads: one receives frames from the raw socket, one keeps the runners' clock (embassy-time's
//! mock driver, which the whole host workspace uses) on real time; the executor thread runs the
//! runners and passes each frame through the line.

use std::cell::Cell;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use ecat_emu::harness;
use ecat_emu::line::Line;
use ecat_emu::pcap::PcapWriter;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::channel::Channel;

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
}

/// Frames waiting for the line; an empty frame wakes the line to look at [`STOP`].
static FRAMES: Channel<CriticalSectionRawMutex, Vec<u8>, 64> = Channel::new();
/// Ctrl-C was pressed or the interface failed.
static STOP: AtomicBool = AtomicBool::new(false);
/// Frames dropped because the line was busy.
static OVERRUNS: AtomicU64 = AtomicU64::new(0);
/// The frames sent back, which the raw socket sees again.
static SENT: std::sync::Mutex<Option<Sent>> = std::sync::Mutex::new(None);

/// Runs `f` on the record of sent frames.
fn sent<R>(f: impl FnOnce(&mut Sent) -> R) -> R {
    let mut guard = SENT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    f(guard.get_or_insert_with(Sent::default))
}

type Capture = PcapWriter<std::io::BufWriter<std::fs::File>>;

/// Serves `options.devices` on `options.iface` until Ctrl-C. Errors are messages for the user.
pub fn serve(options: &Options) -> Result<(), String> {
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
    let mut pcap = match &options.pcap {
        Some(path) => Some(
            std::fs::File::create(path)
                .and_then(|f| PcapWriter::new(std::io::BufWriter::new(f)))
                .map_err(|e| format!("cannot write {path}: {e}"))?,
        ),
        None => None,
    };
    let Port { mut tx, rx } = net::open(&options.iface).map_err(|e| e.to_string())?;
    ctrlc::set_handler(stop).map_err(|e| format!("cannot install the Ctrl-C handler: {e}"))?;
    let receiver = std::thread::spawn(move || receive(rx));
    println!(
        "serving {} on {}; Ctrl-C to stop",
        options.devices.join(", "),
        options.iface
    );
    let processed = Rc::new(Cell::new(0u64));
    let counter = processed.clone();
    harness::serve(devices, |escs| async move {
        std::thread::spawn(pump_clock);
        let line = Line::new(escs);
        loop {
            let mut frame = FRAMES.receive().await;
            if STOP.load(Ordering::SeqCst) {
                break;
            }
            capture(&mut pcap, &frame);
            let Some(len) = line.process(&mut frame) else {
                continue;
            };
            let reply = frame.get(..len).unwrap_or_default();
            capture(&mut pcap, reply);
            sent(|s| s.push(reply));
            if let Some(Err(e)) = tx.send_to(reply, None) {
                eprintln!("send failed: {e}");
            }
            counter.set(counter.get() + 1);
        }
        if let Some(pcap) = &mut pcap {
            let _ = pcap.flush();
        }
    });
    let _ = receiver.join();
    println!(
        "stopped after {} frames ({} dropped while busy)",
        processed.get(),
        OVERRUNS.load(Ordering::SeqCst)
    );
    Ok(())
}

/// Ends [`serve`]: the receiving thread and the line see the flag, the empty frame wakes the line.
fn stop() {
    STOP.store(true, Ordering::SeqCst);
    let _ = FRAMES.try_send(Vec::new());
}

/// Hands every EtherCAT frame from the interface, except the ones this program sent, to the line
/// until [`STOP`].
fn receive(mut rx: Box<dyn pnet_datalink::DataLinkReceiver>) {
    while !STOP.load(Ordering::SeqCst) {
        match rx.next() {
            Ok(frame) if net::is_ethercat(frame) && !sent(|s| s.take(frame)) => {
                if FRAMES.try_send(frame.to_vec()).is_err() {
                    OVERRUNS.fetch_add(1, Ordering::SeqCst);
                }
            }
            Ok(_) => {}
            Err(e) if net::is_timeout(&e) => {}
            Err(e) => {
                eprintln!("receive failed: {e}");
                stop();
            }
        }
    }
}

/// Keeps the runners' clock on real time: the line serves real MainDevices.
fn pump_clock() {
    let start = Instant::now();
    let origin = embassy_time::Instant::now();
    while !STOP.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_micros(200));
        let real = start.elapsed();
        let virtual_ = Duration::from_micros((embassy_time::Instant::now() - origin).as_micros());
        if let Some(behind) = real.checked_sub(virtual_) {
            let behind = u64::try_from(behind.as_micros()).unwrap_or(u64::MAX);
            embassy_time::MockDriver::get().advance(embassy_time::Duration::from_micros(behind));
        }
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
