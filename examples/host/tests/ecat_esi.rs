//! The `ecat-esi` program: the files it writes are the catalog device's description files, and
//! its errors name the problem.

use std::path::PathBuf;
use std::process::{Command, Output};

use ecat_examples::description;

fn ecat_esi(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ecat-esi"))
        .args(args)
        .output()
        .unwrap()
}

/// A fresh directory of this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ecat-esi-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn writes_the_xml_and_the_image_of_the_device() {
    let dir = scratch("ok");
    for device in ["cia402", "drive", "dio", "dio-update", "sensor"] {
        let out = ecat_esi(&["--device", device, "--out", dir.to_str().unwrap()]);
        assert!(out.status.success(), "{out:?}");
        let files = description::by_name(device).unwrap().unwrap();
        let xml = std::fs::read_to_string(dir.join(format!("{device}.xml"))).unwrap();
        let bin = std::fs::read(dir.join(format!("{device}.bin"))).unwrap();
        assert_eq!(xml, files.esi);
        assert_eq!(bin, files.sii);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn an_unknown_device_is_named_with_the_known_ones() {
    let dir = scratch("unknown");
    let out = ecat_esi(&["--device", "servo", "--out", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "ecat-esi: unknown device \"servo\"; known: cia402, drive, dio, dio-update, sensor\n"
    );
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "nothing written"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_missing_directory_is_an_error_with_the_path() {
    let parent = scratch("missing");
    let dir = parent.join("absent");
    let out = ecat_esi(&["--device", "dio", "--out", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8(out.stderr).unwrap();
    let expected = format!("ecat-esi: cannot write {}: ", dir.join("dio.xml").display());
    assert!(stderr.starts_with(&expected), "{stderr}");
    std::fs::remove_dir_all(parent).unwrap();
}

#[test]
fn missing_arguments_print_the_usage() {
    let out = ecat_esi(&["--device", "dio"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "ecat-esi: usage: ecat-esi --device cia402|drive|dio|dio-update|sensor --out DIR [--chip et1100|ax58100|lan9252]\n"
    );
}

/// `--chip` writes the image for a board with that ESC: its configuration area is the chip's
/// (the LAN9252's SPI is PDI type 0x80, no SPI mode in 0x0150), and the ESI's ConfigData with it.
#[test]
fn the_chip_option_writes_the_area_of_that_chip() {
    let dir = scratch("chip");
    let out = ecat_esi(&[
        "--device",
        "cia402",
        "--out",
        dir.to_str().unwrap(),
        "--chip",
        "lan9252",
    ]);
    assert!(out.status.success(), "{out:?}");
    let bin = std::fs::read(dir.join("cia402.bin")).unwrap();
    assert_eq!(
        bin[..4],
        [0x80, 0x04, 0x00, 0x06],
        "LAN9252 SPI, SYNC out, SYNC0 output"
    );
    let xml = std::fs::read_to_string(dir.join("cia402.xml")).unwrap();
    assert!(xml.contains("<ConfigData>8004000664"), "{xml}");
    let out = ecat_esi(&[
        "--device",
        "dio",
        "--out",
        dir.to_str().unwrap(),
        "--chip",
        "et1200",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "ecat-esi: unknown chip \"et1200\"; known: et1100, ax58100, lan9252\n"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
