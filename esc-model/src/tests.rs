//! Byte-exact tests of the emulated ESC against the register and SyncManager rules.

use alloc::vec;
use alloc::vec::Vec;

use ecat_core::AlEvent;
use ecat_core::chip::{Chip, ConfigArea};
use ecat_core::register::{self, sync_manager};

use super::{Esc, EscConfig, PdiStats};

/// Receive mailbox: MainDevice writes, PDI event (typical SM0 control byte).
const MAILBOX_OUT: u8 = 0x26;
/// Send mailbox: PDI writes, PDI event (typical SM1 control byte).
const MAILBOX_IN: u8 = 0x22;
/// Outputs: 3-buffer, MainDevice writes, PDI event.
const BUFFERED_OUT: u8 = 0x24;
/// Inputs: 3-buffer, PDI writes, PDI event.
const BUFFERED_IN: u8 = 0x20;
/// SM0 area.
const SM0: u16 = 0x1000;
/// SM1 area.
const SM1: u16 = 0x1080;
/// Mailbox length.
const MBX_LEN: u16 = 128;
/// SM2 area.
const SM2: u16 = 0x1100;
/// SM3 area.
const SM3: u16 = 0x1180;
/// Process-data length.
const PD_LEN: u16 = 4;
/// Filler of read buffers, to see bytes the ESC did not touch.
const UNTOUCHED: u8 = 0xEE;

/// Status byte bits.
const WRITE_EVENT: u8 = 1 << 0;
const READ_EVENT: u8 = 1 << 1;
const FULL: u8 = 1 << 3;

fn esc() -> Esc {
    Esc::new(EscConfig::default())
}

/// Configures and enables SyncManager `n` the way a MainDevice does: one write of the 7 bytes
/// start..activate.
fn enable(esc: &mut Esc, n: u8, start: u16, length: u16, control: u8) {
    let [s0, s1] = start.to_le_bytes();
    let [l0, l1] = length.to_le_bytes();
    assert!(esc.ecat_write(sync_manager(n), &[s0, s1, l0, l1, control, 0, 1]));
}

/// The standard test layout: mailboxes on SM0/SM1, process data on SM2/SM3.
fn configured() -> Esc {
    let mut esc = esc();
    enable(&mut esc, 0, SM0, MBX_LEN, MAILBOX_OUT);
    enable(&mut esc, 1, SM1, MBX_LEN, MAILBOX_IN);
    enable(&mut esc, 2, SM2, PD_LEN, BUFFERED_OUT);
    enable(&mut esc, 3, SM3, PD_LEN, BUFFERED_IN);
    for n in 0..4 {
        pdi_read(&mut esc, sync_manager(n) + 6, 1);
    }
    assert_eq!(esc.al_event(), AlEvent::NONE);
    esc
}

fn ecat_read(esc: &mut Esc, address: u16, len: usize) -> (bool, Vec<u8>) {
    let mut buf = vec![UNTOUCHED; len];
    let served = esc.ecat_read(address, &mut buf);
    (served, buf)
}

fn ecat_bytes(esc: &mut Esc, address: u16, len: usize) -> Vec<u8> {
    let (served, buf) = ecat_read(esc, address, len);
    assert!(served, "ECAT read at {address:#06x} refused");
    buf
}

fn pdi_read(esc: &mut Esc, address: u16, len: usize) -> Vec<u8> {
    let mut buf = vec![UNTOUCHED; len];
    esc.pdi_read(address, &mut buf);
    buf
}

fn status(esc: &mut Esc, n: u8) -> u8 {
    ecat_bytes(esc, sync_manager(n) + 5, 1)[0]
}

fn pattern(seed: u8, len: u16) -> Vec<u8> {
    (0..len).map(|i| seed.wrapping_add(i as u8)).collect()
}

// ---- register file ----

#[test]
fn dl_information_reflects_the_configuration() {
    let mut esc = Esc::new(EscConfig {
        sync_managers: 4,
        fmmus: 3,
        process_ram_end: 0x2000,
        esc_type: 0x42,
        dc_supported: true,
        ..EscConfig::default()
    });
    // Revision, port descriptor (ports 0 and 1 MII) and features from the chip (ET1100: 0x01FC).
    let info = [0x42, 0, 0, 0, 3, 4, 4, 0x0F, 0xFC, 0x01];
    assert_eq!(ecat_bytes(&mut esc, register::DL_INFORMATION, 10), info);
    assert_eq!(ecat_bytes(&mut esc, register::DL_STATUS, 2), [0x11, 0x02]);
    assert_eq!(ecat_bytes(&mut esc, register::PDI_CONTROL, 1), [0x05]);
    let mask = ecat_bytes(&mut esc, register::AL_EVENT_MASK, 4);
    assert_eq!(mask, [0x0F, 0xFF, 0xFF, 0x00]);
    let watchdogs = [0xC2, 0x09, 0xE8, 0x03, 0xE8, 0x03];
    for (address, expected) in [
        register::WATCHDOG_DIVIDER,
        register::WATCHDOG_TIME_PDI,
        register::WATCHDOG_TIME_PROCESS_DATA,
    ]
    .into_iter()
    .zip(watchdogs.chunks(2))
    {
        assert_eq!(pdi_read(&mut esc, address, 2), expected);
    }
    esc.ecat_write(register::DL_INFORMATION, &[0xFF; 10]);
    esc.pdi_write(register::DL_INFORMATION, &[0xFF; 10]);
    assert_eq!(pdi_read(&mut esc, register::DL_INFORMATION, 10), info);
    assert_eq!(pdi_read(&mut esc, register::FEATURES, 2), [0xFC, 0x01]);
}

#[test]
fn al_control_write_raises_event_until_the_pdi_reads_it() {
    let mut esc = esc();
    assert!(esc.ecat_write(register::AL_CONTROL + 1, &[0]));
    assert_eq!(esc.al_event(), AlEvent::AL_CONTROL);
    esc.pdi_read(register::AL_CONTROL, &mut [0; 1]);
    assert_eq!(esc.al_event(), AlEvent::NONE);

    assert!(esc.ecat_write(register::AL_CONTROL, &[0x02, 0]));
    ecat_bytes(&mut esc, register::AL_CONTROL, 2);
    pdi_read(&mut esc, register::AL_CONTROL + 1, 1);
    assert_eq!(
        esc.al_event(),
        AlEvent::AL_CONTROL,
        "only a PDI read of 0x0120 clears"
    );
    let mut control = [0; 2];
    let sampled = esc.pdi_read(register::AL_CONTROL, &mut control);
    assert_eq!(control, [0x02, 0]);
    assert_eq!(sampled, AlEvent::AL_CONTROL, "sampled before the access");
    assert_eq!(esc.al_event(), AlEvent::NONE);
    assert_eq!(
        esc.pdi_read(register::AL_CONTROL, &mut control),
        AlEvent::NONE
    );
}

#[test]
fn al_status_is_written_by_the_pdi_and_al_control_by_the_main_device() {
    let mut esc = esc();
    assert!(esc.ecat_write(register::AL_STATUS, &[0x08, 0]));
    assert!(esc.ecat_write(register::AL_STATUS_CODE, &[0x11, 0]));
    assert_eq!(
        pdi_read(&mut esc, register::AL_STATUS, 6),
        [0x01, 0, 0, 0, 0, 0],
        "INIT, the reset value"
    );
    esc.pdi_write(register::AL_STATUS, &[0x12, 0]);
    esc.pdi_write(register::AL_STATUS_CODE, &[0x1D, 0]);
    assert_eq!(
        ecat_bytes(&mut esc, register::AL_STATUS, 6),
        [0x12, 0, 0, 0, 0x1D, 0]
    );
    esc.pdi_write(register::AL_CONTROL, &[0x04, 0]);
    assert_eq!(ecat_bytes(&mut esc, register::AL_CONTROL, 2), [0, 0]);
    assert_eq!(esc.al_event(), AlEvent::NONE);
}

#[test]
fn station_address_and_alias_belong_to_opposite_ports() {
    let mut esc = esc();
    esc.pdi_write(register::STATION_ADDRESS, &[0x34, 0x12, 0x78, 0x56]);
    assert!(esc.ecat_write(register::STATION_ADDRESS, &[0x01, 0x10, 0xFF, 0xFF]));
    assert_eq!(
        pdi_read(&mut esc, register::STATION_ADDRESS, 4),
        [0x01, 0x10, 0x78, 0x56]
    );
}

#[test]
fn fmmus_are_written_by_the_main_device_only() {
    let mut esc = esc();
    let last = register::fmmu(7);
    esc.pdi_write(last, &[0xAA; 16]);
    assert!(
        esc.ecat_write(last, &[0x55; 32]),
        "FMMU 8 does not exist: ignored"
    );
    assert_eq!(pdi_read(&mut esc, last, 32), [[0x55; 16], [0; 16]].concat());
}

#[test]
fn irq_is_event_and_mask() {
    let mut esc = esc();
    esc.pdi_write(register::AL_EVENT_MASK, &[0; 4]);
    esc.ecat_write(register::AL_CONTROL, &[0x02, 0]);
    assert_eq!(esc.al_event(), AlEvent::AL_CONTROL);
    assert!(!esc.irq(), "masked");
    esc.pdi_write(
        register::AL_EVENT_MASK,
        &AlEvent::SM_CHANGE.bits().to_le_bytes(),
    );
    assert!(!esc.irq(), "another bit unmasked");
    esc.pdi_write(
        register::AL_EVENT_MASK,
        &AlEvent::AL_CONTROL.bits().to_le_bytes(),
    );
    assert!(esc.irq());
    assert!(esc.ecat_write(register::AL_EVENT_MASK, &[0; 4]));
    assert!(esc.irq(), "the MainDevice cannot write the mask");
    pdi_read(&mut esc, register::AL_CONTROL, 2);
    assert!(!esc.irq(), "event cleared");
}

#[test]
fn sm_change_stays_until_every_changed_activate_byte_is_read() {
    let mut esc = esc();
    assert!(esc.ecat_write(sync_manager(0) + 6, &[0]));
    assert!(esc.ecat_write(sync_manager(1) + 6, &[0]));
    assert_eq!(esc.al_event(), AlEvent::SM_CHANGE);
    ecat_bytes(&mut esc, sync_manager(0), 16);
    pdi_read(&mut esc, sync_manager(0), 6);
    pdi_read(&mut esc, sync_manager(0) + 7, 6);
    assert_eq!(
        esc.al_event(),
        AlEvent::SM_CHANGE,
        "neighbours of the activate bytes"
    );
    pdi_read(&mut esc, sync_manager(0) + 6, 1);
    assert_eq!(esc.al_event(), AlEvent::SM_CHANGE, "SM1 still changed");
    pdi_read(&mut esc, sync_manager(1) + 6, 1);
    assert_eq!(esc.al_event(), AlEvent::NONE);
}

#[test]
fn sm_configuration_is_frozen_for_the_main_device_while_enabled() {
    let mut esc = esc();
    enable(&mut esc, 0, SM0, MBX_LEN, MAILBOX_OUT);
    let registers = [0x00, 0x10, 0x80, 0x00, MAILBOX_OUT, 0, 1, 0];
    assert!(esc.ecat_write(sync_manager(0), &[0x00, 0x18, 0x10, 0x00, 0x20]));
    assert_eq!(ecat_bytes(&mut esc, sync_manager(0), 8), registers);
    assert!(
        esc.ecat_write(sync_manager(0) + 6, &[0]),
        "activate stays writable"
    );
    assert!(esc.ecat_write(sync_manager(0), &[0x00, 0x18, 0x10, 0x00, 0x20]));
    assert_eq!(
        ecat_bytes(&mut esc, sync_manager(0), 5),
        [0x00, 0x18, 0x10, 0x00, 0x20]
    );
}

#[test]
fn pdi_control_is_written_by_the_pdi_only() {
    let mut esc = esc();
    assert!(esc.ecat_write(
        sync_manager(0),
        &[0x00, 0x10, 0x80, 0, MAILBOX_OUT, 0xFF, 0, 0x01]
    ));
    assert_eq!(pdi_read(&mut esc, sync_manager(0) + 5, 3), [0, 0, 0]);
    esc.pdi_write(sync_manager(0), &[0xFF; 8]);
    let expected = [0x00, 0x10, 0x80, 0, MAILBOX_OUT, 0, 0, 0xFF];
    assert_eq!(ecat_bytes(&mut esc, sync_manager(0), 8), expected);
}

// ---- mailbox ----

#[test]
fn mailbox_is_full_when_its_last_byte_is_written() {
    let mut esc = configured();
    assert!(esc.ecat_write(SM0, &pattern(1, MBX_LEN - 1)));
    assert_eq!(status(&mut esc, 0) & FULL, 0);
    assert_eq!(esc.al_event(), AlEvent::NONE);
    assert!(esc.ecat_write(SM0 + MBX_LEN - 1, &[0x77]));
    assert_eq!(status(&mut esc, 0), FULL | WRITE_EVENT);
    assert_eq!(esc.al_event(), AlEvent::sync_manager(0));
    let mut expected = pattern(1, MBX_LEN - 1);
    expected.push(0x77);
    assert_eq!(pdi_read(&mut esc, SM0, usize::from(MBX_LEN)), expected);
}

#[test]
fn mailbox_refuses_writes_while_full() {
    let mut esc = configured();
    assert!(esc.ecat_write(SM0, &pattern(1, MBX_LEN)));
    assert!(!esc.ecat_write(SM0, &pattern(9, MBX_LEN)));
    assert!(!esc.ecat_write(SM0 + 5, &[0]));
    assert_eq!(
        pdi_read(&mut esc, SM0, usize::from(MBX_LEN)),
        pattern(1, MBX_LEN)
    );
    assert!(
        esc.ecat_write(SM0, &pattern(9, MBX_LEN)),
        "emptied by the PDI"
    );
}

#[test]
fn mailbox_refuses_reads_while_empty_and_is_emptied_by_its_last_byte() {
    let mut esc = configured();
    let (served, buf) = ecat_read(&mut esc, SM1, usize::from(MBX_LEN));
    assert!(!served);
    assert_eq!(
        buf,
        vec![UNTOUCHED; usize::from(MBX_LEN)],
        "buffer untouched"
    );
    esc.pdi_write(SM1, &pattern(3, MBX_LEN));
    assert_eq!(status(&mut esc, 1), FULL | WRITE_EVENT);
    assert_eq!(ecat_bytes(&mut esc, SM1, 64), pattern(3, 64));
    assert_eq!(status(&mut esc, 1) & FULL, FULL, "still full");
    assert_eq!(ecat_bytes(&mut esc, SM1 + 64, 64), pattern(3 + 64, 64));
    assert_eq!(status(&mut esc, 1), READ_EVENT);
    assert!(!ecat_read(&mut esc, SM1 + 127, 1).0, "empty again");
}

#[test]
fn receive_mailbox_event_is_set_when_full_and_cleared_by_the_pdi_reading_the_first_byte() {
    let mut esc = configured();
    assert_eq!(
        pdi_read(&mut esc, SM0, 2),
        [0, 0],
        "the PDI reads an empty mailbox as is"
    );
    pdi_read(&mut esc, SM0 + MBX_LEN - 1, 1);
    assert_eq!(status(&mut esc, 0), 0, "an empty mailbox is not emptied");
    esc.ecat_write(SM0, &pattern(1, MBX_LEN));
    assert_eq!(esc.al_event(), AlEvent::sync_manager(0));
    pdi_read(&mut esc, SM0 + 1, 4);
    assert_eq!(
        esc.al_event(),
        AlEvent::sync_manager(0),
        "not the first byte"
    );
    assert_eq!(pdi_read(&mut esc, SM0, 2), [1, 2]);
    assert_eq!(esc.al_event(), AlEvent::NONE);
    assert_eq!(status(&mut esc, 0), FULL, "write event cleared, still full");
    pdi_read(&mut esc, SM0 + MBX_LEN - 1, 1);
    assert_eq!(status(&mut esc, 0), READ_EVENT);
    assert_eq!(
        esc.al_event(),
        AlEvent::NONE,
        "the PDI emptied it: no PDI event"
    );
}

#[test]
fn send_mailbox_event_is_set_when_emptied_and_cleared_by_the_pdi_writing_the_first_byte() {
    let mut esc = configured();
    esc.pdi_write(SM1, &pattern(1, MBX_LEN));
    assert_eq!(
        esc.al_event(),
        AlEvent::NONE,
        "the PDI filled it: no PDI event"
    );
    ecat_bytes(&mut esc, SM1, usize::from(MBX_LEN));
    assert_eq!(esc.al_event(), AlEvent::sync_manager(1));
    esc.pdi_write(SM1 + 1, &[0]);
    assert_eq!(
        esc.al_event(),
        AlEvent::sync_manager(1),
        "not the first byte"
    );
    esc.pdi_write(SM1, &[0]);
    assert_eq!(esc.al_event(), AlEvent::NONE);
    assert_eq!(status(&mut esc, 1), 0);
}

#[test]
fn mailbox_events_need_the_pdi_event_enable_bit() {
    let mut esc = esc();
    enable(&mut esc, 0, SM0, MBX_LEN, MAILBOX_OUT & !0x20);
    pdi_read(&mut esc, sync_manager(0) + 6, 1);
    esc.ecat_write(SM0, &pattern(1, MBX_LEN));
    assert_eq!(status(&mut esc, 0), FULL | WRITE_EVENT);
    assert_eq!(esc.al_event(), AlEvent::NONE);
}

#[test]
fn wrong_side_writes_are_refused_and_reads_see_the_buffer() {
    let mut esc = configured();
    assert!(!esc.ecat_write(SM1, &pattern(5, MBX_LEN)));
    assert_eq!(pdi_read(&mut esc, SM1, 4), [0; 4]);
    assert_eq!(status(&mut esc, 1), 0);
    esc.ecat_write(SM0, &pattern(1, MBX_LEN));
    esc.pdi_write(SM0, &pattern(9, MBX_LEN));
    assert_eq!(
        ecat_bytes(&mut esc, SM0, usize::from(MBX_LEN)),
        pattern(1, MBX_LEN)
    );
    assert_eq!(
        status(&mut esc, 0),
        FULL | WRITE_EVENT,
        "wrong-side read has no effect"
    );
}

#[test]
fn disabling_resets_the_mailbox() {
    let mut esc = configured();
    esc.ecat_write(SM0, &pattern(1, MBX_LEN));
    assert!(esc.ecat_write(sync_manager(0) + 6, &[0]));
    assert_eq!(status(&mut esc, 0), 0);
    assert!(!esc.al_event().intersects(AlEvent::sync_manager(0)));
    assert!(esc.ecat_write(sync_manager(0) + 6, &[1]));
    assert!(
        esc.ecat_write(SM0, &pattern(2, MBX_LEN)),
        "empty after re-enabling"
    );
    assert_eq!(pdi_read(&mut esc, SM0, 2), [2, 3]);
}

/// ESC datasheet section I, "SyncManager deactivation by the PDI": the channel's state is reset
/// and "the entire SyncManager buffer area is read/write protected" while deactivated; the
/// MainDevice sees it in the working counter, which such an access does not increment.
#[test]
fn pdi_deactivation_resets_the_mailbox_and_closes_its_area_to_the_maindevice() {
    let mut esc = configured();
    esc.ecat_write(SM0, &pattern(1, MBX_LEN));
    esc.pdi_write(sync_manager(0) + 7, &[0x01]);
    assert_eq!(status(&mut esc, 0), 0);
    assert_eq!(esc.al_event(), AlEvent::NONE);
    assert!(!esc.ecat_write(SM0, &pattern(2, MBX_LEN)), "not counted");
    esc.pdi_write(SM0, &[0xAB]);
    assert_eq!(
        ecat_read(&mut esc, SM0, 3),
        (false, vec![UNTOUCHED; 3]),
        "nothing read, not counted"
    );
    assert_eq!(
        pdi_read(&mut esc, SM0, 3),
        [0xAB, 2, 3],
        "the write was refused; the PDI reads the memory"
    );
    assert_eq!((status(&mut esc, 0), esc.al_event()), (0, AlEvent::NONE));
    esc.pdi_write(sync_manager(0) + 7, &[0]);
    assert!(esc.ecat_write(SM0, &pattern(4, MBX_LEN)));
    assert!(
        !esc.ecat_write(SM0, &pattern(5, MBX_LEN)),
        "a mailbox again"
    );
}

/// A deactivated 3-buffer channel closes all three buffers of its area; a channel the
/// MainDevice disabled leaves plain memory.
#[test]
fn a_deactivated_three_buffer_area_is_closed_and_a_disabled_one_is_plain_memory() {
    let mut esc = configured();
    esc.pdi_write(sync_manager(2) + 7, &[0x01]);
    for offset in [0, PD_LEN, 3 * PD_LEN - 1] {
        assert!(!esc.ecat_write(SM2 + offset, &[1]), "offset {offset}");
    }
    assert!(esc.ecat_write(SM2 + 3 * PD_LEN, &[1]), "after the area");
    esc.ecat_write(sync_manager(2) + 6, &[0]);
    assert!(esc.ecat_write(SM2, &[7]), "disabled: plain memory");
    assert_eq!(ecat_bytes(&mut esc, SM2, 1), [7]);
}

#[test]
fn access_spanning_plain_ram_and_a_mailbox_follows_each_area() {
    let mut esc = esc();
    enable(&mut esc, 0, SM0 + 16, 16, MAILBOX_OUT);
    assert!(esc.ecat_write(SM0, &pattern(1, 32)));
    assert!(
        !esc.ecat_write(SM0, &pattern(100, 32)),
        "mailbox part refused"
    );
    let mut expected = pattern(100, 16);
    expected.extend(pattern(17, 16));
    assert_eq!(pdi_read(&mut esc, SM0, 32), expected);
}

// ---- 3-buffer ----

#[test]
fn three_buffer_reader_sees_the_newest_complete_buffer() {
    let mut esc = configured();
    assert_eq!(pdi_read(&mut esc, SM2, 4), [0; 4], "nothing written yet");
    esc.ecat_write(SM2, &[0xA0, 0xA1, 0xA2, 0xA3]);
    esc.ecat_write(SM2, &[0xB0, 0xB1, 0xB2, 0xB3]);
    assert_eq!(pdi_read(&mut esc, SM2, 4), [0xB0, 0xB1, 0xB2, 0xB3]);
    esc.ecat_write(SM2, &[0xC0, 0xC1]);
    assert_eq!(
        pdi_read(&mut esc, SM2, 4),
        [0xB0, 0xB1, 0xB2, 0xB3],
        "C half-written"
    );
    esc.ecat_write(SM2 + 2, &[0xC2, 0xC3]);
    assert_eq!(pdi_read(&mut esc, SM2, 4), [0xC0, 0xC1, 0xC2, 0xC3]);
}

#[test]
fn three_buffer_reader_keeps_its_buffer_during_a_read() {
    let mut esc = configured();
    esc.pdi_write(SM3, &[1, 2, 3, 4]);
    assert_eq!(ecat_bytes(&mut esc, SM3, 2), [1, 2]);
    esc.pdi_write(SM3, &[5, 6, 7, 8]);
    assert_eq!(
        ecat_bytes(&mut esc, SM3 + 2, 2),
        [3, 4],
        "same buffer until the next first byte"
    );
    esc.pdi_write(SM3, &[9, 10]);
    assert_eq!(ecat_bytes(&mut esc, SM3, 4), [5, 6, 7, 8]);
    assert_eq!(
        ecat_bytes(&mut esc, SM3, 4),
        [5, 6, 7, 8],
        "no newer complete buffer"
    );
}

#[test]
fn three_buffer_status_and_events() {
    let mut esc = configured();
    assert_eq!(status(&mut esc, 2), 0x30, "no buffer written");
    esc.ecat_write(SM2, &[1, 2, 3, 4]);
    assert_eq!(status(&mut esc, 2), 0x10 | FULL | WRITE_EVENT);
    assert_eq!(esc.al_event(), AlEvent::sync_manager(2));
    pdi_read(&mut esc, SM2, 1);
    assert_eq!(esc.al_event(), AlEvent::NONE);
    assert_eq!(status(&mut esc, 2), 0x10 | FULL, "read started");
    pdi_read(&mut esc, SM2 + 3, 1);
    assert_eq!(status(&mut esc, 2), 0x10 | READ_EVENT, "read ended");
    esc.ecat_write(SM2, &[5, 6, 7, 8]);
    assert_eq!(status(&mut esc, 2), 0x20 | FULL | WRITE_EVENT);

    esc.pdi_write(SM3, &[1, 2, 3, 4]);
    assert_eq!(
        esc.al_event(),
        AlEvent::sync_manager(2),
        "the PDI wrote SM3"
    );
    ecat_bytes(&mut esc, SM3, 4);
    assert_eq!(
        esc.al_event(),
        AlEvent::sync_manager(2) | AlEvent::sync_manager(3)
    );
    esc.pdi_write(SM3, &[9]);
    assert_eq!(esc.al_event(), AlEvent::sync_manager(2));
}

#[test]
fn three_buffer_reader_side_cannot_write() {
    let mut esc = configured();
    assert!(!esc.ecat_write(SM3, &[1, 2, 3, 4]));
    assert_eq!(ecat_bytes(&mut esc, SM3, 4), [0; 4]);
    esc.pdi_write(SM2, &[1, 2, 3, 4]);
    assert_eq!(status(&mut esc, 2), 0x30, "nothing written");
    assert_eq!(pdi_read(&mut esc, SM2, 4), [0; 4]);
}

// ---- robustness ----

#[test]
fn accesses_at_the_end_of_the_address_space_do_not_panic() {
    let mut esc = esc();
    esc.pdi_write(0x2FFE, &[1, 2, 3, 4]);
    assert_eq!(
        ecat_read(&mut esc, 0x2FFE, 4),
        (false, vec![1, 2, 0, 0]),
        "RAM ends at 0x3000"
    );
    assert!(!esc.ecat_write(0x3000, &[1]));
    assert!(esc.ecat_write(0x2FFF, &[1]));
    let (served, buf) = ecat_read(&mut esc, 0xFFF0, 64);
    assert!(!served);
    assert_eq!(buf[..16], [0; 16], "no memory beyond the RAM");
    assert_eq!(
        buf[16..],
        [UNTOUCHED; 48],
        "stops at the end of the address space"
    );
    assert!(!esc.ecat_write(0xFFFF, &[1; 64]));
    assert!(esc.ecat_read(0x1000, &mut []));
    esc.pdi_read(0xFFFF, &mut [0; 3]);
    esc.pdi_write(0xFFF0, &[0; 64]);

    let mut full = Esc::new(EscConfig {
        process_ram_end: 0x1_0000,
        ..EscConfig::default()
    });
    assert!(full.ecat_write(0xFFF0, &pattern(1, 16)));
    assert!(!full.ecat_write(0xFFF0, &pattern(2, 17)), "past 0xFFFF");
    assert_eq!(pdi_read(&mut full, 0xFFFE, 2), [16, 17]);
    assert_eq!(ecat_bytes(&mut full, 0xFFFF, 1), [17]);
}

#[test]
fn pdi_accesses_are_counted() {
    let mut esc = esc();
    esc.pdi_read(0x1000, &mut [0; 10]);
    esc.pdi_read(0xFFFF, &mut [0; 4]);
    esc.pdi_write(register::AL_STATUS, &[1, 0]);
    esc.ecat_read(0x1000, &mut [0; 100]);
    let stats = PdiStats {
        reads: 2,
        writes: 1,
        bytes_read: 14,
        bytes_written: 2,
    };
    assert_eq!(esc.stats(), stats);
}

/// A xorshift64 generator: deterministic and dependency-free.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

#[test]
fn random_accesses_never_panic_and_keep_the_event_register_consistent() {
    const BASES: [u16; 10] = [
        0, 0x0120, 0x0200, 0x0220, 0x07F0, 0x0800, SM0, SM2, 0x2FF0, 0xFFC0,
    ];
    let mut esc = configured();
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    for _ in 0..10_000 {
        let base = BASES[rng.below(BASES.len() as u64) as usize];
        let address = base.wrapping_add(rng.below(0x90) as u16);
        let len = rng.below(48) as usize;
        let mut data: Vec<u8> = (0..len).map(|_| rng.next() as u8).collect();
        match rng.below(4) {
            0 => drop(esc.ecat_read(address, &mut data)),
            1 => drop(esc.ecat_write(address, &data)),
            2 => drop(esc.pdi_read(address, &mut data)),
            _ => drop(esc.pdi_write(address, &data)),
        }
        let mut request = [0; 4];
        let sampled = esc.pdi_read(register::AL_EVENT_REQUEST, &mut request);
        assert_eq!(AlEvent::from_le_bytes(request), esc.al_event());
        assert_eq!(sampled, esc.al_event());
        let mask = AlEvent::from_le_bytes(
            pdi_read(&mut esc, register::AL_EVENT_MASK, 4)
                .try_into()
                .unwrap(),
        );
        assert_eq!(esc.irq(), esc.al_event().intersects(mask));
    }
}

#[test]
fn an_sii_write_beyond_the_eeprom_is_a_command_error_and_allocates_nothing() {
    let mut esc = esc();
    esc.load_eeprom(vec![0; 16]);
    assert!(esc.ecat_write(register::SII_DATA, &[0xAB, 0xCD]));
    // Write enable + write command, word address 0xFFFF_FFFF.
    assert!(esc.ecat_write(register::SII_CONTROL, &[0x01, 0x02, 0xFF, 0xFF, 0xFF, 0xFF]));
    let status = ecat_bytes(&mut esc, register::SII_CONTROL, 2);
    assert_eq!(
        u16::from_le_bytes([status[0], status[1]]) & 0x2000,
        0x2000,
        "command error"
    );
    assert_eq!(esc.eeprom().len(), 16);
    // The last word of the 2 KiB EEPROM is writable.
    assert!(esc.ecat_write(register::SII_CONTROL, &[0x01, 0x02, 0xFF, 0x03, 0x00, 0x00]));
    assert_eq!(esc.eeprom().len(), 2048);
    assert_eq!(&esc.eeprom()[2046..], &[0xAB, 0xCD]);
}

#[test]
fn lrw_through_a_read_write_fmmu_returns_the_memory_before_its_write() {
    let mut esc = esc();
    // FMMU 0: logical 0..2 ↔ physical 0x1200..0x1202, read and write, active.
    let fmmu = [0, 0, 0, 0, 2, 0, 0, 7, 0x00, 0x12, 0, 3, 1, 0, 0, 0];
    assert!(esc.ecat_write(register::FMMU_BASE, &fmmu));
    assert!(esc.ecat_write(0x1200, &[0x11, 0x22]));
    let mut data = [0xAA, 0xBB];
    assert_eq!(
        esc.datagram(12, &mut [0; 4], &mut data),
        3,
        "LRW: read + write"
    );
    assert_eq!(data, [0x11, 0x22], "the memory as it was");
    assert_eq!(
        ecat_bytes(&mut esc, 0x1200, 2),
        [0xAA, 0xBB],
        "then written"
    );
}

// ---- the EEPROM configuration area ----

/// At EEPROM load the ESC puts word 0 into 0x0140/0x0141, word 1 into 0x0150/0x0151, word 2
/// into 0x0982, word 3 into 0x0152 and word 4 into 0x0012 (ESC datasheet section II, "EEPROM
/// configuration area"); neither port writes them. Without an EEPROM PDI control stays 0.
#[test]
fn the_configuration_area_is_loaded_into_its_registers() {
    let blank = Esc::new(EscConfig {
        eeprom: None,
        ..EscConfig::default()
    });
    assert_eq!(blank.register(register::PDI_CONTROL), 0x00, "no PDI");
    let mut esc = esc();
    let area = ConfigArea {
        pdi_control: 0x05,
        esc_configuration: 0x0C,
        pdi_configuration: 0x03,
        sync_latch_configuration: 0x44,
        sync_pulse_length: 0x2710,
        extended_pdi_configuration: 0x1234,
        station_alias: 0xBEEF,
        vendor_words: [0, 0],
    };
    esc.load_eeprom(area.bytes().to_vec());
    assert_eq!(ecat_bytes(&mut esc, 0x0140, 2), [0x05, 0x0C]);
    assert_eq!(ecat_bytes(&mut esc, 0x0150, 4), [0x03, 0x44, 0x34, 0x12]);
    assert_eq!(ecat_bytes(&mut esc, 0x0982, 2), [0x10, 0x27]);
    assert_eq!(
        ecat_bytes(&mut esc, register::STATION_ALIAS, 2),
        [0xEF, 0xBE]
    );
    esc.ecat_write(0x0140, &[0; 2]);
    esc.pdi_write(0x0150, &[0; 4]);
    esc.ecat_write(0x0982, &[0; 2]);
    assert_eq!(ecat_bytes(&mut esc, 0x0140, 2), [0x05, 0x0C], "read-only");
    assert_eq!(ecat_bytes(&mut esc, 0x0150, 4), [0x03, 0x44, 0x34, 0x12]);
    assert_eq!(ecat_bytes(&mut esc, 0x0982, 2), [0x10, 0x27]);
}

/// 0x0141 bit 0, device emulation: the ESC itself copies AL control into AL status; the stack's
/// area leaves it off, so AL status is the PDI's.
#[test]
fn device_emulation_copies_al_control_into_al_status() {
    let mut esc = esc();
    esc.ecat_write(register::AL_CONTROL, &[0x02, 0]);
    assert_eq!(ecat_bytes(&mut esc, register::AL_STATUS, 2), [0x01, 0x00]);
    let area = ConfigArea {
        esc_configuration: 0x01,
        ..ConfigArea::new(&Chip::ET1100, false)
    };
    esc.load_eeprom(area.bytes().to_vec());
    esc.ecat_write(register::AL_CONTROL, &[0x02, 0]);
    assert_eq!(ecat_bytes(&mut esc, register::AL_STATUS, 2), [0x02, 0x00]);
}

/// SYNC0 in acknowledge mode (0x0982 = 0): a pulse raises the signal (0x098E bit 0) and later
/// pulses make no edge until the PDI reads 0x098E; with a pulse length every pulse is an edge.
#[test]
fn acknowledge_mode_holds_sync0_until_the_pdi_reads_its_status() {
    let mut esc = esc();
    assert!(
        esc.sync0_output_enabled(),
        "the stack's area for a DC device"
    );
    assert!(esc.sync0_pulse() && esc.sync0_pulse(), "1 µs pulses");
    let area = ConfigArea {
        sync_pulse_length: 0,
        ..ConfigArea::new(&Chip::ET1100, true)
    };
    esc.load_eeprom(area.bytes().to_vec());
    assert!(esc.sync0_pulse());
    assert!(!esc.sync0_pulse(), "still active");
    assert_eq!(
        ecat_bytes(&mut esc, 0x098E, 1),
        [0x01],
        "an ECAT read leaves it"
    );
    assert!(!esc.sync0_pulse());
    assert_eq!(pdi_read(&mut esc, 0x098E, 1), [0x01]);
    assert_eq!(
        pdi_read(&mut esc, 0x098E, 1),
        [0x00],
        "the PDI read acknowledged it"
    );
    assert!(esc.sync0_pulse());
    let off = ConfigArea::new(&Chip::ET1100, false);
    esc.load_eeprom(off.bytes().to_vec());
    assert!(
        !esc.sync0_output_enabled(),
        "SYNC out unit off, SYNC0 a latch input"
    );
}

/// The LED codes of both outputs.
fn leds(esc: &Esc) -> (u8, u8) {
    (esc.run_led().bits(), esc.err_led().bits())
}

/// RUN follows the state the PDI writes into AL status (section I: INIT off, PREOP blinking,
/// BOOT flickering, SAFEOP single flash, OP on); ERR single-flashes with the error indication.
#[test]
fn run_led_follows_the_al_status() {
    let mut esc = esc();
    assert_eq!(leds(&esc), (0x0, 0x0), "INIT after reset");
    for (status, code) in [
        (0x02, 0xD),
        (0x04, 0x1),
        (0x08, 0xF),
        (0x03, 0xE),
        (0x01, 0x0),
    ] {
        esc.pdi_write(register::AL_STATUS, &[status, 0]);
        assert_eq!(esc.run_led().bits(), code, "AL status {status:#04x}");
    }
    esc.pdi_write(register::AL_STATUS, &[0x12, 0]);
    assert_eq!(leds(&esc), (0xD, 0x1), "PREOP with the error indication");
    esc.pdi_write(register::AL_STATUS, &[0x07, 0]);
    assert_eq!(leds(&esc), (0x0, 0x0), "no state: dark");
}

/// Both ports write the override registers; the next ESM state change ends RUN's override,
/// the same state written again does not; a new error indication ends ERR's.
#[test]
fn led_overrides_last_until_a_state_change_or_a_new_error() {
    let mut esc = esc();
    esc.pdi_write(register::AL_STATUS, &[0x02, 0]);
    assert!(esc.ecat_write(register::RUN_LED_OVERRIDE, &[0x13, 0x1F]));
    assert_eq!(
        leds(&esc),
        (0x3, 0xF),
        "the MainDevice's override: 3 flashes, ERR on"
    );
    esc.pdi_write(register::AL_STATUS, &[0x02, 0]);
    assert_eq!(esc.run_led().bits(), 0x3, "PREOP again is no state change");
    esc.pdi_write(register::AL_STATUS, &[0x04, 0]);
    assert_eq!(esc.run_led().bits(), 0x1, "SAFEOP: the state's code again");
    assert_eq!(
        pdi_read(&mut esc, register::RUN_LED_OVERRIDE, 2),
        [0x03, 0x1F],
        "the enable bit cleared, the code kept; ERR's override stays"
    );
    esc.pdi_write(register::ERR_LED_OVERRIDE, &[0x12]);
    assert_eq!(
        leds(&esc),
        (0x1, 0x2),
        "the PDI's ERR override: double flash"
    );
    esc.pdi_write(register::AL_STATUS, &[0x14, 0]);
    assert_eq!(
        leds(&esc),
        (0x1, 0x1),
        "the error indication set: ERR's override ends"
    );
    esc.pdi_write(register::ERR_LED_OVERRIDE, &[0x12]);
    esc.pdi_write(register::AL_STATUS, &[0x02, 0]);
    assert_eq!(
        leds(&esc),
        (0xD, 0x2),
        "a state change leaves ERR's override alone"
    );
}

/// A process-data watchdog expiry in OP double-flashes ERR until the next state change (the
/// single flash of the error indication then); outside OP it shows nothing.
#[test]
fn err_led_double_flashes_a_watchdog_expiry_in_op() {
    let mut esc = esc();
    esc.pdi_write(register::AL_STATUS, &[0x04, 0]);
    esc.expire_watchdog();
    assert_eq!(
        esc.err_led().bits(),
        0x0,
        "SAFEOP: no process-data watchdog"
    );
    esc.pdi_write(register::ERR_LED_OVERRIDE, &[0x1D]);
    esc.pdi_write(register::AL_STATUS, &[0x08, 0]);
    esc.expire_watchdog();
    assert_eq!(
        leds(&esc),
        (0xF, 0x2),
        "OP: a new error condition ends the override"
    );
    esc.pdi_write(register::AL_STATUS, &[0x14, 0]);
    assert_eq!(leds(&esc), (0x1, 0x1), "SAFEOP with the error indication");
}

/// An EEPROM whose configuration area fails its checksum: ERR flickers (section I, "SII EEPROM
/// loading error") until a reload succeeds.
#[test]
fn err_led_flickers_after_a_failed_eeprom_load() {
    let mut esc = esc();
    let good = esc.eeprom().to_vec();
    let mut bad = good.clone();
    bad[14] ^= 0xFF;
    esc.load_eeprom(bad);
    assert_eq!(esc.err_led().bits(), 0xE);
    esc.load_eeprom(good);
    assert_eq!(esc.err_led().bits(), 0x0);
}
