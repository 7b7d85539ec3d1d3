//! The SyncManager rules that keep a mailbox message moved in chunks correct (issue #21, point 1:
//! `SharedEsc` moves state-machine accesses in chunks, with process-data accesses between them),
//! on the PDI side of the emulated ESC: SM0's buffer is released only when the PDI reads its last
//! byte, SM1's is marked full only when the PDI writes its last byte (ESC datasheet section I,
//! "SyncManager", mailbox mode), whatever other areas the PDI accesses in between.

use ecat_core::AlEvent;
use ecat_core::register::sync_manager;
use ecat_emu::esc::{Esc, EscConfig};

const SM0: u16 = 0x1000;
const SM1: u16 = 0x1080;
const SM2: u16 = 0x1100;
const LEN: u16 = 128;
const CHUNK: u16 = 32;

fn configured() -> Esc {
    let mut esc = Esc::new(EscConfig::default());
    for (n, start, length, control) in [(0, SM0, LEN, 0x26), (1, SM1, LEN, 0x22), (2, SM2, 4, 0x24)]
    {
        let [s0, s1] = start.to_le_bytes();
        let [l0, l1] = length.to_le_bytes();
        assert!(esc.ecat_write(sync_manager(n), &[s0, s1, l0, l1, control, 0, 1]));
        esc.pdi_read(sync_manager(n) + 6, &mut [0]);
    }
    assert_eq!(esc.al_event(), AlEvent::NONE);
    esc
}

fn pattern(seed: u8, len: u16) -> Vec<u8> {
    (0..len).map(|i| seed.wrapping_add(i as u8)).collect()
}

/// A process-data cycle between two chunks: the MainDevice writes SM2, the PDI reads it.
fn cycle_between(esc: &mut Esc) {
    assert!(esc.ecat_write(SM2, &[1, 2, 3, 4]));
    let mut outputs = [0; 4];
    esc.pdi_read(SM2, &mut outputs);
    assert_eq!(outputs, [1, 2, 3, 4]);
}

#[test]
fn a_receive_mailbox_read_in_chunks_is_released_by_its_last_chunk() {
    let mut esc = configured();
    let request = pattern(7, LEN);
    assert!(esc.ecat_write(SM0, &request));
    let mut read = Vec::new();
    for offset in (0..LEN).step_by(usize::from(CHUNK)) {
        let mut chunk = vec![0; usize::from(CHUNK)];
        esc.pdi_read(SM0 + offset, &mut chunk);
        read.extend_from_slice(&chunk);
        // The first chunk read the first byte: the SM0 event is gone.
        assert!(!esc.al_event().intersects(AlEvent::sync_manager(0)));
        let last = offset + CHUNK == LEN;
        assert_eq!(
            esc.ecat_write(SM0, &pattern(9, LEN)),
            last,
            "the MainDevice may write the next request only after the last chunk (offset {offset})"
        );
        if !last {
            cycle_between(&mut esc);
        }
    }
    assert_eq!(read, request);
}

#[test]
fn a_send_mailbox_written_in_chunks_is_full_after_its_last_chunk() {
    let mut esc = configured();
    let answer = pattern(3, LEN);
    for offset in (0..LEN).step_by(usize::from(CHUNK)) {
        let chunk = &answer[usize::from(offset)..usize::from(offset + CHUNK)];
        esc.pdi_write(SM1 + offset, chunk);
        if offset + CHUNK == LEN {
            break;
        }
        let mut probe = [0; 1];
        assert!(
            !esc.ecat_read(SM1 + LEN - 1, &mut probe),
            "the MainDevice's read of SM1 is refused until the last chunk (offset {offset})"
        );
        assert!(!esc.al_event().intersects(AlEvent::sync_manager(1)));
        cycle_between(&mut esc);
    }
    let mut read = vec![0; usize::from(LEN)];
    assert!(esc.ecat_read(SM1, &mut read), "full after the last chunk");
    assert_eq!(read, answer);
}
