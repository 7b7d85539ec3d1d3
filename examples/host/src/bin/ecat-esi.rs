//! Writes the description files of a catalog device: the ESI XML file (ETG.2000) for
//! configuration tools and the SII EEPROM image, generated from the same description.
//!
//! ```text
//! ecat-esi --device cia402|drive|dio|dio-update|sensor --out DIR [--chip et1100|ax58100|lan9252]
//! ```
//!
//! Writes `DIR/<device>.xml` and `DIR/<device>.bin`; `DIR` must exist. `--chip` names the ESC
//! of the board the EEPROM is for: the image's configuration area (PDI type, SPI mode, SYNC
//! unit) is that chip's. Without it: the ET1100 the catalog devices are emulated with.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use ecat_core::chip::Chip;
use ecat_examples::catalog;
use ecat_examples::description;

struct Args {
    device: String,
    out: PathBuf,
    chip: Option<Chip>,
}

fn usage() -> String {
    format!(
        "usage: ecat-esi --device {} --out DIR [--chip et1100|ax58100|lan9252]",
        catalog::NAMES.join("|")
    )
}

fn parse(mut args: impl Iterator<Item = String>) -> Result<Args, String> {
    let (mut device, mut out, mut chip) = (None, None, None);
    while let Some(flag) = args.next() {
        match flag.as_str() {
            "--device" => device = args.next(),
            "--out" => out = args.next().map(PathBuf::from),
            "--chip" => {
                let name = args.next().ok_or_else(usage)?;
                let known = Chip::by_name(&name).ok_or_else(|| {
                    format!("unknown chip {name:?}; known: et1100, ax58100, lan9252")
                })?;
                chip = Some(known);
            }
            _ => return Err(usage()),
        }
    }
    match (device, out) {
        (Some(device), Some(out)) => Ok(Args { device, out, chip }),
        _ => Err(usage()),
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn run(args: Args) -> Result<(), String> {
    let files = match args.chip {
        Some(chip) => description::on_chip(&args.device, chip),
        None => description::by_name(&args.device),
    }
    .ok_or_else(|| {
        format!(
            "unknown device {:?}; known: {}",
            args.device,
            catalog::NAMES.join(", ")
        )
    })?
    .map_err(|e| format!("cannot describe {}: {e:?}", args.device))?;
    let xml = args.out.join(format!("{}.xml", args.device));
    let bin = args.out.join(format!("{}.bin", args.device));
    write(&xml, files.esi.as_bytes())?;
    write(&bin, &files.sii)?;
    println!("wrote {} and {}", xml.display(), bin.display());
    Ok(())
}

fn main() -> ExitCode {
    match parse(std::env::args().skip(1)).and_then(run) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ecat-esi: {e}");
            ExitCode::FAILURE
        }
    }
}
