//! Emulated EtherCAT SubDevices on a Linux network interface, for any MainDevice (ethercrab, SOEM,
//! IgH, TwinCAT in a VM) to drive: frames arrive on the interface, pass through a line of emulated
//! ESCs running the real ecat runners, and go back out.
//!
//! ```text
//! ecat-virtual-slave --iface IFNAME [--device NAME[,NAME...]] [--count N] [--pcap FILE]
//! ```
//!
//! `--device` lists the devices on the line in order; `--count` repeats that list. Needs root or
//! `CAP_NET_RAW`. Ctrl-C ends it cleanly.

use std::process::ExitCode;

use ecat_examples::bridge::{self, Options};
use ecat_examples::catalog;

const USAGE: &str =
    "usage: ecat-virtual-slave --iface IFNAME [--device NAME[,NAME...]] [--count N] [--pcap FILE]";

fn parse(mut args: impl Iterator<Item = String>) -> Result<Options, String> {
    let (mut iface, mut devices, mut count, mut pcap) = (None, None, 1usize, None);
    while let Some(flag) = args.next() {
        let mut value = || args.next().ok_or(format!("{flag} needs a value\n{USAGE}"));
        match flag.as_str() {
            "--iface" => iface = Some(value()?),
            "--device" => devices = Some(value()?),
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
    let devices = devices.unwrap_or_else(|| catalog::DEFAULT.to_owned());
    let line: Vec<String> = devices.split(',').map(str::to_owned).collect();
    let devices: Vec<String> = (0..count).flat_map(|_| line.iter().cloned()).collect();
    if devices.len() > catalog::MAX_COUNT {
        return Err(format!("at most {} devices on a line", catalog::MAX_COUNT));
    }
    Ok(Options {
        iface: iface.ok_or(format!("--iface is required\n{USAGE}"))?,
        devices,
        pcap,
    })
}

fn main() -> ExitCode {
    match parse(std::env::args().skip(1)).and_then(|options| bridge::serve(&options)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ecat-virtual-slave: {e}");
            ExitCode::from(2)
        }
    }
}
