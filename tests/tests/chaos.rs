//! A chaotic MainDevice against the real runners: random AL control values, SyncManager writes,
//! mailbox frames, outputs and time steps. The emulator's livelock detector and the harness's hang
//! guard turn any spin into a failure; after every step the SubDevice has answered: AL status
//! names a state, the error indication and the code agree.

mod common;

use common::od::{BlobApp, TestOd};
use common::{INPUTS, MAILBOX, OUTPUTS};
use ecat_core::{AlStatus, register};
use ecat_emu::harness::{self, Device, Loopback};
use ecat_emu::master::TestMaster;
use embassy_time::Duration;

/// A small deterministic generator (xorshift64*), so a failure replays exactly.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

async fn step(master: &TestMaster, rng: &mut Rng) {
    match rng.below(11) {
        10 => {
            // A well-behaved burst, so that chaos also starts from OP.
            common::configure(master);
            for control in [0x11, 0x12, 0x14] {
                master.request(control).await;
            }
            common::send_outputs(master).await;
            master.request(0x18).await;
        }
        0..=2 => {
            let states = [0x01, 0x02, 0x04, 0x08, 0x11, 0x12, 0x14, 0x18, 0x03, 0x0F];
            let value = if rng.below(4) == 0 {
                rng.next() as u16
            } else {
                states[rng.below(10) as usize]
            };
            master.write_al_control(value);
        }
        3 => common::configure(master),
        4 => {
            let n = rng.below(4) as u8;
            let bytes = rng.next().to_le_bytes();
            master.write(register::sync_manager(n), &bytes);
        }
        5 | 6 => {
            let mut frame = vec![0u8; usize::from(MAILBOX.receive.length)];
            let len = 8 + rng.below(20) as usize;
            for b in &mut frame[6..6 + len] {
                *b = rng.next() as u8;
            }
            frame[..6].copy_from_slice(&[
                len as u8,
                0,
                0,
                0,
                0,
                0x03 | ((rng.below(8) as u8) << 4),
            ]);
            frame[6..8].copy_from_slice(&[0x00, 0x20]);
            master.write(MAILBOX.receive.start, &frame);
            master.read(MAILBOX.send.start, usize::from(MAILBOX.send.length));
        }
        7 => {
            master.write(OUTPUTS.start, &rng.next().to_le_bytes());
            master.read(INPUTS.start, usize::from(INPUTS.length));
        }
        _ => master.advance(Duration::from_millis(rng.below(300))).await,
    }
    master.settle().await;
}

fn check(master: &TestMaster, seed: u64, n: usize) {
    let raw = master.al_status();
    let status = AlStatus::from_bits(raw)
        .unwrap_or_else(|| panic!("seed {seed} step {n}: AL status {raw:#06x} names no state"));
    let code = master.al_status_code();
    if status.error {
        assert_ne!(
            code, 0,
            "seed {seed} step {n}: error indication without a code"
        );
    } else if !status.id_loaded {
        assert_eq!(
            code, 0,
            "seed {seed} step {n}: a code without the error indication"
        );
    }
}

#[test]
fn a_chaotic_main_device_never_breaks_the_runners() {
    for seed in 1..=6u64 {
        let device = Device::new(common::drive(), BlobApp::default(), Loopback)
            .with_dictionary(TestOd::default());
        harness::run(device, move |master| async move {
            let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
            for n in 0..400 {
                step(&master, &mut rng).await;
                check(&master, seed, n);
            }
        });
    }
}
