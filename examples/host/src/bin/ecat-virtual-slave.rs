//! Emulated EtherCAT SubDevices on a Linux network interface, for any MainDevice (ethercrab, SOEM,
//! IgH, TwinCAT in a VM) to drive: frames arrive on the interface, pass through a line of emulated
//! ESCs running the real ecat runners, and go back out.
//!
//! ```text
//! ecat-virtual-slave --iface IFNAME [--device NAME] [--count N] [--pcap FILE]
//! ```
//!
//! Needs root or `CAP_NET_RAW`. Ctrl-C ends it cleanly.

use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use ecat_emu::harness;
use ecat_emu::line::Line;
use ecat_emu::pcap::PcapWriter;
use ecat_examples::catalog;
use ecat_examples::net::{self, Port};
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::channel::Channel;

const USAGE: &str =
    "usage: ecat-virtual-slave --iface IFNAME [--device NAME] [--count N] [--pcap FILE]";

/// Frames waiting for the line; an empty frame wakes the line to look at [`STOP`].
static FRAMES: Channel<CriticalSectionRawMutex, Vec<u8>, 64> = Channel::new();
/// Ctrl-C was pressed or the interface failed.
static STOP: AtomicBool = AtomicBool::new(false);
/// Frames dropped because the line was busy.
static OVERRUNS: AtomicU64 = AtomicU64::new(0);

/// The command line.
struct Args {
    iface: String,
    device: String,
    count: usize,
    pcap: Option<String>,
}

impl Args {
    fn parse(mut args: impl Iterator<Item = String>) -> Result<Self, String> {
        let (mut iface, mut device, mut count, mut pcap) = (None, None, 1, None);
        while let Some(flag) = args.next() {
            let mut value = || args.next().ok_or(format!("{flag} needs a value"));
            match flag.as_str() {
                "--iface" => iface = Some(value()?),
                "--device" => device = Some(value()?),
                "--count" => {
                    count = value()?
                        .parse()
                        .ok()
                        .filter(|&n| (1..=catalog::MAX_COUNT).contains(&n))
                        .ok_or(format!("--count takes 1..={}", catalog::MAX_COUNT))?
                }
                "--pcap" => pcap = Some(value()?),
                "-h" | "--help" => return Err(USAGE.to_owned()),
                other => return Err(format!("unknown argument {other:?}\n{USAGE}")),
            }
        }
        Ok(Self {
            iface: iface.ok_or(format!("--iface is required\n{USAGE}"))?,
            device: device.unwrap_or_else(|| catalog::DEFAULT.to_owned()),
            count,
            pcap,
        })
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ecat-virtual-slave: {e}");
            ExitCode::from(2)
        }
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse(std::env::args().skip(1))?;
    let devices = (0..args.count)
        .map(|_| catalog::device(&args.device))
        .collect::<Option<Vec<_>>>()
        .ok_or(format!(
            "unknown device {:?} (known: {})",
            args.device,
            catalog::NAMES.join(", ")
        ))?;
    let mut pcap = match &args.pcap {
        Some(path) => Some(
            std::fs::File::create(path)
                .and_then(|f| PcapWriter::new(std::io::BufWriter::new(f)))
                .map_err(|e| format!("cannot write {path}: {e}"))?,
        ),
        None => None,
    };
    let Port { mut tx, rx } = net::open(&args.iface).map_err(|e| e.to_string())?;
    ctrlc::set_handler(|| {
        STOP.store(true, Ordering::SeqCst);
        let _ = FRAMES.try_send(Vec::new());
    })
    .map_err(|e| format!("cannot install the Ctrl-C handler: {e}"))?;
    let receiver = std::thread::spawn(move || receive(rx));
    println!(
        "ecat-virtual-slave: {} × {} on {}; Ctrl-C to stop",
        args.count, args.device, args.iface
    );
    let processed = std::rc::Rc::new(std::cell::Cell::new(0u64));
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
            if let Some(Err(e)) = tx.send_to(reply, None) {
                eprintln!("ecat-virtual-slave: send failed: {e}");
            }
            counter.set(counter.get() + 1);
        }
        if let Some(pcap) = &mut pcap {
            let _ = pcap.flush();
        }
    });
    let _ = receiver.join();
    println!(
        "ecat-virtual-slave: stopped after {} frames ({} dropped while busy)",
        processed.get(),
        OVERRUNS.load(Ordering::SeqCst)
    );
    Ok(())
}

/// Hands every EtherCAT request frame from the interface to the line until [`STOP`].
fn receive(mut rx: Box<dyn pnet_datalink::DataLinkReceiver>) {
    while !STOP.load(Ordering::SeqCst) {
        match rx.next() {
            Ok(frame) if net::is_request(frame) => {
                if FRAMES.try_send(frame.to_vec()).is_err() {
                    OVERRUNS.fetch_add(1, Ordering::SeqCst);
                }
            }
            Ok(_) => {}
            Err(e) if net::is_timeout(&e) => {}
            Err(e) => {
                eprintln!("ecat-virtual-slave: receive failed: {e}");
                STOP.store(true, Ordering::SeqCst);
                let _ = FRAMES.try_send(Vec::new());
            }
        }
    }
}

/// Keeps the runners' clock (embassy-time's mock driver, which the whole host workspace uses) on
/// real time: the virtual slave serves real masters.
fn pump_clock() {
    let start = Instant::now();
    let origin = embassy_time::Instant::now();
    while !STOP.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_micros(200));
        let real = start.elapsed();
        let virtual_ = Duration::from_micros((embassy_time::Instant::now() - origin).as_micros());
        if let Some(behind) = real.checked_sub(virtual_) {
            embassy_time::MockDriver::get().advance(embassy_time::Duration::from_micros(
                behind.as_micros() as u64,
            ));
        }
    }
}

fn capture(pcap: &mut Option<PcapWriter<std::io::BufWriter<std::fs::File>>>, frame: &[u8]) {
    if let Some(pcap) = pcap {
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap_or_default();
        if let Err(e) = pcap.write_frame(now, frame) {
            eprintln!("ecat-virtual-slave: capture failed: {e}");
        }
    }
}
