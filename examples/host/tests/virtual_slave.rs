//! The virtual slave's command line: help, limits and exit status (no raw socket needed).

use std::process::Command;

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ecat-virtual-slave"))
        .args(args)
        .output()
        .expect("ecat-virtual-slave runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn help_is_usage_on_stdout_and_success() {
    for flag in ["--help", "-h"] {
        let (code, stdout, stderr) = run(&[flag]);
        assert_eq!(code, Some(0), "{flag}");
        assert!(
            stdout.starts_with("usage: ecat-virtual-slave --iface IFNAME"),
            "{stdout}"
        );
        assert!(stdout.contains("--la-requests"), "{stdout}");
        assert_eq!(stderr, "");
    }
}

#[test]
fn a_wrong_command_line_is_status_2_with_the_usage() {
    let (code, stdout, stderr) = run(&["--bogus"]);
    assert_eq!((code, stdout.as_str()), (Some(2), ""));
    assert!(
        stderr.starts_with("ecat-virtual-slave: unknown argument \"--bogus\"\nusage:"),
        "{stderr}"
    );
}

/// The limit is the product of the list and --count, and the message names the real limit.
#[test]
fn a_line_longer_than_256_subdevices_is_refused_with_the_reason() {
    let (code, _, stderr) = run(&["--iface", "lo", "--device", "dio,sensor", "--count", "129"]);
    assert_eq!(code, Some(2));
    assert_eq!(
        stderr,
        "ecat-virtual-slave: 258 SubDevices (2 named × --count 129): a line holds at most 256 (a \
         frame passes every ESC of the line in one thread; chain instances with --out for more)\n"
    );
}

/// Port 1 of the last ESC leads to the next segment: it cannot be the interface the line
/// serves (frames would come back as requests).
#[test]
fn out_on_the_served_interface_is_refused() {
    let (code, _, stderr) = run(&["--iface", "lo", "--out", "lo"]);
    assert_eq!(code, Some(2));
    assert_eq!(
        stderr,
        "ecat-virtual-slave: --out lo is the interface the line serves: port 1 leads to the next \
         segment\n"
    );
}

/// A failure at run time (here: no such interface) is status 1, not 0 and not the usage's 2.
#[test]
fn a_missing_interface_is_status_1() {
    let (code, _, stderr) = run(&["--iface", "no-such-if0"]);
    assert_eq!(code, Some(1));
    assert!(
        stderr.starts_with("ecat-virtual-slave: no network interface named \"no-such-if0\""),
        "{stderr}"
    );
}
