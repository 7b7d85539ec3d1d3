//! PDI traffic per process-data cycle, counted by the fake chips, for both SPI drivers and the
//! 16-bit microcontroller interface (bus cycles and their data bytes), and two images:
//! the CiA402-like image (11 bytes each way) and 64 bytes each way. A benchmark with exact
//! assertions: the counts are deterministic, so any change to them is a deliberate one.
//!
//! `cargo test -p ecat-emu --test spi_traffic -- --nocapture` prints the table in
//! docs/performance.md ("SPI traffic per process-data cycle").

use core::cell::Cell;
use std::rc::Rc;

use ecat_core::DeviceConfig;
use ecat_core::chip::Chip;
use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_embassy::Pdi;
use ecat_embassy::mcu::Mcu16;
use ecat_embassy::spi::beckhoff::{self, BeckhoffSpi};
use ecat_embassy::spi::lan9252::{self, Lan9252, WriteSpace};
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::mcu::{self, Cycles, FakeBus16};
use ecat_emu::spi::beckhoff::BeckhoffEsc;
use ecat_emu::spi::lan9252::{Lan9252Chip, Lan9252Config};
use ecat_emu::spi::{FakeSpi, Probe, SpiStats};

const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);
/// Cycles measured; every one must cost the same.
const CYCLES: u8 = 10;

/// The image: `size` bytes each way, outputs (SM2) at 0x1100, inputs (SM3) at 0x1200.
fn areas(size: u16) -> (Area, Area) {
    (Area::new(0x1100, size), Area::new(0x1200, size))
}

/// Walks a device with a `size`/`size` image to OP through the PDI `make` builds, then returns
/// the SPI traffic of one cycle.
fn per_cycle<P: Pdi + 'static>(
    esc: EscConfig,
    size: u16,
    make: impl FnOnce(&Emulator, Probe) -> P + 'static,
) -> SpiStats {
    let mut config = DeviceConfig::new(
        MAILBOX,
        ProcessDataSizes {
            outputs: size,
            inputs: size,
        },
    );
    config.sync_manager_count = esc.sync_managers;
    config.process_ram_end = esc.process_ram_end;
    let mut device = Device::new(config, AcceptAll, Loopback);
    device.esc = esc;
    let probe = Probe::default();
    let bus = probe.clone();
    let result = Rc::new(Cell::new(None));
    let out = result.clone();
    harness::run_with_pdi(
        device,
        move |emu: &Emulator| make(emu, bus),
        move |master| async move {
            let (outputs, inputs) = areas(size);
            master.reset().await;
            assert_eq!(master.request(0x01).await, (0x01, 0));
            master.configure_mailbox(&MAILBOX);
            master.configure_process_data(Some(outputs), Some(inputs));
            for state in [0x02, 0x04, 0x08] {
                assert_eq!(master.request(state).await, (state, 0));
                if state == 0x04 {
                    // Valid outputs before OP, as a MainDevice's cyclic frames bring them.
                    master.write(outputs.start, &vec![0; usize::from(size)]);
                    master.settle().await;
                }
            }
            let mut cost = None;
            for cycle in 0..CYCLES {
                let image: Vec<u8> = (0..size).map(|i| (i as u8) ^ cycle).collect();
                let before = probe.stats();
                assert!(master.write(outputs.start, &image));
                master.settle().await;
                let this = probe.stats() - before;
                assert_eq!(*cost.get_or_insert(this), this, "cycle {cycle}");
                assert_eq!(master.read(inputs.start, usize::from(size)), Some(image));
            }
            assert!(probe.violations().is_empty(), "{:?}", probe.violations());
            out.set(cost);
        },
    );
    result.get().expect("measured")
}

fn beckhoff(size: u16, config: beckhoff::Config) -> SpiStats {
    per_cycle(EscConfig::default(), size, move |emu, probe| {
        BeckhoffSpi::new(FakeSpi::new(BeckhoffEsc::new(emu.clone()), probe), config)
    })
}

fn lan9252(size: u16, write_space: WriteSpace) -> SpiStats {
    let esc = EscConfig::of(Chip::LAN9252);
    per_cycle(esc, size, move |emu, probe| {
        let chip = Lan9252Chip::new(emu.clone(), Lan9252Config::default());
        let config = lan9252::Config {
            write_space,
            ..lan9252::Config::default()
        };
        embassy_futures::block_on(Lan9252::start(FakeSpi::new(chip, probe), config)).expect("start")
    })
}

/// Whole DWORDs for `size` bytes at a DWORD-aligned address.
fn dwords(size: u64) -> u64 {
    size.div_ceil(4) * 4
}

/// The Beckhoff protocol's minimum for a cycle on the IRQ that cannot lose a buffer: the AL event
/// (a NOP, 2 address bytes: the output read must follow an event that shows SM2, and its own
/// address phase is sampled before the buffer arrives that the read may take), one read (2 address
/// bytes, wait state byte, data), one write (2 address bytes, data).
fn beckhoff_minimum(size: u64) -> SpiStats {
    SpiStats {
        transactions: 3,
        bytes: 2 + (2 + 1 + size) + (2 + size),
    }
}

/// The LAN9252's minimum without any status poll: AL event through the CSR (command write 7, data
/// read 7), PRAM read (address/length + start 11, FIFO 3 + DWORDs), PRAM write (11, 3 + DWORDs).
fn lan9252_minimum(size: u64) -> SpiStats {
    SpiStats {
        transactions: 6,
        bytes: 7 + 7 + 11 + 3 + dwords(size) + 11 + 3 + dwords(size),
    }
}

fn report(name: &str, size: u16, measured: SpiStats, minimum: SpiStats) {
    println!(
        "| {name} | {size}/{size} | {} | {} | {} | {} |",
        measured.transactions, measured.bytes, minimum.transactions, minimum.bytes
    );
}

#[test]
fn beckhoff_cycles_are_three_transactions_with_seven_bytes_of_overhead() {
    for (size, expected) in [(11, 29), (64, 135)] {
        let measured = beckhoff(size, beckhoff::Config::default());
        let minimum = beckhoff_minimum(u64::from(size));
        report("Beckhoff (ET1100/AX58100)", size, measured, minimum);
        assert_eq!(
            measured,
            SpiStats {
                transactions: 3,
                bytes: expected
            }
        );
        assert_eq!(measured, minimum);
        assert_eq!(measured.bytes - 2 * u64::from(size), 7, "overhead");
    }
    // Without the wait state byte: 3 transactions, 28 bytes (SOES's stock ET1100 driver: 2, 26,
    // reading the outputs on whatever event raised the IRQ).
    let slow_clock = beckhoff::Config {
        read_latency: beckhoff::ReadLatency::SlowClock,
    };
    let measured = beckhoff(11, slow_clock);
    let minimum = SpiStats {
        transactions: 3,
        bytes: 2 + (2 + 11) + (2 + 11),
    };
    report("Beckhoff, no wait state byte", 11, measured, minimum);
    assert_eq!(measured, minimum);
}

#[test]
fn lan9252_cycles_stay_under_half_of_soes() {
    let cases = [
        (11, WriteSpace::EmptyAtStart, 7, 77),
        (64, WriteSpace::EmptyAtStart, 7, 181),
        (11, WriteSpace::Polled, 8, 84),
        (64, WriteSpace::Polled, 8, 188),
    ];
    for (size, write_space, transactions, bytes) in cases {
        let measured = lan9252(size, write_space);
        let name = format!("LAN9252, {write_space:?}");
        report(&name, size, measured, lan9252_minimum(u64::from(size)));
        assert_eq!(
            measured,
            SpiStats {
                transactions,
                bytes
            },
            "{name}, {size}/{size}"
        );
    }
    // SOES's stock LAN9252 driver: 20 transactions, 158 bytes for the 11/11-byte cycle.
    assert!(lan9252(11, WriteSpace::EmptyAtStart).bytes <= 158 / 2);
}

fn mcu16(size: u16) -> SpiStats {
    per_cycle(mcu::et1100(), size, |emu, probe| {
        Mcu16::new(FakeBus16::new(emu.clone(), probe, Cycles::default()))
    })
}

/// The bus's minimum for a cycle that cannot lose a buffer: the AL event (one word: the output
/// read must follow an event that shows SM2), the outputs in words (reads move whole words), the
/// inputs in words and an odd last byte alone (its byte lane).
fn mcu16_minimum(size: u64) -> SpiStats {
    SpiStats {
        transactions: 1 + 2 * size.div_ceil(2),
        bytes: 2 + 2 * size.div_ceil(2) + size,
    }
}

#[test]
fn mcu16_cycles_are_the_words_of_the_images_and_two_al_event_reads() {
    for (size, transactions) in [(11, 14), (64, 66)] {
        let measured = mcu16(size);
        let minimum = mcu16_minimum(u64::from(size));
        report(
            "µC 16-bit (ET1100/AX58100), bus cycles",
            size,
            measured,
            minimum,
        );
        // Besides the minimum: the AL event read before the input write.
        assert_eq!(
            measured,
            SpiStats {
                transactions,
                bytes: minimum.bytes + 2
            }
        );
        assert_eq!(measured.transactions, minimum.transactions + 1);
    }
}
