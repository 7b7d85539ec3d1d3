//! Writes an update file for a firmware update by FoE (`ecat_emu::update`): a 12-byte header
//! (magic `ECFW`, the image's length and CRC-32, little-endian), then the image.
//!
//! ```text
//! ecat-firmware --version N [--size BYTES] --out FILE
//! ecat-firmware --image BIN --out FILE
//! ```
//!
//! `--version` makes an image for the virtual slave's updatable devices (the axis `cia402`,
//! `dio-update`): `BYTES` long (default 65 536), starting with `N` (u32, little-endian), which
//! the device reports as its revision once it runs the image. `--image` wraps a firmware binary
//! instead, e.g. `llvm-objcopy -O binary` of examples/stm32's `bootloader` build. An image is at
//! most the ACTIVE partition's size. Exit status: 0 when the file is written, 1 when a file
//! cannot be read or written or the image is too large, 2 for a wrong command line.

use std::process::ExitCode;

use ecat_emu::flash::layout;
use ecat_emu::update::{self, Header};

const USAGE: &str = "usage: ecat-firmware (--version N [--size BYTES] | --image BIN) --out FILE";

/// The image of a `--version` file when `--size` does not say.
const DEFAULT_SIZE: usize = 65_536;

/// Where the image comes from.
enum Source {
    /// A host image reporting this version, this long.
    Version(u32, usize),
    /// A firmware binary.
    Binary(String),
}

fn parse(mut args: impl Iterator<Item = String>) -> Result<(Source, String), String> {
    let (mut version, mut size, mut image, mut out) = (None, None, None, None);
    while let Some(flag) = args.next() {
        let value = args.next().ok_or(USAGE)?;
        let number = |what: &str| {
            value
                .parse::<u32>()
                .map_err(|_| format!("{flag} takes a number, not {value:?} ({what})"))
        };
        match flag.as_str() {
            "--version" => version = Some(number("the image's version")?),
            "--size" => size = Some(number("the image's length in bytes")? as usize),
            "--image" => image = Some(value),
            "--out" => out = Some(value),
            _ => return Err(USAGE.to_owned()),
        }
    }
    let source = match (version, image, size) {
        (Some(version), None, size) => {
            let size = size.unwrap_or(DEFAULT_SIZE);
            if !(4..=layout::ACTIVE.len()).contains(&size) {
                return Err(format!(
                    "--size {size}: an image takes 4 to {} bytes (the ACTIVE partition)",
                    layout::ACTIVE.len()
                ));
            }
            Source::Version(version, size)
        }
        (None, Some(path), None) => Source::Binary(path),
        _ => return Err(USAGE.to_owned()),
    };
    Ok((source, out.ok_or(USAGE)?))
}

fn run(source: Source, out: &str) -> Result<String, String> {
    let (image, what) = match source {
        Source::Version(version, size) => {
            (update::image(version, size), format!("version {version}"))
        }
        Source::Binary(path) => {
            let image = std::fs::read(&path).map_err(|e| format!("cannot read {path}: {e}"))?;
            if image.len() > layout::ACTIVE.len() {
                return Err(format!(
                    "{path}: {} bytes, the ACTIVE partition holds {}",
                    image.len(),
                    layout::ACTIVE.len()
                ));
            }
            (image, path)
        }
    };
    let file = update::file(&image);
    std::fs::write(out, &file).map_err(|e| format!("cannot write {out}: {e}"))?;
    let header = Header::of(&image);
    Ok(format!(
        "{out}: {} bytes, the update file of an image of {} bytes ({what}), CRC-32 {:#010x}",
        file.len(),
        header.length,
        header.crc
    ))
}

fn main() -> ExitCode {
    let (source, out) = match parse(std::env::args().skip(1)) {
        Ok(parsed) => parsed,
        Err(e) => {
            eprintln!("ecat-firmware: {e}");
            return ExitCode::from(2);
        }
    };
    match run(source, &out) {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("ecat-firmware: {e}");
            ExitCode::FAILURE
        }
    }
}
