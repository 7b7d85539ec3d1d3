//! A small MainDevice on a network interface, built on ethercrab's raw-socket transport: finds the
//! SubDevices, prints their identity and names, brings them to OP, exchanges process data and
//! checks every cycle's working counter. Used by CI against `ecat-virtual-slave` on a veth pair.
//!
//! ```text
//! ecat-scan --iface IFNAME [--cycles N] [--lrw] [--echo] [--silence MS]
//! ecat-scan --iface IFNAME --burst N [--fps F]
//! ```
//!
//! `--lrw` runs the cycles as one LRW frame each over the whole process image, on a raw socket
//! of its own, as SOEM does, instead of ethercrab's cycle (the LRW and an AL status read of
//! every SubDevice, in as many frames as that takes, one after the other): for figures of long
//! lines.
//!
//! `--burst N` instead sends N frames back to back (a BRD of the AL status and a numbered NOP
//! each, on a raw socket of its own), F frames a second (default: as fast as the socket takes
//! them), and counts the answers: every one must come back.
//!
//! `--echo` also checks that every SubDevice with as many input as output bytes returns its
//! outputs as inputs (the loop-back wiring of the virtual slave's digital I/O module).
//! `--silence MS` then stops sending for MS milliseconds of wall-clock time and checks that every
//! SubDevice with outputs fell back to SAFEOP with the SM watchdog code 0x001B while the others
//! stayed in OP (it leaves them there). Exits with status 1 when a check fails.

use std::process::ExitCode;
use std::time::Duration;

use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::subdevice_group::{Op, SubDeviceGroup};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

const MAX_SUBDEVICES: usize = 256;
const MAX_PDI: usize = 2048;
static STORAGE: PduStorage<16, { PduStorage::element_size(1100) }> = PduStorage::new();

const USAGE: &str = "usage: ecat-scan --iface IFNAME [--cycles N] [--lrw] [--echo] [--silence MS]\n       ecat-scan --iface IFNAME --burst N [--fps F]";

struct Args {
    iface: String,
    cycles: u32,
    echo: bool,
    lrw: bool,
    burst: Option<u32>,
    fps: Option<u32>,
    silence: Option<u64>,
}

fn parse(mut args: impl Iterator<Item = String>) -> Result<Args, String> {
    let (mut iface, mut cycles, mut echo, mut burst, mut fps, mut silence) =
        (None, 1000, false, None, None, None);
    let mut lrw = false;
    while let Some(flag) = args.next() {
        match flag.as_str() {
            "--iface" => iface = args.next(),
            "--burst" => {
                burst = Some(
                    args.next()
                        .and_then(|n| n.parse().ok())
                        .ok_or("--burst takes a number")?,
                )
            }
            "--cycles" => {
                cycles = args
                    .next()
                    .and_then(|n| n.parse().ok())
                    .ok_or("--cycles takes a number")?
            }
            "--fps" => {
                fps = Some(
                    args.next()
                        .and_then(|n| n.parse().ok())
                        .filter(|&n| n > 0)
                        .ok_or("--fps takes a positive number")?,
                )
            }
            "--silence" => {
                silence = Some(
                    args.next()
                        .and_then(|n| n.parse().ok())
                        .ok_or("--silence takes milliseconds")?,
                )
            }
            "--echo" => echo = true,
            "--lrw" => lrw = true,
            _ => return Err(USAGE.to_owned()),
        }
    }
    Ok(Args {
        iface: iface.ok_or(USAGE)?,
        cycles,
        echo,
        lrw,
        burst,
        fps,
        silence,
    })
}

fn main() -> ExitCode {
    let result = parse(std::env::args().skip(1)).and_then(|args| match args.burst {
        Some(frames) => burst(&args.iface, frames, args.fps),
        None => futures_lite::future::block_on(run(args)).map_err(|e| e.to_string()),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ecat-scan: {e}");
            ExitCode::FAILURE
        }
    }
}

type Group = SubDeviceGroup<MAX_SUBDEVICES, MAX_PDI, ethercrab::DefaultLock, Op>;

async fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    let (tx, rx, pdu_loop) = STORAGE
        .try_split()
        .map_err(|()| "PDU storage split twice")?;
    let task = tx_rx_task(&args.iface, tx, rx)?;
    std::thread::spawn(move || futures_lite::future::block_on(task));
    let main = MainDevice::new(
        pdu_loop,
        // Long enough for a long line on a loaded machine (ethercrab's defaults, EEPROM 10 ms
        // and PDU 30 ms, failed now and then at 64 SubDevices under load 5): late process-data
        // frames are counted by the round trips instead.
        Timeouts {
            eeprom: Duration::from_millis(100),
            pdu: Duration::from_millis(100),
            ..Timeouts::default()
        },
        MainDeviceConfig {
            dc_static_sync_iterations: 0,
            ..MainDeviceConfig::default()
        },
    );
    let group = main
        .init_single_group::<MAX_SUBDEVICES, MAX_PDI>(ethercat_now)
        .await?;
    println!("{} SubDevices", group.len());
    for sub in group.iter(&main) {
        let id = sub.identity();
        println!(
            "  {:#06x} {:<24} vendor {:#010x} product {:#010x} revision {} serial {:#010x}",
            sub.configured_address(),
            sub.name(),
            id.vendor_id,
            id.product_id,
            id.revision,
            id.serial
        );
    }
    // A SubDevice enters OP after the first valid outputs: request OP, then run the cycle.
    let group: Group = group
        .into_safe_op(&main)
        .await?
        .request_into_op(&main)
        .await?;
    let mut waited = 0;
    while !group.tx_rx(&main).await?.all_op() {
        waited += 1;
        if waited > 1000 {
            return Err("not all SubDevices reached OP within 1000 cycles".into());
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    println!("all SubDevices in OP after {waited} cycles");
    let expected = expected_wkc(&group, &main);
    if args.lrw {
        let image = group
            .iter(&main)
            .map(|sub| sub.io_raw().inputs().len() + sub.io_raw().outputs().len())
            .sum();
        lrw_cycles(&args.iface, args.cycles, image, expected)?;
        println!(
            "{} cycles, working counter {expected} every cycle",
            args.cycles
        );
        return Ok(());
    }
    // One cycle a millisecond on the wall clock: late cycles catch up, up to 10 ms behind.
    let start = std::time::Instant::now();
    let mut next = start;
    let mut round_trips = Vec::with_capacity(usize::try_from(args.cycles).unwrap_or(0));
    for cycle in 0..args.cycles {
        write_outputs(&group, &main, cycle);
        let sent = std::time::Instant::now();
        let response = group.tx_rx(&main).await?;
        round_trips.push(sent.elapsed());
        if response.working_counter != expected {
            return Err(format!(
                "cycle {cycle}: working counter {} instead of {expected}",
                response.working_counter
            )
            .into());
        }
        next_cycle(&mut next);
    }
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "{:.0} cycles/s",
        f64::from(args.cycles) / elapsed.max(f64::MIN_POSITIVE)
    );
    println!("{}", RoundTrips::of(round_trips));
    if args.echo {
        check_echo(&group, &main).await?;
    }
    println!(
        "{} cycles, working counter {expected} every cycle",
        args.cycles
    );
    if let Some(ms) = args.silence {
        return check_silence(&group, &main, ms).await;
    }
    group
        .into_safe_op(&main)
        .await?
        .into_pre_op(&main)
        .await?
        .into_init(&main)
        .await?;
    println!("back in INIT");
    Ok(())
}

/// A cycle whose frames took longer than this to come back is late.
const LATE: Duration = Duration::from_millis(2);

/// The round trips of the process-data cycles: percentiles and how many were [`LATE`].
struct RoundTrips {
    sorted: Vec<Duration>,
}

impl RoundTrips {
    fn of(mut round_trips: Vec<Duration>) -> Self {
        round_trips.sort_unstable();
        Self {
            sorted: round_trips,
        }
    }

    /// The round trip that `percent` % of the cycles did not exceed.
    fn percentile(&self, percent: usize) -> Duration {
        let n = self.sorted.len();
        let at = (n * percent).div_ceil(100).clamp(1, n.max(1)) - 1;
        self.sorted.get(at).copied().unwrap_or_default()
    }
}

impl std::fmt::Display for RoundTrips {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let us = |d: Duration| d.as_micros();
        let late = self.sorted.iter().filter(|&&d| d > LATE).count();
        write!(
            f,
            "round trip p50 {} us, p99 {} us, max {} us; {late} of {} cycles late (over {} ms)",
            us(self.percentile(50)),
            us(self.percentile(99)),
            us(self.sorted.last().copied().unwrap_or_default()),
            self.sorted.len(),
            LATE.as_millis()
        )
    }
}

/// The LRW working counter of a cycle: per SubDevice 1 for its inputs (read) and 2 for its outputs
/// (write), as ESCs count them (ETG.1000.4 §5.4.3).
fn expected_wkc(group: &Group, main: &MainDevice<'_>) -> u16 {
    group
        .iter(main)
        .map(|sub| {
            let io = sub.io_raw();
            u16::from(!io.inputs().is_empty()) + 2 * u16::from(!io.outputs().is_empty())
        })
        .sum()
}

/// Sends nothing for `ms` milliseconds, then reads every SubDevice's AL status: those with
/// outputs must have fallen back to SAFEOP + ERROR with 0x001B (their SM watchdog expired), the
/// others must still be in OP.
async fn check_silence(
    group: &Group,
    main: &MainDevice<'_>,
    ms: u64,
) -> Result<(), Box<dyn std::error::Error>> {
    std::thread::sleep(Duration::from_millis(ms));
    let mut wrong = 0;
    for sub in group.iter(main) {
        // AL status and AL status code, raw: ethercrab's status() reports the error bit as an
        // error.
        let status: u16 = sub.register_read(0x0130u16).await?;
        let code: u16 = sub.register_read(0x0134u16).await?;
        let outputs = !sub.io_raw().outputs().is_empty();
        let expected = if outputs { (0x14, 0x001B) } else { (0x08, 0) };
        let right = (status, code) == expected;
        println!(
            "  {:#06x} after {ms} ms of silence: AL status {status:#04x}, code {code:#06x} ({})",
            sub.configured_address(),
            if right { "as expected" } else { "WRONG" }
        );
        wrong += usize::from(!right);
    }
    if wrong > 0 {
        return Err(format!("{wrong} SubDevices in the wrong state after the silence").into());
    }
    Ok(())
}

/// Fills every SubDevice's outputs with a pattern of the cycle number.
fn write_outputs(group: &Group, main: &MainDevice<'_>, cycle: u32) {
    for (n, sub) in group.iter(main).enumerate() {
        let mut outputs = sub.outputs_raw_mut();
        for (i, byte) in outputs.iter_mut().enumerate() {
            *byte = (cycle as usize + n + i) as u8;
        }
    }
}

/// Holds the outputs for a few cycles and checks that loop-back SubDevices return them.
async fn check_echo(group: &Group, main: &MainDevice<'_>) -> Result<(), String> {
    write_outputs(group, main, 0xA5);
    for _ in 0..10 {
        group.tx_rx(main).await.map_err(|e| e.to_string())?;
        std::thread::sleep(Duration::from_millis(1));
    }
    for sub in group.iter(main) {
        let io = sub.io_raw();
        if io.inputs().len() != io.outputs().len() {
            continue;
        }
        if io.inputs() != io.outputs() {
            return Err(format!(
                "{:#06x}: inputs {:02x?} do not echo outputs {:02x?}",
                sub.configured_address(),
                io.inputs(),
                io.outputs()
            ));
        }
        println!(
            "  {:#06x} echoes {:02x?}",
            sub.configured_address(),
            io.inputs()
        );
    }
    Ok(())
}

/// Sends `frames` frames back to back, each a BRD of the AL status and a NOP with the frame's
/// number, at `fps` frames a second if given, while a second thread counts the answers (source MAC marked by an
/// ESC) until none came for a second. Fails unless every frame came back.
/// `cycles` process-data cycles of one LRW frame each over the `image` bytes from logical address
/// 0 (ethercrab maps its first group there), one a millisecond, on a raw socket of its own: each
/// must come back with the working counter `expected`; prints the round trips.
fn lrw_cycles(iface: &str, cycles: u32, image: usize, expected: u16) -> Result<(), String> {
    use ecat_emu::frame::{self, Datagram};
    let port = ecat_examples::net::open(iface).map_err(|e| e.to_string())?;
    let (mut tx, mut rx) = (port.tx, port.rx);
    let start = std::time::Instant::now();
    let mut next = start;
    let mut round_trips = Vec::with_capacity(usize::try_from(cycles).unwrap_or(0));
    for cycle in 0..cycles {
        let data: Vec<u8> = (0..image).map(|i| (cycle as usize + i) as u8).collect();
        let mut lrw = Datagram::logical(0x0C, 0, &data);
        // The index tells this cycle's frame from a late one of an earlier cycle.
        lrw.index = cycle as u8;
        let request = frame::build(ecat_emu::line::MAIN_DEVICE_MAC, &[lrw]);
        let sent = std::time::Instant::now();
        match tx.send_to(&request, None) {
            Some(Ok(())) => {}
            Some(Err(e)) => return Err(format!("send failed: {e}")),
            None => return Err("send failed".to_owned()),
        }
        let wkc = loop {
            if sent.elapsed() > Duration::from_secs(1) {
                return Err(format!("cycle {cycle}: no frame back within 1 s"));
            }
            match rx.next() {
                Ok(f)
                    if ecat_examples::net::is_ethercat(f)
                        && ecat_examples::net::locally_administered(f) =>
                {
                    let back = frame::datagrams(f).and_then(|d| d.into_iter().next());
                    if let Some(back) = back.filter(|d| d.command == 0x0C && d.index == cycle as u8)
                    {
                        break back.wkc;
                    }
                }
                Ok(_) => {}
                Err(e) if ecat_examples::net::is_timeout(&e) => {}
                Err(e) => return Err(format!("receive failed: {e}")),
            }
        };
        round_trips.push(sent.elapsed());
        if wkc != expected {
            return Err(format!(
                "cycle {cycle}: working counter {wkc} instead of {expected}"
            ));
        }
        next_cycle(&mut next);
    }
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "{:.0} cycles/s (one LRW of {image} bytes each)",
        f64::from(cycles) / elapsed.max(f64::MIN_POSITIVE)
    );
    println!("{}", RoundTrips::of(round_trips));
    Ok(())
}

fn burst(iface: &str, frames: u32, fps: Option<u32>) -> Result<(), String> {
    use ecat_emu::frame::{self, Datagram};
    let port = ecat_examples::net::open(iface).map_err(|e| e.to_string())?;
    let (mut tx, mut rx) = (port.tx, port.rx);
    let counter = std::thread::spawn(move || {
        let mut answers = std::collections::BTreeSet::new();
        let mut last = std::time::Instant::now();
        while last.elapsed() < Duration::from_secs(1) {
            match rx.next() {
                Ok(f)
                    if ecat_examples::net::is_ethercat(f)
                        && ecat_examples::net::locally_administered(f) =>
                {
                    let number = frame::datagrams(f)
                        .and_then(|d| d.get(1).and_then(|nop| nop.data.get(..4)?.try_into().ok()))
                        .map(u32::from_le_bytes);
                    if let Some(number) = number {
                        answers.insert(number);
                        last = std::time::Instant::now();
                    }
                }
                _ => {}
            }
        }
        answers.len()
    });
    let start = std::time::Instant::now();
    for n in 0..frames {
        if let Some(fps) = fps {
            let due = start + Duration::from_secs_f64(f64::from(n) / f64::from(fps));
            if let Some(wait) = due.checked_duration_since(std::time::Instant::now()) {
                std::thread::sleep(wait);
            }
        }
        // A BRD of the AL status (read-only, no side effect), then a NOP that carries the
        // frame's number through the line untouched.
        let brd = Datagram::physical(0x07, 0, 0x0130, &[0, 0]);
        let nop = Datagram::physical(0x00, 0, 0, &n.to_le_bytes());
        let request = frame::build(ecat_emu::line::MAIN_DEVICE_MAC, &[brd, nop]);
        match tx.send_to(&request, None) {
            Some(Ok(())) => {}
            Some(Err(e)) => return Err(format!("send failed: {e}")),
            None => return Err("send failed".to_owned()),
        }
    }
    let sent_in = start.elapsed();
    let answered = counter.join().map_err(|_| "the counting thread failed")?;
    println!(
        "burst: {frames} frames sent in {:.1} ms ({:.0} frames/s), {answered} answered",
        sent_in.as_secs_f64() * 1e3,
        f64::from(frames) / sent_in.as_secs_f64()
    );
    let expected = usize::try_from(frames).unwrap_or(usize::MAX);
    if answered == expected {
        Ok(())
    } else {
        Err(format!(
            "{} of {frames} frames not answered",
            expected.saturating_sub(answered)
        ))
    }
}

/// Sleeps until the next 1 ms cycle after `next` and moves `next` on to it; a MainDevice more
/// than 10 ms behind starts its schedule again from now rather than sending a burst.
fn next_cycle(next: &mut std::time::Instant) {
    *next += Duration::from_millis(1);
    let now = std::time::Instant::now();
    if now > *next + Duration::from_millis(10) {
        *next = now;
    }
    if let Some(wait) = next.checked_duration_since(std::time::Instant::now()) {
        std::thread::sleep(wait);
    }
}
