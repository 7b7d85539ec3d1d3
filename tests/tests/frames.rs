//! The emulated ESCs' EtherCAT port at frame level, byte-exact: hand-built frames through a line of
//! three emulated ESCs, every datagram command with its working counter and ADP increment
//! (ETG.1000.4 §5.4, Tables 13–25), FMMUs (Table 56), SyncManager buffers through datagrams
//! (Table 58), the SII EEPROM interface (Tables 47–51), distributed clocks (§6.8) and what the line
//! does with malformed frames (`ecat_emu::frame`).

use ecat_core::chip::Chip;
use ecat_core::chip::crc8;
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::esc::datagram::Command;
use ecat_emu::frame::{self, Datagram};
use ecat_emu::line::Line;
use embassy_time::{Duration, Instant, MockDriver};

const NOP: u8 = 0;
const APRD: u8 = 1;
const APWR: u8 = 2;
const APRW: u8 = 3;
const FPRD: u8 = 4;
const FPWR: u8 = 5;
const FPRW: u8 = 6;
const BRD: u8 = 7;
const BWR: u8 = 8;
const BRW: u8 = 9;
const LRD: u8 = 10;
const LWR: u8 = 11;
const LRW: u8 = 12;
const ARMW: u8 = 13;
const FRMW: u8 = 14;

/// The MainDevice's source MAC: locally-administered bit (byte 0 bit 1) clear.
const SOURCE: [u8; 6] = [0x10, 0x20, 0x30, 0x40, 0x50, 0x60];
/// Process RAM no SyncManager guards in these tests.
const RAM: u16 = 0x1800;
/// The ESCs' configured station addresses.
const STATIONS: [u16; 3] = [0x1000, 0x1001, 0x1002];

/// Three ESCs with `config`, no station address set.
fn line_of(configs: [EscConfig; 3]) -> Line {
    Line::new(configs.into_iter().map(Emulator::new).collect())
}

/// Three default ESCs (no DC) with the station addresses [`STATIONS`].
fn line() -> Line {
    let line = line_of([EscConfig::default(); 3]);
    address(&line);
    line
}

/// APWR 0x0010 ← [`STATIONS`], one datagram per ESC (ADP 0, −1, −2), as MainDevices do.
fn address(line: &Line) {
    assert!(line.address());
    for (n, station) in STATIONS.into_iter().enumerate() {
        assert_eq!(pdi(line, n, 0x0010, 2), station.to_le_bytes());
    }
}

/// Sends `datagrams` in one frame; returns them as they came back, after checking that the
/// frame came back whole with only the source MAC's locally-administered bit changed outside
/// the datagrams.
fn exchange(line: &Line, datagrams: &[Datagram]) -> Vec<Datagram> {
    let mut sent = frame::build(SOURCE, datagrams);
    let len = sent.len();
    assert_eq!(line.process(&mut sent), Some(len));
    let back = frame::datagrams(&sent).expect("a well-formed frame comes back");
    let mut expected = frame::build(SOURCE, &back);
    expected[6] |= 0x02;
    assert_eq!(sent, expected);
    back
}

/// One datagram through the line.
fn one(line: &Line, datagram: Datagram) -> Datagram {
    exchange(line, &[datagram]).remove(0)
}

/// `datagram` with ADP `adp`, `data` and working counter `wkc`: what should come back.
fn answer(datagram: &Datagram, adp: u16, data: &[u8], wkc: u16) -> Datagram {
    let [a, b] = adp.to_le_bytes();
    Datagram {
        address: [a, b, datagram.address[2], datagram.address[3]],
        data: data.to_vec(),
        wkc,
        ..datagram.clone()
    }
}

/// `datagram` come back with `data` and `wkc`, address unchanged.
fn answered(datagram: &Datagram, data: &[u8], wkc: u16) -> Datagram {
    Datagram {
        data: data.to_vec(),
        wkc,
        ..datagram.clone()
    }
}

/// PDI read of `len` bytes at `address` of ESC `n`.
fn pdi(line: &Line, n: usize, address: u16, len: usize) -> Vec<u8> {
    let mut buf = vec![0; len];
    line.escs()[n].with(|esc| esc.pdi_read(address, &mut buf));
    buf
}

/// PDI write of `data` at `address` of ESC `n`.
fn pdi_write(line: &Line, n: usize, address: u16, data: &[u8]) {
    line.escs()[n].with(|esc| esc.pdi_write(address, data));
}

/// Fills [`RAM`] of the three ESCs with `values[n]` (one byte each).
fn fill_ram(line: &Line, values: [u8; 3]) {
    for (n, value) in values.into_iter().enumerate() {
        pdi_write(line, n, RAM, &[value]);
    }
}

/// The byte at [`RAM`] of each ESC.
fn ram(line: &Line) -> [u8; 3] {
    [0, 1, 2].map(|n| pdi(line, n, RAM, 1)[0])
}

// ---------------------------------------------------------------------------------------------
// Auto-increment addressing: ADP incremented by every ESC, the one that sees 0 is addressed.

#[test]
fn aprd_reads_the_esc_that_sees_adp_zero() {
    let line = line();
    let d = Datagram::physical(APRD, 0xFFFF, 0x0010, &[0xAA, 0xBB]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0002, &[0x01, 0x10], 1));
    let nobody = Datagram::physical(APRD, 0xFFFC, 0x0010, &[0xAA, 0xBB]);
    assert_eq!(
        one(&line, nobody.clone()),
        answer(&nobody, 0xFFFF, &[0xAA, 0xBB], 0)
    );
}

#[test]
fn apwr_writes_only_the_esc_that_sees_adp_zero() {
    let line = line();
    let d = Datagram::physical(APWR, 0xFFFE, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0001, &[0x5A], 1));
    assert_eq!(ram(&line), [0, 0, 0x5A]);
}

#[test]
fn aprw_returns_the_old_data_writes_the_new_and_counts_three() {
    let line = line();
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let d = Datagram::physical(APRW, 0x0000, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0003, &[0x11], 3));
    assert_eq!(ram(&line), [0x5A, 0x22, 0x33]);
}

// ---------------------------------------------------------------------------------------------
// Configured-address addressing: ADP is the station address, never incremented.

#[test]
fn fprd_reads_the_esc_with_that_station_address() {
    let line = line();
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let d = Datagram::physical(FPRD, 0x1001, RAM, &[0]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x22], 1));
    let nobody = Datagram::physical(FPRD, 0x1003, RAM, &[0]);
    assert_eq!(one(&line, nobody.clone()), answered(&nobody, &[0], 0));
}

#[test]
fn fpwr_writes_only_the_esc_with_that_station_address() {
    let line = line();
    let d = Datagram::physical(FPWR, 0x1002, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x5A], 1));
    assert_eq!(ram(&line), [0, 0, 0x5A]);
}

#[test]
fn fprw_returns_the_old_data_writes_the_new_and_counts_three() {
    let line = line();
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let d = Datagram::physical(FPRW, 0x1000, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x11], 3));
    assert_eq!(ram(&line), [0x5A, 0x22, 0x33]);
}

#[test]
fn the_station_alias_addresses_only_when_dl_control_bit_24_is_set() {
    let line = line();
    line.escs()[1].with(|esc| esc.set_register(0x0012, &[0xEE, 0x0B]));
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let by_alias = Datagram::physical(FPRD, 0x0BEE, RAM, &[0]);
    assert_eq!(one(&line, by_alias.clone()), answered(&by_alias, &[0], 0));
    let enable = Datagram::physical(FPWR, 0x1001, 0x0100, &[0, 0, 0, 0x01]);
    assert_eq!(one(&line, enable.clone()).wkc, 1);
    assert_eq!(
        one(&line, by_alias.clone()),
        answered(&by_alias, &[0x22], 1)
    );
    // The station address still addresses it; bits other than 24 do not enable the alias.
    let by_station = Datagram::physical(FPRD, 0x1001, RAM, &[0]);
    assert_eq!(one(&line, by_station.clone()).wkc, 1);
    let other_bits = Datagram::physical(FPWR, 0x1001, 0x0100, &[0xFF, 0xFF, 0xFF, 0xFE]);
    assert_eq!(one(&line, other_bits).wkc, 1);
    assert_eq!(one(&line, by_alias.clone()), answered(&by_alias, &[0], 0));
}

// ---------------------------------------------------------------------------------------------
// Broadcast: every ESC, ADP incremented by each.

#[test]
fn brd_ors_every_escs_data_into_the_datagram() {
    let line = line();
    fill_ram(&line, [0x01, 0x02, 0x04]);
    let d = Datagram::physical(BRD, 0x0000, RAM, &[0x80]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0003, &[0x87], 3));
    assert_eq!(ram(&line), [0x01, 0x02, 0x04]);
}

#[test]
fn bwr_writes_every_esc() {
    let line = line();
    let d = Datagram::physical(BWR, 0x0010, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0013, &[0x5A], 3));
    assert_eq!(ram(&line), [0x5A; 3]);
}

#[test]
fn brw_each_esc_ors_its_data_in_and_writes_the_data_as_it_arrived() {
    let line = line();
    fill_ram(&line, [0x01, 0x02, 0x04]);
    let d = Datagram::physical(BRW, 0xFFFF, RAM, &[0x80]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0002, &[0x87], 9));
    assert_eq!(ram(&line), [0x80, 0x81, 0x83]);
}

// ---------------------------------------------------------------------------------------------
// Read multiple write.

#[test]
fn armw_the_addressed_esc_reads_the_others_write() {
    let line = line();
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let d = Datagram::physical(ARMW, 0x0000, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0003, &[0x11], 3));
    assert_eq!(ram(&line), [0x11, 0x11, 0x11]);
    // Addressed in the middle: the first ESC writes the data as it arrived.
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let d = Datagram::physical(ARMW, 0xFFFF, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answer(&d, 0x0002, &[0x22], 3));
    assert_eq!(ram(&line), [0x5A, 0x22, 0x22]);
}

#[test]
fn frmw_the_station_reads_the_others_write_adp_unchanged() {
    let line = line();
    fill_ram(&line, [0x11, 0x22, 0x33]);
    let d = Datagram::physical(FRMW, 0x1001, RAM, &[0x5A]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x22], 3));
    assert_eq!(ram(&line), [0x5A, 0x22, 0x22]);
}

// ---------------------------------------------------------------------------------------------
// NOP and reserved codes; several datagrams in a frame.

#[test]
fn nop_and_reserved_commands_pass_untouched_and_the_next_datagram_is_processed() {
    let line = line();
    for command in [NOP, 15, 0xFF] {
        let d = Datagram::physical(command, 0x0000, RAM, &[0x5A]);
        let after = Datagram::physical(BRD, 0x0000, 0x0010, &[0, 0]);
        let back = exchange(&line, &[d.clone(), after.clone()]);
        assert_eq!(back, [d, answer(&after, 3, &[0x03, 0x10], 3)], "{command}");
        assert_eq!(ram(&line), [0; 3]);
    }
}

#[test]
fn datagrams_of_a_frame_are_processed_in_order_each_with_its_own_working_counter() {
    let line = line();
    let mut write = Datagram::physical(FPWR, 0x1002, RAM, &[0x5A]);
    write.index = 7;
    write.irq = 0x1234;
    let read = Datagram::physical(BRD, 0x0000, RAM, &[0]);
    let mut counted = Datagram::physical(APRD, 0xFFFF, 0x0010, &[0, 0]);
    counted.wkc = 5;
    let back = exchange(&line, &[write.clone(), read.clone(), counted.clone()]);
    assert_eq!(
        back,
        [
            answered(&write, &[0x5A], 1),
            answer(&read, 3, &[0x5A], 3),
            answer(&counted, 2, &[0x01, 0x10], 6),
        ]
    );
}

#[test]
fn the_line_sets_the_source_macs_locally_administered_bit_only() {
    let line = line();
    let mut sent = frame::build(SOURCE, &[Datagram::physical(NOP, 0, 0, &[])]);
    let mut expected = sent.clone();
    expected[6] = 0x12;
    assert_eq!(line.process(&mut sent), Some(sent.len()));
    assert_eq!(sent, expected);
}

// ---------------------------------------------------------------------------------------------
// Malformed input: the decisions documented in `ecat_emu::frame`.

#[test]
fn a_runt_is_lost() {
    let line = line();
    let full = frame::build(SOURCE, &[Datagram::physical(BWR, 0, RAM, &[0x5A])]);
    for len in [0, 13, 15] {
        let mut runt = full[..len].to_vec();
        assert_eq!(line.process(&mut runt), None, "{len} bytes");
    }
    assert_eq!(ram(&line), [0; 3]);
}

#[test]
fn a_foreign_frame_is_forwarded_unchanged() {
    let line = line();
    let ecat = frame::build(SOURCE, &[Datagram::physical(BWR, 0, RAM, &[0x5A])]);
    let mut ipv4 = ecat.clone();
    ipv4[12..14].copy_from_slice(&[0x08, 0x00]);
    let mut other_type = ecat.clone();
    other_type[15] = 0x40 | other_type[15] & 0x0F; // EtherCAT type 4 (network variables)
    for foreign in [ipv4, other_type] {
        let mut frame = foreign.clone();
        assert_eq!(line.process(&mut frame), Some(foreign.len()));
        assert_eq!(frame, foreign);
    }
    assert_eq!(ram(&line), [0; 3]);
}

#[test]
fn a_datagram_longer_than_the_frame_loses_it_after_every_esc_processed_the_earlier_ones() {
    let line = line();
    let write = Datagram::physical(BWR, 0, RAM, &[0x5A]);
    let long = Datagram::physical(BWR, 0, RAM + 1, &[0xA5; 8]);
    let mut sent = frame::build(SOURCE, &[write.clone(), long]);
    sent.truncate(sent.len() - 3);
    assert_eq!(line.process(&mut sent), None);
    assert_eq!(ram(&line), [0x5A; 3]);
    assert_eq!(pdi(&line, 0, RAM + 1, 1), [0]);
}

#[test]
fn more_datagrams_announced_than_fit_lose_the_frame_after_the_earlier_ones() {
    let line = line();
    let write = Datagram::physical(BWR, 0, RAM, &[0x5A]);
    let mut sent = frame::build(SOURCE, &[write]);
    sent[16 + 7] |= 0x80; // "more follows", but the frame ends
    assert_eq!(line.process(&mut sent), None);
    assert_eq!(ram(&line), [0x5A; 3]);
}

#[test]
fn bytes_after_the_ethercat_length_are_padding_and_stay_untouched() {
    let line = line();
    let read = Datagram::physical(BRD, 0, 0x0010, &[0, 0]);
    let mut sent = frame::build(SOURCE, std::slice::from_ref(&read));
    sent.extend([0xEE; 20]);
    let len = sent.len();
    assert_eq!(line.process(&mut sent), Some(len));
    let mut expected = frame::build(SOURCE, &[answer(&read, 3, &[0x03, 0x10], 3)]);
    expected[6] |= 0x02;
    expected.extend([0xEE; 20]);
    assert_eq!(sent, expected);
}

// ---------------------------------------------------------------------------------------------
// FMMUs (ETG.1000.4 Table 56).

/// A 16-byte FMMU entity.
fn fmmu(
    logical: u32,
    length: u16,
    bits: (u8, u8),
    physical: u16,
    physical_bit: u8,
    kind: u8,
) -> Vec<u8> {
    let mut entity = Vec::new();
    entity.extend(logical.to_le_bytes());
    entity.extend(length.to_le_bytes());
    entity.extend([bits.0, bits.1]);
    entity.extend(physical.to_le_bytes());
    entity.extend([physical_bit, kind, 1, 0, 0, 0]);
    entity
}

/// FPWR of FMMU `n` of station `station`.
fn set_fmmu(line: &Line, station: u16, n: u16, entity: &[u8]) {
    let d = Datagram::physical(FPWR, station, 0x0600 + 16 * n, entity);
    assert_eq!(one(line, d).wkc, 1);
}

/// A write FMMU and a read FMMU of ESC 1 that map logical 0x10000 bit 3 .. 0x10001 bit 4 (10 bits)
/// onto physical 0x1100 bit 5 .. 0x1101 bit 6.
fn bit_fmmu_line(kind: u8) -> Line {
    let line = line();
    set_fmmu(&line, 0x1001, 0, &fmmu(0x10000, 2, (3, 4), 0x1100, 5, kind));
    line
}

#[test]
fn an_fmmu_writes_bit_granular() {
    let line = bit_fmmu_line(2);
    pdi_write(&line, 1, 0x1100, &[0x1F, 0x80]);
    // Logical bits 3..=7 of 0xA8 are 1,0,1,0,1; bits 0..=4 of 0x15 are 1,0,1,0,1.
    let d = Datagram::logical(LWR, 0x10000, &[0xA8, 0x15]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0xA8, 0x15], 1));
    // Physical bits 5..=7 of 0x1100: 1,0,1 → 0xA0 | kept 0x1F; bits 0..=6 of 0x1101:
    // 0,1,1,0,1,0,1 → 0x56 | kept 0x80.
    assert_eq!(pdi(&line, 1, 0x1100, 3), [0xBF, 0xD6, 0x00]);
    assert_eq!(pdi(&line, 0, 0x1100, 2), [0, 0]);
}

#[test]
fn an_fmmu_reads_bit_granular_and_keeps_the_unmapped_bits() {
    let line = bit_fmmu_line(1);
    pdi_write(&line, 1, 0x1100, &[0xBF, 0xD6]);
    let d = Datagram::logical(LRD, 0x10000, &[0x07, 0xE0]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0xAF, 0xF5], 1));
    // Shifted by one byte: only logical 0x10001 bits 0..=4 are in the datagram.
    let d = Datagram::logical(LRD, 0x10001, &[0x00]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x15], 1));
    // Outside the mapping, or with a write-only FMMU, nobody answers.
    let d = Datagram::logical(LRD, 0x10002, &[0x00]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x00], 0));
    let line = bit_fmmu_line(2);
    let d = Datagram::logical(LRD, 0x10000, &[0x00, 0x00]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x00, 0x00], 0));
}

#[test]
fn an_inactive_fmmu_maps_nothing() {
    let line = line();
    let mut entity = fmmu(0x10000, 2, (0, 7), RAM, 0, 3);
    entity[12] = 0;
    set_fmmu(&line, 0x1001, 0, &entity);
    let d = Datagram::logical(LRW, 0x10000, &[0x5A, 0x5A]);
    assert_eq!(one(&line, d.clone()), answered(&d, &[0x5A, 0x5A], 0));
    assert_eq!(ram(&line), [0; 3]);
}

// ---------------------------------------------------------------------------------------------
// Process data: SM2/SM3 3-buffer areas through byte-aligned FMMUs, as in OP.

#[test]
fn command_codes_round_trip() {
    for code in 0..=14 {
        assert_eq!(Command::from_code(code).map(Command::code), Some(code));
    }
    assert_eq!(Command::from_code(15), None);
}

const OUTPUTS: u16 = 0x1000;
const INPUTS: u16 = 0x1100;
const PD: u16 = 11;

/// The 8 SyncManager registers of channel `n` (disabled first, as `TestMaster::configure_sm`),
/// `PD` bytes.
fn configure_sm(line: &Line, station: u16, n: u16, start: u16, control: u8) {
    let at = 0x0800 + 8 * n;
    let disable = Datagram::physical(FPWR, station, at + 6, &[0]);
    assert_eq!(one(line, disable).wkc, 1);
    let [s0, s1] = start.to_le_bytes();
    let [l0, l1] = PD.to_le_bytes();
    let registers = [s0, s1, l0, l1, control, 0, 1, 0];
    assert_eq!(
        one(line, Datagram::physical(FPWR, station, at, &registers)).wkc,
        1
    );
}

/// Three ESCs with SM2 (outputs at 0x1000) and SM3 (inputs at 0x1100) of 11 bytes, mapped to
/// logical 22·n (outputs) and 22·n + 11 (inputs).
fn process_data_line() -> Line {
    let line = line();
    assert!(line.map_process_data(OUTPUTS, INPUTS, PD));
    for n in 0..3 {
        // Status 0x30: no buffer written yet (3-buffer mode).
        assert_eq!(
            pdi(&line, n, 0x0810, 8),
            [0x00, 0x10, 11, 0, 0x64, 0x30, 1, 0]
        );
        assert_eq!(
            pdi(&line, n, 0x0818, 8),
            [0x00, 0x11, 11, 0, 0x20, 0x30, 1, 0]
        );
        let logical = (22 * n as u32).to_le_bytes();
        let mut write = logical.to_vec();
        write.extend([11, 0, 0, 7, 0x00, 0x10, 0, 2, 1, 0, 0, 0]);
        assert_eq!(pdi(&line, n, 0x0600, 16), write);
        let mut read = (22 * n as u32 + 11).to_le_bytes().to_vec();
        read.extend([11, 0, 0, 7, 0x00, 0x11, 0, 1, 1, 0, 0, 0]);
        assert_eq!(pdi(&line, n, 0x0610, 16), read);
    }
    line
}

#[test]
fn lrw_writes_the_outputs_and_reads_the_inputs_of_every_esc() {
    let line = process_data_line();
    for n in 0..3 {
        pdi_write(&line, n, INPUTS, &[0x10 * (n as u8 + 1); 11]);
    }
    let outputs: Vec<u8> = (0..66).collect();
    let d = Datagram::logical(LRW, 0, &outputs);
    let mut expected = outputs.clone();
    for n in 0..3 {
        expected[22 * n + 11..22 * n + 22].fill(0x10 * (n as u8 + 1));
    }
    assert_eq!(one(&line, d.clone()), answered(&d, &expected, 9));
    for n in 0..3 {
        assert_eq!(pdi(&line, n, OUTPUTS, 11), outputs[22 * n..22 * n + 11]);
    }
    // The next cycle: new outputs reach the PDI, new inputs the MainDevice.
    pdi_write(&line, 2, INPUTS, &[0xEE; 11]);
    let d = Datagram::logical(LRW, 0, &[0xC3; 66]);
    let back = one(&line, d);
    assert_eq!(back.wkc, 9);
    assert_eq!(back.data[55..66], [0xEE; 11]);
    assert_eq!(back.data[33..44], [0x20; 11]);
    assert_eq!(pdi(&line, 1, OUTPUTS, 11), [0xC3; 11]);
}

#[test]
fn lrd_lwr_count_one_per_esc_lrw_three() {
    let line = process_data_line();
    let lwr = Datagram::logical(LWR, 0, &[0x5A; 66]);
    assert_eq!(one(&line, lwr.clone()), answered(&lwr, &[0x5A; 66], 3));
    assert_eq!(pdi(&line, 0, OUTPUTS, 11), [0x5A; 11]);
    pdi_write(&line, 1, INPUTS, &[0x77; 11]);
    let lrd = Datagram::logical(LRD, 33, &[0; 11]);
    assert_eq!(one(&line, lrd.clone()), answered(&lrd, &[0x77; 11], 1));
    // Only ESC 1's outputs: LRW counts 2 (write) there and nothing elsewhere.
    let lrw = Datagram::logical(LRW, 22, &[0x33; 11]);
    assert_eq!(one(&line, lrw.clone()), answered(&lrw, &[0x33; 11], 2));
}

// ---------------------------------------------------------------------------------------------
// Mailboxes through FPWR/FPRD.

const MBX_OUT: u16 = 0x1000;
const MBX_IN: u16 = 0x1080;

/// ESC 0 with SM0 (MainDevice writes, 11 bytes at 0x1000) and SM1 (MainDevice reads, 11 bytes at
/// 0x1080) in mailbox mode.
fn mailbox_line() -> Line {
    let line = line();
    configure_sm(&line, 0x1000, 0, MBX_OUT, 0x26);
    configure_sm(&line, 0x1000, 1, MBX_IN, 0x22);
    line
}

/// SM `n`'s status byte (0x0805 + 8n) through FPRD.
fn sm_status(line: &Line, n: u16) -> u8 {
    one(line, Datagram::physical(FPRD, 0x1000, 0x0805 + 8 * n, &[0])).data[0]
}

#[test]
fn sm0_is_full_once_its_last_byte_is_written() {
    let line = mailbox_line();
    let first = Datagram::physical(FPWR, 0x1000, MBX_OUT, &[1; 10]);
    assert_eq!(one(&line, first).wkc, 1);
    assert_eq!(sm_status(&line, 0) & 0x08, 0);
    let last = Datagram::physical(FPWR, 0x1000, MBX_OUT + 10, &[2]);
    assert_eq!(one(&line, last).wkc, 1);
    assert_eq!(sm_status(&line, 0) & 0x08, 0x08);
    // Full: the next write is refused, and the PDI reads what the MainDevice wrote.
    let again = Datagram::physical(FPWR, 0x1000, MBX_OUT, &[3; 11]);
    assert_eq!(one(&line, again).wkc, 0);
    let mut expected = vec![1; 10];
    expected.push(2);
    assert_eq!(pdi(&line, 0, MBX_OUT, 11), expected);
    assert_eq!(sm_status(&line, 0) & 0x08, 0);
}

#[test]
fn sm1_is_emptied_by_reading_its_last_byte() {
    let line = mailbox_line();
    let read = Datagram::physical(FPRD, 0x1000, MBX_IN, &[0; 11]);
    assert_eq!(one(&line, read.clone()), answered(&read, &[0; 11], 0));
    pdi_write(&line, 0, MBX_IN, &[0x42; 11]);
    assert_eq!(sm_status(&line, 1) & 0x08, 0x08);
    let head = Datagram::physical(FPRD, 0x1000, MBX_IN, &[0; 10]);
    assert_eq!(one(&line, head.clone()), answered(&head, &[0x42; 10], 1));
    assert_eq!(sm_status(&line, 1) & 0x08, 0x08);
    let last = Datagram::physical(FPRD, 0x1000, MBX_IN + 10, &[0]);
    assert_eq!(one(&line, last.clone()), answered(&last, &[0x42], 1));
    assert_eq!(sm_status(&line, 1) & 0x08, 0);
    assert_eq!(one(&line, read.clone()), answered(&read, &[0; 11], 0));
}

// ---------------------------------------------------------------------------------------------
// The SII EEPROM interface (ETG.1000.4 Tables 47–51).

/// An SII image of 0x40 words: configuration area with alias `alias` and a correct CRC (unless
/// `bad_crc`), then the bytes 0x10, 0x11, … .
fn sii_image(alias: u16, bad_crc: bool) -> Vec<u8> {
    let mut image: Vec<u8> = (0..0x80u8).map(|b| b + 0x10).collect();
    image[8..10].copy_from_slice(&alias.to_le_bytes());
    image[14] = crc8(&image[..14]) ^ u8::from(bad_crc);
    image[15] = 0;
    image
}

/// ESC 1 with `image` loaded.
fn sii_line(image: Vec<u8>) -> Line {
    let line = line();
    line.escs()[1].with(|esc| esc.load_eeprom(image));
    line
}

/// 0x0502 of ESC 1.
fn sii_status(line: &Line) -> u16 {
    let d = one(line, Datagram::physical(FPRD, 0x1001, 0x0502, &[0, 0]));
    assert_eq!(d.wkc, 1);
    u16::from_le_bytes([d.data[0], d.data[1]])
}

/// FPWR 0x0502 ← control, word address (6 bytes), as ethercrab does.
fn sii_command(line: &Line, control: u16, word: u16) {
    let [c0, c1] = control.to_le_bytes();
    let [w0, w1] = word.to_le_bytes();
    let d = Datagram::physical(FPWR, 0x1001, 0x0502, &[c0, c1, w0, w1, 0, 0]);
    assert_eq!(one(line, d).wkc, 1);
}

/// ethercrab's read: status check, command, status poll, 8 bytes of data.
fn sii_read(line: &Line, word: u16) -> Vec<u8> {
    assert_eq!(sii_status(line), 0x0040);
    sii_command(line, 0x0100, word);
    assert_eq!(sii_status(line), 0x0040);
    let d = one(line, Datagram::physical(FPRD, 0x1001, 0x0508, &[0; 8]));
    assert_eq!(d.wkc, 1);
    d.data
}

#[test]
fn sii_reads_8_bytes_at_a_word_address_and_0xff_beyond_the_image() {
    let line = sii_line(sii_image(0, false));
    assert_eq!(
        sii_read(&line, 0x0008),
        [0x20, 0x21, 0x22, 0x23, 0x24, 0x25, 0x26, 0x27]
    );
    assert_eq!(
        sii_read(&line, 0x003E),
        [0x8C, 0x8D, 0x8E, 0x8F, 0xFF, 0xFF, 0xFF, 0xFF]
    );
    assert_eq!(sii_read(&line, 0x1000), [0xFF; 8]);
}

#[test]
fn sii_writes_a_word_only_with_write_enable() {
    let line = sii_line(sii_image(0, false));
    let data = Datagram::physical(FPWR, 0x1001, 0x0508, &[0xAA, 0x55]);
    assert_eq!(one(&line, data).wkc, 1);
    sii_command(&line, 0x0200, 0x0020);
    assert_eq!(sii_status(&line), 0x4040);
    assert_eq!(
        line.escs()[1].with(|esc| esc.eeprom()[0x40..0x42].to_vec()),
        [0x50, 0x51]
    );
    sii_command(&line, 0x0201, 0x0020);
    assert_eq!(sii_status(&line), 0x0040);
    assert_eq!(sii_read(&line, 0x0020)[..4], [0xAA, 0x55, 0x52, 0x53]);
}

#[test]
fn sii_reload_copies_the_alias_and_a_bad_crc_sets_bit_11() {
    let line = sii_line(sii_image(0x0BEE, false));
    assert_eq!(pdi(&line, 1, 0x0012, 2), [0xEE, 0x0B]);
    // A new alias and its CRC written into the EEPROM take effect at the reload.
    let mut config = sii_image(0x0CAF, false);
    for word in [4u16, 7] {
        let at = usize::from(word) * 2;
        let data = Datagram::physical(FPWR, 0x1001, 0x0508, &config[at..at + 2]);
        assert_eq!(one(&line, data).wkc, 1);
        sii_command(&line, 0x0201, word);
    }
    assert_eq!(pdi(&line, 1, 0x0012, 2), [0xEE, 0x0B]);
    sii_command(&line, 0x0400, 0);
    assert_eq!(sii_status(&line), 0x0040);
    assert_eq!(pdi(&line, 1, 0x0012, 2), [0xAF, 0x0C]);
    // A corrupted CRC: the reload keeps the alias and reports bit 11.
    config[14] ^= 1;
    let data = Datagram::physical(FPWR, 0x1001, 0x0508, &config[14..16]);
    assert_eq!(one(&line, data).wkc, 1);
    sii_command(&line, 0x0201, 7);
    sii_command(&line, 0x0400, 0);
    assert_eq!(sii_status(&line), 0x0840);
    assert_eq!(pdi(&line, 1, 0x0012, 2), [0xAF, 0x0C]);
}

#[test]
fn a_bad_crc_at_power_on_sets_bit_11_and_leaves_the_alias() {
    let line = sii_line(sii_image(0x0BEE, true));
    assert_eq!(sii_status(&line), 0x0840);
    assert_eq!(pdi(&line, 1, 0x0012, 2), [0, 0]);
}

#[test]
fn sii_ignores_commands_of_the_port_that_does_not_own_it() {
    let line = sii_line(sii_image(0, false));
    let to_pdi = Datagram::physical(FPWR, 0x1001, 0x0500, &[0x01]);
    assert_eq!(one(&line, to_pdi).wkc, 1);
    // The MainDevice's command, address and data bytes are ignored.
    sii_command(&line, 0x0100, 0x0008);
    assert_eq!(sii_status(&line), 0x0040);
    assert_eq!(
        pdi(&line, 1, 0x0502, 14),
        [0x40, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
    );
    // The PDI, owner now, reads.
    pdi_write(&line, 1, 0x0502, &[0x00, 0x01, 0x09, 0x00, 0x00, 0x00]);
    let d = one(&line, Datagram::physical(FPRD, 0x1001, 0x0508, &[0; 8]));
    assert_eq!(d.data, [0x22, 0x23, 0x24, 0x25, 0x26, 0x27, 0x28, 0x29]);
    // Back to the MainDevice: the PDI's commands are ignored, the MainDevice's executed.
    let to_ecat = Datagram::physical(FPWR, 0x1001, 0x0500, &[0x00]);
    assert_eq!(one(&line, to_ecat).wkc, 1);
    pdi_write(&line, 1, 0x0502, &[0x00, 0x01, 0x00, 0x00, 0x00, 0x00]);
    assert_eq!(
        pdi(&line, 1, 0x0502, 10),
        [0x40, 0, 9, 0, 0, 0, 0x22, 0x23, 0x24, 0x25]
    );
    assert_eq!(sii_read(&line, 0x0008)[0], 0x20);
}

// ---------------------------------------------------------------------------------------------
// Distributed clocks (ETG.1000.4 §6.8).

/// An ESC without a DC unit (the DC bits of 0x0008 clear).
fn no_dc() -> EscConfig {
    EscConfig {
        dc_supported: false,
        ..EscConfig::default()
    }
}

/// The emulated chips have DC as the silicon does (ET1100, AX58100, LAN9252: features 0x0008
/// bits 2, 3 and 8): a BWR to 0x0900 counts every ESC, as SOEM's and ethercrab's DC probes expect.
#[test]
fn the_emulated_chips_have_dc_as_the_silicon_does() {
    for chip in Chip::ALL {
        let line = line_of([EscConfig::of(chip); 3]);
        let probe = Datagram::physical(BWR, 0, 0x0900, &[0; 4]);
        assert_eq!(
            one(&line, probe.clone()),
            answer(&probe, 3, &[0; 4], 3),
            "{}",
            chip.name
        );
        address(&line);
        let features = one(&line, Datagram::physical(FPRD, 0x1001, 0x0008, &[0; 2]));
        assert_eq!(features.data, chip.features.to_le_bytes(), "{}", chip.name);
        assert_eq!(features.data[0] & 0x0C, 0x0C, "DC, 64-bit");
    }
}

#[test]
fn an_esc_without_dc_does_not_count_dc_registers() {
    let line = line_of([no_dc(); 3]);
    address(&line);
    let probe = Datagram::physical(BWR, 0, 0x0900, &[0; 4]);
    assert_eq!(one(&line, probe.clone()), answer(&probe, 3, &[0; 4], 0));
    let time = Datagram::physical(FPRD, 0x1000, 0x0910, &[0xAA; 8]);
    assert_eq!(one(&line, time.clone()), answered(&time, &[0xAA; 8], 0));
    // Straddling 0x08FF/0x0900 does not count either; 0x0A00 is outside the DC unit.
    let straddle = Datagram::physical(FPRD, 0x1000, 0x08FF, &[0; 2]);
    assert_eq!(one(&line, straddle).wkc, 0);
    let after = Datagram::physical(FPRD, 0x1000, 0x0A00, &[0; 2]);
    assert_eq!(one(&line, after).wkc, 1);
}

#[test]
fn an_esc_with_dc_latches_receive_times_and_shows_local_time_plus_offset() {
    let dc = EscConfig::default();
    let line = line_of([no_dc(), dc, no_dc()]);
    address(&line);
    MockDriver::get().advance(Duration::from_micros(1_234_567));
    let now = Instant::now().as_micros() * 1_000;
    let probe = Datagram::physical(BWR, 0, 0x0900, &[0; 4]);
    assert_eq!(one(&line, probe.clone()), answer(&probe, 3, &[0; 4], 1));
    let receive = one(&line, Datagram::physical(FPRD, 0x1001, 0x0900, &[0; 16]));
    assert_eq!(receive.data, (now as u32).to_le_bytes().repeat(4));
    let unit = one(&line, Datagram::physical(FPRD, 0x1001, 0x0918, &[0; 8]));
    assert_eq!(unit.data, now.to_le_bytes());
    let offset: u64 = 0x0123_4567_89AB_CDEF;
    let set = Datagram::physical(FPWR, 0x1001, 0x0920, &offset.to_le_bytes());
    assert_eq!(one(&line, set).wkc, 1);
    let system = one(&line, Datagram::physical(FPRD, 0x1001, 0x0910, &[0; 8]));
    assert_eq!(system.wkc, 1);
    assert_eq!(system.data, now.wrapping_add(offset).to_le_bytes());
    // Set directly: the local clock of the ESC.
    let time = line.escs()[1].with(|esc| {
        esc.set_local_time(1_000);
        let mut buf = [0; 8];
        esc.ecat_read(0x0910, &mut buf);
        buf
    });
    assert_eq!(time, 1_000u64.wrapping_add(offset).to_le_bytes());
}
