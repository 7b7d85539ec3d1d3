//! `sdo <case> <n>`: runs one SDO case `n` times through the core. Run under callgrind by
//! `bench/callgrind.sh`; the difference between n = 1001 and n = 1 divided by 1000 is the cost
//! of one case.
//!
//! Cases: `expedited-upload` (0x1018:01 with a 128-byte mailbox), `expedited-upload-pdo` (the
//! same from a dictionary with PDO and sync parameter objects), `upload-1k-128` and
//! `upload-1k-1024` (a 1 KiB string, segmented with 128-byte mailboxes, normal with 1024-byte),
//! `download-1k-128`, `download-1k-1024` (1 KiB into a DOMAIN streamed to the application).

use ecat_bench::{Bench, Od, Sink, device};
use ecat_core::dictionary::VisibleString;
use ecat_emu::devices::Drive;

fn upload(bench_case: &str, n: usize) {
    let big = bench_case.ends_with("1024");
    let config = device(if big { 1024 } else { 128 });
    let mut od = Od {
        text: VisibleString::new(&[b'x'; 1024]),
        ..Od::default()
    };
    if big {
        run::<1024>(&config, &mut od, bench_case, n);
    } else {
        run::<128>(&config, &mut od, bench_case, n);
    }
}

fn run<const MBX: usize>(config: &ecat_core::DeviceConfig, od: &mut Od, case: &str, n: usize) {
    let mut bench = Bench::<MBX>::new(config);
    let capacity = MBX - 6 - 2 - 1;
    for _ in 0..n {
        match case {
            "expedited-upload" => {
                assert_eq!(bench.exchange(od, &mut (), &UPLOAD_1018_01)[2], 0x43);
            }
            c if c.starts_with("upload-1k") => {
                let answer = bench.exchange(
                    od,
                    &mut (),
                    &[0x00, 0x20, 0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0],
                );
                assert_eq!(answer[2], 0x41);
                let mut received = answer.len() - 10;
                let mut toggle = 0u8;
                while received < 1024 {
                    let answer = bench.exchange(
                        od,
                        &mut (),
                        &[0x00, 0x20, 0x60 | toggle, 0, 0, 0, 0, 0, 0, 0],
                    );
                    received += answer.len() - 3;
                    toggle ^= 0x10;
                }
            }
            c if c.starts_with("download-1k") => {
                let data = [b'y'; 1024];
                let first = (MBX - 16).min(1024);
                let mut sink = Sink::default();
                let mut request = vec![0x00, 0x20, 0x21, 0x01, 0x20, 0x00, 0x00, 0x04, 0x00, 0x00];
                request.extend_from_slice(&data[..first]);
                assert_eq!(bench.exchange(od, &mut sink, &request)[2], 0x60);
                let mut sent = first;
                let mut toggle = 0u8;
                while sent < 1024 {
                    let k = (1024 - sent).min(capacity);
                    let last = u8::from(sent + k == 1024);
                    let mut segment = vec![0x00, 0x20, toggle | last];
                    segment.extend_from_slice(&data[sent..sent + k]);
                    assert_eq!(bench.exchange(od, &mut sink, &segment)[2], 0x20 | toggle);
                    sent += k;
                    toggle ^= 0x10;
                }
                assert_eq!(sink.bytes, 1024);
            }
            other => panic!("unknown case {other}"),
        }
    }
}

/// CoE header + SDO expedited upload request of 0x1018:01.
const UPLOAD_1018_01: [u8; 10] = [0x00, 0x20, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0];

/// `expedited-upload-pdo`: the same upload from the CiA402-like drive's dictionary, which has PDO
/// mapping, assignment and sync parameter objects (the SubDevice recomputes their layout only
/// when one is written).
fn upload_from_drive(n: usize) {
    let config = device(128);
    let mut bench = Bench::<128>::new(&config);
    let mut od = <Drive>::default();
    for _ in 0..n {
        assert_eq!(bench.exchange(&mut od, &mut (), &UPLOAD_1018_01)[2], 0x43);
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let case = args.next().unwrap_or_else(|| "expedited-upload".into());
    let n = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    if case == "sizes" {
        println!(
            "SubDevice<128>: {} bytes",
            core::mem::size_of::<ecat_core::SubDevice<'static, 128>>()
        );
        println!(
            "SubDevice<1024>: {} bytes",
            core::mem::size_of::<ecat_core::SubDevice<'static, 1024>>()
        );
        return;
    }
    if case == "expedited-upload-pdo" {
        return upload_from_drive(n);
    }
    upload(&case, n);
}
