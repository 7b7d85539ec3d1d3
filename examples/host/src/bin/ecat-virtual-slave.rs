//! Emulated EtherCAT SubDevices on a Linux network interface, for any MainDevice (ethercrab, SOEM,
//! IgH, TwinCAT in a VM) to drive: frames arrive on the interface, pass through a line of emulated
//! ESCs running the real ecat runners, and go back out.
//!
//! ```text
//! ecat-virtual-slave --iface IFNAME [--device NAME[,NAME...]] [--count N] [--pcap FILE] [--la-requests] [--out IF2] [--chained]
//! ```
//!
//! `--device` lists the devices on the line in order; `--count` repeats that list. `--out` makes
//! the line a segment of a longer one: frames leave the last ESC through IF2 to the next segment
//! (another instance, started with `--chained`) and come back through it. Needs root or
//! `CAP_NET_RAW`. Ctrl-C, SIGTERM and SIGHUP end it cleanly. Exit status: 0 after a clean stop,
//! 1 when the interface or the capture file fails, 2 for a wrong command line.

use std::process::ExitCode;

use ecat_examples::bridge::{self, Options};
use ecat_examples::catalog;

const USAGE: &str =
    "usage: ecat-virtual-slave --iface IFNAME [--device NAME[,NAME...]] [--count N] \
[--pcap FILE] [--la-requests] [--out IF2]

Serves emulated EtherCAT SubDevices on a network interface (needs root or CAP_NET_RAW).

  --iface IFNAME     the interface the MainDevice's frames arrive on
  --device NAMES     the devices on the line, in cable order (default: dio)
  --count N          repeats the --device list N times
  --pcap FILE        writes every frame in and out to a capture file
  --la-requests      also serve frames whose source MAC has the locally-administered bit set
                     (a MainDevice on an interface with such a MAC, e.g. IgH on a veth); by
                     default they are answers of a line, as ESCs mark them, and pass unserved
  --out IF2          port 1 of the last ESC: frames leave the line through IF2 to the next
                     segment (an instance with --chained on the other end) and come back
                     through it, then go out of IFNAME; without it port 1 has no link and the
                     last ESC loops frames back
  --chained          IFNAME is linked to the --out interface of the previous segment, not to
                     a MainDevice: every EtherCAT frame on it is served
  -h, --help         prints this help

Ctrl-C, SIGTERM or SIGHUP stop it cleanly (summary printed, capture file complete).";

/// What the command line asks for.
enum Command {
    Help,
    Serve(Options),
}

fn parse(mut args: impl Iterator<Item = String>) -> Result<Command, String> {
    let (mut iface, mut devices, mut count, mut pcap) = (None, None, 1usize, None);
    let (mut la_requests, mut out, mut chained) = (false, None, false);
    let short = USAGE.lines().next().unwrap_or(USAGE);
    while let Some(flag) = args.next() {
        let mut value = || args.next().ok_or(format!("{flag} needs a value\n{short}"));
        match flag.as_str() {
            "--iface" => iface = Some(value()?),
            "--device" => devices = Some(value()?),
            "--count" => {
                count = value()?
                    .parse()
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or("--count takes a number of at least 1")?
            }
            "--pcap" => pcap = Some(value()?),
            "--la-requests" => la_requests = true,
            "--out" => out = Some(value()?),
            "--chained" => chained = true,
            "-h" | "--help" => return Ok(Command::Help),
            other => return Err(format!("unknown argument {other:?}\n{short}")),
        }
    }
    let devices = devices.unwrap_or_else(|| catalog::DEFAULT.to_owned());
    let line: Vec<String> = devices.split(',').map(str::to_owned).collect();
    let total = line.len().saturating_mul(count);
    if total > catalog::MAX_COUNT {
        return Err(format!(
            "{total} SubDevices ({} named × --count {count}): a line holds at most {} ({})",
            line.len(),
            catalog::MAX_COUNT,
            catalog::MAX_COUNT_REASON
        ));
    }
    let devices: Vec<String> = (0..count).flat_map(|_| line.iter().cloned()).collect();
    let iface = iface.ok_or(format!("--iface is required\n{short}"))?;
    if out.as_ref() == Some(&iface) {
        return Err(format!(
            "--out {iface} is the interface the line serves: port 1 leads to the next segment"
        ));
    }
    Ok(Command::Serve(Options {
        iface,
        devices,
        pcap,
        la_requests,
        chained,
        out,
    }))
}

fn main() -> ExitCode {
    let options = match parse(std::env::args().skip(1)) {
        Ok(Command::Help) => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Ok(Command::Serve(options)) => options,
        Err(e) => {
            eprintln!("ecat-virtual-slave: {e}");
            return ExitCode::from(2);
        }
    };
    match bridge::serve(&options) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ecat-virtual-slave: {e}");
            ExitCode::FAILURE
        }
    }
}
