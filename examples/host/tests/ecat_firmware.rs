//! The `ecat-firmware` program: the update file it writes is `ecat_emu::update`'s, byte for
//! byte, and a wrong command line or image is refused with the reason.

use std::path::PathBuf;
use std::process::{Command, Output};

use ecat_emu::update::{self, Header};

fn ecat_firmware(args: &[&str]) -> Output {
    let program = env!("CARGO_BIN_EXE_ecat-firmware");
    Command::new(program).args(args).output().unwrap()
}

/// A path in the temporary directory, unique to this test process.
fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("ecat-firmware-{}-{name}", std::process::id()))
}

#[test]
fn a_version_makes_the_host_image_in_an_update_file() {
    let out = scratch("v2.ecfw");
    let path = out.to_str().unwrap();
    let run = ecat_firmware(&["--version", "2", "--size", "5000", "--out", path]);
    assert!(run.status.success(), "{run:?}");
    let file = std::fs::read(&out).unwrap();
    let image = update::image(2, 5000);
    assert_eq!(file, update::file(&image));
    assert_eq!(&file[..4], b"ECFW");
    assert_eq!(file[Header::SIZE..Header::SIZE + 4], 2u32.to_le_bytes());
    let crc = Header::of(&image).crc;
    assert_eq!(
        String::from_utf8(run.stdout).unwrap(),
        format!(
            "{}: 5012 bytes, the update file of an image of 5000 bytes (version 2), CRC-32 {crc:#010x}\n",
            out.display()
        )
    );
    std::fs::remove_file(out).unwrap();
}

#[test]
fn an_image_is_wrapped_as_it_is() {
    let (bin, out) = (scratch("firmware.bin"), scratch("firmware.ecfw"));
    let binary: Vec<u8> = (0..3000u32).map(|n| (n * 7) as u8).collect();
    std::fs::write(&bin, &binary).unwrap();
    let run = ecat_firmware(&[
        "--image",
        bin.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{run:?}");
    assert_eq!(std::fs::read(&out).unwrap(), update::file(&binary));
    std::fs::remove_file(bin).unwrap();
    std::fs::remove_file(out).unwrap();
}

#[test]
fn a_wrong_command_line_is_status_2_with_the_reason() {
    let usage = "ecat-firmware: usage: ecat-firmware (--version N [--size BYTES] | --image BIN) --out FILE\n";
    for (args, stderr) in [
        (&["--version", "2"][..], usage.to_owned()),
        (&["--version", "2", "--image", "a.bin", "--out", "x"][..], usage.to_owned()),
        (&["--version", "two", "--out", "x"][..], "ecat-firmware: --version takes a number, not \"two\" (the image's version)\n".to_owned()),
        (
            &["--version", "2", "--size", "245761", "--out", "x"][..],
            "ecat-firmware: --size 245761: an image takes 4 to 245760 bytes (the ACTIVE partition)\n".to_owned(),
        ),
    ] {
        let run = ecat_firmware(args);
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        assert_eq!(String::from_utf8(run.stderr).unwrap(), stderr, "{args:?}");
    }
}

#[test]
fn an_image_larger_than_active_is_status_1() {
    let (bin, out) = (scratch("large.bin"), scratch("large.ecfw"));
    std::fs::write(&bin, vec![0; 245_761]).unwrap();
    let run = ecat_firmware(&[
        "--image",
        bin.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert_eq!(
        String::from_utf8(run.stderr).unwrap(),
        format!(
            "ecat-firmware: {}: 245761 bytes, the ACTIVE partition holds 245760\n",
            bin.display()
        )
    );
    assert!(!out.exists(), "nothing written");
    std::fs::remove_file(bin).unwrap();
}
