//! The fuzz target of the FoE parser and server ([`ecat_emu::fuzz_foe::foe`]) on the stable
//! toolchain: a whole write and read as a seed, and random byte strings. A panic here is a bug in
//! the core (or a broken rule of the target).

use ecat_emu::fuzz_foe::foe;
use proptest::prelude::*;

/// One step of the target's input: BOOT, a 64-byte mailbox, the frame.
fn step(frame: &[u8]) -> Vec<u8> {
    let mut s = vec![3, 64, frame.len() as u8];
    s.extend(frame);
    s
}

fn frame(opcode: u8, value: u32, data: &[u8]) -> Vec<u8> {
    let mut f = vec![opcode, 0];
    f.extend(value.to_le_bytes());
    f.extend(data);
    f
}

/// A write of 70 bytes in two segments (58, 12; packet 2 repeated, once answered busy), then a
/// read of the 300-byte file: the paths the target exists for, run clean.
#[test]
fn a_write_and_a_read_run_clean() {
    let mut input = step(&frame(2, 0, b"a"));
    for (packet, data) in [(1, &[7u8; 58][..]), (2, &[8; 12]), (2, &[8; 12])] {
        input.extend(step(&frame(3, packet, data)));
    }
    input.extend(step(&frame(1, 0, b"a")));
    for packet in 1..=6 {
        input.extend(step(&frame(4, packet, &[])));
    }
    foe(&input);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_bytes_run_clean(data in proptest::collection::vec(any::<u8>(), 0..600)) {
        foe(&data);
    }

    /// Frames that start like FoE frames (opcode 1..=6, the name `a`, small packet numbers), so
    /// the random steps reach the transfers.
    #[test]
    fn random_frames_run_clean(
        steps in proptest::collection::vec(
            (0u8..=0x83, 6u8..=80, 1u8..=6, 0u32..4, proptest::collection::vec(any::<u8>(), 0..80)),
            0..40,
        )
    ) {
        let mut input = Vec::new();
        for (state, size, opcode, value, data) in steps {
            let name: &[u8] = if opcode <= 2 { b"a" } else { &data };
            let f = frame(opcode, value, name);
            input.extend([state, size, f.len().min(255) as u8]);
            input.extend(&f[..f.len().min(255)]);
        }
        foe(&input);
    }
}
